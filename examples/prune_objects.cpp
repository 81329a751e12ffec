// Loads a problem file, creates an object pruner plugin by name and prints which
// objects it says must be removed before the target can be retrieved.
//
//   ./build/bin/example_prune_objects problems/default.yaml [pruner-name]
#include <iostream>

#include "cluttertamp/io/problem_io.hpp"
#include "cluttertamp/plugin/object_pruner.hpp"
#include "cluttertamp/plugin/registry.hpp"

int main(int argc, char** argv) {
  if (argc < 2) {
    std::cerr << "usage: " << argv[0] << " PROBLEM.yaml [PRUNER]\n";
    return 2;
  }
  try {
    const cluttertamp::Problem problem = cluttertamp::io::load_problem(argv[1]);
    const cluttertamp::plugin::Registry registry(cluttertamp::plugin::Registry::default_search_paths());
    const auto pruner = registry.create<cluttertamp::plugin::ObjectPruner>(argc > 2 ? argv[2] : "corridor");

    std::map<std::string, std::uint64_t> counters;
    const cluttertamp::plugin::Samplers no_samplers;
    cluttertamp::plugin::PlanningContext context{problem, cluttertamp::plugin::Deadline::after(problem.time_limit),
                                                 problem.seed, counters, no_samplers};
    const auto answer = pruner->prune(context, cluttertamp::WorldState::initial(problem.scene));
    if (answer.failure) {
      std::cout << "no removal sequence: " << answer.failure->reason << "\n";
      return 1;
    }
    const cluttertamp::Scene& scene = problem.scene;
    std::cout << "to retrieve '" << scene.objects[scene.target].id << "', remove in this order:";
    for (cluttertamp::ObjectIndex i : answer.removal_sequences.front()) std::cout << " " << scene.objects[i].id;
    std::cout << "\n";
    return 0;
  } catch (const cluttertamp::InputError& e) {
    std::cerr << e.diagnostics().str();
    return 2;
  }
}
