// `cluttertamp bench occlusion`: the occlusion planner on generated occlusion shelves,
// beside Tian et al.'s Table II. It runs as a sweep (shards, -j, records, merge).
#include <algorithm>
#include <iostream>
#include <map>
#include <memory>
#include <optional>
#include <sstream>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "bench/json_file.hpp"
#include "bench/measures.hpp"
#include "bench/ompl_log.hpp"
#include "bench/prose.hpp"
#include "bench/reports.hpp"
#include "bench/settings.hpp"
#include "bench/svg_plot.hpp"
#include "bench/table_plot.hpp"
#include "bench/sweep.hpp"
#include "cluttertamp/bench/bench.hpp"
#include "cluttertamp/io/robot_description_io.hpp"
#include "cluttertamp/io/text_file.hpp"
#include "cluttertamp/plugin/registry.hpp"
#include "cluttertamp/plugin/task_planner.hpp"
#include "cluttertamp/run/runner.hpp"
#include "cluttertamp/run/shelf_runs.hpp"
#include "cluttertamp/scenes/shelf_generator.hpp"
#include "cluttertamp/version.hpp"

namespace cluttertamp::bench {

namespace {

struct Run {
  std::string layout;
  int objects = 0;
  std::uint64_t scene_seed = 0, seed = 0;
  bool solved = false;
  double seconds = 0.0;
  std::uint64_t removed = 0, final_sequence = 0, iterations = 0, observed_initially = 0, found_by_touch = 0;
  std::string reason;
};

// Table II of the paper: |O_r|, time (s), iterations, success (%), by object count.
const std::map<int, PaperMeasures> kTableII{{12, {2.84, 18.85, 3.14, 95}}, {16, {4.02, 27.45, 5.2, 90}}, {20, {4.86, 36.01, 6.56, 90}}};

std::vector<int> sizes_of(const BenchArgs& args) { return args.sizes.empty() ? std::vector<int>{12, 16, 20} : args.sizes; }
std::vector<std::string> layouts_of(const BenchArgs& args) {
  return args.occlusion_layouts.empty() ? std::vector<std::string>{"columns", "random"} : args.occlusion_layouts;
}

// Run i of the sweep: layout, then size, then shelf, then seed.
struct OcclusionRef {
  std::size_t layout = 0, size = 0;
  int scene = 0, run = 0;
};
OcclusionRef ref_of(std::size_t i, const BenchArgs& args) {
  const std::size_t runs = static_cast<std::size_t>(args.runs), per_size = static_cast<std::size_t>(args.instances) * runs;
  const std::size_t per_layout = sizes_of(args).size() * per_size;
  return {i / per_layout, (i % per_layout) / per_size, static_cast<int>((i % per_size) / runs), static_cast<int>(i % runs)};
}
std::size_t run_count(const BenchArgs& args) {
  return layouts_of(args).size() * sizes_of(args).size() * static_cast<std::size_t>(args.instances) * static_cast<std::size_t>(args.runs);
}

scenes::OcclusionSpec spec_of(const std::string& layout, int objects) {
  scenes::OcclusionSpec spec;
  spec.layout = layout == "random" ? scenes::OcclusionLayout::random : scenes::OcclusionLayout::columns;
  spec.objects = objects;
  spec.columns = objects / 4;
  return spec;
}

// Sizes a layout cannot hold are bad input before any run (a sweep's shards all refuse them).
void check_sizes(const BenchArgs& args) {
  for (const std::string& layout : layouts_of(args)) {
    for (int n : sizes_of(args)) {
      if (layout == "columns" && n % 4 != 0) {
        throw InputError({"--sizes", 0, 0}, "occlusion shelves in columns hold columns of 4: " + std::to_string(n) + " is not a multiple of 4");
      }
    }
  }
}

Record record_of(const Run& run, const Result& r) {
  return {{"problem", run.layout + std::to_string(run.objects)},
          {"layout", run.layout},
          {"objects", run.objects},
          {"scene_seed", run.scene_seed},
          {"planner", "occlusion"},
          {"seed", run.seed},
          {"solved", run.solved},
          {"time_s", run.seconds},
          {"task_s", r.time.task_planning},
          {"motion_s", r.time.motion_planning},
          {"removed", run.removed},
          {"counters", r.counters},
          {"reason", run.reason},
          {"version", std::string(version())}};
}

Run run_of(const Record& r) {
  auto count = [&](const char* name) {
    const auto& c = r.at("counters");
    return c.contains(name) ? c[name].get<std::uint64_t>() : std::uint64_t{0};
  };
  return {r.at("layout").get<std::string>(),  r.at("objects").get<int>(),       r.at("scene_seed").get<std::uint64_t>(),
          r.at("seed").get<std::uint64_t>(),  r.at("solved").get<bool>(),      number(r, "time_s"),
          r.at("removed").get<std::uint64_t>(), count(counter::final_sequence), count(counter::iterations),
          count(counter::observed_initially), count(counter::found_by_touch),   r.at("reason").get<std::string>()};
}

// Plans the runs it is given, generating each shelf once.
class OcclusionRunner {
 public:
  explicit OcclusionRunner(const BenchArgs& args)
      : args_(args),
        robot_(std::make_shared<const robot::RobotDescription>(io::load_robot_description(args.robot))),
        registry_(plugin::Registry::default_search_paths()),
        samplers_(run::shipped_samplers(registry_)),
        planner_(registry_.create<plugin::TaskPlanner>("occlusion", {}, {"bench occlusion", 0, 0})) {}

  Record run(const OcclusionRef& ref) {
    Run run;
    run.layout = layouts_of(args_).at(ref.layout);
    run.objects = sizes_of(args_).at(ref.size);
    run.scene_seed = args_.seed + static_cast<std::uint64_t>(ref.scene);
    run.seed = static_cast<std::uint64_t>(ref.run);
    const Result r = run::plan_scene(scene(run), robot_, *planner_, samplers_, run.seed, args_.time_limit);
    run.solved = r.solved;
    run.seconds = r.time.total;
    run.removed = r.moved_objects.size();
    run.reason = r.reason;
    return record_of(run, r);
  }

 private:
  const Scene& scene(const Run& run) {
    const std::string key = run.layout + " " + std::to_string(run.objects) + " " + std::to_string(run.scene_seed);
    if (scene_.first != key) {
      try {
        scene_ = {key, scenes::generate_occlusion_scene(spec_of(run.layout, run.objects), run.scene_seed)};
      } catch (const std::runtime_error& e) {
        throw InputError({"--sizes", 0, 0}, std::to_string(run.objects) + " objects, " + run.layout + ": " + e.what());
      }
    }
    return scene_.second;
  }

  const BenchArgs& args_;
  std::shared_ptr<const robot::RobotDescription> robot_;
  plugin::Registry registry_;
  plugin::Samplers samplers_;
  std::shared_ptr<plugin::TaskPlanner> planner_;
  std::pair<std::string, Scene> scene_;
};

Measures measures_of(const std::vector<Run>& runs, const std::string& layout, int objects) {
  Measures m;
  for (const Run& r : runs) {
    if (r.layout != layout || r.objects != objects) continue;
    m.add(r.solved, double(r.removed), r.seconds, double(r.iterations));
    if (r.solved) m.final_sequence.push_back(double(r.final_sequence));
  }
  return m;
}

// Per layout: success rates by size (the paper's hatched), then the final removal
// sequence |O_r| and the time of each solved run as box plots with the paper's means
// as diamonds, and each size's unsolved runs as a red cross with their count.
void write_svg(const std::filesystem::path& file, const std::vector<Run>& runs, const BenchArgs& args) {
  std::vector<TablePlot> tables;
  for (const std::string& layout : layouts_of(args)) {
    TablePlot& table = tables.emplace_back();
    table.title = "Table II (Tian et al., T-RO 2023), " + layout + " shelves: ours beside the paper's";
    table.removed_title = "|O_r|, final sequence, solved runs";
    const std::vector<int> sizes = sizes_of(args);
    for (std::size_t k = 0; k < sizes.size(); ++k) {
      const Measures m = measures_of(runs, layout, sizes[k]);
      PlotColumn column{series_colour(k), m.success(), m.final_sequence, m.seconds, m.runs - m.solved, {}, {}, {}, {}};
      if (const auto paper = kTableII.find(sizes[k]); paper != kTableII.end()) {
        column.paper_success = paper->second.success;
        column.paper_removed = paper->second.removed;
        column.paper_seconds = paper->second.seconds;
      }
      table.groups.push_back({"|O| = " + std::to_string(sizes[k]), {std::move(column)}});
    }
  }
  write_table_svg(file, tables);
}

// The run's seed is its number on its shelf (0, 1, ...).
void write_csv(const std::filesystem::path& file, const std::vector<Run>& runs) {
  std::ostringstream csv;
  csv << "objects,scene_seed,run,solved,time_s,removed,iterations,observed_initially,found_by_touch,reason,layout,final_sequence\n";
  for (const Run& r : runs) {
    csv << r.objects << "," << r.scene_seed << "," << r.seed << "," << (r.solved ? 1 : 0) << ","
        << r.seconds << "," << r.removed << "," << r.iterations << "," << r.observed_initially << "," << r.found_by_touch << ","
        << csv_field(r.reason) << "," << r.layout << "," << r.final_sequence << "\n";
  }
  io::write_text_file(file, csv.str(), "CSV file");
}

}  // namespace

int occlusion(const BenchArgs& args) {
  check_sizes(args);
  const SweepPlan plan{"occlusion", settings_of(args), run_count(args), [&](std::size_t i) {
                         const OcclusionRef ref = ref_of(i, args);
                         return layouts_of(args)[ref.layout] + ", " + std::to_string(sizes_of(args)[ref.size]) + " objects, shelf " +
                                std::to_string(ref.scene + 1) + " of " + std::to_string(args.instances) + ", seed " + std::to_string(ref.run);
                       }};
  return run_and_report(
      plan, args, [&] { return std::make_unique<OcclusionRunner>(args); },
      [&](OcclusionRunner& runner, std::size_t i) { return runner.run(ref_of(i, args)); }, report_occlusion);
}

int report_occlusion(const BenchArgs& args, const std::vector<Record>& records) {
  std::vector<Run> runs;
  for (const Record& r : records) runs.push_back(run_of(r));
  std::cout << "Occlusion (Tian et al., Table II): " << args.instances << " generated shelves per size, " << args.runs
            << " run(s) each, " << args.time_limit << " s per run\n";
  bool goals_met = true;
  nlohmann::ordered_json summary = nlohmann::ordered_json::array();
  for (const std::string& layout : layouts_of(args)) {
    std::cout << "\n"
              << wrapped(layout == "columns" ? "Columns: each object hidden by the one in front, in columns of 4 (the target needs at least 3 removals)"
                                             : "Random: Table I shelves seen from the front at the objects' height, the target hidden");
    std::vector<std::string> headers;
    std::vector<std::vector<std::string>> columns;
    for (int n : sizes_of(args)) {
      const Measures m = measures_of(runs, layout, n);
      goals_met = goals_met && m.success() >= 95.0 && m.solved > 0 && m.time_median() <= 1.0;
      const auto paper = kTableII.count(n) ? std::optional<PaperMeasures>(kTableII.at(n)) : std::nullopt;
      headers.push_back("|O| = " + std::to_string(n) + " (paper)");
      columns.push_back(m.cells(paper));
      nlohmann::ordered_json j{{"layout", layout}, {"objects", n}};
      j.update(m.json(paper));
      summary.push_back(j);
    }
    print_measures(std::cout, headers, columns, 24);
  }
  std::cout << wrapped("The paper's times are for its implementation and machine; its |O_r| for its own scenes, beside the final "
                       "removal sequence here (the moved objects the plan needed moved: moving one only to look behind it is "
                       "the extra cost the paper describes).")
            << "goal: success >= 95 % and median <= 1 s for every size: " << (goals_met ? "met" : "NOT met") << "\n";
  if (!args.csv.empty()) write_csv(args.csv, runs);
  if (!args.json.empty()) {
    write_json_file(args.json, nlohmann::ordered_json{{"bench", "occlusion"}, {"scenes_per_size", args.instances},
                                                      {"runs", args.runs}, {"time_limit_s", args.time_limit},
                                                      {"sizes", summary}});
  }
  if (!args.svg.empty()) write_svg(args.svg, runs, args);
  if (!args.ompl_log.empty()) {
    std::vector<OmplLogPlanner> planners;
    for (const std::string& layout : layouts_of(args)) {
      for (int n : sizes_of(args)) {
        OmplLogPlanner p{layout + std::to_string(n) + "/occlusion", {}};
        for (const Record& r : records) {
          if (r.at("layout") == layout && r.at("objects") == n) p.runs.push_back(&r);
        }
        planners.push_back(std::move(p));
      }
    }
    write_ompl_log(args.ompl_log, {"cluttertamp_bench_occlusion", settings_of(args).dump(2), args.seed, args.time_limit}, planners);
  }
  return goal_exit_code(args.check_goals, goals_met);
}

}  // namespace cluttertamp::bench
