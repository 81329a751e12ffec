// `cluttertamp bench retrieval`: Tables I, V and VI of Tian et al. (T-RO 2023) beside
// the paper's numbers, as a table, CSV and JSON.
//   I:  retrieval_graph with the three initial exploration limits (and the
//       traversability-graph baseline, Fig. 15) on generated 12/16/20-object shelves;
//   V:  retrieval_graph (L = 1) against traversability_graph on 100-object shelves;
//   VI: retrieval_graph (L = 1) against the exhaustive optimum on the bundled
//       16-object shelves whose fewest objects to move is 2, 3 and 4.
#include <chrono>
#include <cstdio>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <limits>
#include <map>
#include <optional>

#include <nlohmann/json.hpp>

#include "bench/json_file.hpp"
#include "cluttertamp/bench/bench.hpp"
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

// One row of a table: a planner with its parameters on a set of scenes.
struct Row {
  std::string table, scenes, planner, initial_limit;
  int objects = 0;
  const std::vector<Scene>* instances = nullptr;
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

std::string text(const Figure& f) {
  if (std::isnan(f.mean)) return "-";
  char out[48];
  if (std::isnan(f.sd)) {
    std::snprintf(out, sizeof out, "%.2f", f.mean);
  } else {
    std::snprintf(out, sizeof out, "%.2f(%.2f)", f.mean, f.sd);
  }
  return out;
}

Figure of(const std::vector<double>& v) { return v.empty() ? Figure{} : Figure{mean(v), stddev(v)}; }

std::uint64_t counter(const Result& r, const std::string& name) { return r.counters.count(name) ? r.counters.at(name) : 0; }

// Generated shelves of `objects` cylinders whose target needs a removal, as the paper's.
// With args.fit_to_robot the shelf goes where `robot` reaches it, and `robot` becomes the
// description to plan these scenes with: its home replaced by the fit's start when the
// home reaches into the cabinet.
std::vector<Scene> generated(int objects, const BenchArgs& args, std::shared_ptr<const robot::RobotDescription>& robot,
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
      std::printf("shelf%d for %s: %s%s\n", objects, robot->name().c_str(), scenes::describe_placement(fit).c_str(),
                  fit.start ? "; the home reaches into the cabinet, so the runs start with the tool drawn back" : "");
    }
  }
  std::vector<Scene> out;
  for (std::uint64_t seed = args.seed; static_cast<int>(out.size()) < args.instances && seed < args.seed + 1000; ++seed) {
    Scene scene = scenes::generate_shelf_scene(spec, seed);  // throws runtime_error: too crowded
    if (!run::target_comes_out_directly(scene, robot, samplers, seed)) out.push_back(std::move(scene));
  }
  return out;
}

class Bench {
 public:
  explicit Bench(const BenchArgs& args)
      : args_(args),
        registry_(plugin::Registry::default_search_paths()),
        samplers_(run::shipped_samplers(registry_)),
        robot_(std::make_shared<const robot::RobotDescription>(io::load_robot_description(args.robot))) {
    if (!args.csv.empty()) {
      csv_.open(args.csv);
      csv_ << "objects,initial_L,instance,run,solved,removed,time_s,task_s,motion_s,iterations,table,planner,scenes,"
              "sequences,seed,scene\n";
    }
  }

  const plugin::Samplers& samplers() const { return samplers_; }
  const std::shared_ptr<const robot::RobotDescription>& robot() const { return robot_; }
  /// The description the scenes named `scenes` are planned with, when not robot().
  void set_robot(const std::string& scenes, std::shared_ptr<const robot::RobotDescription> robot) {
    robots_[scenes] = std::move(robot);
  }

  void set_total(int runs) { total_ = runs; }

  static void header() {
    std::cout << std::left << std::setw(6) << "table" << std::setw(14) << "scenes" << std::setw(27) << "planner (L init)"
              << std::setw(13) << "|O_r|" << std::setw(13) << "paper" << std::setw(15) << "total s" << std::setw(8)
              << "median" << std::setw(8) << "p90" << std::setw(14) << "paper" << std::setw(14) << "task s" << std::setw(13) << "paper"
              << std::setw(14) << "motion s" << std::setw(14) << "paper" << std::setw(7) << "iter" << std::setw(6)
              << "paper" << std::setw(7) << "seqs" << std::setw(12) << "paper" << std::setw(8) << "success"
              << std::setw(7) << "paper" << "checks (median)\n";
  }

  void run(const Row& row) {
    Measured m;
    for (std::size_t i = 0; i < row.instances->size(); ++i) {
      for (int run = 0; run < args_.runs; ++run) measure(row, (*row.instances)[i], i, run, m);
    }
    if (args_.verbosity != Verbosity::quiet) std::cerr << "\r" << std::string(60, ' ') << "\r";
    print(row, m);
    measured_[{row.scenes, row.planner + "/" + row.initial_limit}] = std::move(m);
  }

  void write_json() const {
    if (!args_.json.empty()) write_json_file(args_.json, rows_);
  }

 private:
  void measure(const Row& row, const Scene& scene, std::size_t instance, int run, Measured& m) {
    Parameters parameters;
    if (!row.initial_limit.empty()) parameters.set("initial_L", row.initial_limit);
    const auto planner = registry_.create<plugin::TaskPlanner>(row.planner, parameters);
    const std::uint64_t seed = args_.seed + static_cast<std::uint64_t>(run);
    const auto t0 = std::chrono::steady_clock::now();
    const auto fitted = robots_.find(row.scenes);
    const Result r = run::plan_scene(scene, fitted == robots_.end() ? robot_ : fitted->second, *planner, samplers_, seed,
                                     args_.time_limit);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    ++m.runs;
    m.checks.push_back(double(counter(r, counter::collision_checks)));
    for (const auto& [name, totals] : r.phases) {
      PhaseTotals& sum = m.phases[name];
      sum.calls += totals.calls;
      sum.collision_checks += totals.collision_checks;
      sum.seconds += totals.seconds;
    }
    if (!r.solved) ++m.failures[r.reason];
    if (r.solved) {
      ++m.solved;
      m.removed.push_back(double(r.moved_objects.size()));
      m.removed_by_run[{instance, run}] = double(r.moved_objects.size());
      m.total.push_back(seconds);
      m.task.push_back(r.time.task_planning);
      m.motion.push_back(r.time.motion_planning);
      if (r.counters.count(counter::iterations)) m.iterations.push_back(double(counter(r, counter::iterations)));
      if (r.counters.count(counter::planning_sequences)) m.sequences.push_back(double(counter(r, counter::planning_sequences)));
    }
    if (csv_.is_open()) {
      csv_ << row.objects << "," << row.initial_limit << "," << instance << "," << run << "," << r.solved << ","
           << r.moved_objects.size() << "," << seconds << "," << r.time.task_planning << "," << r.time.motion_planning
           << "," << counter(r, counter::iterations) << "," << row.table << "," << row.planner << "," << row.scenes << ","
           << counter(r, counter::planning_sequences) << "," << seed << "," << csv_field(scene.name) << "\n";
    }
    ++done_;
    if (args_.verbosity != Verbosity::quiet) {
      const int bar = total_ ? 30 * done_ / total_ : 30;
      std::cerr << "\r[" << std::string(static_cast<std::size_t>(bar), '#') << std::string(static_cast<std::size_t>(30 - bar), ' ')
                << "] " << done_ << "/" << total_ << " table " << row.table << " " << row.planner << std::flush;
    }
  }

  void print(const Row& row, const Measured& m) {
    const double success = m.runs ? 100.0 * m.solved / m.runs : 0.0;
    const std::string name = row.planner + (row.initial_limit.empty() ? "" : " (" + row.initial_limit + ")");
    auto number = [](double v, int digits) {
      if (std::isnan(v)) return std::string("-");
      char out[32];
      std::snprintf(out, sizeof out, "%.*f", digits, v);
      return std::string(out);
    };
    const Figure iterations = of(m.iterations);
    std::cout << std::left << std::setw(6) << row.table << std::setw(14) << row.scenes << std::setw(27) << name
              << std::setw(13) << text(of(m.removed)) << std::setw(13) << text(row.paper.removed) << std::setw(15)
              << text(of(m.total)) << std::setw(8) << number(m.total.empty() ? kNone : median(m.total), 2) << std::setw(8)
              << number(m.total.empty() ? kNone : percentile(m.total, 90), 2) << std::setw(14)
              << text(row.paper.total) << std::setw(14) << text(of(m.task)) << std::setw(13) << text(row.paper.task)
              << std::setw(14) << text(of(m.motion)) << std::setw(14) << text(row.paper.motion) << std::setw(7)
              << number(iterations.mean, 2) << std::setw(6) << number(row.paper.iterations.mean, 2) << std::setw(7)
              << number(of(m.sequences).mean, 2) << std::setw(12) << text(row.paper.sequences) << std::setw(8)
              << number(success, 0) << std::setw(7) << number(row.paper.success, 0)
              << number(m.checks.empty() ? kNone : median(m.checks), 0) << std::endl;
    print_phases(m);
    for (const auto& [reason, count] : m.failures) std::cout << "      failed " << count << "x: " << reason << "\n";
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
    const auto baseline = measured_.find({row.scenes, baseline_of(row.table) + "/"});
    if (row.planner == "retrieval_graph" && baseline != measured_.end()) {
      const Paired p = paired(m, baseline->second);
      std::cout << "      paired with " << baseline_of(row.table) << " on the " << p.runs << " runs both solved: |O_r| "
                << number(p.removed, 2) << " against " << number(p.baseline_removed, 2);
      if (p.runs > 0) {
        const double more = 100.0 * (p.removed / p.baseline_removed - 1.0);
        std::cout << " (" << (more >= 0 ? "+" : "") << number(more, 1) << " %)";
      }
      std::cout << std::endl;
      pair = {{"against", baseline_of(row.table)}, {"runs", p.runs},
              {"removed", p.runs ? nlohmann::ordered_json(p.removed) : nlohmann::ordered_json(nullptr)},
              {"against_removed", p.runs ? nlohmann::ordered_json(p.baseline_removed) : nlohmann::ordered_json(nullptr)}};
    }
    rows_.push_back({{"table", row.table},
                     {"scenes", row.scenes},
                     {"objects", row.objects},
                     {"planner", row.planner},
                     {"initial_L", row.initial_limit.empty() ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(row.initial_limit)},
                     {"instances", row.instances->size()},
                     {"runs", args_.runs},
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
                       {"success", std::isnan(row.paper.success) ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(row.paper.success)}}}});
  }

  // Per run, every phase's time and collision checks (the motion planner's by how each
  // query ended), most checks first: where the time went, without a profiler.
  void print_phases(const Measured& m) const {
    if (m.runs == 0 || m.phases.empty()) return;
    std::vector<std::pair<std::string, PhaseTotals>> sorted(m.phases.begin(), m.phases.end());
    std::stable_sort(sorted.begin(), sorted.end(),
                     [](const auto& a, const auto& b) { return a.second.collision_checks > b.second.collision_checks; });
    std::cout << "      per run:";
    for (const auto& [name, t] : sorted) {
      char out[128];
      std::snprintf(out, sizeof out, " %s %.1fx %.3fs %.0fk;", name.c_str(), double(t.calls) / m.runs, t.seconds / m.runs,
                    double(t.collision_checks) / m.runs / 1000.0);
      std::cout << out;
    }
    std::cout << "\n";
  }

  static nlohmann::ordered_json phases_json(const Measured& m) {
    nlohmann::ordered_json out = nlohmann::ordered_json::object();
    for (const auto& [name, t] : m.phases) {
      const double runs = std::max(1, m.runs);
      out[name] = {{"calls_per_run", double(t.calls) / runs},
                   {"collision_checks_per_run", double(t.collision_checks) / runs},
                   {"time_per_run_s", t.seconds / runs}};
    }
    return out;
  }

  const BenchArgs& args_;
  plugin::Registry registry_;
  plugin::Samplers samplers_;
  std::shared_ptr<const robot::RobotDescription> robot_;
  std::map<std::string, std::shared_ptr<const robot::RobotDescription>> robots_;
  std::ofstream csv_;
  nlohmann::ordered_json rows_ = nlohmann::ordered_json::array();
  std::map<std::pair<std::string, std::string>, Measured> measured_;  // (scenes, planner/initial_L) -> its runs
  int done_ = 0, total_ = 0;
};

}  // namespace

int retrieval(const BenchArgs& args) {
  Bench bench(args);
  const std::vector<std::string> tables = args.tables.empty() ? std::vector<std::string>{"I"} : args.tables;
  auto wants = [&](const std::string& t) { return std::find(tables.begin(), tables.end(), t) != tables.end(); };

  // Instances first (generating or loading can fail on bad input before any run).
  std::map<std::string, std::vector<Scene>> scenes;
  std::vector<Row> rows;
  try {
    if (wants("I")) {
      for (int n : args.sizes.empty() ? std::vector<int>{12, 16, 20} : args.sizes) {
        const std::string key = "shelf" + std::to_string(n);
        auto robot = bench.robot();
        scenes[key] = generated(n, args, robot, bench.samplers());
        bench.set_robot(key, robot);
        for (const std::string strategy : {"one", "nodecol", "objects"}) {
          const Paper p = kTableI.count({n, strategy}) ? kTableI.at({n, strategy}) : Paper{};
          rows.push_back({"I", key, "retrieval_graph", strategy, n, nullptr, p});
        }
        rows.push_back({"I", key, "traversability_graph", "", n, nullptr, {}});
      }
    }
    if (wants("V")) {
      auto robot = bench.robot();
      scenes["shelf100"] = generated(100, args, robot, bench.samplers(), args.table_v_width);
      bench.set_robot("shelf100", robot);
      rows.push_back({"V", "shelf100", "traversability_graph", "", 100, nullptr, kTableVNam});
      rows.push_back({"V", "shelf100", "retrieval_graph", "one", 100, nullptr, kTableVOurs});
    }
    if (wants("VI")) {
      for (const auto& [minimum, paper] : kTableVI) {
        const std::string key = "shelf16-min" + std::to_string(minimum);
        scenes[key] = {io::load_scene(args.table_vi_scenes / (key + ".yaml"))};
        rows.push_back({"VI", key, "exhaustive", "", 16, nullptr, paper.first});
        rows.push_back({"VI", key, "retrieval_graph", "one", 16, nullptr, paper.second});
      }
    }
  } catch (const std::runtime_error& e) {
    if (dynamic_cast<const InputError*>(&e)) throw;
    std::cerr << "bench retrieval: " << e.what() << "\n";
    return run::ExitCode::bad_input;
  }
  if (!args.planners.empty()) {
    std::erase_if(rows, [&](const Row& row) {
      return std::find(args.planners.begin(), args.planners.end(), row.planner) == args.planners.end();
    });
  }
  int total = 0;
  for (Row& row : rows) {
    row.instances = &scenes[row.scenes];
    total += static_cast<int>(row.instances->size()) * args.runs;
  }
  bench.set_total(total);
  Bench::header();
  for (const Row& row : rows) bench.run(row);
  bench.write_json();
  return run::ExitCode::solved;
}

}  // namespace cluttertamp::bench
