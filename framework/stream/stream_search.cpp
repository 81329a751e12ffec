#include "cluttertamp/stream/stream_search.hpp"

#include <algorithm>
#include <memory>
#include <set>
#include <stdexcept>
#include <utility>

#include "cluttertamp/core/free_beside.hpp"
#include "stream/searches.hpp"

namespace cluttertamp::stream {

const char* algorithm_name(Algorithm algorithm) {
  return algorithm == Algorithm::adaptive ? "adaptive" : "incremental";
}

std::optional<Algorithm> algorithm_from_name(std::string_view name) {
  if (name == "adaptive" || name == "focused") return Algorithm::adaptive;
  if (name == "incremental") return Algorithm::incremental;
  return std::nullopt;
}

StreamSolution solve(const StreamProblem& problem, plugin::PlanningContext& context, const StreamSearchOptions& options) {
  if (!problem.domain || !problem.problem || !problem.streams) {
    throw std::invalid_argument("stream::solve: domain, problem and streams are required");
  }
  auto core = std::make_unique<detail::SearchCore>(problem, context, options);
  auto queue = std::make_unique<detail::SkeletonQueue>(*core);
  StreamSolution solution = core->run([&] {
    if (options.algorithm == Algorithm::incremental) detail::incremental_search(*core);
    else detail::adaptive_search(*core, *queue);
  });
  // Ended by the time limit (solved or not: success_cost may keep it going to the
  // limit), it may hold millions of instances and two groundings: freed beside the
  // caller, but the generators first, here: they are the plugins' code.
  if (context.deadline.expired()) {
    core->release_generators();
    free_beside(std::make_pair(std::move(queue), std::move(core)));
  }
  return solution;
}

pddl::Problem with_certified_facts(const pddl::Domain& domain, const pddl::Problem& problem,
                                   const StreamSolution& solution) {
  pddl::Problem out = problem;
  std::set<std::string> used;  // generated values the plan uses
  for (const StreamPlanStep& s : solution.plan) {
    for (const std::string& arg : s.arguments) {
      if (!arg.empty() && arg[0] == '#' && used.insert(arg).second) out.objects.push_back({arg, {"object"}, {}});
    }
  }
  for (const pddl::Atom& a : solution.certified) {
    const bool relevant = domain.predicates.count(a.predicate) &&
                          std::all_of(a.args.begin(), a.args.end(), [&](const pddl::Term& t) {
                            return t.name.empty() || t.name[0] != '#' || used.count(t.name);
                          });
    if (relevant) out.init.push_back(a);
  }
  return out;
}

std::vector<pddl::PlanStep> pddl_plan(const StreamSolution& solution) {
  std::vector<pddl::PlanStep> out;
  for (const StreamPlanStep& s : solution.plan) out.push_back({s.action, s.arguments, {}});
  return out;
}

}  // namespace cluttertamp::stream
