// Creates the grasp sampler a problem file names and asks it for grasps of every
// object: a way to try a sampler plugin, yours included.
//
//   ./build/bin/example_try_grasps PROBLEM.yaml [--plugin-path DIR] [--all]
//
// --all also lists every blocked grasp: its approach direction (degrees, world frame),
// the objects in its way and why.
#include <cmath>
#include <iostream>
#include <string>
#include <vector>

#include "cluttertamp/collision/shared_world.hpp"
#include "cluttertamp/robot/robot_description.hpp"
#include "cluttertamp/io/problem_io.hpp"
#include "cluttertamp/plugin/grasp_sampler.hpp"
#include "cluttertamp/plugin/registry.hpp"
#include "cluttertamp/run/runner.hpp"

int main(int argc, char** argv) {
  using namespace cluttertamp;
  std::vector<std::string> args(argv + 1, argv + argc);
  const bool all = std::erase(args, "--all") > 0;
  if (args.size() != 1 && !(args.size() == 3 && args[1] == "--plugin-path")) {
    std::cerr << "usage: " << argv[0] << " PROBLEM.yaml [--plugin-path DIR] [--all]\n";
    return 2;
  }
  try {
    const Problem problem = io::load_problem(args[0]);
    run::RunOptions options;
    if (args.size() == 3) options.plugin_paths.emplace_back(args[2]);
    const plugin::Registry registry(run::plugin_search_paths(problem, options));
    const auto choice = problem.samplers.find(plugin::KindOf<plugin::GraspSampler>::name);
    if (choice == problem.samplers.end()) {
      std::cerr << args[0] << ": the problem names no grasp_sampler\n";
      return 2;
    }
    const auto sampler = registry.create<plugin::GraspSampler>(choice->second.name, choice->second.parameters, choice->second.where);
    collision::SharedWorld world(problem.scene, problem.robot.loaded);
    std::map<std::string, std::uint64_t> counters;
    const plugin::Samplers samplers;
    plugin::PlanningContext context{problem, plugin::Deadline::after(problem.time_limit), problem.seed, counters, samplers, &world};
    WorldState state = WorldState::initial(problem.scene);
    state.robot_configuration = robot::initial_configuration(problem.robot);
    std::cout << "grasp sampler '" << choice->second.name << "':\n";
    for (ObjectIndex i = 0; i < problem.scene.objects.size(); ++i) {
      const plugin::GraspAnswer answer = sampler->sample(context, {i, state});
      std::cout << "  " << problem.scene.objects[i].id << ": " << answer.usable.size() << " usable";
      if (const plugin::BlockedGrasp* b = answer.least_blocked()) {
        std::cout << ", least blocked by";
        for (ObjectIndex o : b->blocking_objects) std::cout << " " << problem.scene.objects[o].id;
      }
      std::cout << "\n";
      for (std::size_t k = 0; all && k < answer.blocked.size(); ++k) {
        const plugin::BlockedGrasp& b = answer.blocked[k];
        const Eigen::Vector3d approach = b.grasp.world_T_gripper.linear().col(2);
        std::cout << "    " << std::lround(std::atan2(approach.y(), approach.x()) * 180.0 / M_PI) << " deg:";
        for (ObjectIndex o : b.blocking_objects) std::cout << " " << problem.scene.objects[o].id;
        std::cout << " (" << b.reason << ")\n";
      }
    }
    return 0;
  } catch (const InputError& e) {
    std::cerr << e.diagnostics().str();
    return 2;
  }
}
