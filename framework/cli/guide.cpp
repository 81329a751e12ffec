// `cluttertamp guide`: write the automatic guidance (physics::generate_guidance) of a
// reach problem to a guidance file, for grtc to read, or for a person to edit.
#include <fstream>
#include <iomanip>
#include <iostream>

#include "cli/commands.hpp"
#include "cluttertamp/io/guidance_io.hpp"
#include "cluttertamp/io/problem_io.hpp"
#include "cluttertamp/physics/guidance.hpp"

namespace cluttertamp::cli {

int guide(const GuideArgs& args) {
  const Problem problem = io::load_problem(args.problem);
  if (!std::holds_alternative<ReachTask>(problem.task)) {
    throw InputError({args.problem.string(), 0, 0}, "guide needs a problem with task: {reach: <target>}");
  }
  const Scene& scene = problem.scene;
  const WorldState initial = WorldState::initial(scene);
  const physics::PushWorld world(scene, initial);
  const Eigen::Vector3d exit = physics::gripper_at_exit(scene);
  const physics::Guidance guidance = physics::generate_guidance(world, world.state_of(initial, exit), exit.head<2>(),
                                                                args.max_guides, args.diameter);
  std::ofstream out(args.output);
  if (!out) throw InputError({args.output.string(), 0, 0}, "cannot write the guidance file");
  out << io::guidance_to_yaml(scene, guidance);
  if (args.verbosity != Verbosity::quiet) {
    std::cout << "wrote " << args.output.string() << ": " << guidance.size() << " guide" << (guidance.size() == 1 ? "" : "s")
              << "\n";
    for (const physics::Guide& g : guidance) {
      std::cout << std::fixed << std::setprecision(3) << "  push " << scene.objects[g.object].id << " to (" << g.centre.x()
                << ", " << g.centre.y() << "), diameter " << g.diameter << " m\n";
    }
  }
  return 0;
}

}  // namespace cluttertamp::cli
