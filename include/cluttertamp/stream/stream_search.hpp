#pragma once

#include <cstdint>
#include <functional>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "cluttertamp/core/result.hpp"
#include "cluttertamp/export.hpp"
#include "cluttertamp/pddl/ast.hpp"
#include "cluttertamp/pddl/validator.hpp"
#include "cluttertamp/plugin/context.hpp"
#include "cluttertamp/plugin/stream_sampler.hpp"
#include "cluttertamp/stream/stream_file.hpp"

namespace cluttertamp::stream {

/// The stream search algorithms of PDDLStream (Garrett et al., ICAPS 2020).
///  - incremental: evaluate every stream instance whose domain facts hold, one call
///    each per round (level by level), then search with the real facts; repeat.
///  - adaptive (focused): search with optimistic outputs for the streams not yet
///    evaluated, evaluate only the streams the optimistic plan needs (its stream plan,
///    refined as a tree of bindings in a skeleton queue), disable evaluated instances
///    and re-enable them when the level rises. A stream with :fluents is evaluated in
///    the state before the plan step that needs it, and what it certifies holds there.
enum class Algorithm { adaptive, incremental };

CLUTTERTAMP_API const char* algorithm_name(Algorithm algorithm);
CLUTTERTAMP_API std::optional<Algorithm> algorithm_from_name(std::string_view name);

/// How the searches treat one stream of the stream file (PDDLStream's StreamInfo and
/// FunctionInfo, the parts that apply here).
struct StreamOptions {
  /// A test or generator: every instance whose inputs are real values is called once as
  /// soon as it exists, instead of waiting for a plan to need it (cheap tests, e.g. a
  /// region check). Functions are always evaluated on real values at once.
  bool eager = false;
  /// A function: its value where not yet evaluated, in the adaptive search's optimistic
  /// plans (PDDLStream's opt_fn as a constant). A lower bound keeps plans cost-aware
  /// without ruling any out; 0 by default.
  double optimistic_value = 0.0;
  /// The adaptive search evaluates a skeleton's instances of this stream after its
  /// other streams, unless those need its outputs (PDDLStream's defer_fn, simplified):
  /// an expensive stream is then not called for a skeleton a cheap one rules out.
  bool defer = false;
  /// A test or generator: the chance that a call succeeds (PDDLStream's p_success), in
  /// [0, 1]. The adaptive search evaluates a skeleton's instances that are ready in
  /// increasing order of overhead / (1 - p_success), so that a cheap stream likely to
  /// fail rules a skeleton out before dear ones run (streams at 1 keep the stream
  /// plan's order). 0: never assumed optimistically; only real evaluations certify its
  /// facts, so the adaptive search needs it `eager` (a region test, say).
  double p_success = 1.0;
  /// A test or generator: the relative cost of a call, for that order (any unit, the
  /// same for every stream; PDDLStream's overhead). At least 0.
  double overhead = 1.0;
};

struct StreamSearchOptions {
  Algorithm algorithm = Algorithm::adaptive;
  /// The symbolic search (search::search_names()).
  std::string search = "lazy-gbfs-ff";
  /// adaptive: work of stream evaluation allowed per unit of work of symbolic search
  /// before searching again, at least `min_sampling` each time. Both are counted, never
  /// timed, so a seed gives the same plan on any machine, in units of about a
  /// microsecond on our machine: a stream call is `call_cost` units plus the collision
  /// checks it makes; a search is `search_cost` units plus 10 per grounded operator and
  /// per generated state. (The defaults match the earlier 0.01 s in seconds.)
  double sampling_ratio = 1.0;
  double call_cost = 200.0;
  double search_cost = 200.0;
  double min_sampling = 10000.0;
  /// adaptive: actions an optimistic plan may have beyond the shortest plan found, per
  /// level above that plan's. Longer plans wait, so that short skeletons are sampled
  /// again first. 2 lets a pick-and-place domain add one removal (a pick and a place)
  /// per level.
  int plan_growth = 2;
  /// Once a plan is found, a cost-aware search on the real facts (search::search_names();
  /// empty: none) within `polish_expansions` expansions; its plan replaces the first
  /// when cheaper (action costs and function values; steps without a metric). Then
  /// single actions and pairs whose removal leaves a valid plan are dropped.
  std::string polish_search = "wastar-ff";
  std::uint64_t polish_expansions = 100000;
  /// A plan is returned once its cost (action costs and function values on the real
  /// values; its length without a metric) is at most this (PDDLStream's success_cost).
  /// Until then the search goes on for plans cheaper than the best so far (the symbolic
  /// searches bounded by its cost) for `improve_work` more units of work, counted as
  /// `sampling_ratio` counts them, and returns the best plan found when that runs out,
  /// when no cheaper plan exists or at the time limit. Infinity: the first plan.
  double success_cost = std::numeric_limits<double>::infinity();
  double improve_work = 1e6;
  /// Per stream, by name as the stream file declares it (lower case); streams not
  /// named take the defaults. A name the stream file lacks is an InputError.
  std::map<std::string, StreamOptions> streams;
  /// Called with a line per search iteration (level, plan found, queue, calls), if set.
  std::function<void(const std::string&)> trace;
};

/// A stream-based planning problem. Pointers must outlive the call.
struct StreamProblem {
  const pddl::Domain* domain = nullptr;
  const pddl::Problem* problem = nullptr;
  const StreamFile* streams = nullptr;
  /// Values of the problem's objects handed to streams; an object without one is
  /// handed over as its name (a std::string).
  std::map<std::string, plugin::StreamValue> values;
  /// The code behind each stream, predicate and function, by name; rules need none.
  std::map<std::string, plugin::StreamSampler*> bindings;
};

/// One step of a plan: the action and its arguments, problem objects by name and
/// stream outputs by their generated names ("#g3": output ?g of the 3rd value made).
struct StreamPlanStep {
  std::string action;
  std::vector<std::string> arguments;
};

struct StreamStatistics {
  std::uint64_t stream_calls = 0;      ///< calls of a generator's next()
  std::uint64_t stream_instances = 0;  ///< generators created
  std::uint64_t searches = 0;          ///< symbolic searches run
  std::uint64_t skeletons = 0;         ///< adaptive: optimistic plans queued
  std::uint64_t level = 0;             ///< adaptive: the final level; incremental: rounds
  std::uint64_t values = 0;            ///< stream outputs made
  std::uint64_t plans = 0;             ///< plans found that hold with real facts
  double search_seconds = 0;
  double stream_seconds = 0;
  std::map<std::string, std::uint64_t> calls_per_stream;
};

struct StreamSolution {
  bool solved = false;
  std::string reason;  ///< why not solved
  std::vector<StreamPlanStep> plan;
  /// The plan's cost on the real values (action costs and function values; its length
  /// without a metric), where it could be costed (every function in the plan valued).
  std::optional<double> cost;
  /// The value of every generated object the plan uses.
  std::map<std::string, plugin::StreamValue> values;
  /// Every fact an evaluated stream certified (the plan's static support among them).
  std::vector<pddl::Atom> certified;
  StreamStatistics statistics;
  std::vector<Failure> failures;  ///< what streams said when they produced nothing
};

/// Solves a stream problem within `context.deadline`. Every returned plan is checked
/// against the real facts: each precondition and the goal hold with facts the initial
/// state or an evaluated stream certified (a stream with :fluents: certified in the
/// state where the plan uses them). Throws InputError (at the declaration) for a
/// stream, predicate or function without a binding, a stream with :fluents under the
/// incremental search (PDDLStream's incremental algorithm refuses them too), or a
/// test with :fluents whose fact the domain uses negated; a planning failure is a
/// solution with solved = false and a reason.
CLUTTERTAMP_API StreamSolution solve(const StreamProblem& problem, plugin::PlanningContext& context,
                                     const StreamSearchOptions& options);

/// `problem` with the generated objects a solution's plan uses and the facts of the
/// domain's predicates its streams certified about them (and the problem's objects)
/// added: the plan is then a
/// plain PDDL plan for pddl::validate_plan. Values the plan never uses are left out,
/// so quantifiers range over the plan's values only.
CLUTTERTAMP_API pddl::Problem with_certified_facts(const pddl::Domain& domain, const pddl::Problem& problem,
                                                   const StreamSolution& solution);

/// The solution's plan as PDDL plan steps.
CLUTTERTAMP_API std::vector<pddl::PlanStep> pddl_plan(const StreamSolution& solution);

}  // namespace cluttertamp::stream
