// `cluttertamp compare`: the stream search focused and unfocused (Tian et al., Section
// V-C, Table IV): {adaptive, incremental} x {pruned by the object pruner, all objects
// movable} on each problem, with N seeds each; a sweep like the benches.

#include <algorithm>
#include <cstdio>
#include <iomanip>
#include <iostream>
#include <map>
#include <memory>
#include <optional>
#include <sstream>

#include <nlohmann/json.hpp>

#include "bench/json_file.hpp"
#include "bench/ompl_log.hpp"
#include "bench/prose.hpp"
#include "bench/reports.hpp"
#include "bench/settings.hpp"
#include "bench/sweep.hpp"
#include "cluttertamp/io/text_file.hpp"
#include "cluttertamp/version.hpp"
#include "cluttertamp/bench/bench.hpp"
#include "bench/statistics.hpp"
#include "bench/svg_plot.hpp"
#include "bench/table_plot.hpp"
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
  std::uint64_t seed = 0;
};

struct Row {
  std::string problem, file;
  std::size_t objects = 0;
  Setting setting;
  std::vector<Run> runs;
};

// The paper's Table IV (mean planning time, s): with pruning ("Our Method +
// PDDLStream") and without (PDDLStream), for the 4- and 8-object scenes. The 8-object
// run without pruning did not finish: its 120 s is a lower bound.
struct PaperTime {
  double seconds;
  bool lower_bound = false;
};
std::optional<PaperTime> paper_time_of(std::size_t objects, bool prune) {
  if (objects == 4) return prune ? PaperTime{25.31} : PaperTime{33.65};
  if (objects == 8) return prune ? PaperTime{28.82} : PaperTime{120, true};
  return std::nullopt;
}
std::string paper_time(std::size_t objects, bool prune) {
  const auto paper = paper_time_of(objects, prune);
  if (!paper) return "-";
  return paper->lower_bound ? ">" + fixed(paper->seconds, 0) : fixed(paper->seconds, 2);
}

std::uint64_t counter(const Record& r, const char* name) {
  const auto& counters = r.at("counters");
  return counters.contains(name) ? counters[name].get<std::uint64_t>() : 0;
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

std::size_t setting_index(const Setting& setting) {
  for (std::size_t s = 0; s < std::size(kSettings); ++s) {
    if (kSettings[s].label() == setting.label()) return s;
  }
  return 0;
}

// Per problem a column per setting: success, |O_r| and times of the solved runs, the
// paper's mean time (Table IV) as a diamond where the table prints it.
void write_svg(const std::vector<Row>& rows, const std::filesystem::path& file) {
  TablePlot table{"Table IV (Tian et al., T-RO 2023): the stream search focused and unfocused, ours beside the paper's", "|O_r|, solved runs", {}, {}};
  std::vector<bool> present(std::size(kSettings), false);
  for (const Row& r : rows) {
    if (table.groups.empty() || table.groups.back().label != r.problem) table.groups.push_back({r.problem, {}});
    const std::size_t s = setting_index(r.setting);
    present[s] = true;
    PlotColumn column{series_colour(s), success(r), field(r, &Run::moved), field(r, &Run::seconds), 0, {}, {}, {}, {}};
    for (const Run& run : r.runs) column.unsolved += !run.solved;
    if (const auto paper = paper_time_of(r.objects, r.setting.prune)) {
      column.paper_seconds = paper->seconds;
      if (paper->lower_bound) column.paper_seconds_note = "> " + fixed(paper->seconds, 0);
    }
    table.groups.back().columns.push_back(std::move(column));
  }
  for (std::size_t s = 0; s < std::size(kSettings); ++s) {
    if (present[s]) table.series.emplace_back(series_colour(s), kSettings[s].label());
  }
  write_table_svg(file, {table});
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

void write_csv(const std::filesystem::path& file, const std::vector<Row>& rows) {
  std::ostringstream csv;
  csv << "problem,objects,algorithm,pruned,seed,solved,time_s,stream_calls,motion_planning_calls,plan_length,objects_moved,reason\n";
  for (const Row& row : rows) {
    for (const Run& run : row.runs) {
      csv << row.problem << ',' << row.objects << ',' << row.setting.algorithm << ',' << row.setting.prune << ',' << run.seed << ','
          << run.solved << ',' << run.seconds << ',' << run.stream_calls << ',' << run.motion_calls << ',' << run.plan_length << ','
          << run.moved << ',' << csv_text(run.reason) << '\n';
    }
  }
  io::write_text_file(file, csv.str(), "CSV file");
}

// The comparison's problems, loaded (each process of a sweep loads them all: cheap).
std::vector<Problem> load_problems(const BenchArgs& args) {
  std::vector<Problem> problems;
  for (std::size_t p = 0; p < args.problems.size(); ++p) {
    problems.push_back(io::load_problem(args.problems[p]));
    if (!std::holds_alternative<PddlTask>(problems.back().task)) {
      throw InputError({args.problems[p].string(), 0, 0}, "compare needs a problem with task: pddl (a stream problem)");
    }
  }
  return problems;
}

// A row of the comparison: a problem with a setting. Pruning chooses among a scene's
// objects; a PDDL problem file fixes its facts, so it has no pruned rows.
struct RowRef {
  std::size_t problem = 0, setting = 0;
};
std::vector<RowRef> rows_of(const std::vector<Problem>& problems) {
  std::vector<RowRef> rows;
  for (std::size_t p = 0; p < problems.size(); ++p) {
    const bool scene_facts = !std::get<PddlTask>(problems[p].task).problem;
    for (std::size_t s = 0; s < std::size(kSettings); ++s) {
      if (scene_facts || !kSettings[s].prune) rows.push_back({p, s});
    }
  }
  return rows;
}

// Plans the runs it is given: run i is row i / runs, seed seed + i % runs.
class CompareRunner {
 public:
  CompareRunner(const BenchArgs& args, std::vector<Problem> problems, std::vector<RowRef> rows)
      : args_(args), problems_(std::move(problems)), rows_(std::move(rows)) {}

  Record run(std::size_t i) {
    const RowRef& ref = rows_.at(i / static_cast<std::size_t>(args_.runs));
    const Setting& setting = kSettings[ref.setting];
    const Problem& given = problems_[ref.problem];
    run::RunOptions options;
    if (args_.time_limit > 0) options.time_limit = args_.time_limit;
    options.plugin_paths = args_.plugin_paths;
    options.seed = args_.seed + static_cast<std::uint64_t>(i % static_cast<std::size_t>(args_.runs));
    if (!registry_ || registry_problem_ != ref.problem) {
      registry_ = std::make_unique<plugin::Registry>(run::plugin_search_paths(given, options));
      registry_problem_ = ref.problem;
    }
    // The problem's own stream_planner parameters stay (stream options, polish); the
    // setting decides the algorithm and pruning.
    Problem problem = given;
    problem.planner.name = "stream_planner";
    problem.planner.parameters = given.planner.name == "stream_planner" ? given.planner.parameters.fresh() : Parameters{};
    problem.planner.parameters.set("algorithm", setting.algorithm);
    problem.planner.parameters.set("trace", false);  // a line per iteration would bury the table
    problem.planner.parameters.set("prune", setting.prune);
    const run::RunOutcome outcome = run::plan(problem, *registry_, options);
    const Result& r = outcome.result;
    return {{"problem", given.name},
            {"problem_file", args_.problems[ref.problem].string()},
            {"objects", given.scene.objects.size()},
            {"planner", "stream_planner"},
            {"parameters", {{"algorithm", setting.algorithm}, {"prune", setting.prune}}},
            {"seed", *options.seed},
            {"solved", r.solved},
            {"time_s", r.time.total},
            {"task_s", r.time.task_planning},
            {"motion_s", r.time.motion_planning},
            {"removed", r.moved_objects.size()},
            {"steps", r.plan.size()},
            {"counters", r.counters},
            {"reason", r.solved ? std::string() : r.reason.substr(0, r.reason.find('\n'))},
            {"version", std::string(version())}};
  }

 private:
  const BenchArgs& args_;
  std::vector<Problem> problems_;
  std::vector<RowRef> rows_;
  std::unique_ptr<plugin::Registry> registry_;
  std::size_t registry_problem_ = 0;
};

// The rows of the records, in the order of the runs.
std::vector<Row> rows_of(const std::vector<Record>& records) {
  std::vector<Row> rows;
  for (const Record& r : records) {
    const Setting setting{r.at("parameters").at("algorithm").get<std::string>(), r.at("parameters").at("prune").get<bool>()};
    const std::string file = r.at("problem_file").get<std::string>();
    if (rows.empty() || rows.back().file != file || rows.back().setting.label() != setting.label()) {
      rows.push_back({r.at("problem").get<std::string>(), file, r.at("objects").get<std::size_t>(), setting, {}});
    }
    rows.back().runs.push_back({r.at("solved").get<bool>(), number(r, "time_s"), counter(r, counter::stream_calls),
                                counter(r, counter::motion_planning_calls), r.at("steps").get<std::uint64_t>(),
                                r.at("removed").get<std::uint64_t>(), r.at("reason").get<std::string>(),
                                r.at("seed").get<std::uint64_t>()});
  }
  return rows;
}

}  // namespace

int compare(const CompareArgs& given) {
  BenchArgs args;
  args.what = "compare";
  args.problems = given.problems;
  args.runs = given.runs;
  args.seed = given.seed;
  args.time_limit = given.time_limit.value_or(0.0);
  args.plugin_paths = given.plugin_paths;
  args.json = given.json.value_or("");
  args.csv = given.csv.value_or("");
  args.svg = given.svg.value_or("");
  args.ompl_log = given.ompl_log;
  args.verbosity = given.verbosity;
  args.check_goals = given.check_goals;
  args.sweep = given.sweep;
  return compare_runs(args);
}

int compare_runs(const BenchArgs& given) {
  const BenchArgs args = with_absolute_paths(given);
  std::vector<Problem> problems = load_problems(args);
  std::vector<RowRef> rows = rows_of(problems);
  const std::size_t runs = static_cast<std::size_t>(args.runs);
  const SweepPlan plan{"compare", settings_of(args), rows.size() * runs, [&](std::size_t i) {
                         const RowRef& ref = rows.at(i / runs);
                         return problems[ref.problem].name + ": " + kSettings[ref.setting].label() + ", seed " +
                                std::to_string(args.seed + i % runs);
                       }};
  return run_and_report(
      plan, args, [&] { return std::make_unique<CompareRunner>(args, problems, rows); },
      [](CompareRunner& runner, std::size_t i) { return runner.run(i); }, report_compare);
}

int report_compare(const BenchArgs& args, const std::vector<Record>& records) {
  const std::vector<Row> rows = rows_of(records);
  int name_width = 12;  // the longest problem name and a space
  for (const Row& r : rows) name_width = std::max(name_width, static_cast<int>(r.problem.size()) + 1);
  std::cout << std::left << std::setw(name_width) << "problem" << std::setw(25) << "setting" << std::setw(8) << "success"
            << std::setw(14) << "mean(std) s" << std::setw(7) << "paper" << std::setw(8) << "streams" << std::setw(7) << "motion"
            << std::setw(6) << "steps" << "moved\n";
  nlohmann::json json = nlohmann::json::array();
  for (const Row& r : rows) {
    const auto t = field(r, &Run::seconds);
    const std::string mean_std = fixed(mean(t)) + "(" + fixed(stddev(t)) + ")";
    std::cout << std::left << std::setw(name_width) << r.problem << std::setw(25) << r.setting.label() << std::setw(8)
              << (fixed(success(r), 0) + "%") << std::setw(14) << mean_std << std::setw(7) << paper_time(r.objects, r.setting.prune)
              << std::setw(8) << fixed(mean(field(r, &Run::stream_calls)), 1) << std::setw(7)
              << fixed(mean(field(r, &Run::motion_calls)), 1) << std::setw(6) << fixed(mean(field(r, &Run::plan_length)), 1)
              << fixed(mean(field(r, &Run::moved)), 1) << "\n";
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
  std::cout << wrapped("Times of solved runs (medians in the JSON); paper: Tian et al. Table IV, mean time (its 4- and 8-object scenes).");
  if (!args.csv.empty()) write_csv(args.csv, rows);
  if (!args.json.empty()) write_json_file(args.json, json);
  if (!args.svg.empty()) write_svg(rows, args.svg);
  if (!args.ompl_log.empty()) {
    std::vector<OmplLogPlanner> planners;
    for (const Row& row : rows) {
      OmplLogPlanner p{row.problem + "/stream_planner[algorithm=" + row.setting.algorithm + ",prune=" + (row.setting.prune ? "true" : "false") + "]", {}};
      for (const Record& r : records) {
        if (r.at("problem_file") == row.file && r.at("parameters").at("algorithm") == row.setting.algorithm &&
            r.at("parameters").at("prune") == row.setting.prune) {
          p.runs.push_back(&r);
        }
      }
      planners.push_back(std::move(p));
    }
    write_ompl_log(args.ompl_log, {"cluttertamp_compare", settings_of(args).dump(2), args.seed, args.time_limit}, planners);
  }
  bool all = true;
  for (const Row& r : rows) all = all && success(r) == 100.0;
  return goal_exit_code(args.check_goals, all);
}

}  // namespace cluttertamp::bench
