// `cluttertamp bench retrieval`: Tables I, V and VI of Tian et al. (T-RO 2023) beside
// the paper's numbers, as a table, CSV and JSON.
//   I:  retrieval_graph with the three initial exploration limits (and the
//       traversability-graph baseline, Fig. 15) on generated 12/16/20-object shelves;
//   V:  retrieval_graph (L = 1) against traversability_graph on 100-object shelves;
//   VI: retrieval_graph (L = 1) against the exhaustive optimum on the bundled
//       16-object shelves whose fewest objects to move is 2, 3 and 4.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cmath>
#include <iomanip>
#include <iostream>
#include <limits>
#include <map>
#include <optional>
#include <sstream>

#include <nlohmann/json.hpp>

#include "bench/json_file.hpp"
#include "bench/ompl_log.hpp"
#include "bench/reports.hpp"
#include "bench/settings.hpp"
#include "bench/svg_plot.hpp"
#include "bench/sweep.hpp"
#include "cluttertamp/bench/bench.hpp"
#include "cluttertamp/io/text_file.hpp"
#include "cluttertamp/version.hpp"
#include "cluttertamp/run/shelf_runs.hpp"
#include "bench/statistics.hpp"
#include "cluttertamp/io/robot_description_io.hpp"
#include "cluttertamp/scenes/shelf_fit.hpp"
#include "cluttertamp/io/scene_io.hpp"
#include "cluttertamp/plugin/registry.hpp"
#include "cluttertamp/plugin/task_planner.hpp"
#include "cluttertamp/run/runner.hpp"
#include "cluttertamp/scenes/shelf_generator.hpp"

namespace cluttertamp::bench {

namespace {

constexpr double kNone = std::numeric_limits<double>::quiet_NaN();

// A paper figure: mean and standard deviation, NaN where the paper gives none.
struct Figure {
  double mean = kNone, sd = kNone;
};

// What the paper reports for one row (|O_r| counts the target).
struct Paper {
  Figure removed, total, task, motion, iterations, sequences;
  double success = kNone;
};

// One row of a table: a planner with its parameters on a set of `instances` scenes.
struct Row {
  std::string table, scenes, planner, initial_limit;
  int objects = 0;
  std::size_t instances = 0;
  Paper paper;
};

struct Measured {
  std::vector<double> removed, total, task, motion, iterations, sequences;
  std::vector<double> checks;  // collision checks of every run, solved or not
  std::map<std::string, PhaseTotals> phases;  // summed over every run
  std::map<std::string, int> failures;  // the reasons of the runs that failed, with their counts
  int solved = 0, runs = 0;
  std::map<std::pair<std::size_t, int>, double> removed_by_run;  // (instance, run) -> |O_r|, solved runs
};

// The planner each table's retrieval_graph row is compared with run by run.
std::string baseline_of(const std::string& table) {
  return table == "V" ? "traversability_graph" : table == "VI" ? "exhaustive" : "";
}

// |O_r| of two planners over the runs both solved (same scene, same seed).
struct Paired {
  int runs = 0;
  double removed = 0.0, baseline_removed = 0.0;  // means
};

Paired paired(const Measured& m, const Measured& baseline) {
  Paired p;
  for (const auto& [run, removed] : m.removed_by_run) {
    const auto other = baseline.removed_by_run.find(run);
    if (other == baseline.removed_by_run.end()) continue;
    ++p.runs;
    p.removed += removed;
    p.baseline_removed += other->second;
  }
  if (p.runs > 0) {
    p.removed /= p.runs;
    p.baseline_removed /= p.runs;
  }
  return p;
}

Paper table_i(Figure removed, Figure total, double iterations, double success) {
  Paper p;
  p.removed = removed;
  p.total = total;
  p.iterations = {iterations, kNone};
  p.success = success;
  return p;
}
const std::map<std::pair<int, std::string>, Paper> kTableI{
    {{12, "one"}, table_i({2.14, 0.34}, {10.54, 5.89}, 1.78, 100)},
    {{12, "nodecol"}, table_i({2.35, 0.47}, {9.85, 4.91}, 1.5, 100)},
    {{12, "objects"}, table_i({2.36, 1.08}, {8.95, 5.74}, 1, 100)},
    {{16, "one"}, table_i({2.81, 0.52}, {20.50, 6.71}, 3.18, 95)},
    {{16, "nodecol"}, table_i({3.15, 0.53}, {16.25, 6.0}, 1.76, 100)},
    {{16, "objects"}, table_i({3.35, 1.0}, {21.43, 7.50}, 1, 100)},
    {{20, "one"}, table_i({3.28, 0.58}, {21.73, 7.13}, 3.28, 95)},
    {{20, "nodecol"}, table_i({3.57, 0.62}, {17.63, 7.18}, 1.92, 95)},
    {{20, "objects"}, table_i({4.25, 0.82}, {15.73, 7.38}, 1, 100)},
};
Paper table_v(Figure task, Figure motion, Figure total, Figure sequences, Figure removed) {
  Paper p;
  p.task = task;
  p.motion = motion;
  p.total = total;
  p.sequences = sequences;
  p.removed = removed;
  return p;
}
const Paper kTableVNam = table_v({9.71, 0.58}, {126.40, 31.44}, {136.10, 31.52}, {5.05, 1.57}, {10.95, 0.88});
const Paper kTableVOurs = table_v({40.95, 4.72}, {78.54, 6.68}, {119.49, 9.52}, {1.30, 0.47}, {10.45, 0.51});
Paper table_vi(Figure removed, Figure total) {
  Paper p;
  p.removed = removed;
  p.total = total;
  return p;
}
const std::map<int, std::pair<Paper, Paper>> kTableVI{  // brute force, ours
    {2, {table_vi({2, 0}, {4.34, 0.11}), table_vi({2.25, 0.45}, {4.11, 0.65})}},
    {3, {table_vi({3, 0}, {18.39, 2.54}), table_vi({3.18, 0.38}, {14.71, 2.26})}},
    {4, {table_vi({4, 0}, {145.56, 7.44}), table_vi({4.27, 0.44}, {20.84, 5.57})}},
};

// Generated shelves of `objects` cylinders whose target needs a removal, as the paper's,
// with the seed of each. With args.fit_to_robot the shelf goes where `robot` reaches it,
// and `robot` becomes the description to plan these scenes with: its home replaced by
// the fit's start when the home reaches into the cabinet. Fewer than args.instances
// within 1000 seeds is bad input.
std::vector<std::pair<std::uint64_t, Scene>> generated(int objects, const BenchArgs& args, std::shared_ptr<const robot::RobotDescription>& robot,
                                                       const plugin::Samplers& samplers, double width = 0.0) {
  scenes::ShelfSpec spec;
  spec.objects = objects;
  spec.width = width;
  spec.min_gap = args.min_gap;
  if (args.fit_to_robot) {
    const scenes::ShelfFit fit = scenes::fit_shelf_to_robot(spec, robot);
    spec = fit.spec;
    if (fit.start) robot = std::make_shared<const robot::RobotDescription>(robot->with_home(*fit.start));
    if (args.verbosity != Verbosity::quiet) {
      std::cerr << "shelf" << objects << " for " << robot->name() << ": " << scenes::describe_placement(fit)
                << (fit.start ? "; the home reaches into the cabinet, so the runs start with the tool drawn back" : "") << "\n";
    }
  }
  std::vector<std::pair<std::uint64_t, Scene>> out;
  int unreachable = 0;
  for (std::uint64_t seed = args.seed; static_cast<int>(out.size()) < args.instances && seed < args.seed + 1000; ++seed) {
    Scene scene;
    try {
      scene = scenes::generate_shelf_scene(spec, seed);
    } catch (const std::runtime_error& e) {
      throw InputError({"--sizes", 0, 0}, "shelf" + std::to_string(objects) + ": " + e.what());
    }
    // A shelf whose target the robot cannot retrieve even alone measures no planner.
    const run::TargetAccess access = run::target_access(scene, robot, samplers, seed);
    if (access == run::TargetAccess::after_removals) out.emplace_back(seed, std::move(scene));
    if (access == run::TargetAccess::never) ++unreachable;
  }
  if (static_cast<int>(out.size()) < args.instances) {
    throw InputError({"--scenes", 0, 0}, "only " + std::to_string(out.size()) + " of " + std::to_string(args.instances) + " generated shelves of " +
                                             std::to_string(objects) + " objects need a removal within 1000 seeds from " +
                                             std::to_string(args.seed) +
                                             (unreachable > 0 ? "; in " + std::to_string(unreachable) +
                                                                    " the robot cannot retrieve the target even from the shelf emptied of the others"
                                                              : std::string()));
  }
  return out;
}

// The rows of the tables asked for, from the arguments alone: every shard of a sweep
// and `bench merge` make the same list.
std::vector<Row> rows_of(const BenchArgs& args) {
  const std::vector<std::string> tables = args.tables.empty() ? std::vector<std::string>{"I"} : args.tables;
  auto wants = [&](const std::string& t) { return std::find(tables.begin(), tables.end(), t) != tables.end(); };
  const auto generated_count = static_cast<std::size_t>(args.instances);
  std::vector<Row> rows;
  if (wants("I")) {
    for (int n : args.sizes.empty() ? std::vector<int>{12, 16, 20} : args.sizes) {
      const std::string key = "shelf" + std::to_string(n);
      for (const std::string strategy : {"one", "nodecol", "objects"}) {
        const Paper p = kTableI.count({n, strategy}) ? kTableI.at({n, strategy}) : Paper{};
        rows.push_back({"I", key, "retrieval_graph", strategy, n, generated_count, p});
      }
      rows.push_back({"I", key, "traversability_graph", "", n, generated_count, {}});
    }
  }
  if (wants("V")) {
    rows.push_back({"V", "shelf100", "traversability_graph", "", 100, generated_count, kTableVNam});
    rows.push_back({"V", "shelf100", "retrieval_graph", "one", 100, generated_count, kTableVOurs});
  }
  if (wants("VI")) {
    for (const auto& [minimum, paper] : kTableVI) {
      const std::string key = "shelf16-min" + std::to_string(minimum);
      rows.push_back({"VI", key, "exhaustive", "", 16, 1, paper.first});
      rows.push_back({"VI", key, "retrieval_graph", "one", 16, 1, paper.second});
    }
  }
  if (!args.planners.empty()) {
    std::erase_if(rows, [&](const Row& row) {
      return std::find(args.planners.begin(), args.planners.end(), row.planner) == args.planners.end();
    });
  }
  return rows;
}

// Run `index` of the sweep: the row, the scene of the row's set and the run's number.
struct RunRef {
  std::size_t row = 0, instance = 0;
  int run = 0;
};

std::vector<RunRef> runs_of(const std::vector<Row>& rows, int runs) {
  std::vector<RunRef> out;
  for (std::size_t r = 0; r < rows.size(); ++r) {
    for (std::size_t i = 0; i < rows[r].instances; ++i) {
      for (int k = 0; k < runs; ++k) out.push_back({r, i, k});
    }
  }
  return out;
}

std::string row_name(const Row& row) { return row.planner + (row.initial_limit.empty() ? "" : " (" + row.initial_limit + ")"); }

// Plans the runs it is given, making each row's scenes when a run first needs them.
class Runner {
 public:
  explicit Runner(const BenchArgs& args)
      : args_(args),
        registry_(plugin::Registry::default_search_paths()),
        samplers_(run::shipped_samplers(registry_)),
        robot_(std::make_shared<const robot::RobotDescription>(io::load_robot_description(args.robot))) {}

  Record run(const Row& row, std::size_t instance, int run) {
    const Scenes& set = scenes(row);
    const auto& [scene_seed, scene] = set.scenes.at(instance);
    Parameters parameters;
    if (!row.initial_limit.empty()) parameters.set("initial_L", row.initial_limit);
    const auto planner = registry_.create<plugin::TaskPlanner>(row.planner, parameters);
    const std::uint64_t seed = args_.seed + static_cast<std::uint64_t>(run);
    const auto t0 = std::chrono::steady_clock::now();
    const Result r = run::plan_scene(scene, set.robot, *planner, samplers_, seed, args_.time_limit);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    nlohmann::ordered_json phases = nlohmann::ordered_json::object();
    for (const auto& [name, t] : r.phases) phases[name] = {{"calls", t.calls}, {"collision_checks", t.collision_checks}, {"seconds", t.seconds}};
    return {{"table", row.table},
            {"scenes", row.scenes},
            {"objects", row.objects},
            {"problem", scene.name},
            {"scene_seed", scene_seed ? nlohmann::ordered_json(*scene_seed) : nlohmann::ordered_json(nullptr)},
            {"instance", instance},
            {"planner", row.planner},
            {"parameters", row.initial_limit.empty() ? nlohmann::ordered_json::object() : nlohmann::ordered_json{{"initial_L", row.initial_limit}}},
            {"run", run},
            {"seed", seed},
            {"solved", r.solved},
            {"time_s", seconds},
            {"task_s", r.time.task_planning},
            {"motion_s", r.time.motion_planning},
            {"removed", r.moved_objects.size()},
            {"counters", r.counters},
            {"phases", phases},
            {"reason", r.reason},
            {"version", std::string(version())}};
  }

 private:
  struct Scenes {
    std::vector<std::pair<std::optional<std::uint64_t>, Scene>> scenes;
    std::shared_ptr<const robot::RobotDescription> robot;
  };

  const Scenes& scenes(const Row& row) {
    const auto known = scenes_.find(row.scenes);
    if (known != scenes_.end()) return known->second;
    Scenes set;
    set.robot = robot_;
    if (row.table == "VI") {
      set.scenes.emplace_back(std::nullopt, io::load_scene(args_.table_vi_scenes / (row.scenes + ".yaml")));
    } else {
      for (auto& [seed, scene] : generated(row.objects, args_, set.robot, samplers_, row.table == "V" ? args_.table_v_width : 0.0)) {
        set.scenes.emplace_back(seed, std::move(scene));
      }
    }
    return scenes_.emplace(row.scenes, std::move(set)).first->second;
  }

  const BenchArgs& args_;
  plugin::Registry registry_;
  plugin::Samplers samplers_;
  std::shared_ptr<const robot::RobotDescription> robot_;
  std::map<std::string, Scenes> scenes_;
};

std::uint64_t counter_of(const Record& r, const char* name) {
  const auto counters = r.find("counters");
  if (counters == r.end()) return 0;
  const auto it = counters->find(name);
  return it == counters->end() ? 0 : it->get<std::uint64_t>();
}

// A row's measures from its runs' records.
Measured measured_of(const std::vector<const Record*>& runs) {
  Measured m;
  for (const Record* run : runs) {
    const Record& r = *run;
    ++m.runs;
    m.checks.push_back(double(counter_of(r, counter::collision_checks)));
    for (const auto& [name, totals] : r.at("phases").items()) {
      PhaseTotals& sum = m.phases[name];
      sum.calls += totals.at("calls").get<std::uint64_t>();
      sum.collision_checks += totals.at("collision_checks").get<std::uint64_t>();
      sum.seconds += totals.at("seconds").get<double>();
    }
    if (!r.at("solved").get<bool>()) {
      ++m.failures[r.at("reason").get<std::string>()];
      continue;
    }
    const double removed = number(r, "removed");
    ++m.solved;
    m.removed.push_back(removed);
    m.removed_by_run[{r.at("instance").get<std::size_t>(), r.at("run").get<int>()}] = removed;
    m.total.push_back(number(r, "time_s"));
    m.task.push_back(number(r, "task_s"));
    m.motion.push_back(number(r, "motion_s"));
    if (r.at("counters").contains(counter::iterations)) m.iterations.push_back(double(counter_of(r, counter::iterations)));
    if (r.at("counters").contains(counter::planning_sequences)) m.sequences.push_back(double(counter_of(r, counter::planning_sequences)));
  }
  return m;
}

// The terminal's table: one per paper table, each with the paper's columns for it,
// ours and the paper's side by side; at most 100 columns (the CSV and JSON hold the
// rest: standard deviations, percentiles, checks, phases).
struct Column {
  const char* label;
  int digits;
  double (*ours)(const Measured&);
  double (*paper)(const Paper&);
};
double success_of(const Measured& m) { return m.runs ? 100.0 * m.solved / m.runs : kNone; }
double mean_or_none(const std::vector<double>& v) { return v.empty() ? kNone : mean(v); }
const Column kRemoved{"|O_r|", 2, [](const Measured& m) { return mean_or_none(m.removed); }, [](const Paper& p) { return p.removed.mean; }};
const Column kTime{"time", 2, [](const Measured& m) { return mean_or_none(m.total); }, [](const Paper& p) { return p.total.mean; }};
const Column kMedian{"median", 2, [](const Measured& m) { return m.total.empty() ? kNone : median(m.total); }, nullptr};
const Column kTask{"task", 2, [](const Measured& m) { return mean_or_none(m.task); }, [](const Paper& p) { return p.task.mean; }};
const Column kMotion{"motion", 2, [](const Measured& m) { return mean_or_none(m.motion); }, [](const Paper& p) { return p.motion.mean; }};
const Column kIterations{"iter", 2, [](const Measured& m) { return mean_or_none(m.iterations); }, [](const Paper& p) { return p.iterations.mean; }};
const Column kSequences{"seqs", 2, [](const Measured& m) { return mean_or_none(m.sequences); }, [](const Paper& p) { return p.sequences.mean; }};
const Column kSuccess{"succ%", 0, success_of, [](const Paper& p) { return p.success; }};

std::vector<Column> columns_of(const std::string& table) {
  if (table == "V") return {kRemoved, kTask, kMotion, kTime, kSequences};
  if (table == "VI") return {kRemoved, kTime, kMedian, kSuccess};
  return {kRemoved, kTime, kMedian, kIterations, kSuccess};
}

struct NameWidths {
  std::size_t scenes = 7, planner = 8;
};

NameWidths name_widths(const std::vector<Row>& rows, const std::string& table) {
  NameWidths w;
  for (const Row& row : rows) {
    if (row.table != table) continue;
    w.scenes = std::max(w.scenes, row.scenes.size() + 1);
    w.planner = std::max(w.planner, row_name(row).size());  // a cell's leading space follows it
  }
  return w;
}

// `line` cut to the terminal's 100 columns.
std::string fitted(std::string line) {
  if (line.size() > 100) line = line.substr(0, 97) + "...";
  return line;
}

std::string number_text(double v, int digits) {
  if (std::isnan(v)) return "-";
  char out[32];
  std::snprintf(out, sizeof out, "%.*f", digits, v);
  return out;
}

// A table cell: at most 6 characters in its 7 columns (fewer decimals for large
// values), so that a space always stands before it.
std::string cell_text(double v, int digits) {
  std::string text = number_text(v, digits);
  while (text.size() > 6 && digits > 0) text = number_text(v, --digits);
  return text;
}

void print_table_header(const std::string& table, const NameWidths& w) {
  std::ostringstream line;
  line << std::left << std::setw(static_cast<int>(w.scenes)) << "scenes" << std::setw(static_cast<int>(w.planner)) << "planner"
       << std::right;
  for (const Column& c : columns_of(table)) {
    line << std::setw(7) << c.label;
    if (c.paper) line << std::setw(7) << "paper";
  }
  std::cout << "\nTable " << table << "\n" << line.str() << "\n";
}

void print_row(const Row& row, const Measured& m, const NameWidths& w) {
  std::ostringstream line;
  line << std::left << std::setw(static_cast<int>(w.scenes)) << row.scenes << std::setw(static_cast<int>(w.planner)) << row_name(row)
       << std::right;
  for (const Column& c : columns_of(row.table)) {
    line << std::setw(7) << cell_text(c.ours(m), c.digits);
    if (c.paper) line << std::setw(7) << cell_text(c.paper(row.paper), c.digits);
  }
  std::cout << line.str() << "\n";
}


// Per run, every phase's time and collision checks (the motion planner's by how each
// query ended), most checks first: where the time went, without a profiler.
void print_phases(const Measured& m) {
  if (m.runs == 0 || m.phases.empty()) return;
  std::vector<std::pair<std::string, PhaseTotals>> sorted(m.phases.begin(), m.phases.end());
  std::stable_sort(sorted.begin(), sorted.end(), [](const auto& a, const auto& b) { return a.second.collision_checks > b.second.collision_checks; });
  std::cout << "      per run:";
  for (const auto& [name, t] : sorted) {
    char out[128];
    std::snprintf(out, sizeof out, " %s %.1fx %.3fs %.0fk;", name.c_str(), double(t.calls) / m.runs, t.seconds / m.runs,
                  double(t.collision_checks) / m.runs / 1000.0);
    std::cout << out;
  }
  std::cout << "\n";
}

nlohmann::ordered_json phases_json(const Measured& m) {
  nlohmann::ordered_json out = nlohmann::ordered_json::object();
  for (const auto& [name, t] : m.phases) {
    const double runs = std::max(1, m.runs);
    out[name] = {{"calls_per_run", double(t.calls) / runs},
                 {"collision_checks_per_run", double(t.collision_checks) / runs},
                 {"time_per_run_s", t.seconds / runs}};
  }
  return out;
}

// Prints a row's line of the table (with its phases, failures and pairing) and returns
// its JSON.
nlohmann::ordered_json report_row(const Row& row, const Measured& m, const Measured* baseline, int runs, const NameWidths& widths,
                                  bool verbose) {
  const double success = m.runs ? 100.0 * m.solved / m.runs : 0.0;
  print_row(row, m, widths);
  if (verbose) print_phases(m);
  for (const auto& [reason, count] : m.failures) std::cout << fitted("      failed " + std::to_string(count) + "x: " + reason) << "\n";
  auto figure = [&](const std::vector<double>& v) {
    nlohmann::ordered_json f = {{"mean", mean(v)}, {"std", stddev(v)}, {"median", median(v)}};
    return v.empty() ? nlohmann::ordered_json(nullptr) : f;
  };
  auto paper = [](const Figure& f) {
    return std::isnan(f.mean) ? nlohmann::ordered_json(nullptr)
                              : nlohmann::ordered_json{{"mean", f.mean}, {"std", std::isnan(f.sd) ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(f.sd)}};
  };
  // Against the table's baseline on the runs both solved: a planner that fails the
  // hard scenes would look better on the means alone.
  nlohmann::ordered_json pair = nullptr;
  if (row.planner == "retrieval_graph" && baseline) {
    const Paired p = paired(m, *baseline);
    std::cout << "      paired with " << baseline_of(row.table) << " on the " << p.runs << " runs both solved: |O_r| "
              << number_text(p.removed, 2) << " against " << number_text(p.baseline_removed, 2);
    if (p.runs > 0) {
      const double more = 100.0 * (p.removed / p.baseline_removed - 1.0);
      std::cout << " (" << (more >= 0 ? "+" : "") << number_text(more, 1) << " %)";
    }
    std::cout << "\n";
    pair = {{"against", baseline_of(row.table)}, {"runs", p.runs},
            {"removed", p.runs ? nlohmann::ordered_json(p.removed) : nlohmann::ordered_json(nullptr)},
            {"against_removed", p.runs ? nlohmann::ordered_json(p.baseline_removed) : nlohmann::ordered_json(nullptr)}};
  }
  return {{"table", row.table},
          {"scenes", row.scenes},
          {"objects", row.objects},
          {"planner", row.planner},
          {"initial_L", row.initial_limit.empty() ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(row.initial_limit)},
          {"instances", row.instances},
          {"runs", runs},
          {"success_rate", success},
          {"removed", figure(m.removed)},
          {"time_s", figure(m.total)},
          {"time_p90_s", m.total.empty() ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(percentile(m.total, 90))},
          {"collision_checks", figure(m.checks)},
          {"phases", phases_json(m)},
          {"failures", m.failures},
          {"task_time_s", figure(m.task)},
          {"motion_time_s", figure(m.motion)},
          {"iterations", figure(m.iterations)},
          {"planning_sequences", figure(m.sequences)},
          {"paired", pair},
          {"paper",
           {{"removed", paper(row.paper.removed)},
            {"time_s", paper(row.paper.total)},
            {"task_time_s", paper(row.paper.task)},
            {"motion_time_s", paper(row.paper.motion)},
            {"iterations", paper(row.paper.iterations)},
            {"planning_sequences", paper(row.paper.sequences)},
            {"success", std::isnan(row.paper.success) ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(row.paper.success)}}}};
}

std::string row_key(const std::string& scenes, const std::string& planner, const std::string& initial_limit) {
  return scenes + "/" + planner + "/" + initial_limit;
}

void write_csv(const std::filesystem::path& file, const std::vector<Record>& records) {
  std::ostringstream csv;
  csv << "objects,initial_L,instance,run,solved,removed,time_s,task_s,motion_s,iterations,table,planner,scenes,sequences,seed,scene\n";
  for (const Record& r : records) {
    const auto& parameters = r.at("parameters");
    csv << r.at("objects").get<int>() << "," << (parameters.contains("initial_L") ? parameters["initial_L"].get<std::string>() : "") << ","
        << r.at("instance").get<std::size_t>() << "," << r.at("run").get<int>() << "," << r.at("solved").get<bool>() << ","
        << r.at("removed").get<std::size_t>() << "," << number(r, "time_s") << "," << number(r, "task_s") << "," << number(r, "motion_s")
        << "," << counter_of(r, counter::iterations) << "," << r.at("table").get<std::string>() << "," << r.at("planner").get<std::string>()
        << "," << r.at("scenes").get<std::string>() << "," << counter_of(r, counter::planning_sequences) << ","
        << r.at("seed").get<std::uint64_t>() << "," << csv_field(r.at("problem").get<std::string>()) << "\n";
  }
  io::write_text_file(file, csv.str(), "CSV file");
}

// A row's colour in the plots: one per planner and initial exploration limit.
const char* colour_of(const Row& row) {
  if (row.planner == "traversability_graph") return "#e7298a";
  if (row.planner == "exhaustive") return "#66a61e";
  if (row.initial_limit == "nodecol") return "#d95f02";
  if (row.initial_limit == "objects") return "#7570b3";
  return "#1b9e77";
}

// One SVG of every table: per table, success rates (ours; the paper's hatched), then
// |O_r| and the time of each solved run as box plots with the paper's means as
// diamonds, and each row's unsolved runs as a red cross with their count.
void write_svg(const std::filesystem::path& file, const std::vector<Row>& rows, const std::map<std::string, Measured>& measured) {
  std::vector<std::string> tables;
  for (const Row& row : rows) {
    if (std::find(tables.begin(), tables.end(), row.table) == tables.end()) tables.push_back(row.table);
  }
  const double left = 70, slot = 64, panel_h = 150, gap = 75, title_h = 50;
  std::size_t widest = 1;
  for (const std::string& t : tables) {
    widest = std::max<std::size_t>(widest, std::count_if(rows.begin(), rows.end(), [&](const Row& r) { return r.table == t; }));
  }
  const double panel_w = std::max(360.0, slot * double(widest));
  SvgPlot plot(left + panel_w + 30, double(tables.size()) * (title_h + 25 + 3 * (panel_h + gap)));
  double top = 0;
  for (const std::string& t : tables) {
    std::vector<const Row*> in;
    for (const Row& row : rows) {
      if (row.table == t) in.push_back(&row);
    }
    const auto m = [&](const Row* row) -> const Measured& { return measured.at(row_key(row->scenes, row->planner, row->initial_limit)); };
    plot.text(left, top + 20, "Table " + t + " (Tian et al., T-RO 2023): ours beside the paper's");
    plot.legend(left, top + 38, "hatch", "paper's success rate");
    plot.legend(left + 160, top + 38, "diamond", "paper's mean");
    plot.legend(left + 270, top + 38, "cross", "unsolved runs (count)");
    top += title_h + 25;
    std::vector<double> removed, times;
    for (const Row* row : in) {
      removed.insert(removed.end(), m(row).removed.begin(), m(row).removed.end());
      times.insert(times.end(), m(row).total.begin(), m(row).total.end());
      if (!std::isnan(row->paper.removed.mean)) removed.push_back(row->paper.removed.mean);
      if (!std::isnan(row->paper.total.mean)) times.push_back(row->paper.total.mean);
    }
    const SvgPlot::Panel rate = plot.panel(left, top, panel_w, panel_h, 100, "success rate", "%");
    const SvgPlot::Panel objects = plot.panel(left, top + panel_h + gap, panel_w, panel_h, removed.empty() ? 1.0 : *std::max_element(removed.begin(), removed.end()),
                                              "|O_r|, objects moved (target included), solved runs");
    const SvgPlot::Panel time = plot.panel_for(left, top + 2 * (panel_h + gap), panel_w, panel_h, times, "planning time of solved runs, s");
    for (std::size_t k = 0; k < in.size(); ++k) {
      const Row& row = *in[k];
      const Measured& mk = m(&row);
      const double x = left + slot * (double(k) + 0.5), w = slot * 0.55;
      plot.bar(rate, x - w / 2, w / 2, success_of(mk) >= 0 ? success_of(mk) : 0.0, colour_of(row));
      if (!std::isnan(row.paper.success)) plot.bar(rate, x, w / 2, row.paper.success, "hatch", colour_of(row));
      plot.box(objects, x, w, mk.removed, colour_of(row));
      if (!std::isnan(row.paper.removed.mean)) plot.diamond(objects, x, row.paper.removed.mean);
      plot.box(time, x, w, mk.total, colour_of(row));
      if (!std::isnan(row.paper.total.mean)) plot.diamond(time, x, row.paper.total.mean);
      for (const SvgPlot::Panel* p : {&objects, &time}) plot.unsolved(*p, x, mk.runs - mk.solved);
      // Two short lines under each: the scenes ("shelf12", "min2") and the planner.
      const std::string scenes = row.scenes.find('-') == std::string::npos ? row.scenes : row.scenes.substr(row.scenes.find('-') + 1);
      const std::string planner = !row.initial_limit.empty()                 ? "L=" + row.initial_limit
                                  : row.planner == "traversability_graph" ? std::string("trav.graph")
                                                                          : row.planner;
      for (const SvgPlot::Panel* p : {&rate, &objects, &time}) {
        plot.x_label(*p, x, scenes);
        plot.text(x, p->bottom() + 30, planner, "middle");
      }
    }
    top += 3 * (panel_h + gap);
  }
  plot.write(file);
}

SweepPlan plan_of(const BenchArgs& args, const std::vector<Row>& rows, const std::vector<RunRef>& refs) {
  return {"retrieval", settings_of(args), refs.size(), [&rows, &refs](std::size_t i) {
            const RunRef& ref = refs.at(i);
            return rows[ref.row].scenes + " " + row_name(rows[ref.row]) + ", scene " + std::to_string(ref.instance) + ", run " +
                   std::to_string(ref.run);
          }};
}

}  // namespace

int report_retrieval(const BenchArgs& args, const std::vector<Record>& records) {
  const std::vector<Row> rows = rows_of(args);
  std::map<std::string, std::vector<const Record*>> by_row;
  for (const Record& r : records) {
    const auto& parameters = r.at("parameters");
    by_row[row_key(r.at("scenes").get<std::string>(), r.at("planner").get<std::string>(),
                   parameters.contains("initial_L") ? parameters["initial_L"].get<std::string>() : "")]
        .push_back(&r);
  }
  std::map<std::string, Measured> measured;
  for (const Row& row : rows) measured[row_key(row.scenes, row.planner, row.initial_limit)] = measured_of(by_row[row_key(row.scenes, row.planner, row.initial_limit)]);
  std::cout << "Tian et al., T-RO 2023: ours beside the paper's. Means over solved runs (" << args.runs << " per scene, "
            << fixed(args.time_limit, 0) << " s each);\ntimes in s (the paper's: its Python on its machine); succ%: runs solved\n";
  nlohmann::ordered_json json = nlohmann::ordered_json::array();
  std::string table;
  NameWidths widths;
  for (const Row& row : rows) {
    if (row.table != table) {
      table = row.table;
      widths = name_widths(rows, table);
      print_table_header(table, widths);
    }
    const auto baseline = measured.find(row_key(row.scenes, baseline_of(row.table), ""));
    json.push_back(report_row(row, measured[row_key(row.scenes, row.planner, row.initial_limit)],
                              baseline == measured.end() || baseline_of(row.table).empty() ? nullptr : &baseline->second, args.runs,
                              widths, args.verbosity == Verbosity::verbose));
  }
  if (args.verbosity != Verbosity::verbose) std::cout << "\n(-v: where each row's time went, phase by phase; the CSV and JSON: every figure)\n";
  if (!args.json.empty()) write_json_file(args.json, json);
  if (!args.csv.empty()) write_csv(args.csv, records);
  if (!args.svg.empty()) write_svg(args.svg, rows, measured);
  if (!args.ompl_log.empty()) {
    std::vector<OmplLogPlanner> planners;
    for (const Row& row : rows) {
      const std::string key = row_key(row.scenes, row.planner, row.initial_limit);
      planners.push_back({row.scenes + "/" + row.planner + (row.initial_limit.empty() ? "" : "[initial_L=" + row.initial_limit + "]"), by_row[key]});
    }
    write_ompl_log(args.ompl_log, {"cluttertamp_bench_retrieval", settings_of(args).dump(2), args.seed, args.time_limit}, planners);
  }
  return run::ExitCode::solved;
}

int retrieval(const BenchArgs& args) {
  const std::vector<Row> rows = rows_of(args);
  const std::vector<RunRef> refs = runs_of(rows, args.runs);
  return run_and_report(
      plan_of(args, rows, refs), args, [&] { return std::make_unique<Runner>(args); },
      [&](Runner& runner, std::size_t i) {
        const RunRef& ref = refs.at(i);
        return runner.run(rows[ref.row], ref.instance, ref.run);
      },
      report_retrieval);
}

}  // namespace cluttertamp::bench
