#include <map>
#include <iostream>
#include <memory>
#include <set>
#include <string>

#include "cli/command_line/command.hpp"
#include "cluttertamp/io/text_file.hpp"
#include "cluttertamp/physics/push_planning.hpp"
#include "cluttertamp/search/planner.hpp"

namespace cluttertamp::cli {

namespace {

// One bench on the command line: its own arguments, with its own defaults, and the
// function that runs it.
struct BenchCommand {
  CLI::App* app = nullptr;
  std::shared_ptr<BenchArgs> args;
  std::function<int(BenchArgs&)> run;
};


// The options several benches take, worded the same in each; each bench declares only
// those that apply to it, so that any other is an error.
class BenchOptions {
 public:
  BenchOptions(CLI::App& app, BenchArgs& args) : app_(app), args_(args) {}

  BenchOptions& seed(const std::string& help) {
    app_.add_option("--seed", args_.seed, help)->capture_default_str()->check(seed_validator());
    return *this;
  }
  BenchOptions& runs(const std::string& help, int default_runs) {
    args_.runs = default_runs;
    app_.add_option("--runs", args_.runs, help)->capture_default_str()->check(CLI::Range(1, 1000));
    return *this;
  }
  BenchOptions& time_limit(const std::string& help, double seconds) {
    args_.time_limit = seconds;
    app_.add_option("--time-limit", args_.time_limit, help)->capture_default_str()->check(finite_positive());
    return *this;
  }
  BenchOptions& scenes(const std::string& help, int default_scenes) {
    args_.instances = default_scenes;
    app_.add_option("--scenes", args_.instances, help)->capture_default_str()->check(CLI::Range(1, 1000));
    return *this;
  }
  BenchOptions& sizes(const std::string& help, std::vector<int> defaults, bool one = false) {
    args_.sizes = std::move(defaults);
    auto* option = app_.add_option("--sizes", args_.sizes, help)->capture_default_str()->check(CLI::Range(1, 400));
    if (one) option->expected(1);
    return *this;
  }
  BenchOptions& objects(const std::string& help, int default_objects) {
    args_.objects = default_objects;
    app_.add_option("--objects", args_.objects, help)->capture_default_str()->check(CLI::Range(1, 60));
    return *this;
  }
  BenchOptions& samples(const std::string& help) {
    app_.add_option("--samples", args_.samples, help)->capture_default_str()->check(CLI::Range(500, 10000000));
    return *this;
  }
  CLI::Option* robot(const std::string& help, const std::string& bundled) {
    args_.robot = source_file(bundled);
    return app_.add_option("--robot", args_.robot, help)->capture_default_str()->check(CLI::ExistingFile);
  }
  BenchOptions& json(const std::string& what) {
    app_.add_option("--json", args_.json, "Also write " + what + " as JSON to this file");
    return *this;
  }
  BenchOptions& csv(const std::string& columns) {
    app_.add_option("--csv", args_.csv, "Also write every run as CSV to this file (" + columns + ")");
    return *this;
  }
  BenchOptions& svg(const std::string& what) {
    app_.add_option("--svg", args_.svg, "Also plot " + what + " (SVG) to this file");
    return *this;
  }
  /// --shard, -j, --records and --ompl-log: the bench runs as a sweep (see `bench merge`).
  BenchOptions& sweep() {
    add_sweep_options(app_, args_.sweep, &args_.ompl_log);
    return *this;
  }
  /// --shard, -j and --records for a speed bench: its runs are timed batches.
  BenchOptions& timed_sweep() {
    add_sweep_options(app_, args_.sweep, nullptr,
                      "Batches timed at once, each in a child process of its own: they share this machine's cores, so "
                      "above its idle cores they slow each other (the counts are as with -j 1)");
    return *this;
  }
  /// --check-goals for a bench whose report says whether the paper's (or our) goals were met.
  BenchOptions& goals(const std::string& goal) {
    app_.add_flag("--check-goals", args_.check_goals, "Exit code 1 when a goal is missed: " + goal + " (else 0 whenever the bench ran)");
    return *this;
  }

 private:
  CLI::App& app_;
  BenchArgs& args_;
};

// A bench's outputs are checked before it runs: a sweep's results are never lost to an
// unwritable path found at its end.
void check_outputs(const BenchArgs& args) {
  if (!args.json.empty()) io::check_writable(args.json, "JSON file (--json)");
  if (!args.csv.empty()) io::check_writable(args.csv, "CSV file (--csv)");
  if (!args.svg.empty()) io::check_writable(args.svg, "SVG file (--svg)");
  if (!args.sweep.records.empty()) io::check_writable(args.sweep.records, "records file (--records)");
  if (!args.ompl_log.empty()) io::check_writable(args.ompl_log, "OMPL benchmark log (--ompl-log)");
}

BenchCommand add_bench(CLI::App& bench, CommonOptions& common, const std::string& name, const std::string& help,
                       std::function<int(BenchArgs&)> run) {
  auto args = std::make_shared<BenchArgs>();
  args->what = name;
  CLI::App* app = bench.add_subcommand(name, help);
  add_package_paths(*app, common);
  add_memory_limit(*app, common);
  add_verbosity(*app, args->verbosity, "Also say why each step went as it did");
  return {app, args, std::move(run)};
}

BenchCommand declare_collision(CLI::App& bench, CommonOptions& common) {
  BenchCommand c = add_bench(bench, common, "collision", "Time FK, IK, collision and sweep queries on a generated shelf", bench::collision);
  BenchOptions(*c.app, *c.args)
      .seed("Seed of the generated shelf and the sampled configurations")
      .samples("Queries per measurement, timed in batches of 50")
      .objects("Cylinders in the generated shelf", 20)
      .json("the medians")
      .svg("the times of each query's batches beside its goal")
      .timed_sweep()
      .goals("the speed goals the report lists");
  BenchOptions(*c.app, *c.args).robot("Robot description (a UR arm: the bench times its analytic IK)", "domains/robots/ur10_ag95.yaml");
  return c;
}

BenchCommand declare_samplers(CLI::App& bench, CommonOptions& common) {
  BenchCommand c = add_bench(bench, common, "samplers", "Time the shipped grasp, motion and pick-and-place samplers", bench::samplers);
  BenchOptions(*c.app, *c.args)
      .seed("Seed of the generated shelves and the samplers")
      .samples("Queries in all: one generated shelf per 1000")
      .objects("Cylinders in each generated shelf", 20)
      .json("the medians")
      .svg("the times of each query's calls beside its goal")
      .timed_sweep()
      .goals("the sampler speed goals the report lists");
  BenchOptions(*c.app, *c.args).robot("Robot description", "domains/robots/ur10_ag95.yaml");
  return c;
}

BenchCommand declare_physics(CLI::App& bench, CommonOptions& common) {
  BenchCommand c = add_bench(bench, common, "physics", "Time the pushing physics against real time on a generated shelf", bench::physics);
  BenchOptions(*c.app, *c.args)
      .seed("Seed of the generated shelf and the pushes")
      .samples("Simulated pushes: one per 100 (at least five batches)")
      .objects("Cylinders in the generated shelf (the speed goal is for 10)", 10)
      .json("the measurements")
      .svg("the speed of each batch of pushes beside the goal")
      .timed_sweep()
      .goals("at least 20 times real time with 10 objects (the arm: 10 times)");
  c.app->add_option("--pusher", c.args->pusher,
                    "gripper: a floating gripper in a Table I shelf; arm: the robot's arm on a planar base in a pushing shelf "
                    "like Papallas & Dogar's (generate --push)")
      ->capture_default_str()
      ->check(CLI::IsMember({"gripper", "arm"}));
  BenchOptions(*c.app, *c.args).robot("Robot description (--pusher arm)", "domains/robots/ur10_ag95.yaml");
  return c;
}

BenchCommand declare_pddl(CLI::App& bench, CommonOptions& common) {
  BenchCommand c = add_bench(bench, common, "pddl",
                             "Time searches on PDDL instances (a folder, or a tree in the IPC layout); every plan is "
                             "checked by the validator (an invalid one: exit code 3; a refused file: 2, after the rest ran)",
                             bench::pddl);
  BenchArgs& args = *c.args;
  BenchOptions(*c.app, args)
      .runs("Runs per instance and search (the times are their medians)", 3)
      .time_limit("Seconds per search, parsing and grounding included", 60)
      .json("every run and the per-folder summary")
      .csv("one row per instance and search")
      .svg("per domain folder the coverage and times of each search")
      .sweep();
  args.pddl_instances = source_file("test/data/pddl");
  c.app->add_option("--instances", args.pddl_instances,
                    "A folder of problem files, or a folder of such folders (the IPC layout); each problem's domain is "
                    "domain_<p>, <p>-domain.pddl, domain-<p> or the folder's domain.pddl")
      ->capture_default_str()
      ->check(CLI::ExistingDirectory);
  c.app->add_option("--per-domain", args.per_domain, "Only the first N problems of each folder, in natural order (0: all)")
      ->capture_default_str()
      ->check(finite_non_negative());
  c.app->add_option("--reference-costs", args.reference_costs,
                    "File of 'folder/problem cost' lines, best known costs for the IPC quality score (default: the "
                    "cheapest plan of the searches run)")
      ->check(CLI::ExistingFile);
  c.app->add_option("--landmarks", args.landmarks, "Landmarks of lama-first: rhw or zhu-givan (as pddl --landmarks)")
      ->capture_default_str()
      ->check(CLI::IsMember({"rhw", "zhu-givan"}));
  c.app->add_option("--search", args.searches, "Searches to run (repeatable; default lama-first, astar-lmcut)")
      ->expected(1)
      ->allow_extra_args(false)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll)
      ->check(CLI::IsMember(search::search_names()));
  c.app->add_option("--parse-objects", args.parse_objects, "Also time parsing a generated Blocksworld problem with this many objects (0: not)")
      ->capture_default_str()
      ->check(CLI::Range(0, 10000000));
  return c;
}

BenchCommand declare_retrieval(CLI::App& bench, CommonOptions& common) {
  BenchCommand c = add_bench(bench, common, "retrieval", "Tables I, V and VI of Tian et al.: the retrieval planners on shelves", bench::retrieval);
  BenchArgs& args = *c.args;
  BenchOptions(*c.app, args)
      .seed("First seed of the generated shelves and of the runs")
      .scenes("Generated shelves per object count (Tables I and V)", 5)
      .sizes("Table I: object counts", {12, 16, 20})
      .runs("Runs per shelf and planner (seeds seed, seed+1, ...)", 3)
      .time_limit("Seconds per run", 60)
      .json("every row with the paper's figures")
      .csv("one row per run")
      .svg("per table the success rates, |O_r| and times of each row beside the paper's")
      .sweep();
  c.app->add_option("--table", args.tables,
                    "I (12/16/20 objects, L strategies), V (100 objects, against traversability_graph), VI (known "
                    "minima, against exhaustive); repeatable, default I")
      ->expected(1)
      ->allow_extra_args(false)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll)
      ->check(CLI::IsMember({"I", "V", "VI"}));
  c.app->add_option("--planner", args.planners, "Run only this planner's rows (repeatable; retrieval_graph, traversability_graph, exhaustive)")
      ->expected(1)
      ->allow_extra_args(false)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll)
      ->check(CLI::IsMember({"retrieval_graph", "traversability_graph", "exhaustive"}));
  args.table_vi_scenes = source_file("problems/table6");
  c.app->add_option("--table6-scenes", args.table_vi_scenes, "Directory of shelf16-min{2,3,4}.yaml (Table VI)")
      ->capture_default_str()
      ->check(CLI::ExistingDirectory);
  c.app->add_option("--min-gap", args.min_gap, "Least distance between generated cylinders and to the walls, m (0: the paper's recipe)")
      ->capture_default_str()
      ->check(finite_range(0.0, 0.2));
  c.app->add_option("--table5-width", args.table_v_width,
                    "Interior width of Table V's 100-object cabinets, m (default: 3.0, the generator's; wider is sparser)")
      ->check(finite_range(1.0, 10.0));
  CLI::Option* robot = BenchOptions(*c.app, args).robot(
      "Robot description; given, the generated shelves go where it reaches them, as generate --robot places them",
      "domains/robots/ur10_ag95.yaml");
  c.run = [robot](BenchArgs& a) {
    a.fit_to_robot = robot->count() > 0;
    return bench::retrieval(a);
  };
  return c;
}

BenchCommand declare_push(CLI::App& bench, CommonOptions& common) {
  BenchCommand c = add_bench(bench, common, "push",
                             "RRT, KPIECE and guided reaching through clutter on shelf scenes (Fig. 6 of Papallas & Dogar)",
                             bench::push);
  BenchArgs& args = *c.args;
  BenchOptions(*c.app, args)
      .seed("First seed of the runs")
      .runs("Runs per scene and planner (seeds seed, seed+1, ...)", 3)
      .json("the summary with per-scene figures")
      .csv("one row per run")
      .svg("success rates beside the paper's and the times per scene")
      .goals("guided planning beats RRT and KPIECE on success rate")
      .sweep();
  args.time_limit = 0;
  c.app->add_option("--time-limit", args.time_limit,
                    "Seconds per run (default: each problem's own time_limit, 300 in the bundled sets as in the paper)")
      ->check(finite_positive());
  args.push_scenes = source_file("problems/push/paper10");
  c.app->add_option("--push-scenes", args.push_scenes,
                    "Directory of reach problems pNN.yaml, each with its guidance pNN-guidance.yaml (else: generated)")
      ->capture_default_str()
      ->check(CLI::ExistingDirectory);
  // Given, each overrides the parameter of every problem's planner.
  auto goal_distance = std::make_shared<double>(), goal_heading = std::make_shared<double>(), steer = std::make_shared<double>();
  auto params = std::make_shared<std::vector<std::string>>();
  CLI::Option* distance_option =
      c.app->add_option("--goal-distance", *goal_distance,
                        "The target counts as reached this close, m (goal_distance: the pocket's, or the reach point's with goal: point); "
                        "default: each problem's own")
          ->check(finite_positive());
  CLI::Option* heading_option =
      c.app->add_option("--goal-heading", *goal_heading, "... and within this angle of the hand's heading, rad (goal_heading); default: each problem's own")
          ->check(finite_positive());
  CLI::Option* steer_option =
      c.app->add_option("--steer", *steer, "Fraction of every planner's sampled controls steered towards the target (steer); default: each problem's own")
          ->check(finite_range(0.0, 1.0));
  c.app->add_option("--param", *params,
                    "KEY=VALUE: a planner parameter every run takes over its problem's own (repeatable; VALUE a number, true/false, "
                    "[a, b, ...] or text), e.g. --param max_propagations=0");
  c.app->add_option("--planner", args.planners, "Run only this planner (repeatable; rrt, kpiece, guided; default all three)")
      ->expected(1)
      ->allow_extra_args(false)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll)
      ->check(CLI::IsMember({"rrt", "kpiece", "guided"}));
  c.run = [=](BenchArgs& a) {
    if (a.check_goals && !a.planners.empty() && std::set<std::string>(a.planners.begin(), a.planners.end()).size() < 3) {
      throw InputError({"--check-goals", 0, 0}, "the goal compares guided planning with RRT and KPIECE: run all three planners");
    }
    const auto number = [](double v) {
      char text[32];
      std::snprintf(text, sizeof text, "%.10g", v);
      return std::string(text);
    };
    for (const std::string& kv : *params) {
      const std::size_t eq = kv.find('=');
      if (eq == 0 || eq == std::string::npos || eq + 1 == kv.size()) {
        throw InputError({"--param", 0, 0}, "'" + kv + "' is not KEY=VALUE");
      }
      if (kv.substr(0, eq) == "planner") {
        throw InputError({"--param", 0, 0}, "the bench chooses each run's planner (rrt, kpiece, guided): 'planner' cannot be set");
      }
      a.push_overrides[kv.substr(0, eq)] = kv.substr(eq + 1);
    }
    if (distance_option->count()) a.push_overrides["goal_distance"] = number(*goal_distance);
    if (heading_option->count()) a.push_overrides["goal_heading"] = number(*goal_heading);
    if (steer_option->count()) a.push_overrides["steer"] = number(*steer);
    return bench::push(a);
  };
  return c;
}

BenchCommand declare_occlusion(CLI::App& bench, CommonOptions& common) {
  BenchCommand c = add_bench(bench, common, "occlusion", "The occlusion planner on generated occlusion shelves (Table II of Tian et al.)",
                             bench::occlusion);
  BenchArgs& args = *c.args;
  BenchOptions(*c.app, args)
      .seed("First seed of the generated shelves and of the runs")
      .scenes("Generated shelves per size (the paper's 20)", 20)
      .sizes("Object counts", {12, 16, 20})
      .runs("Runs per shelf (seeds seed, seed+1, ...)", 3)
      .time_limit("Seconds per run", 60)
      .json("the table with the paper's figures")
      .csv("one row per run")
      .svg("per layout the success rates, |O_r| and times of each size beside the paper's")
      .sweep()
      .goals("success >= 95 % and a median time <= 1 s for every size");
  c.app->add_option("--occlusion-layout", args.occlusion_layouts,
                    "'columns' (each object hidden by the one in front) and/or 'random' (Table I shelves seen from the "
                    "front, the target hidden); repeatable, default both")
      ->expected(1)
      ->allow_extra_args(false)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll)
      ->check(CLI::IsMember({"columns", "random"}));
  BenchOptions(*c.app, args).robot("Robot description", "domains/robots/ur10_ag95.yaml");
  return c;
}

BenchCommand declare_mobile(CLI::App& bench, CommonOptions& common) {
  BenchCommand c = add_bench(bench, common, "mobile",
                             "retrieval_graph with a mobile manipulator on generated tables for three initial exploration "
                             "limits (Table III of Tian et al.)",
                             bench::mobile);
  BenchArgs& args = *c.args;
  BenchOptions(*c.app, args)
      .seed("First seed of the generated tables and of the runs")
      .scenes("Tables wanted", 20)
      .sizes("Objects per table", {20}, true)
      .runs("Runs per table and limit (seeds 0, 1, ...)", 3)
      .time_limit("Seconds per run, and the outer limit of each table's check", 60)
      .json("the summary")
      .csv("one row per run")
      .svg("the success rates, |O_r| and times of each initial limit beside the paper's")
      .sweep()
      .goals("L = 1 moves at most 2.2 objects on average (target included) with a median time <= 1 s");
  c.app->add_option("--mobile-tables", args.mobile_tables,
                    "fig9 keeps the generated tables where, as in the paper's Fig. 9, one object is in the way from some "
                    "side and two or more from the robot's (proved by the exhaustive planner); random keeps every table")
      ->capture_default_str()
      ->check(CLI::IsMember({"fig9", "random"}));
  BenchOptions(*c.app, args).robot("Robot description (a mobile manipulator)", "domains/robots/pr2_mobile.yaml");
  return c;
}

// `bench sweep FILE`: the runs a sweep file lists.
BenchCommand declare_file_sweep(CLI::App& bench, CommonOptions& common) {
  BenchCommand c = add_bench(bench, common, "sweep",
                             "Every problem of a sweep file with every planner of its parameter grid and every seed "
                             "(docs/file-formats.md, \"Sweep files\")",
                             bench::file_sweep);
  c.app->add_option("file", c.args->sweep_file, "The sweep file (YAML)")->required()->check(CLI::ExistingFile);
  BenchOptions(*c.app, *c.args)
      .json("a row per problem and planner")
      .csv("one row per run")
      .svg("the success rate and times of every row")
      .sweep()
      .goals("every run solved");
  return c;
}

// `bench merge FILES...`: the report of a sweep's shards, as one run would print it.
BenchCommand declare_merge(CLI::App& bench, CommonOptions& common) {
  auto merge = std::make_shared<bench::MergeArgs>();
  BenchCommand c = add_bench(bench, common, "merge",
                             "Report the records files of a sweep's shards (--shard K/N --records FILE) together: the same "
                             "tables, CSV, JSON and plots as one unsharded run of the same runs",
                             [merge](BenchArgs& args) {
                               merge->verbosity = args.verbosity;
                               if (!merge->json.empty()) io::check_writable(merge->json, "JSON file (--json)");
                               if (!merge->csv.empty()) io::check_writable(merge->csv, "CSV file (--csv)");
                               if (!merge->svg.empty()) io::check_writable(merge->svg, "SVG file (--svg)");
                               if (!merge->records.empty()) io::check_writable(merge->records, "records file (--records)");
                               if (!merge->ompl_log.empty()) io::check_writable(merge->ompl_log, "OMPL benchmark log (--ompl-log)");
                               return bench::merge(*merge);
                             });
  c.app->add_option("files", merge->files, "Records files (--records) of the shards of one sweep")->required()->check(CLI::ExistingFile);
  c.app->add_option("--json", merge->json, "Also write the bench's JSON to this file");
  c.app->add_option("--csv", merge->csv, "Also write every run as CSV to this file");
  c.app->add_option("--svg", merge->svg, "Also plot the bench's figures (SVG) to this file");
  c.app->add_option("--records", merge->records, "Also write the merged records as one records file");
  c.app->add_option("--ompl-log", merge->ompl_log, "Also write the runs in OMPL's benchmark log format");
  c.app->add_flag("--check-goals", merge->check_goals, "Exit code 1 when a goal the bench checks is missed");
  return c;
}

// `bench worker SETTINGS`: a child process of -j (not for people: hidden from --help).
BenchCommand declare_worker(CLI::App& bench, CommonOptions& common) {
  auto settings = std::make_shared<std::filesystem::path>();
  BenchCommand c = add_bench(bench, common, "worker", "", [settings](BenchArgs& args) { return bench::sweep_worker(*settings, args.sweep); });
  c.app->group("");
  c.app->add_option("settings", *settings, "The sweep's settings, as the parent wrote them")->required()->check(CLI::ExistingFile);
  c.app->add_option_function<std::string>("--shard", [args = c.args](const std::string& text) { args->sweep.shard = bench::parse_shard(text); })
      ->required()
      ->check(shard_validator());
  c.app->add_option("--records", c.args->sweep.records, "Where the runs go")->required();
  return c;
}

}  // namespace

Command declare_bench(CLI::App& app, CommonOptions& common) {
  auto* bench = app.add_subcommand("bench", "Run one of the papers' experiments or a speed measurement; 'bench BENCH --help' lists its options");
  bench->require_subcommand(1);
  auto benches = std::make_shared<std::vector<BenchCommand>>();
  for (auto declare : {declare_collision, declare_pddl, declare_samplers, declare_retrieval, declare_physics, declare_push,
                       declare_occlusion, declare_mobile, declare_file_sweep, declare_merge, declare_worker}) {
    benches->push_back(declare(*bench, common));
  }
  return {bench, [benches, &common] {
            for (BenchCommand& c : *benches) {
              if (!c.app->parsed()) continue;
              check_outputs(*c.args);
              c.args->sweep.package_paths = common.package_paths;
              c.args->sweep.memory_limit_mib = common.memory_limit_mib;
              try {
                return c.run(*c.args);
              } catch (const bench::WorkerFailed& e) {
                std::cerr << "cluttertamp bench " << c.app->get_name() << ": " << e.what();
                return e.exit_code;
              }
            }
            throw std::logic_error("bench: no bench was parsed");
          }};
}

}  // namespace cluttertamp::cli
