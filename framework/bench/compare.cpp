// `cluttertamp compare`: the stream search focused and unfocused (Tian et al., Section
// V-C, Table IV): {adaptive, incremental} x {pruned by the object pruner, all objects
// movable} on each problem, with N seeds each.

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <sstream>

#include <nlohmann/json.hpp>

#include "bench/json_file.hpp"
#include "bench/sweep.hpp"
#include "cluttertamp/bench/bench.hpp"
#include "bench/statistics.hpp"
#include "bench/svg_plot.hpp"
#include "cluttertamp/io/problem_io.hpp"
#include "cluttertamp/plugin/registry.hpp"
#include "cluttertamp/run/runner.hpp"

namespace cluttertamp::bench {

namespace {

struct Setting {
  std::string algorithm;
  bool prune = false;
  std::string label() const { return algorithm + (prune ? " + pruning" : ", all movable"); }
};

const Setting kSettings[] = {{"adaptive", true}, {"adaptive", false}, {"incremental", true}, {"incremental", false}};

struct Run {
  bool solved = false;
  double seconds = 0;
  std::uint64_t stream_calls = 0, motion_calls = 0, plan_length = 0, moved = 0;
  std::string reason;  ///< why not solved (first line)
};

struct Row {
  std::string problem;
  std::size_t objects = 0;
  Setting setting;
  std::vector<Run> runs;
};

// The paper's Table IV (mean planning time, s): with pruning ("Our Method +
// PDDLStream") and without (PDDLStream), for the 4- and 8-object scenes.
std::string paper_time(std::size_t objects, bool prune) {
  if (objects == 4) return prune ? "25.31" : "33.65";
  if (objects == 8) return prune ? "28.82" : ">120";
  return "-";
}

std::uint64_t counter(const Result& r, const char* name) {
  const auto it = r.counters.find(name);
  return it == r.counters.end() ? 0 : it->second;
}

// A measure of the runs (solved ones only, unless asked), as numbers.
template <class T>
std::vector<double> field(const Row& row, T Run::*member, bool solved_only = true) {
  std::vector<double> out;
  for (const Run& r : row.runs) {
    if (!solved_only || r.solved) out.push_back(static_cast<double>(r.*member));
  }
  return out;
}

double success(const Row& row) {
  std::size_t n = 0;
  for (const Run& r : row.runs) n += r.solved;
  return row.runs.empty() ? 0.0 : 100.0 * double(n) / double(row.runs.size());
}

// Time against object count, one line per setting: median time of all runs
// (failures count with the time limit they used).
void write_svg(const std::vector<Row>& rows, const std::filesystem::path& file) {
  const double left = 60, right = 190, top = 30, bottom = 50, w = 640, h = 400;
  double max_t = 1e-3, min_x = 1e9, max_x = 0;
  for (const Row& r : rows) {
    max_t = std::max(max_t, median(field(r, &Run::seconds, false)));
    min_x = std::min(min_x, double(r.objects));
    max_x = std::max(max_x, double(r.objects));
  }
  if (max_x <= min_x) max_x = min_x + 1;
  auto x = [&](double v) { return left + (v - min_x) / (max_x - min_x) * (w - left - right); };
  const char* colours[] = {"#1b9e77", "#d95f02", "#7570b3", "#e7298a"};
  SvgPlot plot(w, h, 12);
  const SvgPlot::Panel panel = plot.panel(left, top, w - left - right, h - top - bottom, max_t, "median time (s)", "");
  plot.text((left + w - right) / 2, h - 10, "objects", "middle");
  std::map<std::size_t, bool> ticks;
  for (const Row& r : rows) ticks[r.objects] = true;
  for (const auto& [n, unused] : ticks) plot.x_label(panel, x(double(n)), std::to_string(n));
  for (std::size_t s = 0; s < std::size(kSettings); ++s) {
    std::vector<std::pair<double, double>> points;
    for (const Row& r : rows) {
      if (r.setting.label() == kSettings[s].label()) points.emplace_back(x(double(r.objects)), median(field(r, &Run::seconds, false)));
    }
    plot.line(panel, points, colours[s]);
    plot.text(w - right + 10, top + 20 * double(s + 1), kSettings[s].label(), "start", colours[s]);
  }
  plot.write(file);
}

// Why the runs of a row failed: each distinct reason with its count.
std::map<std::string, int> reasons(const Row& row) {
  std::map<std::string, int> out;
  for (const Run& r : row.runs) {
    if (!r.solved) ++out[r.reason.empty() ? "(no reason given)" : r.reason];
  }
  return out;
}

void print_failures(const std::vector<Row>& rows) {
  bool header = false;
  for (const Row& r : rows) {
    for (const auto& [reason, count] : reasons(r)) {
      if (!header) std::cout << "Failed runs:\n";
      header = true;
      std::cout << "  " << r.problem << ", " << r.setting.label() << ": " << count << "x " << reason << "\n";
    }
  }
}

// A CSV field: quoted when it holds a comma, a quote or a line break.
std::string csv_text(const std::string& text) {
  if (text.find_first_of(",\"\n") == std::string::npos) return text;
  std::string out = "\"";
  for (char c : text) out += c == '"' ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

}  // namespace

int compare(const CompareArgs& args) {
  std::vector<Row> rows;
  std::size_t total = 0, done = 0;
  std::vector<Problem> problems;
  for (const auto& file : args.problems) problems.push_back(io::load_problem(file));
  total = problems.size() * std::size(kSettings) * static_cast<std::size_t>(args.runs);
  std::ofstream csv;
  if (args.csv) {
    csv.open(*args.csv);
    if (!csv) throw InputError({args.csv->string(), 0, 0}, "cannot write the CSV file");
    csv << "problem,objects,algorithm,pruned,seed,solved,time_s,stream_calls,motion_planning_calls,plan_length,objects_moved,reason\n";
  }
  for (std::size_t p = 0; p < problems.size(); ++p) {
    Problem problem = problems[p];
    if (!std::holds_alternative<PddlTask>(problem.task)) {
      throw InputError({args.problems[p].string(), 0, 0}, "compare needs a problem with task: pddl (a stream problem)");
    }
    problem.planner.name = "stream_planner";
    run::RunOptions options;
    options.time_limit = args.time_limit;
    options.plugin_paths = args.plugin_paths;
    const plugin::Registry registry(run::plugin_search_paths(problem, options));
    // Pruning chooses among a scene's objects; a PDDL problem file fixes its facts.
    const bool scene_facts = !std::get<PddlTask>(problem.task).problem;
    for (const Setting& setting : kSettings) {
      if (setting.prune && !scene_facts) {
        done += static_cast<std::size_t>(args.runs);
        continue;
      }
      Row row{problem.name, problem.scene.objects.size(), setting, {}};
      // The problem's own stream_planner parameters stay (stream options, polish); the
      // setting decides the algorithm and pruning.
      problem.planner.parameters = problems[p].planner.name == "stream_planner" ? problems[p].planner.parameters.fresh()
                                                                                : Parameters{};
      problem.planner.parameters.set("algorithm", setting.algorithm);
      problem.planner.parameters.set("trace", false);  // a line per iteration would bury the table
      problem.planner.parameters.set("prune", setting.prune);
      for (int k = 0; k < args.runs; ++k) {
        options.seed = args.seed + static_cast<std::uint64_t>(k);
        if (progress_shown(args.verbosity)) {
          std::cerr << "\r[" << ++done << "/" << total << "] " << problem.name << ": " << setting.label() << ", seed "
                    << *options.seed << "          " << std::flush;
        }
        const run::RunOutcome outcome = run::plan(problem, registry, options);
        const Result& r = outcome.result;
        Run run{r.solved, r.time.total, counter(r, counter::stream_calls), counter(r, counter::motion_planning_calls),
                r.plan.size(), r.moved_objects.size(), r.solved ? "" : r.reason.substr(0, r.reason.find('\n'))};
        row.runs.push_back(run);
        if (csv) {
          csv << problem.name << ',' << row.objects << ',' << setting.algorithm << ',' << setting.prune << ','
              << *options.seed << ',' << run.solved << ',' << run.seconds << ',' << run.stream_calls << ','
              << run.motion_calls << ',' << run.plan_length << ',' << run.moved << ',' << csv_text(run.reason) << '\n';
        }
      }
      rows.push_back(std::move(row));
    }
  }
  if (progress_shown(args.verbosity)) std::cerr << "\r" << std::string(70, ' ') << "\r";

  int name_width = 12;  // the longest problem name and a space
  for (const Row& r : rows) name_width = std::max(name_width, static_cast<int>(r.problem.size()) + 1);
  std::cout << std::left << std::setw(name_width) << "problem" << std::setw(27) << "setting" << std::setw(9) << "success"
            << std::setw(9) << "median" << std::setw(15) << "mean(std) s" << std::setw(8) << "paper" << std::setw(9)
            << "streams" << std::setw(8) << "motion" << std::setw(7) << "steps" << "moved\n";
  nlohmann::json json = nlohmann::json::array();
  for (const Row& r : rows) {
    const auto t = field(r, &Run::seconds);
    const std::string mean_std = fixed(mean(t)) + "(" + fixed(stddev(t)) + ")";
    std::cout << std::left << std::setw(name_width) << r.problem << std::setw(27) << r.setting.label() << std::setw(9)
              << (fixed(success(r), 0) + "%") << std::setw(9) << fixed(median(t)) << std::setw(15) << mean_std
              << std::setw(8) << paper_time(r.objects, r.setting.prune) << std::setw(9)
              << fixed(mean(field(r, &Run::stream_calls)), 1) << std::setw(8)
              << fixed(mean(field(r, &Run::motion_calls)), 1) << std::setw(7)
              << fixed(mean(field(r, &Run::plan_length)), 1) << fixed(mean(field(r, &Run::moved)), 1) << "\n";
    json.push_back({{"problem", r.problem},
                    {"objects", r.objects},
                    {"algorithm", r.setting.algorithm},
                    {"pruned", r.setting.prune},
                    {"runs", r.runs.size()},
                    {"success_rate", success(r) / 100.0},
                    {"time_s", {{"median", median(t)}, {"mean", mean(t)}, {"std", stddev(t)}}},
                    {"stream_calls_mean", mean(field(r, &Run::stream_calls))},
                    {"motion_planning_calls_mean", mean(field(r, &Run::motion_calls))},
                    {"plan_length_mean", mean(field(r, &Run::plan_length))},
                    {"objects_moved_mean", mean(field(r, &Run::moved))},
                    {"paper_mean_time_s", paper_time(r.objects, r.setting.prune)},
                    {"failure_reasons", reasons(r)}});
  }
  print_failures(rows);
  std::cout << "Times of solved runs; paper: Tian et al. Table IV, mean time (their 4- and 8-object scenes).\n";
  if (args.json) write_json_file(*args.json, json);
  if (args.svg) write_svg(rows, *args.svg);
  bool all = true;
  for (const Row& r : rows) all = all && success(r) == 100.0;
  return goal_exit_code(args.check_goals, all);
}

}  // namespace cluttertamp::bench
