#pragma once
// Internal: what the two stream searches share. The objects and facts so far
// (FactBase), the stream evaluator, the symbolic searches on the real or the
// optimistic facts, the checks of a plan against the real facts, and the plans found
// (the cheapest kept, polished, and the solution written out). The incremental search
// (incremental_search.cpp) and the adaptive one (adaptive_search.cpp, with its
// SkeletonQueue) decide what to evaluate and when to search; this decides neither.

#include <cstdint>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "cluttertamp/plugin/context.hpp"
#include "cluttertamp/search/grounding.hpp"
#include "cluttertamp/stream/stream_search.hpp"
#include "stream/evaluator.hpp"
#include "stream/fact_base.hpp"
#include "stream/support.hpp"

namespace cluttertamp::stream::detail {

/// An action of a plan with its arguments as objects.
struct Step {
  const pddl::Action* action = nullptr;
  std::vector<ObjectId> args;
};

/// Where a plan needs its facts: the steps whose precondition or effect conditions
/// rest on each fact (the plan's length for the goal), and the state before each step.
struct Uses {
  std::map<FactKey, std::set<int>> steps;
  std::vector<State> states;  ///< before each step, then the final state
};

/// The state of one stream search and the work both algorithms share (see above).
class SearchCore {
 public:
  /// Checks the stream options against the stream file (InputError listing every
  /// problem), loads the initial objects and facts. Every argument must outlive it.
  SearchCore(const StreamProblem& problem, plugin::PlanningContext& context, const StreamSearchOptions& options);
  SearchCore(const SearchCore&) = delete;
  SearchCore& operator=(const SearchCore&) = delete;

  /// Runs `search` (one of the two algorithms) and returns the solution: the best plan
  /// found when the time limit ends the search for a cheaper one, the reason otherwise.
  StreamSolution run(const std::function<void()>& search);

  /// Destroys every generator (plugin code, which must not outlive its sampler).
  void release_generators() { evaluator_.release_generators(); }

  FactBase& facts() { return base_; }
  StreamEvaluator& evaluator() { return evaluator_; }
  StreamSolution& out() { return out_; }
  plugin::PlanningContext& context() { return context_; }
  const StreamSearchOptions& options() const { return options_; }
  const StreamProblem& problem() const { return problem_; }
  /// Tests certifying predicates the domain uses only negated: false until evaluated.
  const std::set<std::string>& negated_tests() const { return negated_tests_; }
  /// Work of searches and stream evaluation so far, in StreamSearchOptions' units.
  double& work() { return work_; }
  /// The work of the last symbolic search, and its grounding.
  double last_search_work() const { return last_search_work_; }
  const search::GroundingStats& last_grounding() const { return last_grounding_; }

  /// A plan found by the symbolic search on the real facts, and on the optimistic ones
  /// too when `optimistic`; nothing when it finds none. Throws search::TimeLimit when
  /// the run's time is up.
  std::optional<std::vector<Step>> plan_symbolic(bool optimistic);

  /// The support of a plan: every precondition and the goal, state by state.
  std::optional<Support> plan_support(const std::vector<Step>& steps, bool optimistic, Uses* uses = nullptr);

  static Env env_of(const Step& s);

  /// The state before step `k` of `steps` (the final state for k = steps.size()).
  State state_before(const std::vector<Step>& steps, std::size_t k);

  /// True when the plan holds with real facts, every negated test it relies on
  /// evaluated (now, if need be) and false.
  bool verify(const std::vector<Step>& steps);

  /// The test instance that decides a negated fact.
  std::optional<int> test_instance(const FactKey& fact);

  /// A plan that holds with real facts: polished, kept if the cheapest so far. Returns
  /// whether the search is done (the best plan then is the solution): its cost is at
  /// most `success_cost` or 0 (nothing is cheaper), or the new plan cannot be costed
  /// to compare (a function without a value: the search would find it again and again).
  bool accept(std::vector<Step> steps);

  /// Whether the work allowed for cheaper plans after the first is spent; then the best
  /// plan is the solution.
  bool improved_enough();

  /// The search ends without a cheaper plan: the best one found, if any, is the solution.
  void settle();

  /// Throws TimeLimit once the run's time is up, looking at the clock every 256th call:
  /// a stream whose inputs nothing binds ranges over every object, and each new
  /// optimistic value multiplies its instances.
  void keep_time_limit();

 private:
  // A plan and its cost on the real values, if it could be costed.
  struct Costed {
    std::vector<Step> steps;
    std::optional<double> cost;
  };

  void check_bindings() const;

  void load_initial();

  void add_named(const pddl::TypedName& named);

  bool certified_by_test(const std::string& predicate) const;

  // Plans with the real facts, and the optimistic ones if asked.
  // The PDDL problem of the facts so far: the real ones, and the optimistic ones too
  // when `optimistic`.
  pddl::Problem symbolic_problem(bool optimistic);

  // Once a plan is found: a cost-aware search (`polish_search`, within
  // `polish_expansions`) on the real facts, whose plan replaces it when cheaper (action
  // costs and function values; steps without a metric) and valid; then the steps whose
  // removal leaves a valid plan go. The first plan of a greedy search may take detours
  // (a pick and place to get the hand free, a value from an earlier skeleton) that cost
  // nothing to find and much to run. The cost is wanted only against `success_cost`.
  Costed polished(std::vector<Step> steps);

  double cost_in(const std::map<std::string, double>& cost_of, const std::vector<Step>& steps) const;

  std::vector<Step> cheaper_plan(const search::Task& task, const std::map<std::string, double>& cost_of, std::vector<Step> steps);

  // False when a function on real values has none (its call failed): the real
  // problem could not be costed.
  bool every_function_valued();

  std::string name_of(const Step& step) const;

  // Function values: real ones where evaluated, 0 (a lower bound) where optimistic.
  void add_function_values(pddl::Problem& p, bool optimistic);

  Step step_of(const std::string& name);

  // Greedy action elimination: while dropping one action, or two (a place and the pick
  // that undoes it need not be neighbours), leaves a plan that holds with real facts,
  // drop them; singles before pairs, earliest first, so a plan always shortens the same
  // way. The searches are not cost-optimal and the incremental one plans with every
  // value it has, so such detours do occur.
  std::vector<Step> without_pointless_steps(std::vector<Step> steps);

  // The symbolic searches look only for plans cheaper than the best so far.
  double cost_bound() const;

  void solved(Costed plan);

  pddl::Atom atom_of(const FactKey& f) const;

  const StreamProblem& problem_;
  const pddl::Domain& domain_;
  plugin::PlanningContext& context_;
  const StreamSearchOptions& options_;
  FactBase base_;
  State initial_state_;
  std::set<std::string> negated_tests_;
  double last_search_seconds_ = 0;
  double last_search_work_ = 0;  // of the last search, in StreamSearchOptions' units
  search::GroundingStats last_grounding_;
  std::uint64_t ticks_ = 0;  // keep_time_limit's calls
  double work_ = 0;  // of searches and stream evaluation so far, in StreamSearchOptions' units
  std::optional<Costed> best_;  // the cheapest plan found
  std::optional<double> improve_from_;  // work_ when the first plan above success_cost was found
  // Each iteration's problem holds the last one's objects and more: grounded on the
  // last one's work. The real facts' problems and the optimistic ones are two series.
  search::Grounding optimistic_grounding_{domain_};
  search::Grounding real_grounding_{domain_};
  StreamSolution out_;
  StreamEvaluator evaluator_{problem_, base_, context_, options_, out_};
};

}  // namespace cluttertamp::stream::detail
