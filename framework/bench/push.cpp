// `cluttertamp bench push`: reaching through clutter on the bundled shelf scenes by
// unguided RRT and KPIECE1 (rtc_ompl) and by guided planning (grtc with each scene's
// guidance file), several seeds each, beside Papallas & Dogar's Fig. 6.
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <sstream>

#include <nlohmann/json.hpp>

#include "bench/json_file.hpp"
#include "cluttertamp/bench/bench.hpp"
#include "bench/statistics.hpp"
#include "bench/svg_plot.hpp"
#include "cluttertamp/io/problem_io.hpp"
#include "cluttertamp/plugin/push_sampler.hpp"
#include "cluttertamp/plugin/registry.hpp"
#include "cluttertamp/run/runner.hpp"

namespace cluttertamp::bench {

namespace fs = std::filesystem;

namespace {

struct Setting {
  std::string name;     // rrt, kpiece, guided
  double paper_success;  // Fig. 6(a), out of 100 runs within 300 s
};
const Setting kSettings[] = {{"rrt", 17}, {"kpiece", 26}, {"guided", 67}};

struct Run {
  std::string scene, setting;
  std::uint64_t seed = 0;
  bool solved = false;
  double seconds = 0, guidance_seconds = 0;
  std::uint64_t propagations = 0, guides = 0, guides_satisfied = 0, guides_skipped = 0;
  std::string reason;
};

std::uint64_t counter(const Result& r, const std::string& name) {
  const auto it = r.counters.find(name);
  return it == r.counters.end() ? 0 : it->second;
}

// The problem a setting runs: the scene's problem with its planner (and, guided, the
// push sampler and the scene's guidance file) replaced, reaching within the bench's
// tolerances.
Problem configured(Problem problem, const std::string& setting, const fs::path& guidance, const BenchArgs& args) {
  problem.planner.parameters = Parameters{};
  problem.planner.parameters.set("goal_distance", args.goal_distance);
  problem.planner.parameters.set("goal_heading", args.goal_heading);
  problem.planner.parameters.set("steer", args.steer);
  if (setting == "guided") {
    problem.planner.name = "grtc";
    problem.planner.parameters.set("guidance", fs::exists(guidance) ? guidance.string() : std::string("auto"));
    problem.planner.parameters.set("planner", std::string("rrt"));
    problem.samplers[plugin::KindOf<plugin::PushSampler>::name] = PluginChoice{"push_ompl", {}, {}};
  } else {
    problem.planner.name = "rtc_ompl";
    problem.planner.parameters.set("planner", setting);
  }
  return problem;
}

struct Summary {
  std::size_t runs = 0, solved = 0;
  std::vector<double> times;  // of solved runs
  double success() const { return runs ? 100.0 * double(solved) / double(runs) : 0.0; }
};

Summary summarise(const std::vector<Run>& runs, const std::string& setting, const std::string& scene = "") {
  Summary s;
  for (const Run& r : runs) {
    if (r.setting != setting || (!scene.empty() && r.scene != scene)) continue;
    ++s.runs;
    if (r.solved) {
      ++s.solved;
      s.times.push_back(r.seconds);
    }
  }
  return s;
}

const char* colour(std::size_t setting) {
  static const char* colours[] = {"#d95f02", "#7570b3", "#1b9e77"};
  return colours[setting % 3];
}

// Left: success rate per setting, ours beside the paper's (hatched). Right: mean
// planning time of solved runs per scene and setting, with 95 % confidence intervals.
void write_svg(const std::vector<Run>& runs, const std::vector<std::string>& scenes, double time_limit,
               const fs::path& file) {
  const double h = 360, top = 30, bottom = 60, left1 = 50, w1 = 220, left2 = 340, w2 = 560;
  SvgPlot plot(left2 + w2 + 20, h);
  // (a) success rate.
  const SvgPlot::Panel rate = plot.panel(left1, top, w1, h - top - bottom, 100,
                                         "(a) success rate: ours (" + fixed(time_limit, 0) + " s), paper hatched (300 s)",
                                         "%");
  for (std::size_t s = 0; s < std::size(kSettings); ++s) {
    const double x = left1 + 10 + double(s) * 70;
    const double ours = summarise(runs, kSettings[s].name).success(), paper = kSettings[s].paper_success;
    plot.bar(rate, x, 25, ours, colour(s));
    plot.bar(rate, x + 27, 25, paper, "hatch", colour(s));
    plot.x_label(rate, x + 26, kSettings[s].name);
    plot.text(x + 12, rate.y(ours) - 4, fixed(ours, 0), "middle");
  }
  // (b) mean time per scene.
  double max_t = 1e-3;
  for (const std::string& scene : scenes) {
    for (const Setting& s : kSettings) {
      const Summary m = summarise(runs, s.name, scene);
      max_t = std::max(max_t, mean(m.times) + ci95_half_width(m.times));
    }
  }
  const SvgPlot::Panel times = plot.panel(left2, top, w2, h - top - bottom, max_t,
                                          "(b) mean planning time of solved runs, s (95 % CI)");
  const double group = w2 / double(std::max<std::size_t>(1, scenes.size()));
  for (std::size_t k = 0; k < scenes.size(); ++k) {
    const double x0 = left2 + double(k) * group;
    plot.x_label(times, x0 + group / 2, "P" + std::to_string(k + 1));
    for (std::size_t s = 0; s < std::size(kSettings); ++s) {
      const Summary m = summarise(runs, kSettings[s].name, scenes[k]);
      const double bar = group / 4, x = x0 + bar / 2 + double(s) * bar;
      plot.unsolved(times, x + bar * 0.45, static_cast<int>(m.runs - m.solved));  // a scene never solved still shows
      if (m.times.empty()) continue;
      const double t = mean(m.times), ci = ci95_half_width(m.times);
      plot.bar(times, x, bar * 0.9, t, colour(s));
      plot.error_bar(times, x + bar * 0.45, t - ci, t + ci);
    }
  }
  for (std::size_t s = 0; s < std::size(kSettings); ++s) {
    plot.legend(left2 + 10 + double(s) * 90, h - 13, colour(s), kSettings[s].name);
  }
  plot.legend(left2 + 10 + 3 * 90, h - 13, "cross", "unsolved runs");
  plot.write(file);
}

}  // namespace

int push(const BenchArgs& args) {
  std::vector<fs::path> files;
  for (const auto& entry : fs::directory_iterator(args.push_scenes)) {
    const fs::path& p = entry.path();
    const std::string name = p.filename().string();
    if (p.extension() == ".yaml" && name.find("-scene") == std::string::npos && name.find("-guidance") == std::string::npos) {
      files.push_back(p);
    }
  }
  std::sort(files.begin(), files.end());
  if (files.empty()) throw InputError({args.push_scenes.string(), 0, 0}, "no problem files (*.yaml) in this directory");

  std::ofstream csv;
  if (!args.csv.empty()) {
    csv.open(args.csv);
    if (!csv) throw InputError({args.csv.string(), 0, 0}, "cannot write the CSV file");
    csv << "scene,planner,seed,solved,time_s,guidance_time_s,propagations,guides,guides_satisfied,reason,guides_skipped\n";
  }
  std::vector<Run> runs;
  std::vector<std::string> scenes;
  const std::size_t total = files.size() * std::size(kSettings) * static_cast<std::size_t>(args.runs);
  std::size_t done = 0;
  for (const fs::path& file : files) {
    const Problem problem = io::load_problem(file);
    if (!std::holds_alternative<ReachTask>(problem.task)) {
      throw InputError({file.string(), 0, 0}, "bench push needs problems with task: {reach: <target>}");
    }
    scenes.push_back(problem.name);
    const fs::path guidance = fs::absolute(file.parent_path() / (file.stem().string() + "-guidance.yaml"));
    run::RunOptions options;
    options.time_limit = args.time_limit;
    const plugin::Registry registry(run::plugin_search_paths(problem, options));
    for (const Setting& setting : kSettings) {
      const Problem configured_problem = configured(problem, setting.name, guidance, args);
      for (int k = 0; k < args.runs; ++k) {
        options.seed = args.seed + static_cast<std::uint64_t>(k);
        if (args.verbosity != Verbosity::quiet) {
          std::cerr << "\r[" << ++done << "/" << total << "] " << problem.name << ": " << setting.name << ", seed "
                    << *options.seed << "          " << std::flush;
        }
        const Result r = run::plan(configured_problem, registry, options).result;
        Run run{problem.name, setting.name, *options.seed, r.solved, r.time.total,
                setting.name == "guided" ? r.time.task_planning : 0.0, counter(r, counter::propagations),
                counter(r, counter::guides), counter(r, counter::guides_satisfied), counter(r, counter::guides_skipped), r.reason};
        if (csv) {
          csv << run.scene << ',' << run.setting << ',' << run.seed << ',' << run.solved << ',' << run.seconds << ','
              << run.guidance_seconds << ',' << run.propagations << ',' << run.guides << ',' << run.guides_satisfied
              << ',' << csv_field(run.reason) << ',' << run.guides_skipped << "\n";
        }
        runs.push_back(std::move(run));
      }
    }
  }
  if (args.verbosity != Verbosity::quiet) std::cerr << "\r" << std::string(70, ' ') << "\r";

  std::cout << "Reaching through clutter on " << files.size() << " scenes (" << args.push_scenes.string() << "), "
            << args.runs << " seeds each, " << fixed(args.time_limit, 0) << " s per run, reached within "
            << fixed(args.goal_distance, 3) << " m and " << fixed(args.goal_heading, 2) << " rad, steering "
            << fixed(args.steer, 2) << "\n\n";
  std::cout << std::left << std::setw(9) << "planner" << std::setw(7) << "runs" << std::setw(9) << "success" << std::setw(14)
            << "paper (300 s)" << std::setw(26) << "mean time s [95% CI]" << std::setw(9) << "median" << "propagations\n";
  nlohmann::ordered_json json{{"scenes", scenes},
                              {"runs_per_scene", args.runs},
                              {"time_limit_s", args.time_limit},
                              {"goal_distance_m", args.goal_distance},
                              {"goal_heading_rad", args.goal_heading},
                              {"steer", args.steer},
                              {"planners", nlohmann::ordered_json::array()}};
  std::map<std::string, Summary> summaries;
  for (const Setting& s : kSettings) {
    const Summary& m = summaries[s.name] = summarise(runs, s.name);
    std::vector<double> propagations;
    for (const Run& r : runs) {
      if (r.setting == s.name && r.solved) propagations.push_back(double(r.propagations));
    }
    const double t = mean(m.times), ci = ci95_half_width(m.times);
    std::cout << std::left << std::setw(9) << s.name << std::setw(7) << m.runs << std::setw(9)
              << (fixed(m.success(), 0) + "%") << std::setw(14) << (fixed(s.paper_success, 0) + "%") << std::setw(26)
              << (fixed(t) + " [" + fixed(std::max(0.0, t - ci)) + ", " + fixed(t + ci) + "]") << std::setw(9)
              << fixed(median(m.times)) << fixed(mean(propagations), 0) << "\n";
    nlohmann::ordered_json row{{"planner", s.name},
                               {"runs", m.runs},
                               {"solved", m.solved},
                               {"success_rate", m.success() / 100},
                               {"paper_success_rate", s.paper_success / 100},
                               {"time_s", {{"mean", t}, {"ci95", {std::max(0.0, t - ci), t + ci}}, {"median", median(m.times)}}},
                               {"per_scene", nlohmann::ordered_json::array()}};
    for (const std::string& scene : scenes) {
      const Summary p = summarise(runs, s.name, scene);
      row["per_scene"].push_back({{"scene", scene}, {"success_rate", p.success() / 100}, {"mean_time_s", mean(p.times)},
                                  {"ci95_half_width_s", ci95_half_width(p.times)}});
    }
    json["planners"].push_back(row);
  }
  std::cout << "\nper scene: success (mean time of solved runs, s)\n" << std::left << std::setw(16) << "scene";
  for (const Setting& s : kSettings) std::cout << std::setw(18) << s.name;
  std::cout << "\n";
  for (const std::string& scene : scenes) {
    std::cout << std::setw(16) << scene;
    for (const Setting& s : kSettings) {
      const Summary p = summarise(runs, s.name, scene);
      std::cout << std::setw(18) << (fixed(p.success(), 0) + "% (" + fixed(mean(p.times)) + ")");
    }
    std::cout << "\n";
  }
  const Summary& guided = summaries["guided"];
  const bool met = guided.success() > summaries["rrt"].success() && guided.success() > summaries["kpiece"].success();
  // How surprising the differences are if the planners were equally successful.
  std::ostringstream against;
  nlohmann::ordered_json p_values;
  for (const char* other : {"rrt", "kpiece"}) {
    const Summary& o = summaries[other];
    const double p = fisher_exact_p(guided.solved, guided.runs, o.solved, o.runs);
    against << (p_values.empty() ? "" : "; ") << guided.solved << "/" << guided.runs << " against " << other << " "
            << o.solved << "/" << o.runs << ", Fisher's exact p " << (p < 0.001 ? "< 0.001" : "= " + fixed(p, 3));
    p_values[other] = p;
  }
  std::cout << "\nPaper: Papallas & Dogar 2020, Fig. 6 (10 scenes x 10 runs, 300 s; guided = GRTC-HITL, a person's "
               "guidance).\nGoal, guided beats RRT and KPIECE on success rate at equal time limits: "
            << (met ? "met" : "NOT met") << " (guided " << against.str() << ")\n";
  json["goal_met"] = met;
  json["goal_p_values"] = p_values;
  if (!args.json.empty()) write_json_file(args.json, json);
  if (!args.svg.empty()) write_svg(runs, scenes, args.time_limit, args.svg);
  return goal_exit_code(args.check_goals, met);
}

}  // namespace cluttertamp::bench
