#include "cli/command_line/command.hpp"

namespace cluttertamp::cli {

Command declare_generate(CLI::App& app, CommonOptions& common) {
  auto args = std::make_shared<GenerateArgs>();
  auto* generate = app.add_subcommand("generate", "Generate a shelf scene (Tian et al., Section VI-B) and optionally a problem file");
  add_package_paths(*generate, common);
  auto* objects = generate->add_option("--objects", args->objects,
                                       "Cylinders in the shelf (12 to 20, and 100, in the paper); with --push the obstacles "
                                       "besides the target (default 10)")
                      ->capture_default_str()
                      ->check(CLI::Range(1, 500));
  generate->add_option("--width", args->width,
                       "Cabinet interior width, m (default: 0.9 for 12 objects to 1.2 for 20, +0.0225 per object beyond)")
      ->check(finite_range(0.1, 10.0));
  generate->add_option("--depth", args->depth, "Cabinet interior depth, m (default: 0.6 for 12 objects to 0.7 for 20 and beyond)")
      ->check(finite_range(0.1, 2.0));
  generate->add_option("--min-gap", args->min_gap,
                       "Least distance between cylinders and to the walls, m (default 0, the paper's recipe: any "
                       "collision-free placement, so neighbours may touch; with --table 0.01)")
      ->check(finite_range(0.0, 0.2));
  generate->add_option("--min-removals", args->min_removals,
                       "Keep only scenes whose fewest objects to move, target included, is this (Table VI: 2, 3, 4); "
                       "proved with the exhaustive planner")
      ->check(CLI::Range(2, 10));
  generate->add_option("--check-time", args->check_time, "Seconds for the exhaustive check of one scene")
      ->capture_default_str()
      ->check(finite_positive());
  generate->add_option("--seed", args->seed, "Seed of the first scene tried")->capture_default_str();
  generate->add_option("--output", args->output, "Scene file to write")->required();
  generate->add_option("--problem", args->problem, "Also write a problem file for the scene here");
  args->robot = source_file("domains/robots/ur10_ag95.yaml");
  auto* robot = generate->add_option("--robot", args->robot,
                                     "Robot description (with --table: pr2_mobile); given, a shelf's opening and floor are "
                                     "moved to where this robot's arm reaches inside it (kept when it reaches all of it)")
                    ->capture_default_str()
                    ->check(CLI::ExistingFile);
  generate->add_flag("--table", args->table,
                     "A table reachable from every side (Tian et al., Fig. 9): --objects cylinders, the target in the middle, "
                     "--width the table's side (default 0.7 m); its problem uses pr2_mobile (unless --robot names another) "
                     "and retrieval_graph with area_margin 0.3");
  auto* occlusion = generate->add_flag("--occlusion", args->occlusion,
                     "An occlusion shelf (Tian et al., Fig. 7): --objects / 4 columns of 4 cylinders, each hidden from the "
                     "camera by the one in front, the target at the back of one; its problem uses the occlusion planner");
  generate->add_option("--occlusion-layout", args->occlusion_layout,
                       "With --occlusion: 'columns' (above) or 'random': --objects cylinders drawn as for Table I, the "
                       "camera in front at their height, the target the hidden one nearest the back wall's middle")
      ->capture_default_str()
      ->check(CLI::IsMember({"columns", "random"}))
      ->needs(occlusion);
  generate->add_flag("--push", args->push,
                     "A pushing shelf like Papallas & Dogar's (2020, Section VI-B): 0.59 m deep, 0.584 m wide, 0.26 m "
                     "high, the target (radius 3 cm, 10 cm tall) at the back and --objects such obstacles (friction 0.4, "
                     "boards 0.5) where they fit; its problem reaches the target by pushing with the robot's arm on a planar "
                     "base, with the paper's controls and goal (rtc_ompl)");
  generate->add_flag("!--any", args->require_removal,
                     "Keep the first scene even if the target comes out without removing anything");
  generate->add_option("--attempts", args->max_attempts, "Scenes tried (seeds seed, seed+1, ...)")
      ->capture_default_str()
      ->check(CLI::Range(1, 100000));
  add_memory_limit(*generate, common);
  add_verbosity(*generate, args->verbosity, "Also say which seeds were rejected");
  return {generate, [args, robot, objects] {
            if (args->table && !robot->count()) args->robot = source_file("domains/robots/pr2_mobile.yaml");
            if (args->push && !objects->count()) args->objects = 10;
            args->fit_to_robot = robot->count() > 0 && !args->table && !args->occlusion && !args->push;
            return cli::generate(*args);
          }};
}

}  // namespace cluttertamp::cli
