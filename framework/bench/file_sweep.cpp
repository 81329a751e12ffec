// `cluttertamp bench sweep FILE`: every problem of a sweep file with every planner of
// its grid and every seed, as a sweep (shards, -j, records, merge).
#include <algorithm>
#include <iomanip>
#include <iostream>
#include <map>
#include <memory>
#include <optional>
#include <sstream>

#include <nlohmann/json.hpp>

#include "bench/json_file.hpp"
#include "bench/ompl_log.hpp"
#include "bench/reports.hpp"
#include "bench/settings.hpp"
#include "bench/statistics.hpp"
#include "bench/svg_plot.hpp"
#include "bench/sweep.hpp"
#include "cluttertamp/bench/bench.hpp"
#include "cluttertamp/io/problem_io.hpp"
#include "cluttertamp/io/sweep_file.hpp"
#include "cluttertamp/io/text_file.hpp"
#include "cluttertamp/plugin/registry.hpp"
#include "cluttertamp/run/runner.hpp"
#include "cluttertamp/version.hpp"

namespace cluttertamp::bench {

namespace fs = std::filesystem;

namespace {

// Run i of the sweep: problem, then planner, then seed.
struct FileRef {
  std::size_t problem = 0, planner = 0, seed = 0;
};
FileRef ref_of(std::size_t i, const io::SweepSpec& spec) {
  const std::size_t per_problem = spec.planners.size() * spec.seeds.size();
  return {i / per_problem, (i % per_problem) / spec.seeds.size(), i % spec.seeds.size()};
}

// `problem` planned by `planner`: with the problem's own planner parameters when the
// plugin is the same, the sweep's over them.
Problem with_planner(Problem problem, const io::SweepPlanner& planner) {
  Parameters parameters = problem.planner.name == planner.plugin ? problem.planner.parameters : Parameters{};
  for (const std::string& key : planner.parameters.keys()) parameters.set(key, *planner.parameters.get(key));
  problem.planner = PluginChoice{planner.plugin, parameters, planner.where};
  return problem;
}

// The sweep as the records' settings carry it, so that shards of a changed file never merge.
nlohmann::ordered_json spec_json(const io::SweepSpec& spec) {
  nlohmann::ordered_json planners = nlohmann::ordered_json::array();
  for (const io::SweepPlanner& p : spec.planners) {
    planners.push_back({{"label", p.label}, {"plugin", p.plugin}, {"parameters", p.parameters.to_yaml()}});
  }
  nlohmann::ordered_json problems = nlohmann::ordered_json::array();
  for (const fs::path& p : spec.problems) problems.push_back(p.string());
  return {{"problems", problems},
          {"planners", planners},
          {"seeds", spec.seeds},
          {"time_limit", spec.time_limit ? nlohmann::ordered_json(*spec.time_limit) : nlohmann::ordered_json(nullptr)}};
}

// Every problem loads and every planner of the sweep is created for it, before any
// run: a misspelt plugin or parameter is bad input at once, whichever shard meets it.
void check_plugins(const io::SweepSpec& spec) {
  Diagnostics errors;
  for (const fs::path& file : spec.problems) {
    const io::ProblemReading reading = io::read_problem(file, errors);
    if (!reading.whole) continue;
    const plugin::Registry registry(run::plugin_search_paths(reading.problem, {}));
    for (const io::SweepPlanner& planner : spec.planners) {
      run::create_plugins(with_planner(reading.problem, planner), registry, errors, run::ProblemPart::whole);
    }
  }
  errors.throw_if_any();
}

// Plans the runs it is given, loading each problem once.
class FileRunner {
 public:
  explicit FileRunner(const io::SweepSpec& spec) : spec_(spec) {}

  Record run(const FileRef& ref) {
    if (!loaded_ || loaded_->index != ref.problem) {
      loaded_.reset();  // the registry goes after every plugin object of the last problem
      auto l = std::make_unique<Loaded>();
      l->index = ref.problem;
      l->problem = io::load_problem(spec_.problems.at(ref.problem));
      l->registry = std::make_unique<plugin::Registry>(run::plugin_search_paths(l->problem, {}));
      loaded_ = std::move(l);
    }
    const io::SweepPlanner& planner = spec_.planners.at(ref.planner);
    run::RunOptions options;
    options.seed = spec_.seeds.at(ref.seed);
    options.time_limit = spec_.time_limit;
    const run::RunOutcome outcome = run::plan(with_planner(loaded_->problem, planner), *loaded_->registry, options);
    const Result& r = outcome.result;
    return {{"problem", loaded_->problem.name},
            {"problem_file", spec_.problems[ref.problem].string()},
            {"planner", planner.label},
            {"plugin", planner.plugin},
            {"parameters", planner.parameters.to_yaml()},
            {"seed", *options.seed},
            {"solved", r.solved},
            {"exit_code", outcome.info.exit_code},
            {"time_s", r.time.total},
            {"task_s", r.time.task_planning},
            {"motion_s", r.time.motion_planning},
            {"removed", r.moved_objects.size()},
            {"steps", r.plan.size()},
            {"counters", r.counters},
            {"reason", r.reason},
            {"version", std::string(version())}};
  }

 private:
  struct Loaded {
    std::size_t index = 0;
    Problem problem;
    std::unique_ptr<plugin::Registry> registry;
  };
  const io::SweepSpec& spec_;
  std::unique_ptr<Loaded> loaded_;
};

// One row of the report: a problem with one planner, over the seeds.
struct Row {
  std::string problem, planner;
  std::vector<const Record*> runs;
  std::size_t solved() const {
    return static_cast<std::size_t>(std::count_if(runs.begin(), runs.end(), [](const Record* r) { return r->at("solved").get<bool>(); }));
  }
  double success() const { return runs.empty() ? 0.0 : 100.0 * double(solved()) / double(runs.size()); }
  std::vector<double> solved_values(const char* key) const {
    std::vector<double> out;
    for (const Record* r : runs) {
      if (r->at("solved").get<bool>()) out.push_back(number(*r, key));
    }
    return out;
  }
};

// Rows in the order of the runs (problem by problem, planner by planner).
std::vector<Row> rows_of(const std::vector<Record>& records) {
  std::vector<Row> rows;
  std::map<std::pair<std::string, std::string>, std::size_t> index;
  for (const Record& r : records) {
    const auto key = std::make_pair(r.at("problem_file").get<std::string>(), r.at("planner").get<std::string>());
    const auto [at, added] = index.emplace(key, rows.size());
    if (added) rows.push_back({r.at("problem").get<std::string>(), key.second, {}});
    rows[at->second].runs.push_back(&r);
  }
  return rows;
}

std::string clipped(const std::string& text, std::size_t width) {
  return text.size() < width ? text : text.substr(0, width - 2) + "~";
}

// Success rate and the times of solved runs (box plots, unsolved runs as red crosses)
// per row, rows numbered under the axes and named in a key below.
void write_svg(const fs::path& file, const std::vector<Row>& rows) {
  const double left = 70, slot = 46, panel_h = 160, top = 40, line = 15;
  const double panel_w = std::max(300.0, slot * double(rows.size()));
  SvgPlot plot(2 * (left + panel_w) + 30, top + panel_h + 60 + line * double(rows.size()));
  std::vector<double> times;
  for (const Row& row : rows) {
    const std::vector<double> t = row.solved_values("time_s");
    times.insert(times.end(), t.begin(), t.end());
  }
  const SvgPlot::Panel rate = plot.panel(left, top, panel_w, panel_h, 100, "success rate", "%");
  const SvgPlot::Panel time = plot.panel_for(2 * left + panel_w, top, panel_w, panel_h, times, "planning time of solved runs, s");
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const Row& row = rows[k];
    const double offset = slot * (double(k) + 0.5), w = slot * 0.6;
    plot.bar(rate, rate.left + offset - w / 2, w, row.success(), series_colour(k));
    plot.box(time, time.left + offset, w, row.solved_values("time_s"), series_colour(k));
    plot.unsolved(time, time.left + offset, static_cast<int>(row.runs.size() - row.solved()));
    for (const SvgPlot::Panel* p : {&rate, &time}) plot.x_label(*p, p->left + offset, std::to_string(k + 1));
    plot.text(left, top + panel_h + 55 + line * double(k), std::to_string(k + 1) + ": " + row.problem + " / " + row.planner);
  }
  plot.legend(2 * left + panel_w, top + panel_h + 40, "cross", "unsolved runs (count)");
  plot.write(file);
}

void write_csv(const fs::path& file, const std::vector<Record>& records) {
  std::ostringstream csv;
  csv << "problem,planner,seed,solved,exit_code,time_s,removed,steps,reason\n";
  for (const Record& r : records) {
    csv << csv_field(r.at("problem").get<std::string>()) << ',' << csv_field(r.at("planner").get<std::string>()) << ','
        << r.at("seed").get<std::uint64_t>() << ',' << (r.at("solved").get<bool>() ? 1 : 0) << ',' << r.at("exit_code").get<int>()
        << ',' << number(r, "time_s") << ',' << r.at("removed").get<std::size_t>() << ',' << r.at("steps").get<std::size_t>() << ','
        << csv_field(r.at("reason").get<std::string>()) << "\n";
  }
  io::write_text_file(file, csv.str(), "CSV file");
}

}  // namespace

int file_sweep(const BenchArgs& given) {
  const BenchArgs args = with_absolute_paths(given);
  const io::SweepSpec spec = io::load_sweep_file(args.sweep_file);
  check_plugins(spec);
  nlohmann::ordered_json settings = settings_of(args);
  settings["sweep"] = spec_json(spec);
  const SweepPlan plan{"sweep", settings, spec.runs(), [&](std::size_t i) {
                         const FileRef ref = ref_of(i, spec);
                         return spec.problems[ref.problem].stem().string() + ", " + spec.planners[ref.planner].label + ", seed " +
                                std::to_string(spec.seeds[ref.seed]);
                       }};
  return run_and_report(
      plan, args, [&] { return std::make_unique<FileRunner>(spec); },
      [&](FileRunner& runner, std::size_t i) { return runner.run(ref_of(i, spec)); }, report_file_sweep);
}

int report_file_sweep(const BenchArgs& args, const std::vector<Record>& records) {
  const std::vector<Row> rows = rows_of(records);
  std::cout << "Sweep " << args.sweep_file.string() << ": " << records.size() << " runs\n\n"
            << std::left << std::setw(18) << "problem" << std::setw(37) << "planner" << std::right << std::setw(6) << "runs"
            << std::setw(9) << "success" << std::setw(11) << "median s" << std::setw(11) << "mean |O_r|" << std::setw(7) << "steps"
            << "\n";
  nlohmann::ordered_json json_rows = nlohmann::ordered_json::array();
  bool all_solved = true;
  for (const Row& row : rows) {
    const std::vector<double> times = row.solved_values("time_s"), removed = row.solved_values("removed"),
                              steps = row.solved_values("steps");
    all_solved = all_solved && row.solved() == row.runs.size();
    std::cout << std::left << std::setw(18) << clipped(row.problem, 18) << std::setw(37) << clipped(row.planner, 37) << std::right
              << std::setw(6) << row.runs.size() << std::setw(9) << (fixed(row.success(), 0) + "%") << std::setw(11)
              << (times.empty() ? "-" : fixed(median(times), 3)) << std::setw(11) << (removed.empty() ? "-" : fixed(mean(removed)))
              << std::setw(7) << (steps.empty() ? "-" : fixed(mean(steps), 1)) << "\n";
    json_rows.push_back({{"problem", row.problem},
                         {"problem_file", row.runs.front()->at("problem_file")},
                         {"planner", row.planner},
                         {"plugin", row.runs.front()->at("plugin")},
                         {"parameters", row.runs.front()->at("parameters")},
                         {"runs", row.runs.size()},
                         {"solved", row.solved()},
                         {"success_rate", row.success() / 100},
                         {"time_median_s", times.empty() ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(median(times))},
                         {"time_mean_s", times.empty() ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(mean(times))},
                         {"removed_mean", removed.empty() ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(mean(removed))},
                         {"steps_mean", steps.empty() ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(mean(steps))}});
  }
  std::cout << "\nMedian time, |O_r| (objects moved) and steps are over solved runs.\n";
  if (!args.csv.empty()) write_csv(args.csv, records);
  if (!args.json.empty()) {
    write_json_file(args.json, nlohmann::ordered_json{{"bench", "sweep"}, {"file", args.sweep_file.string()}, {"runs", records.size()},
                                                      {"rows", json_rows}});
  }
  if (!args.svg.empty()) write_svg(args.svg, rows);
  if (!args.ompl_log.empty()) {
    std::vector<OmplLogPlanner> planners;
    for (const Row& row : rows) planners.push_back({row.problem + "/" + row.planner, row.runs});
    write_ompl_log(args.ompl_log, {"cluttertamp_bench_sweep", settings_of(args).dump(2), 0, 0}, planners);
  }
  return goal_exit_code(args.check_goals, all_solved);
}

}  // namespace cluttertamp::bench
