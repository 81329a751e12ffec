// cluttertamp: the command-line front end. Parses arguments with CLI11 and maps every
// outcome to the documented exit codes (docs/commands.md, "Exit codes").
#include <CLI/CLI.hpp>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <iostream>
#include <limits>
#include <new>

#include "cli/commands.hpp"
#include "cluttertamp/core/diagnostics.hpp"
#include "cluttertamp/core/memory_limit.hpp"
#include "cluttertamp/physics/push_planning.hpp"
#include "cluttertamp/run/runner.hpp"
#include "cluttertamp/search/planner.hpp"
#include "cluttertamp/version.hpp"

namespace cli = cluttertamp::cli;
using cluttertamp::run::ExitCode;

namespace {

void add_verbosity(CLI::App& app, cli::Verbosity& verbosity, const std::string& verbose_help) {
  auto* quiet = app.add_flag_callback("-q,--quiet", [&] { verbosity = cli::Verbosity::quiet; },
                                      "Print only errors");
  app.add_flag_callback("-v,--verbose", [&] { verbosity = cli::Verbosity::verbose; }, verbose_help)
      ->excludes(quiet);
}

// --memory-limit on the commands that plan or search (0: the default).
void add_memory_limit(CLI::App& app, std::size_t& mib) {
  app.add_option("--memory-limit", mib,
                 "Address space limit, MiB (default " + std::to_string(cluttertamp::default_memory_limit_mib()) +
                     ": three quarters of this machine's memory); a search that reaches it ends with \"memory limit "
                     "reached\" (exit code 1, result.json written)")
      ->check(CLI::Range(std::size_t{64}, std::size_t{1} << 40));
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"cluttertamp " + std::string(cluttertamp::version()) +
               ": task and motion planning for retrieving objects from clutter.\n"
               "Exit codes: 0 solved (or valid), 1 no plan within the limits, 2 bad input, 3 internal error."};
  app.set_version_flag("--version", std::string(cluttertamp::version()));
  app.require_subcommand(1);

  std::size_t memory_limit = 0;  // MiB; 0: the default
  cli::PlanArgs plan_args;
  auto* plan = app.add_subcommand("plan", "Plan a problem file; write OUTPUT/result.json");
  plan->add_option("problem", plan_args.problem, "Problem file (YAML)")->required()->check(CLI::ExistingFile);
  plan->add_option("--seed", plan_args.seed, "Random seed, 0 to 2^63-1 (overrides the problem file's planner.seed)")
      ->check(CLI::Validator(
          [](const std::string& text) {
            std::int64_t value = 0;
            const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
            return error == std::errc() && end == text.data() + text.size() && value >= 0
                       ? std::string()
                       : "must be a whole number from 0 to 9223372036854775807";
          },
          "SEED", "non-negative integer"));
  plan->add_option("--time-limit", plan_args.time_limit, "Wall-clock limit in seconds, > 0 (overrides planner.time_limit)")
      ->check(CLI::Validator(
          [](const std::string& text) {
            double value = 0;
            return CLI::detail::lexical_cast(text, value) && std::isfinite(value) && value > 0
                       ? std::string()
                       : "must be a finite number of seconds greater than 0";
          },
          "SECONDS", "finite positive"));
  plan->add_option("--planner", plan_args.planner,
                   "Task planner plugin to run instead of the problem file's planner.plugin (its parameters are "
                   "dropped), e.g. exhaustive or traversability_graph to compare with retrieval_graph");
  plan->add_option("-o,--output", plan_args.output, "Directory for result.json")->capture_default_str();
  plan->add_option("--plugin-path", plan_args.plugin_paths, "Search this plugin directory first (repeatable)")
      ->expected(1)
      ->allow_extra_args(false)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  plan->add_flag("--html", plan_args.html, "Also write OUTPUT/plan.html, a page that replays the plan (see view)");
  plan->add_option("--repeat", plan_args.repeat,
                   "Plan N times and check that every result equals the first apart from time fields (exit code 3 "
                   "when one differs, naming the first difference); OUTPUT/result.json is the first run's")
      ->check(CLI::Range(1, 1000));
  plan->add_option("--load", plan_args.load,
                   "Run N busy threads on the planner's CPU while it plans (the planner then gets a fraction of one "
                   "core, as on a loaded machine): with --repeat or --expect, shows that load changes nothing")
      ->check(CLI::Range(0, 16));
  plan->add_option("--expect", plan_args.expect,
                   "Compare the result with this earlier result.json apart from time fields and the problem and scene "
                   "paths (exit code 3 when they differ, naming the first difference)")
      ->check(CLI::ExistingFile);
  add_memory_limit(*plan, memory_limit);
  add_verbosity(*plan, plan_args.verbosity, "Also print the plugin search (directories, plugins, failures)");

  cli::ObserveArgs observe_args;
  auto* observe = app.add_subcommand(
      "observe", "What the scene's camera sees: each object observed or hidden, how much of it is in view and "
                 "what hides it (ray casting; Tian et al., Section V-A)");
  observe->add_option("file", observe_args.file, "Scene or problem file")->required()->check(CLI::ExistingFile);
  observe->add_option("--remove", observe_args.remove, "Take these objects away first (ids, repeatable or comma-separated)")
      ->delimiter(',');
  observe->add_option("--min-visible", observe_args.min_visible_fraction,
                      "Observed when at least this fraction of the surface facing the camera is in view")
      ->capture_default_str()->check(CLI::Range(0.001, 1.0));
  observe->add_flag("--json", observe_args.json, "Print JSON: [{object, observed, visible_fraction, occluders}]");

  cli::ViewArgs view_args;
  auto* view = app.add_subcommand(
      "view", "Write one self-contained HTML page replaying a result.json in 3-D (opens from disk, no server, no network)");
  view->add_option("result", view_args.result, "A result.json written by plan")->required()->check(CLI::ExistingFile);
  view->add_option("--problem", view_args.problem, "The problem file (default: the one result.json names)")->check(CLI::ExistingFile);
  view->add_option("-o,--output", view_args.output, "Page to write (default: plan.html beside the result)");
  add_verbosity(*view, view_args.verbosity, "Same output as the default");

  cli::ValidateArgs validate_args;
  auto* validate = app.add_subcommand("validate", "Check problem and scene files; print every error with its location");
  validate->add_option("files", validate_args.files, "Problem or scene files (YAML)")->required();
  validate->add_flag("--no-plugins", validate_args.skip_plugins,
                     "Do not check that the plugins a problem names exist and accept their parameters");
  validate->add_option("--plugin-path", validate_args.plugin_paths, "Search this plugin directory first (repeatable)")
      ->expected(1)
      ->allow_extra_args(false)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  add_verbosity(*validate, validate_args.verbosity, "Also list every object of each valid scene");

  cli::PluginsArgs plugins_args;
  auto* plugins = app.add_subcommand("plugins", "List the plugins found, with kinds and versions, and any that failed to load");
  plugins->add_option("--plugin-path", plugins_args.plugin_paths, "Search this plugin directory first (repeatable)")
      ->expected(1)
      ->allow_extra_args(false)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  add_verbosity(*plugins, plugins_args.verbosity, "Also print each plugin's library path and the parameters it reads (key, type, default, help)");

  cli::PddlArgs pddl_args;
  auto* pddl = app.add_subcommand("pddl", "Plan a PDDL domain and problem; print the plan in IPC format");
  pddl->add_option("domain", pddl_args.domain, "PDDL domain file")->required();
  pddl->add_option("problem", pddl_args.problem, "PDDL problem file")->required();
  pddl->add_option("--search", pddl_args.search, "Search algorithm")
      ->capture_default_str()
      ->check(CLI::IsMember(cluttertamp::search::search_names()));
  pddl->add_option("--time-limit", pddl_args.time_limit, "Seconds")->capture_default_str()->check(CLI::PositiveNumber);
  pddl->add_option("--max-expansions", pddl_args.max_expansions, "Stop after this many expansions");
  pddl->add_option("--weight", pddl_args.weight, "Weight of h in wastar-ff")->capture_default_str()->check(CLI::Range(1.0, 1000.0));
  pddl->add_option("--plan", pddl_args.plan_file, "Also write the plan to this file");
  add_memory_limit(*pddl, memory_limit);
  add_verbosity(*pddl, pddl_args.verbosity, "Same output as the default");

  cli::ValidatePlanArgs validate_plan_args;
  auto* validate_plan = app.add_subcommand("validate-plan", "Check a plan against a PDDL domain and problem");
  validate_plan->add_option("domain", validate_plan_args.domain, "PDDL domain file")->required();
  validate_plan->add_option("problem", validate_plan_args.problem, "PDDL problem file")->required();
  validate_plan->add_option("plan", validate_plan_args.plan, "Plan file: (action arg ...) per line")->required();
  add_verbosity(*validate_plan, validate_plan_args.verbosity, "Same output as the default");

  cli::GenerateArgs generate_args;
  auto* generate = app.add_subcommand("generate", "Generate a shelf scene (Tian et al., Section VI-B) and optionally a problem file");
  generate->add_option("--objects", generate_args.objects, "Cylinders in the shelf (12 to 20, and 100, in the paper)")
      ->capture_default_str()
      ->check(CLI::Range(1, 500));
  generate->add_option("--width", generate_args.width,
                       "Cabinet interior width, m (default: 0.9 for 12 objects to 1.2 for 20, +0.0225 per object beyond)")
      ->check(CLI::Range(0.1, 10.0));
  generate->add_option("--depth", generate_args.depth, "Cabinet interior depth, m (default: 0.6 for 12 objects to 0.7 for 20 and beyond)")
      ->check(CLI::Range(0.1, 2.0));
  generate->add_option("--min-gap", generate_args.min_gap,
                       "Least distance between cylinders and to the walls, m (default 0, the paper's recipe: any "
                       "collision-free placement, so neighbours may touch; with --table 0.01)")
      ->check(CLI::Range(0.0, 0.2));
  generate->add_option("--min-removals", generate_args.min_removals,
                       "Keep only scenes whose fewest objects to move, target included, is this (Table VI: 2, 3, 4); "
                       "proved with the exhaustive planner")
      ->check(CLI::Range(2, 10));
  generate->add_option("--check-time", generate_args.check_time, "Seconds for the exhaustive check of one scene")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  generate->add_option("--seed", generate_args.seed, "Seed of the first scene tried")->capture_default_str();
  generate->add_option("--output", generate_args.output, "Scene file to write")->required();
  generate->add_option("--problem", generate_args.problem, "Also write a problem file for the scene here");
  generate_args.robot = std::filesystem::path(CLUTTERTAMP_SOURCE_DIR) / "domains/robots/ur10_ag95.yaml";
  auto* generate_robot = generate->add_option("--robot", generate_args.robot, "Robot description (with --table: pr2_mobile)")
                             ->capture_default_str()
                             ->check(CLI::ExistingFile);
  generate->add_flag("--table", generate_args.table,
                     "A table reachable from every side (Tian et al., Fig. 9): --objects cylinders, the target in the middle, "
                     "--width the table's side (default 0.7 m); its problem uses pr2_mobile (unless --robot names another) "
                     "and retrieval_graph with area_margin 0.3");
  auto* occlusion_flag = generate->add_flag("--occlusion", generate_args.occlusion,
                     "An occlusion shelf (Tian et al., Fig. 7): --objects / 4 columns of 4 cylinders, each hidden from the "
                     "camera by the one in front, the target at the back of one; its problem uses the occlusion planner");
  generate->add_option("--occlusion-layout", generate_args.occlusion_layout,
                       "With --occlusion: 'columns' (above) or 'random': --objects cylinders drawn as for Table I, the "
                       "camera in front at their height, the target the hidden one nearest the back wall's middle")
      ->capture_default_str()
      ->check(CLI::IsMember({"columns", "random"}))
      ->needs(occlusion_flag);
  generate->add_flag("!--any", generate_args.require_removal,
                     "Keep the first scene even if the target comes out without removing anything");
  generate->add_option("--attempts", generate_args.max_attempts, "Scenes tried (seeds seed, seed+1, ...)")
      ->capture_default_str()
      ->check(CLI::Range(1, 100000));
  add_memory_limit(*generate, memory_limit);
  add_verbosity(*generate, generate_args.verbosity, "Also say which seeds were rejected");

  cli::GuideArgs guide_args;
  auto* guide = app.add_subcommand(
      "guide", "Guide a reach problem from a browser (Papallas & Dogar's GRTC-HITL): serves a page on localhost where "
               "you click an object, then where it should go; the push is planned, and \"let the robot finish\" "
               "reaches the target in the time left. With --auto, write the automatic guidance to a file instead");
  guide->add_option("problem", guide_args.problem, "Problem file with task: {reach: <target>}")->required()->check(CLI::ExistingFile);
  guide->add_flag("--auto", guide_args.automatic,
                  "Write the automatic guidance (the objects on the straight way from the exit to the target, each "
                  "pushed sideways off it) to --output and exit");
  guide->add_option("-o,--output", guide_args.output,
                    "With --auto: the guidance file to write (required). Serving: the directory the session is saved in "
                    "after every input: guidance.yaml, result.json, and plan.html once finished (default: out/guide)");
  guide->add_option("--port", guide_args.port, "Port to serve on (0: any free port; the address is printed)")
      ->capture_default_str()->check(CLI::Range(0, 65535));
  guide->add_option("--host", guide_args.host, "Address to serve on (127.0.0.1: this machine only)")->capture_default_str();
  guide->add_option("--push-time", guide_args.push_time, "Planning seconds per guide at most (never beyond the time left)")
      ->capture_default_str()->check(CLI::PositiveNumber);
  guide->add_option("--time-limit", guide_args.time_limit,
                    "Planning seconds for the whole session, pushes and reach (overrides planner.time_limit)")
      ->check(CLI::PositiveNumber);
  guide->add_option("--seed", guide_args.seed, "Random seed (overrides planner.seed)");
  guide->add_option("--max-guides", guide_args.max_guides, "With --auto: at most this many guides")->capture_default_str()->check(CLI::Range(0, 100));
  guide->add_option("--diameter", guide_args.diameter, "Diameter of every guide's region, m")->capture_default_str()->check(CLI::Range(0.01, 1.0));
  add_memory_limit(*guide, memory_limit);
  add_verbosity(*guide, guide_args.verbosity, "Same output as the default");

  cli::SelfCollisionArgs self_args;
  auto* self = app.add_subcommand(
      "self-collisions",
      "Count which pairs of a robot's links touch over random configurations; list those that never do, for disabled_collisions");
  self->add_option("robot", self_args.robot, "Robot description file")->required()->check(CLI::ExistingFile);
  self->add_option("--samples", self_args.samples, "Random configurations")->capture_default_str()->check(CLI::Range(100, 10000000));
  self->add_option("--seed", self_args.seed, "Seed of the configurations")->capture_default_str();
  add_verbosity(*self, self_args.verbosity, "Also list the pairs that never touched with their counts");

  cli::BenchArgs bench_args;
  auto* bench = app.add_subcommand(
      "bench",
      "Measure speed: 'collision' times FK, IK, collision and sweep queries; 'pddl' times searches on PDDL instances; "
      "'samplers' times grasp, motion and pick-and-place queries; 'retrieval' runs the retrieval planners on shelves "
      "(Tables I, V and VI of Tian et al.); 'physics' times the pushing physics against real time; 'push' runs RRT, "
      "KPIECE and guided reaching through clutter on the bundled shelves (Fig. 6 of Papallas & Dogar); 'occlusion' runs the "
      "occlusion planner on generated occlusion shelves (Table II of Tian et al.); 'mobile' runs retrieval_graph with "
      "pr2_mobile on generated tables for three initial exploration limits (Table III)");
  bench->add_option("what", bench_args.what, "What to measure")
      ->required()
      ->check(CLI::IsMember({"collision", "pddl", "samplers", "retrieval", "physics", "push", "occlusion", "mobile"}));
  bench->add_option("--seed", bench_args.seed, "Seed of the generated scene and samples")->capture_default_str();
  bench->add_option("--samples", bench_args.samples, "collision: queries per measurement; samplers: 1000 per generated scene")->capture_default_str()->check(CLI::Range(500, 10000000));
  auto* objects_option = bench->add_option("--objects", bench_args.objects, "Cylinders in the generated shelf (physics: default 10)")->capture_default_str()->check(CLI::Range(1, 60));
  bench->add_option("--json", bench_args.json, "Also write the results as JSON to this file");
  bench_args.pddl_instances = std::filesystem::path(CLUTTERTAMP_SOURCE_DIR) / "test/data/pddl";
  bench->add_option("--parse-objects", bench_args.parse_objects,
                    "pddl: also time parsing a generated Blocksworld problem with this many objects (0: not)")
      ->capture_default_str()
      ->check(CLI::Range(0, 10000000));
  bench->add_option("--instances", bench_args.pddl_instances, "pddl: directory of <family>/{domain,p*}.pddl")
      ->capture_default_str()
      ->check(CLI::ExistingDirectory);
  bench->add_option("--search", bench_args.searches, "pddl: searches to run (repeatable; default lazy-gbfs-ff, astar-lmcut)")
      ->expected(1)
      ->allow_extra_args(false)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll)
      ->check(CLI::IsMember(cluttertamp::search::search_names()));
  bench->add_option("--time-limit", bench_args.time_limit, "pddl: seconds per search; retrieval, push: per run")->capture_default_str()->check(CLI::PositiveNumber);
  bench->add_option("--runs", bench_args.runs, "pddl, retrieval, push, occlusion: runs per instance (seeds seed, seed+1, ...)")->capture_default_str()->check(CLI::Range(1, 100));
  auto* scenes_option = bench->add_option("--scenes", bench_args.instances,
                                          "retrieval: generated scenes per object count (tables I and V); occlusion: per "
                                          "size (default 20)")
      ->capture_default_str()
      ->check(CLI::Range(1, 1000));
  bench->add_option("--sizes", bench_args.sizes, "retrieval, occlusion: object counts (default 12 16 20)")->check(CLI::Range(1, 400));
  bench->add_option("--occlusion-layout", bench_args.occlusion_layouts,
                    "occlusion: 'columns' (each object hidden by the one in front) and/or 'random' (Table I shelves "
                    "seen from the front, the target hidden); repeatable, default both")
      ->expected(1)
      ->allow_extra_args(false)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll)
      ->check(CLI::IsMember({"columns", "random"}));
  bench->add_option("--csv", bench_args.csv, "retrieval, push, occlusion: also write every run as CSV");
  bench->add_option("--svg", bench_args.svg, "push: also plot success rates and mean times (SVG)");
  bench_args.push_scenes = std::filesystem::path(CLUTTERTAMP_SOURCE_DIR) / "problems/push/shelf10";
  bench->add_option("--push-scenes", bench_args.push_scenes,
                    "push: directory of reach problems pNN.yaml, each with its guidance pNN-guidance.yaml (else: generated)")
      ->capture_default_str()
      ->check(CLI::ExistingDirectory);
  bench_args.goal_distance = cluttertamp::physics::ReachTolerances{}.distance;
  bench_args.goal_heading = cluttertamp::physics::ReachTolerances{}.heading;
  bench->add_option("--goal-distance", bench_args.goal_distance,
                    "push: the target counts as reached with its centre this close to the pocket between the gripper's fingers, m")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  bench->add_option("--goal-heading", bench_args.goal_heading,
                    "push: ... and the target within this angle of the gripper's heading, rad")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  bench_args.steer = cluttertamp::physics::KinodynamicSettings{}.steer;
  bench->add_option("--steer", bench_args.steer,
                    "push: fraction of every planner's sampled controls steered towards the target (guided: its reach)")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 1.0));
  bench->add_option("--table", bench_args.tables,
                    "retrieval: I (12/16/20 objects, L strategies), V (100 objects, against traversability_graph), "
                    "VI (known minima, against exhaustive); repeatable, default I")
      ->expected(1)
      ->allow_extra_args(false)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll)
      ->check(CLI::IsMember({"I", "V", "VI"}));
  bench->add_option("--planner", bench_args.planners,
                    "retrieval: run only this planner's rows (repeatable; retrieval_graph, traversability_graph, exhaustive)")
      ->expected(1)
      ->allow_extra_args(false)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll)
      ->check(CLI::IsMember({"retrieval_graph", "traversability_graph", "exhaustive"}));
  bench_args.table_vi_scenes = std::filesystem::path(CLUTTERTAMP_SOURCE_DIR) / "problems/table6";
  bench->add_option("--table6-scenes", bench_args.table_vi_scenes, "retrieval: directory of shelf16-min{2,3,4}.yaml")
      ->capture_default_str()
      ->check(CLI::ExistingDirectory);
  bench->add_option("--min-gap", bench_args.min_gap,
                    "retrieval: least distance between generated cylinders and to the walls, m (0: the paper's recipe)")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 0.2));
  bench->add_option("--table5-width", bench_args.table_v_width,
                    "retrieval: interior width of Table V's 100-object cabinets, m (default: 3.0, the generator's; "
                    "wider is sparser)")
      ->check(CLI::Range(1.0, 10.0));
  bench->add_option("--mobile-tables", bench_args.mobile_tables,
                    "mobile: fig9 keeps the generated tables where, as in the paper's Fig. 9, one object is in the way "
                    "from some side and two or more from the robot's (proved by the exhaustive planner); random keeps "
                    "every table")
      ->capture_default_str()
      ->check(CLI::IsMember({"fig9", "random"}));
  add_memory_limit(*bench, memory_limit);
  add_verbosity(*bench, bench_args.verbosity, "Same output as the default");
  bench_args.robot = std::filesystem::path(CLUTTERTAMP_SOURCE_DIR) / "domains/robots/ur10_ag95.yaml";
  auto* bench_robot = bench->add_option("--robot", bench_args.robot,
                                        "Robot description (collision: a UR arm, the bench times analytic IK; mobile: "
                                        "default pr2_mobile)")
      ->capture_default_str()
      ->check(CLI::ExistingFile);

  cli::CompareArgs compare_args;
  auto* compare = app.add_subcommand(
      "compare", "Stream planning focused and not: {adaptive, incremental} x {pruned, all movable} (Tian et al., Table IV)");
  compare->add_option("problems", compare_args.problems, "Stream problem files (task: pddl); with several, --svg plots time against object count")
      ->required()
      ->check(CLI::ExistingFile);
  compare->add_option("--runs", compare_args.runs, "Seeds per setting (seed, seed+1, ...)")
      ->capture_default_str()
      ->check(CLI::Range(1, 1000));
  compare->add_option("--seed", compare_args.seed, "First seed")->capture_default_str();
  compare->add_option("--time-limit", compare_args.time_limit, "Seconds per run (default: each problem's planner.time_limit)")
      ->check(CLI::PositiveNumber);
  compare->add_option("--json", compare_args.json, "Also write the table as JSON to this file");
  compare->add_option("--csv", compare_args.csv, "Also write every run as CSV to this file");
  compare->add_option("--svg", compare_args.svg, "Also plot median time against object count (SVG) to this file");
  compare->add_option("--plugin-path", compare_args.plugin_paths, "Search this plugin directory first (repeatable)")
      ->allow_extra_args(false);
  add_memory_limit(*compare, memory_limit);
  add_verbosity(*compare, compare_args.verbosity, "Same output as the default");

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    app.exit(e);
    return ExitCode::bad_input;
  }

  cluttertamp::set_memory_limit(memory_limit);
  try {
    if (*plan) return cli::plan(plan_args);
    if (*validate) return cli::validate(validate_args);
    if (*plugins) return cli::plugins(plugins_args);
    if (*compare) return cli::compare(compare_args);
    if (*bench) {
      if (bench_args.what == "pddl") return cli::bench_pddl(bench_args);
      if (bench_args.what == "samplers") return cli::bench_samplers(bench_args);
      if (bench_args.what == "retrieval") return cli::bench_retrieval(bench_args);
      if (bench_args.what == "push") return cli::bench_push(bench_args);
      if (bench_args.what == "mobile") {
        if (!scenes_option->count()) bench_args.instances = 20;
        if (!bench_robot->count()) bench_args.robot = std::filesystem::path(CLUTTERTAMP_SOURCE_DIR) / "domains/robots/pr2_mobile.yaml";
        return cli::bench_mobile(bench_args);
      }
      if (bench_args.what == "occlusion") {
        if (!scenes_option->count()) bench_args.instances = 20;  // the paper's 20 instances per size
        return cli::bench_occlusion(bench_args);
      }
      if (bench_args.what == "physics") {
        if (!objects_option->count()) bench_args.objects = 10;  // the speed goal is for 10
        return cli::bench_physics(bench_args);
      }
      return cli::bench_collision(bench_args);
    }
    if (*pddl) return cli::pddl(pddl_args);
    if (*generate) {
      if (generate_args.table && !generate_robot->count()) {
        generate_args.robot = std::filesystem::path(CLUTTERTAMP_SOURCE_DIR) / "domains/robots/pr2_mobile.yaml";
      }
      return cli::generate(generate_args);
    }
    if (*guide) return cli::guide(guide_args);
    if (*view) return cli::view(view_args);
    if (*observe) return cli::observe(observe_args);
    if (*validate_plan) return cli::validate_plan(validate_plan_args);
    if (*self) return cli::self_collisions(self_args);
  } catch (const cluttertamp::InputError& e) {
    std::cerr << e.diagnostics().str();
    return ExitCode::bad_input;
  } catch (const std::bad_alloc&) {
    std::cerr << "cluttertamp: " << cluttertamp::run::memory_limit_reason() << "\n";
    return ExitCode::no_plan;
  } catch (const std::exception& e) {
    std::cerr << "cluttertamp: internal error: " << e.what() << "\n";
    return ExitCode::internal_error;
  } catch (...) {
    std::cerr << "cluttertamp: internal error: an exception of unknown type\n";
    return ExitCode::internal_error;
  }
  return ExitCode::internal_error;
}
