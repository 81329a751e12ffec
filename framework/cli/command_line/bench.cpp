#include "cli/command_line/command.hpp"
#include "cluttertamp/io/text_file.hpp"
#include "cluttertamp/physics/push_planning.hpp"
#include "cluttertamp/search/planner.hpp"

namespace cluttertamp::cli {

namespace {

// Runs the bench `args.what` names; defaults that differ per bench are set here, where
// the command line says whether the user gave them.
int run_bench(BenchArgs& args, const CLI::Option& objects, const CLI::Option& scenes, const CLI::Option& robot) {
  // A sweep's results are never lost to an unwritable path found at its end.
  if (!args.json.empty()) io::check_writable(args.json, "JSON file (--json)");
  if (!args.csv.empty()) io::check_writable(args.csv, "CSV file (--csv)");
  if (!args.svg.empty()) io::check_writable(args.svg, "SVG file (--svg)");
  if (args.what == "pddl") return bench::pddl(args);
  if (args.what == "samplers") return bench::samplers(args);
  if (args.what == "retrieval") {
    args.fit_to_robot = robot.count() > 0;
    return bench::retrieval(args);
  }
  if (args.what == "push") return bench::push(args);
  if (args.what == "mobile") {
    if (!scenes.count()) args.instances = 20;
    if (!robot.count()) args.robot = source_file("domains/robots/pr2_mobile.yaml");
    return bench::mobile(args);
  }
  if (args.what == "occlusion") {
    if (!scenes.count()) args.instances = 20;  // the paper's 20 instances per size
    return bench::occlusion(args);
  }
  if (args.what == "physics") {
    if (!objects.count()) args.objects = 10;  // the physics speed goal is for 10 objects
    return bench::physics(args);
  }
  return bench::collision(args);
}

}  // namespace

Command declare_bench(CLI::App& app, CommonOptions& common) {
  auto args = std::make_shared<BenchArgs>();
  auto* bench = app.add_subcommand(
      "bench",
      "Measure speed: 'collision' times FK, IK, collision and sweep queries; 'pddl' times searches on PDDL instances; "
      "'samplers' times grasp, motion and pick-and-place queries; 'retrieval' runs the retrieval planners on shelves "
      "(Tables I, V and VI of Tian et al.); 'physics' times the pushing physics against real time; 'push' runs RRT, "
      "KPIECE and guided reaching through clutter on the bundled shelves (Fig. 6 of Papallas & Dogar); 'occlusion' runs the "
      "occlusion planner on generated occlusion shelves (Table II of Tian et al.); 'mobile' runs retrieval_graph with "
      "pr2_mobile on generated tables for three initial exploration limits (Table III)");
  add_package_paths(*bench, common);
  bench->add_option("what", args->what, "What to measure")
      ->required()
      ->check(CLI::IsMember({"collision", "pddl", "samplers", "retrieval", "physics", "push", "occlusion", "mobile"}));
  bench->add_option("--seed", args->seed, "Seed of the generated scene and samples")->capture_default_str();
  bench->add_option("--samples", args->samples, "collision: queries per measurement; samplers: 1000 per generated scene")->capture_default_str()->check(CLI::Range(500, 10000000));
  auto* objects = bench->add_option("--objects", args->objects, "Cylinders in the generated shelf (physics: default 10)")->capture_default_str()->check(CLI::Range(1, 60));
  bench->add_option("--json", args->json, "Also write the results as JSON to this file");
  args->pddl_instances = source_file("test/data/pddl");
  bench->add_option("--parse-objects", args->parse_objects,
                    "pddl: also time parsing a generated Blocksworld problem with this many objects (0: not)")
      ->capture_default_str()
      ->check(CLI::Range(0, 10000000));
  bench->add_option("--instances", args->pddl_instances,
                    "pddl: a folder of problem files, or a folder of such folders (the IPC layout); each problem's "
                    "domain is domain_<p>, <p>-domain.pddl, domain-<p> or the folder's domain.pddl")
      ->capture_default_str()
      ->check(CLI::ExistingDirectory);
  bench->add_option("--per-domain", args->per_domain, "pddl: only the first N problems of each folder, in natural order (0: all)")
      ->capture_default_str()
      ->check(finite_non_negative());
  bench->add_option("--reference-costs", args->reference_costs,
                    "pddl: file of 'folder/problem cost' lines, best known costs for the IPC quality score (default: "
                    "the cheapest plan of the searches run)")
      ->check(CLI::ExistingFile);
  bench->add_option("--search", args->searches, "pddl: searches to run (repeatable; default lama-first, astar-lmcut)")
      ->expected(1)
      ->allow_extra_args(false)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll)
      ->check(CLI::IsMember(search::search_names()));
  bench->add_option("--time-limit", args->time_limit, "pddl: seconds per search; retrieval, push: per run")->capture_default_str()->check(finite_positive());
  bench->add_option("--runs", args->runs, "pddl, retrieval, push, occlusion: runs per instance (seeds seed, seed+1, ...)")->capture_default_str()->check(CLI::Range(1, 100));
  auto* scenes = bench->add_option("--scenes", args->instances,
                                          "retrieval: generated scenes per object count (tables I and V); occlusion: per "
                                          "size (default 20)")
      ->capture_default_str()
      ->check(CLI::Range(1, 1000));
  bench->add_option("--sizes", args->sizes, "retrieval, occlusion: object counts (default 12 16 20)")->check(CLI::Range(1, 400));
  bench->add_option("--occlusion-layout", args->occlusion_layouts,
                    "occlusion: 'columns' (each object hidden by the one in front) and/or 'random' (Table I shelves "
                    "seen from the front, the target hidden); repeatable, default both")
      ->expected(1)
      ->allow_extra_args(false)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll)
      ->check(CLI::IsMember({"columns", "random"}));
  bench->add_option("--csv", args->csv, "pddl, retrieval, push, occlusion: also write every run as CSV");
  bench->add_option("--svg", args->svg, "push: also plot success rates and mean times (SVG)");
  args->push_scenes = source_file("problems/push/shelf10");
  bench->add_option("--push-scenes", args->push_scenes,
                    "push: directory of reach problems pNN.yaml, each with its guidance pNN-guidance.yaml (else: generated)")
      ->capture_default_str()
      ->check(CLI::ExistingDirectory);
  args->goal_distance = physics::ReachTolerances{}.distance;
  args->goal_heading = physics::ReachTolerances{}.heading;
  bench->add_option("--goal-distance", args->goal_distance,
                    "push: the target counts as reached with its centre this close to the pocket between the gripper's fingers, m")
      ->capture_default_str()
      ->check(finite_positive());
  bench->add_option("--goal-heading", args->goal_heading,
                    "push: ... and the target within this angle of the gripper's heading, rad")
      ->capture_default_str()
      ->check(finite_positive());
  args->steer = physics::KinodynamicSettings{}.steer;
  bench->add_option("--steer", args->steer,
                    "push: fraction of every planner's sampled controls steered towards the target (guided: its reach)")
      ->capture_default_str()
      ->check(finite_range(0.0, 1.0));
  bench->add_option("--table", args->tables,
                    "retrieval: I (12/16/20 objects, L strategies), V (100 objects, against traversability_graph), "
                    "VI (known minima, against exhaustive); repeatable, default I")
      ->expected(1)
      ->allow_extra_args(false)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll)
      ->check(CLI::IsMember({"I", "V", "VI"}));
  bench->add_option("--planner", args->planners,
                    "retrieval: run only this planner's rows (repeatable; retrieval_graph, traversability_graph, exhaustive)")
      ->expected(1)
      ->allow_extra_args(false)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll)
      ->check(CLI::IsMember({"retrieval_graph", "traversability_graph", "exhaustive"}));
  args->table_vi_scenes = source_file("problems/table6");
  bench->add_option("--table6-scenes", args->table_vi_scenes, "retrieval: directory of shelf16-min{2,3,4}.yaml")
      ->capture_default_str()
      ->check(CLI::ExistingDirectory);
  bench->add_option("--min-gap", args->min_gap,
                    "retrieval: least distance between generated cylinders and to the walls, m (0: the paper's recipe)")
      ->capture_default_str()
      ->check(finite_range(0.0, 0.2));
  bench->add_option("--table5-width", args->table_v_width,
                    "retrieval: interior width of Table V's 100-object cabinets, m (default: 3.0, the generator's; "
                    "wider is sparser)")
      ->check(finite_range(1.0, 10.0));
  bench->add_option("--mobile-tables", args->mobile_tables,
                    "mobile: fig9 keeps the generated tables where, as in the paper's Fig. 9, one object is in the way "
                    "from some side and two or more from the robot's (proved by the exhaustive planner); random keeps "
                    "every table")
      ->capture_default_str()
      ->check(CLI::IsMember({"fig9", "random"}));
  add_memory_limit(*bench, common);
  add_verbosity(*bench, args->verbosity, "Same output as the default");
  args->robot = source_file("domains/robots/ur10_ag95.yaml");
  auto* robot = bench->add_option("--robot", args->robot,
                                        "Robot description (collision: a UR arm, the bench times analytic IK; retrieval: "
                                        "given, the generated shelves go where it reaches them, as generate --robot places "
                                        "them; mobile: default pr2_mobile)")
      ->capture_default_str()
      ->check(CLI::ExistingFile);
  return {bench, [args, objects, scenes, robot] { return run_bench(*args, *objects, *scenes, *robot); }};
}

}  // namespace cluttertamp::cli
