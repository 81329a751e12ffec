// `cluttertamp bench push`: reaching through clutter on the bundled shelf scenes by
// unguided RRT and KPIECE1 (rtc_ompl) and by guided planning (grtc with each scene's
// guidance file), several seeds each, beside Papallas & Dogar's Fig. 6.
#include <cmath>
#include <cstdlib>
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
#include "bench/prose.hpp"
#include "bench/reports.hpp"
#include "bench/settings.hpp"
#include "bench/sweep.hpp"
#include "cluttertamp/bench/bench.hpp"
#include "cluttertamp/io/text_file.hpp"
#include "cluttertamp/version.hpp"
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

// The settings a bench runs, as indices into kSettings in its order: those --planner
// names, else all.
std::vector<std::size_t> chosen_settings(const BenchArgs& args) {
  std::vector<std::size_t> chosen;
  for (std::size_t s = 0; s < std::size(kSettings); ++s) {
    if (args.planners.empty() || std::find(args.planners.begin(), args.planners.end(), kSettings[s].name) != args.planners.end()) {
      chosen.push_back(s);
    }
  }
  return chosen;
}

struct Run {
  std::string scene, setting;
  std::uint64_t seed = 0;
  bool solved = false;
  double seconds = 0, guidance_seconds = 0;
  std::uint64_t propagations = 0, guides = 0, guides_satisfied = 0, guides_skipped = 0;
  std::string reason;
  std::string guidance;  // guided: where the guidance came from and each guide, as followed
};

// The guidance a guided run followed, as the records keep it: {source, guides: [{object,
// centre, diameter, satisfied}]}; null for the others.
nlohmann::ordered_json guidance_json(const Scene& scene, const Result& r) {
  if (!r.guidance) return nullptr;
  nlohmann::ordered_json guides = nlohmann::ordered_json::array();
  for (const GuideRecord& g : r.guidance->guides) {
    guides.push_back({{"object", scene.objects.at(g.object).id}, {"centre", {g.centre.x(), g.centre.y()}},
                      {"diameter", g.diameter}, {"satisfied", g.satisfied}});
  }
  return {{"source", r.guidance->source}, {"guides", guides}};
}

// One line: "SOURCE: o3 to (0.850, 0.300) d 0.1 satisfied; ...".
std::string guidance_text(const nlohmann::ordered_json& g) {
  if (g.is_null()) return "";
  std::string text = g.at("source").get<std::string>() + ":";
  for (const auto& guide : g.at("guides")) {
    text += " " + guide.at("object").get<std::string>() + " to (" + fixed(guide.at("centre")[0].get<double>(), 3) + ", " +
            fixed(guide.at("centre")[1].get<double>(), 3) + ") d " + fixed(guide.at("diameter").get<double>(), 3) +
            (guide.at("satisfied").get<bool>() ? " satisfied;" : " not satisfied;");
  }
  return text;
}

std::uint64_t counter(const Result& r, const std::string& name) {
  const auto it = r.counters.find(name);
  return it == r.counters.end() ? 0 : it->second;
}

// Keys grtc reads that rtc_ompl does not know: left out when a guided problem's
// parameters configure the unguided planners.
bool guided_only(const std::string& key) {
  return key == "guidance" || key == "max_guides" || key == "guide_diameter" || key == "unsatisfied_guides";
}

// A value as written on the command line: true/false, a number, [a, b, ...] or text.
ParameterValue parameter_value(const std::string& text) {
  if (text == "true" || text == "false") return text == "true";
  // Decimal numbers only: strtod's inf, nan and hex stay text (and fail as such).
  const auto number = [](const std::string& t) -> std::optional<double> {
    if (t.empty() || t.find_first_not_of("+-0123456789.eE") != std::string::npos) return std::nullopt;
    char* end = nullptr;
    const double v = std::strtod(t.c_str(), &end);
    if (end != t.c_str() + t.size() || !std::isfinite(v)) return std::nullopt;
    return v;
  };
  if (text.size() >= 2 && text.front() == '[' && text.back() == ']') {
    std::vector<double> values;
    std::stringstream items(text.substr(1, text.size() - 2));
    for (std::string item; std::getline(items, item, ',');) {
      item.erase(0, item.find_first_not_of(' '));
      item.erase(item.find_last_not_of(' ') + 1);
      const auto v = number(item);
      if (!v) return text;
      values.push_back(*v);
    }
    return values;
  }
  if (const auto v = number(text)) {
    // Whole numbers written without a point are integers ("1e5" too): integer keys take them.
    if (text.find('.') == std::string::npos && std::floor(*v) == *v && std::abs(*v) < 9e15) return static_cast<std::int64_t>(*v);
    return *v;
  }
  return text;
}

// The problem a setting runs: the scene's problem with its own planner parameters (the
// guided planner's keys left out of the unguided ones), the planner and its search
// chosen by the setting, then the bench's overrides. Guided: grtc with the problem's
// guidance, else the scene's guidance file, else generated, and the problem's push
// sampler, else push_ompl.
Problem configured(Problem problem, const std::string& setting, const fs::path& guidance, const BenchArgs& args) {
  const bool guided = setting == "guided";
  Parameters parameters;
  for (const std::string& key : problem.planner.parameters.keys()) {
    if (!guided && guided_only(key)) continue;
    parameters.set(key, *problem.planner.parameters.get(key));
  }
  parameters.set("planner", std::string(guided ? "rrt" : setting));
  for (const auto& [key, value] : args.push_overrides) {
    if (guided || !guided_only(key)) parameters.set(key, parameter_value(value), {"bench push --param", 0, 0});
  }
  if (guided) {
    problem.planner.name = "grtc";
    if (!parameters.contains("guidance")) {
      parameters.set("guidance", fs::exists(guidance) ? guidance.string() : std::string("auto"));
    }
    if (!problem.samplers.count(plugin::KindOf<plugin::PushSampler>::name)) {
      problem.samplers[plugin::KindOf<plugin::PushSampler>::name] = PluginChoice{"push_ompl", {}, {}};
    }
  } else {
    problem.planner.name = "rtc_ompl";
  }
  problem.planner.parameters = std::move(parameters);
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

// The settings the runs hold, as indices into kSettings (a bench run with --planner, or
// the records of one, holds fewer than all).
std::vector<std::size_t> present_settings(const std::vector<Run>& runs) {
  std::vector<std::size_t> present;
  for (std::size_t s = 0; s < std::size(kSettings); ++s) {
    if (summarise(runs, kSettings[s].name).runs > 0) present.push_back(s);
  }
  return present;
}

const char* colour(std::size_t setting) {
  static const char* colours[] = {"#d95f02", "#7570b3", "#1b9e77"};
  return colours[setting % 3];
}

// Left: success rate per setting, ours beside the paper's (hatched). Right: the
// planning times of solved runs per scene and setting as box plots (a log axis when
// they span more than a decade), unsolved runs as red crosses with their count.
void write_svg(const std::vector<Run>& runs, const std::vector<std::string>& scenes, double time_limit,
               const fs::path& file) {
  const std::vector<std::size_t> present = present_settings(runs);
  const double h = 360, top = 30, bottom = 60, left1 = 50, w1 = 220, left2 = 340, w2 = 560;
  SvgPlot plot(left2 + w2 + 20, h);
  // (a) success rate.
  const SvgPlot::Panel rate = plot.panel(left1, top, w1, h - top - bottom, 100,
                                         "(a) success rate: ours (" + (time_limit > 0 ? fixed(time_limit, 0) + " s" : std::string("own limits")) +
                                             "), paper hatched (300 s)",
                                         "%");
  for (const std::size_t s : present) {
    const double x = left1 + 10 + double(s) * 70;
    const double ours = summarise(runs, kSettings[s].name).success(), paper = kSettings[s].paper_success;
    plot.bar(rate, x, 25, ours, colour(s));
    plot.bar(rate, x + 27, 25, paper, "hatch", colour(s));
    plot.x_label(rate, x + 26, kSettings[s].name);
    plot.text(x + 12, rate.y(ours) - 4, fixed(ours, 0), "middle");
  }
  // (b) times per scene.
  std::vector<double> all_times;
  for (const Run& r : runs) {
    if (r.solved) all_times.push_back(r.seconds);
  }
  const SvgPlot::Panel times = plot.panel_for(left2, top, w2, h - top - bottom, all_times, "(b) planning time of solved runs, s");
  const double group = w2 / double(std::max<std::size_t>(1, scenes.size()));
  for (std::size_t k = 0; k < scenes.size(); ++k) {
    const double x0 = left2 + double(k) * group;
    plot.x_label(times, x0 + group / 2, "P" + std::to_string(k + 1));
    for (const std::size_t s : present) {
      const Summary m = summarise(runs, kSettings[s].name, scenes[k]);
      const double bar = group / 4, x = x0 + bar / 2 + double(s) * bar;
      plot.unsolved(times, x + bar * 0.45, static_cast<int>(m.runs - m.solved));  // a scene never solved still shows
      plot.box(times, x + bar * 0.45, bar * 0.8, m.times, colour(s));
    }
  }
  for (const std::size_t s : present) {
    plot.legend(left2 + 10 + double(s) * 90, h - 13, colour(s), kSettings[s].name);
  }
  plot.legend(left2 + 10 + 3 * 90, h - 13, "cross", "unsolved runs");
  plot.write(file);
}

// The bench's problem files: pNN.yaml of args.push_scenes, sorted (the scenes and
// guidance files beside them excluded).
std::vector<fs::path> problem_files(const BenchArgs& args) {
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
  return files;
}

// Run i of the sweep: file i / (settings x runs), then setting, then seed; `setting`
// indexes kSettings.
struct PushRef {
  std::size_t file = 0, setting = 0;
  int run = 0;
};
PushRef push_ref(std::size_t i, const std::vector<std::size_t>& settings, int runs) {
  const std::size_t per_file = settings.size() * static_cast<std::size_t>(runs);
  return {i / per_file, settings[(i % per_file) / static_cast<std::size_t>(runs)], static_cast<int>(i % static_cast<std::size_t>(runs))};
}

Record record_of(const Run& run, const Result& r, const Scene& scene) {
  return {{"problem", run.scene},     {"planner", run.setting},          {"seed", run.seed},
          {"solved", run.solved},     {"time_s", run.seconds},           {"guidance_time_s", run.guidance_seconds},
          {"counters", r.counters},   {"reason", run.reason},            {"guidance", guidance_json(scene, r)},
          {"version", std::string(version())}};
}

Run run_of(const Record& r) {
  auto count = [&](const char* name) {
    const auto& c = r.at("counters");
    return c.contains(name) ? c[name].get<std::uint64_t>() : std::uint64_t{0};
  };
  return {r.at("problem").get<std::string>(), r.at("planner").get<std::string>(), r.at("seed").get<std::uint64_t>(),
          r.at("solved").get<bool>(), number(r, "time_s"), number(r, "guidance_time_s"), count(counter::propagations),
          count(counter::guides), count(counter::guides_satisfied), count(counter::guides_skipped), r.at("reason").get<std::string>(),
          r.contains("guidance") ? guidance_text(r.at("guidance")) : std::string()};
}

// Plans the runs it is given, loading each problem file once.
class PushRunner {
 public:
  explicit PushRunner(const BenchArgs& args) : args_(args), files_(problem_files(args)) {}

  Record run(const PushRef& ref) {
    const Loaded& loaded = load(ref.file);
    const Setting& setting = kSettings[ref.setting];
    run::RunOptions options;
    options.time_limit = args_.time_limit > 0 ? args_.time_limit : loaded.problem.time_limit;
    options.seed = args_.seed + static_cast<std::uint64_t>(ref.run);
    const Result r = run::plan(configured(loaded.problem, setting.name, loaded.guidance, args_), *loaded.registry, options).result;
    const Run run{loaded.problem.name, setting.name, *options.seed, r.solved, r.time.total,
                  setting.name == "guided" ? r.time.task_planning : 0.0, counter(r, counter::propagations),
                  counter(r, counter::guides), counter(r, counter::guides_satisfied), counter(r, counter::guides_skipped), r.reason, std::string()};
    return record_of(run, r, loaded.problem.scene);
  }

 private:
  struct Loaded {
    Problem problem;
    fs::path guidance;
    std::unique_ptr<plugin::Registry> registry;
  };
  const Loaded& load(std::size_t file) {
    if (loaded_.first == file && loaded_.second) return *loaded_.second;
    auto l = std::make_unique<Loaded>();
    l->problem = io::load_problem(files_.at(file));
    if (!std::holds_alternative<ReachTask>(l->problem.task)) {
      throw InputError({files_[file].string(), 0, 0}, "bench push needs problems with task: {reach: <target>}");
    }
    l->guidance = fs::absolute(files_[file].parent_path() / (files_[file].stem().string() + "-guidance.yaml"));
    run::RunOptions options;
    l->registry = std::make_unique<plugin::Registry>(run::plugin_search_paths(l->problem, options));
    loaded_ = {file, std::move(l)};
    return *loaded_.second;
  }

  const BenchArgs& args_;
  std::vector<fs::path> files_;
  std::pair<std::size_t, std::unique_ptr<Loaded>> loaded_{0, nullptr};
};

void write_csv(const fs::path& file, const std::vector<Run>& runs) {
  std::ostringstream csv;
  csv << "scene,planner,seed,solved,time_s,guidance_time_s,propagations,guides,guides_satisfied,reason,guides_skipped,guidance\n";
  for (const Run& run : runs) {
    csv << run.scene << ',' << run.setting << ',' << run.seed << ',' << run.solved << ',' << run.seconds << ',' << run.guidance_seconds
        << ',' << run.propagations << ',' << run.guides << ',' << run.guides_satisfied << ',' << csv_field(run.reason) << ','
        << run.guides_skipped << ',' << csv_field(run.guidance) << "\n";
  }
  io::write_text_file(file, csv.str(), "CSV file");
}

}  // namespace

int push(const BenchArgs& args) {
  const std::size_t files = problem_files(args).size();
  const std::vector<std::size_t> settings = chosen_settings(args);
  const std::size_t total = files * settings.size() * static_cast<std::size_t>(args.runs);
  const SweepPlan plan{"push", settings_of(args), total, [&](std::size_t i) {
                         const PushRef ref = push_ref(i, settings, args.runs);
                         return "problem " + std::to_string(ref.file + 1) + " of " + std::to_string(files) + ", " +
                                kSettings[ref.setting].name + ", seed " + std::to_string(args.seed + static_cast<std::uint64_t>(ref.run));
                       }};
  return run_and_report(
      plan, args, [&] { return std::make_unique<PushRunner>(args); },
      [&](PushRunner& runner, std::size_t i) { return runner.run(push_ref(i, settings, args.runs)); }, report_push);
}

int report_push(const BenchArgs& args, const std::vector<Record>& records) {
  std::vector<Run> runs;
  std::vector<std::string> scenes;  // in the order of the runs
  for (const Record& r : records) {
    runs.push_back(run_of(r));
    if (std::find(scenes.begin(), scenes.end(), runs.back().scene) == scenes.end()) scenes.push_back(runs.back().scene);
  }
  if (!args.csv.empty()) write_csv(args.csv, runs);
  std::string overrides;
  for (const auto& [key, value] : args.push_overrides) overrides += (overrides.empty() ? "" : ", ") + key + " = " + value;
  std::cout << wrapped("Reaching through clutter on " + std::to_string(scenes.size()) + " scenes (" + args.push_scenes.string() + "), " +
                           std::to_string(args.runs) + " seeds each, " +
                           (args.time_limit > 0 ? fixed(args.time_limit, 0) + " s per run" : std::string("each problem's time limit")) +
                           "; each problem's physics and planner parameters" +
                           (overrides.empty() ? std::string(" as written") : ", with " + overrides + " for every run"))
            << "\n";
  std::cout << std::left << std::setw(9) << "planner" << std::setw(7) << "runs" << std::setw(9) << "success" << std::setw(14)
            << "paper (300 s)" << std::setw(26) << "mean time s [95% CI]" << std::setw(9) << "median" << "propagations\n";
  nlohmann::ordered_json json{{"scenes", scenes},
                              {"runs_per_scene", args.runs},
                              {"time_limit_s", args.time_limit},
                              {"overrides", args.push_overrides},
                              {"planners", nlohmann::ordered_json::array()}};
  const std::vector<std::size_t> present = present_settings(runs);
  std::map<std::string, Summary> summaries;
  for (const std::size_t index : present) {
    const Setting& s = kSettings[index];
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
  for (const std::size_t s : present) std::cout << std::setw(18) << kSettings[s].name;
  std::cout << "\n";
  for (const std::string& scene : scenes) {
    std::cout << std::setw(16) << scene;
    for (const std::size_t s : present) {
      const Summary p = summarise(runs, kSettings[s].name, scene);
      std::cout << std::setw(18) << (fixed(p.success(), 0) + "% (" + fixed(mean(p.times)) + ")");
    }
    std::cout << "\n";
  }
  // The goal compares guided planning with both others: judged only when all three ran.
  const bool judged = present.size() == std::size(kSettings);
  const Summary& guided = summaries["guided"];
  const bool met = judged && guided.success() > summaries["rrt"].success() && guided.success() > summaries["kpiece"].success();
  // How surprising the differences are if the planners were equally successful.
  std::ostringstream against;
  nlohmann::ordered_json p_values;
  for (const char* other : {"rrt", "kpiece"}) {
    if (!judged) break;
    const Summary& o = summaries[other];
    const double p = fisher_exact_p(guided.solved, guided.runs, o.solved, o.runs);
    against << (p_values.empty() ? "" : "; ") << guided.solved << "/" << guided.runs << " against " << other << " "
            << o.solved << "/" << o.runs << ", Fisher's exact p " << (p < 0.001 ? "< 0.001" : "= " + fixed(p, 3));
    p_values[other] = p;
  }
  std::cout << "\n"
            << wrapped("Paper: Papallas & Dogar 2020, Fig. 6 (10 scenes x 10 runs, 300 s; guided = GRTC-HITL, a person's guidance).\n"
                       "Goal, guided beats RRT and KPIECE on success rate at equal time limits: " +
                       (judged ? std::string(met ? "met" : "NOT met") + " (guided " + against.str() + ")"
                               : std::string("not judged (it needs all three planners' runs)")));
  json["goal_met"] = judged ? nlohmann::ordered_json(met) : nlohmann::ordered_json(nullptr);
  json["goal_p_values"] = p_values;
  if (!args.json.empty()) write_json_file(args.json, json);
  if (!args.svg.empty()) write_svg(runs, scenes, args.time_limit, args.svg);
  if (!args.ompl_log.empty()) {
    std::vector<OmplLogPlanner> planners;
    for (const std::size_t index : present) {
      const Setting& s = kSettings[index];
      OmplLogPlanner p{s.name, {}};
      for (const Record& r : records) {
        if (r.at("planner") == s.name) p.runs.push_back(&r);
      }
      planners.push_back(std::move(p));
    }
    write_ompl_log(args.ompl_log, {"cluttertamp_bench_push", settings_of(args).dump(2), args.seed, args.time_limit}, planners);
  }
  return goal_exit_code(args.check_goals, met);
}

}  // namespace cluttertamp::bench
