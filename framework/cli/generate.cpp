// `cluttertamp generate`: shelf scenes as in Tian et al., Section VI-B, and a problem
// file beside each, keeping only scenes whose target cannot be retrieved without
// removing something (checked with the shipped samplers).
#include <cmath>
#include <cstdio>
#include <optional>
#include <sstream>
#include <iostream>

#include "cli/commands.hpp"
#include "cluttertamp/run/shelf_runs.hpp"
#include "cluttertamp/io/robot_description_io.hpp"
#include "cluttertamp/scenes/shelf_fit.hpp"
#include "cluttertamp/collision/collision_world.hpp"
#include "cluttertamp/collision/shared_world.hpp"
#include "cluttertamp/io/scene_io.hpp"
#include "cluttertamp/io/text_file.hpp"
#include "cluttertamp/manipulation/actions.hpp"
#include "cluttertamp/plugin/grasp_sampler.hpp"
#include "cluttertamp/plugin/motion_sampler.hpp"
#include "cluttertamp/plugin/placement_sampler.hpp"
#include "cluttertamp/plugin/registry.hpp"
#include "cluttertamp/plugin/task_planner.hpp"
#include "cluttertamp/run/runner.hpp"
#include "cluttertamp/scenes/shelf_generator.hpp"
#include "cluttertamp/physics/push_world.hpp"

namespace cluttertamp::cli {

namespace fs = std::filesystem;

namespace {

// Seeds the exhaustive search runs with: motion planning is randomized, so a set one
// draw finds no motion for may work with another; the minimum must hold for all.
constexpr std::uint64_t kProofSeeds = 3;

// The work budget of a generated pushing problem: physics propagations of 1 s.
constexpr int kPushPropagations = 15000;

// Why `scene`'s fewest objects to move (target included) is not `wanted`, or nothing
// when it is: retrieval_graph's plan bounds it from above, the exhaustive search
// of every smaller set, with seeds 0, 1, 2, proves it.
std::optional<std::string> min_removals_differ(const Scene& scene, const GenerateArgs& args,
                                               const std::shared_ptr<const robot::RobotDescription>& robot,
                                               const plugin::Registry& registry, const plugin::Samplers& samplers) {
  const Result quick = run::plan_scene(scene, robot, *registry.create<plugin::TaskPlanner>("retrieval_graph"), samplers, 0, 10);
  if (quick.solved && static_cast<int>(quick.moved_objects.size()) < args.min_removals) {
    return "retrieval_graph moves only " + std::to_string(quick.moved_objects.size());
  }
  Parameters limit;
  limit.set("max_removals", static_cast<std::int64_t>(args.min_removals - 1));
  for (std::uint64_t seed = 0; seed < kProofSeeds; ++seed) {
    const Result best =
        run::plan_scene(scene, robot, *registry.create<plugin::TaskPlanner>("exhaustive", limit), samplers, seed, args.check_time);
    const std::string with = "exhaustive (seed " + std::to_string(seed) + ")";
    if (!best.solved) return with + ": " + best.reason;
    if (static_cast<int>(best.moved_objects.size()) != args.min_removals) {
      return with + ": the minimum is " + std::to_string(best.moved_objects.size());
    }
  }
  return std::nullopt;
}

// "[0.1, -2, ...]": joint values as the problem file writes them, exact enough to
// reproduce the configuration the fit checked.
std::string yaml_list(const Eigen::VectorXd& values) {
  std::string text = "[";
  for (Eigen::Index i = 0; i < values.size(); ++i) {
    char number[32];
    std::snprintf(number, sizeof number, "%.10g", std::abs(values[i]) < 1e-12 ? 0.0 : values[i]);  // no "1e-17"
    text += (i ? ", " : "") + std::string(number);
  }
  return text + "]";
}

std::string number(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.4g", std::abs(v) < 1e-12 ? 0.0 : v);
  return text;
}

// A pushing shelf and, asked for, its reach problem with the paper's robot, controls
// (velocities within +-0.1 m/s and rad/s, each held 1 s) and goal (the hand's reach
// point within 0.07 m of the target, as the paper's public code has it).
int generate_push(const GenerateArgs& args, const robot::RobotDescription& robot) {
  if (args.table || args.occlusion || args.min_removals > 0) {
    throw InputError({"--push", 0, 0}, "a pushing shelf takes --objects, --width, --depth and --min-gap only");
  }
  scenes::PushShelfSpec spec;
  spec.obstacles = args.objects;
  if (args.width > 0) spec.width = args.width;
  if (args.depth > 0) spec.depth = args.depth;
  if (args.min_gap) spec.min_gap = *args.min_gap;
  io::check_writable(args.output, "scene file (--output)");
  if (!args.problem.empty()) io::check_writable(args.problem, "problem file (--problem)");
  Scene scene;
  try {
    scene = scenes::generate_push_shelf(spec, args.seed);
  } catch (const std::runtime_error& e) {
    std::cerr << "generate --push: --objects " << args.objects << ": " << e.what() << "\n";
    return run::ExitCode::bad_input;
  }
  io::write_scene(args.output, scene);
  if (args.verbosity != Verbosity::quiet) {
    std::cout << "wrote " << args.output.string() << ": the target and " << args.objects << " obstacles (seed " << args.seed << ")\n";
  }
  if (args.problem.empty()) return run::ExitCode::solved;
  // The paper's base turns about a centre 1.27 m behind the hand: the arm's base goes
  // ahead of it by what the arm's own reach leaves of that.
  const double offset = physics::base_offset_for_lever(physics::arm_pusher(robot, robot.home()), physics::kPaperLever);
  const fs::path dir = fs::absolute(args.problem).parent_path();
  std::ostringstream out;
  out << "# Reaching through clutter by pushing, generated by cluttertamp generate --push (seed " << args.seed << "), set up\n"
      << "# as Papallas & Dogar (2020) did: the arm on a planar base turning within +-pi/4, the hand " << number(physics::kPaperLever) << " m\n"
      << "# ahead of the base's centre; controls within +-0.05 m/s and rad/s held 1 s, goal bias 0.1 and\n"
      << "# states sampled in a 4 m square about the shelf (the paper's code); reached with the hand's\n"
      << "# reach point within 0.07 m of the target; friction the larger of two bodies' (MuJoCo's); an\n"
      << "# object tilted beyond 0.1 rad or a wall pressed with more than 9 N ends a push (invalid).\n"
      << "# Format: docs/file-formats.md, \"Problem files\".\n"
      << "version: 1\n"
      << "name: " << args.problem.stem().string() << "\n"
      << "scene: " << fs::relative(fs::absolute(args.output), dir).string() << "\n"
      << "robot: {description: " << fs::relative(fs::absolute(args.robot), dir).string() << "}\n"
      << "task: {reach: target}\n"
      << "physics: {pusher: arm, base_offset: [" << number(offset) << ", 0], yaw_limits: [-0.7854, 0.7854], friction_combine: max,\n"
      << "          tip_limit: 0.1, wall_force_limit: 9}\n"
      << "planner:\n"
      << "  plugin: rtc_ompl\n"
      << "  time_limit: 300\n"
      << "  seed: 0\n"
      << "  parameters: {planner: rrt, goal: point, goal_distance: 0.07, goal_bias: 0.1, step: 1, max_steps: 1,\n"
      << "               max_speed: 0.05, max_side_speed: 0.05, max_turn: 0.05,\n"
      << "               sample_bounds: [" << number(spec.front - 3.19) << ", -2, " << number(spec.front + 0.81) << ", 2],\n"
      << "               max_propagations: " << kPushPropagations << "}  # work budget\n"
      << "# Guided planning (grtc, bench push) pushes each guide with the same controls.\n"
      << "plugins:\n"
      << "  push_sampler: {plugin: push_ompl, parameters: {step: 1, max_steps: 1, max_speed: 0.05, max_side_speed: 0.05, max_turn: 0.05}}\n";
  io::write_text_file(args.problem, out.str(), "problem file");
  if (args.verbosity != Verbosity::quiet) std::cout << "wrote " << args.problem.string() << "\n";
  return run::ExitCode::solved;
}

// A home in self collision leaves no test grasp and no start: every problem drawn for it
// would be refused. Bad input, said before any shelf is drawn.
void check_home_clear_of_itself(const std::shared_ptr<const robot::RobotDescription>& robot, const std::string& file) {
  const collision::CollisionWorld world(Scene{}, robot);
  auto context = world.make_context();
  Diagnostics errors;
  for (const auto& [a, b] : world.self_contacts(robot->home(), *context)) {
    errors.error({file, 0, 0}, "the robot's home is in self collision: '" + robot->model()->links()[a].name + "' touches '" +
                                   robot->model()->links()[b].name + "' (give another home, or disable the pair if these links may touch)");
  }
  errors.throw_if_any();
}

}  // namespace

int generate(const GenerateArgs& args) {
  auto robot = std::make_shared<const robot::RobotDescription>(io::load_robot_description(args.robot));
  if (args.push) return generate_push(args, *robot);
  check_home_clear_of_itself(robot, args.robot.string());
  const plugin::Registry registry(plugin::Registry::default_search_paths());
  const bool check = (args.require_removal && !args.occlusion && !args.table) || args.min_removals > 0;
  const plugin::Samplers samplers = check ? run::shipped_samplers(registry) : plugin::Samplers{};
  scenes::ShelfSpec spec;
  spec.objects = args.objects;
  spec.width = args.width;
  spec.depth = args.depth;
  if (args.min_gap) spec.min_gap = *args.min_gap;
  std::optional<Eigen::VectorXd> start;  // the problem's robot configuration, when not the home
  if (args.fit_to_robot) {
    const scenes::ShelfFit fit = scenes::fit_shelf_to_robot(spec, robot);
    spec = fit.spec;
    if (args.verbosity != Verbosity::quiet) {
      std::printf("shelf for %s: %s (%d where it stood)\n", robot->name().c_str(), scenes::describe_placement(fit).c_str(),
                  fit.reached_as_given);
    }
    if (fit.start) {
      // The checks below and the problem file start the robot where the fit found it clear.
      start = fit.start;
      robot = std::make_shared<const robot::RobotDescription>(robot->with_home(*fit.start));
      if (args.verbosity != Verbosity::quiet) {
        std::printf("the robot's home reaches into the cabinet: the problem starts with the tool drawn back %.2f m (its `configuration`)\n",
                    fit.start_drawn_back);
      }
    }
  }
  if (args.occlusion && (args.width > 0 || args.depth > 0 || args.min_removals > 0)) {
    throw InputError({"--occlusion", 0, 0}, "an occlusion shelf is sized by its columns: --width, --depth and --min-removals do not apply");
  }
  if (args.table && (args.occlusion || args.depth > 0 || args.min_removals > 0)) {
    throw InputError({"--table", 0, 0}, "a table scene takes --objects and --width (the table's side) only");
  }
  io::check_writable(args.output, "scene file (--output)");
  if (!args.problem.empty()) io::check_writable(args.problem, "problem file (--problem)");
  int unreachable = 0;  // scenes whose target the robot cannot retrieve even from the emptied shelf
  for (int attempt = 0; attempt < args.max_attempts; ++attempt) {
    const std::uint64_t seed = args.seed + static_cast<std::uint64_t>(attempt);
    Scene scene;
    try {
      if (args.table) {
        scenes::TableSpec table;
        table.objects = args.objects;
        if (args.width > 0) table.size = args.width;
        if (args.min_gap) table.min_gap = *args.min_gap;
        scene = scenes::generate_table_scene(table, seed);
      } else if (args.occlusion) {
        scenes::OcclusionSpec occlusion;
        if (args.occlusion_layout == "random") {
          occlusion.layout = scenes::OcclusionLayout::random;
          occlusion.objects = args.objects;
        } else {
          if (args.objects % 4 != 0) throw std::runtime_error("an occlusion shelf holds columns of 4: a multiple of 4 objects");
          occlusion.columns = args.objects / 4;
        }
        scene = scenes::generate_occlusion_scene(occlusion, seed);
      } else {
        scene = scenes::generate_shelf_scene(spec, seed);
      }
    } catch (const std::runtime_error& e) {
      std::cerr << "generate: --objects " << args.objects << ": " << e.what() << "\n";
      return run::ExitCode::bad_input;
    }
    // Checked as written: the file rounds poses, and a motion plan can hinge on that.
    const fs::path written = args.output.string() + ".tmp";
    io::write_scene(written, scene);
    scene = io::load_scene(written);
    fs::remove(written);
    if (!args.occlusion && !args.table && args.require_removal) {
      const run::TargetAccess access = run::target_access(scene, robot, samplers, seed);
      if (access == run::TargetAccess::directly) {
        if (args.verbosity == Verbosity::verbose) std::cerr << "seed " << seed << ": the target comes out directly; next\n";
        continue;
      }
      if (access == run::TargetAccess::never) {
        ++unreachable;
        if (args.verbosity == Verbosity::verbose) {
          std::cerr << "seed " << seed << ": the robot cannot retrieve the target even with every other object gone; next\n";
        }
        continue;
      }
    }
    if (args.min_removals > 0) {
      if (const auto why = min_removals_differ(scene, args, robot, registry, samplers)) {
        if (args.verbosity != Verbosity::quiet) std::cerr << "seed " << seed << ": " << *why << "; next\n";
        continue;
      }
    }
    io::write_scene(args.output, scene);
    if (args.verbosity != Verbosity::quiet) {
      std::cout << "wrote " << args.output.string() << ": " << scene.objects.size() << " objects (seed " << seed << ")\n";
    }
    if (!args.problem.empty()) {
      const fs::path dir = fs::absolute(args.problem).parent_path();
      std::ostringstream out;
      out << "# Generated by cluttertamp generate (seed " << seed << ")"
          << (args.min_removals > 0 ? "; fewest objects to move, target included: " + std::to_string(args.min_removals) +
                                          " (proved by the exhaustive planner, seeds 0-2)"
                                    : "")
          << ". Format: docs/file-formats.md, \"Problem files\".\n"
          << "version: 1\n"
          << "scene: " << fs::relative(fs::absolute(args.output), dir).string() << "\n"
          << "robot: {description: " << fs::relative(fs::absolute(args.robot), dir).string()
          << (start ? ", configuration: " + yaml_list(*start) : std::string()) << "}\n"
          << "task: {retrieve: target}\n"
          << (args.table ? "planner: {plugin: retrieval_graph, time_limit: 120, seed: 0, parameters: {area_margin: 0.3, grasp_orders: 3}}\n"
                         : std::string("planner: {plugin: ") + (args.occlusion ? "occlusion" : "retrieval_graph") +
                               ", time_limit: 60, seed: 0}\n")
          << (args.table ? "plugins: {grasp_sampler: {plugin: grasp_side, parameters: {spread: 180, directions: 18, base_distance: 0.6}}, motion_sampler: motion_ompl, "
                           "placement_sampler: placement_region}\n"
                         : "plugins: {grasp_sampler: grasp_side, motion_sampler: motion_ompl, placement_sampler: placement_region}\n");
      io::write_text_file(args.problem, out.str(), "problem file");
      if (args.verbosity != Verbosity::quiet) std::cout << "wrote " << args.problem.string() << "\n";
    }
    return run::ExitCode::solved;
  }
  std::cerr << "generate: none of " << args.max_attempts << " scenes qualified ("
            << (args.min_removals > 0 ? "minimum |O_r| " + std::to_string(args.min_removals) : "a removal needed") << ")";
  if (unreachable > 0) {
    std::cerr << "; in " << unreachable << " of them the robot cannot retrieve the target even from the shelf emptied of the others"
              << " (its grasps, its reach or the exit pose; --any keeps the first scene unchecked)";
  }
  std::cerr << "\n";
  return run::ExitCode::no_plan;
}

}  // namespace cluttertamp::cli
