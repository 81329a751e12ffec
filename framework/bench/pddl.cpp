// `cluttertamp bench pddl`: time, expansions and plan cost per instance and search, so
// runs can be compared with other planners.
#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdlib>
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
#include "bench/svg_plot.hpp"
#include "bench/sweep.hpp"
#include "cluttertamp/bench/bench.hpp"
#include "cluttertamp/version.hpp"
#include "bench/statistics.hpp"
#include "cluttertamp/io/text_file.hpp"
#include "cluttertamp/pddl/parser.hpp"
#include "cluttertamp/pddl/validator.hpp"
#include "cluttertamp/run/runner.hpp"
#include "cluttertamp/search/grounding.hpp"
#include "cluttertamp/search/planner.hpp"

namespace cluttertamp::bench {

namespace fs = std::filesystem;

namespace {

struct Pair {
  std::string domain_folder;  ///< the folder's name: the per-domain tables' key
  fs::path domain, problem;   ///< domain empty: none found for this problem
};

// "p2" before "p10": runs of digits compare as numbers.
bool natural_less(const std::string& a, const std::string& b) {
  std::size_t i = 0, j = 0;
  while (i < a.size() && j < b.size()) {
    if (std::isdigit(static_cast<unsigned char>(a[i])) && std::isdigit(static_cast<unsigned char>(b[j]))) {
      std::size_t ei = i, ej = j;
      while (ei < a.size() && std::isdigit(static_cast<unsigned char>(a[ei]))) ++ei;
      while (ej < b.size() && std::isdigit(static_cast<unsigned char>(b[ej]))) ++ej;
      const std::string x = a.substr(i, ei - i), y = b.substr(j, ej - j);
      const std::size_t zx = x.find_first_not_of('0'), zy = y.find_first_not_of('0');
      const std::string nx = zx == std::string::npos ? "" : x.substr(zx), ny = zy == std::string::npos ? "" : y.substr(zy);
      if (nx.size() != ny.size()) return nx.size() < ny.size();
      if (nx != ny) return nx < ny;
      i = ei;
      j = ej;
      continue;
    }
    if (a[i] != b[j]) return a[i] < b[j];
    ++i;
    ++j;
  }
  return a.size() - i < b.size() - j;
}

bool names_a_domain(const std::string& file_name) {
  std::string lower = file_name;
  std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char c) { return std::tolower(c); });
  return lower.find("domain") != std::string::npos;
}

// The domain file of a problem, as the IPC collections lay them out (and Fast
// Downward's driver looks for them): one per problem first, then the folder's.
fs::path domain_for(const fs::path& folder, const std::string& problem) {
  const std::string stem = fs::path(problem).stem().string();
  std::vector<std::string> candidates{"domain_" + problem, stem + "-domain.pddl", "domain-" + problem};
  if (const auto dash = problem.find('-'); dash != std::string::npos) candidates.push_back(problem.substr(0, dash) + "-domain.pddl");
  if (problem.size() > 1 && problem[0] == 'p') candidates.push_back("d" + problem.substr(1));
  if (problem.rfind("typed-", 0) == 0) candidates.push_back("domain-typed.pddl");
  candidates.push_back("domain.pddl");
  candidates.push_back("domain-untyped.pddl");
  for (const std::string& c : candidates) {
    if (fs::is_regular_file(folder / c)) return folder / c;
  }
  return {};
}

// The problems of one domain folder, in natural order, the first `first` of them (0: all).
std::vector<Pair> problems_of(const fs::path& folder, int first) {
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(folder)) {
    const std::string name = e.path().filename().string();
    if (e.is_regular_file() && name.ends_with(".pddl") && !names_a_domain(name)) names.push_back(name);
  }
  std::sort(names.begin(), names.end(), [](const std::string& a, const std::string& b) {
    return natural_less(fs::path(a).stem().string(), fs::path(b).stem().string());  // p05 before p05-2
  });
  if (first > 0 && names.size() > static_cast<std::size_t>(first)) names.resize(static_cast<std::size_t>(first));
  std::vector<Pair> out;
  for (const std::string& name : names) out.push_back({folder.filename().string(), domain_for(folder, name), folder / name});
  return out;
}

// A folder of folders of problems (the IPC layout), or else one folder of problems.
std::vector<Pair> instances(const fs::path& root, int first) {
  std::vector<Pair> out;
  std::vector<fs::path> folders;
  for (const auto& e : fs::directory_iterator(root)) {
    if (e.is_directory()) folders.push_back(e.path());
  }
  std::sort(folders.begin(), folders.end(),
            [](const fs::path& a, const fs::path& b) { return natural_less(a.filename().string(), b.filename().string()); });
  for (const fs::path& folder : folders) {
    for (Pair& p : problems_of(folder, first)) out.push_back(std::move(p));
  }
  return out.empty() ? problems_of(root, first) : out;
}

// "folder/problem-stem cost" per line; '#' begins a comment.
std::map<std::string, double> reference_costs(const fs::path& file) {
  std::map<std::string, double> out;
  if (file.empty()) return out;
  std::istringstream in(io::read_text_file(file, "reference costs file"));
  std::string line;
  for (std::size_t number = 1; std::getline(in, line); ++number) {
    if (const auto hash = line.find('#'); hash != std::string::npos) line.resize(hash);
    std::istringstream fields(line);
    std::string name, cost_text, extra;
    if (!(fields >> name)) continue;
    fields >> cost_text;
    char* end = nullptr;
    const double cost = std::strtod(cost_text.c_str(), &end);
    if (cost_text.empty() || *end != '\0' || !std::isfinite(cost) || cost < 0 || (fields >> extra)) {
      throw InputError({file.string(), number, 1},
                       "expected 'folder/problem cost' (a cost of 0 or more), got '" + line + "'");
    }
    if (!out.emplace(name, cost).second) throw InputError({file.string(), number, 1}, "'" + name + "' is given twice");
  }
  return out;
}

struct Run {
  std::string instance, domain_folder, search;
  fs::path domain, problem;
  bool solved = false;
  bool valid = false;  // the plan passed the validator
  std::string reason;
  double cost = 0;
  std::size_t length = 0;
  std::uint64_t expanded = 0, evaluated = 0;
  double ground_s = 0, search_s = 0, total_s = 0;  // medians over runs
  int runs = 0;
  double score = 0;  // IPC quality score: best known cost / ours
};

// One search on one instance, `runs` times (a time-out is not run again).
Run measure(const Pair& pair, const pddl::Domain& domain, const pddl::Problem& problem, const std::string& algorithm,
            const BenchArgs& args, double parse_s) {
  Run row;
  std::vector<double> ground_s, search_s, total_s;
  search::SearchResult last;
  search::Task task;
  for (int run = 0; run < args.runs; ++run) {
    const auto t0 = std::chrono::steady_clock::now();
    const auto since = [&] { return parse_s + std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); };
    search::GroundingStats stats;
    const auto stopped = [&](std::string reason) {  // grounding's failure is this instance's result
      last = {};
      last.reason = std::move(reason);
      ground_s.push_back(since());
      search_s.push_back(0.0);
      total_s.push_back(ground_s.back());
    };
    try {
      task = search::ground(domain, problem, &stats, std::max(0.0, args.time_limit - parse_s));  // the limit holds grounding too
    } catch (const search::TimeLimit&) {
      stopped("time limit (grounding)");
      break;
    } catch (const search::TooLarge& e) {
      stopped(std::string("grounding: ") + e.what());
      break;
    }
    search::SearchOptions options;
    options.algorithm = algorithm;
    options.landmarks = args.landmarks;
    options.time_limit = std::max(0.0, args.time_limit - since());
    last = search::plan(task, options);
    ground_s.push_back(stats.seconds);
    search_s.push_back(last.statistics.seconds);
    total_s.push_back(since());
    if (!last.solved) break;  // a time-out does not get faster
  }
  row.solved = last.solved;
  row.reason = last.solved ? "" : last.reason;
  row.cost = last.cost;
  row.length = last.plan.size();
  row.expanded = last.statistics.expanded;
  row.evaluated = last.statistics.evaluated;
  row.ground_s = median(ground_s);
  row.search_s = median(search_s);
  row.total_s = median(total_s);
  row.runs = static_cast<int>(total_s.size());
  if (last.solved) {  // checked again, by the validator, on the PDDL itself
    std::string text;
    for (search::OperatorId op : last.plan) text += task.operators[op].name + "\n";
    const pddl::PlanValidation v =
        pddl::validate_plan(domain, problem, pddl::parse_plan(text, pair.problem.string() + " (plan)", domain, problem));
    row.valid = v.valid;
    if (!v.valid) row.reason = "INVALID PLAN: " + v.reason;
  }
  return row;
}

// IPC quality scores: the best known cost (the reference's, or the cheapest of the
// searches run here) over each valid plan's; 0 unsolved.
void score(std::vector<Run>& rows, const std::map<std::string, double>& reference) {
  std::map<std::string, double> best = reference;
  for (const Run& r : rows) {
    if (!r.valid) continue;
    auto [it, inserted] = best.emplace(r.instance, r.cost);
    if (!inserted) it->second = std::min(it->second, r.cost);
  }
  for (Run& r : rows) {
    if (!r.valid) continue;
    const double b = best.at(r.instance);
    r.score = r.cost <= 0 ? 1.0 : std::min(1.0, b / r.cost);
  }
}

// A table's first cell: a name too wide for its column (IPC instance names run to 40
// characters) stands on a line of its own and its row follows with the cell empty, so
// the columns stay aligned within 100 characters. Call it before the row's statement.
std::string first_cell(const std::string& name, std::size_t width) {
  if (name.size() < width) return name;
  std::cout << name << "\n";
  return "";
}

void print_summary(const std::vector<Run>& rows, const std::vector<std::string>& searches, nlohmann::ordered_json& json) {
  std::vector<std::string> folders;
  for (const Run& r : rows) {
    if (std::find(folders.begin(), folders.end(), r.domain_folder) == folders.end()) folders.push_back(r.domain_folder);
  }
  std::cout << "\nper domain: solved (plans valid), IPC quality score, medians over the solved\n"
            << std::left << std::setw(34) << "domain" << std::setw(14) << "search" << std::right << std::setw(10) << "solved"
            << std::setw(9) << "score" << std::setw(10) << "length" << std::setw(12) << "total s" << "\n";
  for (const std::string& search : searches) {
    int all_total = 0, all_solved = 0;
    double all_score = 0;
    for (const std::string& folder : folders) {
      int total = 0, solved = 0;
      double sum = 0;
      std::vector<double> lengths, seconds;
      for (const Run& r : rows) {
        if (r.domain_folder != folder || r.search != search) continue;
        ++total;
        sum += r.score;
        if (!r.valid) continue;
        ++solved;
        lengths.push_back(static_cast<double>(r.length));
        seconds.push_back(r.total_s);
      }
      all_total += total;
      all_solved += solved;
      all_score += sum;
      const std::string cell = first_cell(folder, 34);
      std::cout << std::left << std::setw(34) << cell << std::setw(14) << search << std::right << std::setw(10)
                << (std::to_string(solved) + "/" + std::to_string(total)) << std::setw(9) << fixed(sum, 2) << std::setw(10)
                << (solved ? fixed(median(lengths), 1) : "-") << std::setw(12) << (solved ? fixed(median(seconds), 3) : "-")
                << "\n";
      json.push_back({{"domain_folder", folder},
                      {"search", search},
                      {"instances", total},
                      {"solved", solved},
                      {"score", sum},
                      {"plan_length_median", median(lengths)},
                      {"total_seconds_median", median(seconds)}});
    }
    std::cout << std::left << std::setw(34) << "all" << std::setw(14) << search << std::right << std::setw(10)
              << (std::to_string(all_solved) + "/" + std::to_string(all_total)) << std::setw(9) << fixed(all_score, 2) << "\n";
  }
}

void write_csv(const fs::path& file, const std::vector<Run>& rows) {
  std::string text = "domain_folder,instance,search,solved,valid,reason,cost,plan_length,expanded,evaluated,grounding_s,search_s,total_s,runs,score\n";
  for (const Run& r : rows) {
    text += csv_field(r.domain_folder) + "," + csv_field(r.instance) + "," + csv_field(r.search) + "," +
            (r.solved ? "1" : "0") + "," + (r.valid ? "1" : "0") + "," + csv_field(r.reason) + "," + std::to_string(r.cost) +
            "," + std::to_string(r.length) + "," + std::to_string(r.expanded) + "," + std::to_string(r.evaluated) + "," +
            fixed(r.ground_s, 4) + "," + fixed(r.search_s, 4) + "," + fixed(r.total_s, 4) + "," + std::to_string(r.runs) +
            "," + fixed(r.score, 4) + "\n";
  }
  io::write_text_file(file, text, "CSV file");
}

}  // namespace

// Parsing a Blocksworld problem of `objects` blocks in stacks of ten (the domain and
// problem made here, in memory): median seconds of `runs` parses of the problem.
double parse_seconds(int objects, int runs) {
  const pddl::Domain domain = pddl::parse_domain(
      "(define (domain blocks) (:requirements :strips)"
      " (:predicates (on ?x ?y) (ontable ?x) (clear ?x) (handempty) (holding ?x))"
      " (:action pick-up :parameters (?x) :precondition (and (clear ?x) (ontable ?x) (handempty))"
      "  :effect (and (not (ontable ?x)) (not (clear ?x)) (not (handempty)) (holding ?x))))",
      "generated-domain.pddl");
  std::string text = "(define (problem generated) (:domain blocks) (:objects";
  for (int i = 0; i < objects; ++i) text += " b" + std::to_string(i);
  text += ") (:init (handempty)";
  for (int i = 0; i < objects; ++i) {
    text += i % 10 == 0 ? " (ontable b" + std::to_string(i) + ")"
                        : " (on b" + std::to_string(i) + " b" + std::to_string(i - 1) + ")";
    if (i % 10 == 9 || i + 1 == objects) text += " (clear b" + std::to_string(i) + ")";
  }
  text += ") (:goal (holding b0)))";
  std::vector<double> seconds;
  for (int run = 0; run < std::max(1, runs); ++run) {
    const auto t0 = std::chrono::steady_clock::now();
    const pddl::Problem problem = pddl::parse_problem(text, "generated-problem.pddl", domain);
    seconds.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    if (problem.objects.size() != static_cast<std::size_t>(objects)) throw std::logic_error("bench pddl: the generated problem lost objects");
  }
  return median(seconds);
}

namespace {

Record record_of(const Run& r, const std::string& refused) {
  return {{"problem", r.instance},
          {"domain_folder", r.domain_folder},
          {"domain_file", r.domain.string()},
          {"problem_file", r.problem.string()},
          {"planner", r.search},
          {"solved", r.solved},
          {"valid", r.valid},
          {"reason", r.reason},
          {"refused", refused},
          {"cost", r.cost},
          {"plan_length", r.length},
          {"expanded", r.expanded},
          {"evaluated", r.evaluated},
          {"ground_s", r.ground_s},
          {"search_s", r.search_s},
          {"time_s", r.total_s},
          {"runs", r.runs},
          {"version", std::string(version())}};
}

Run run_of(const Record& r) {
  Run run;
  run.instance = r.at("problem").get<std::string>();
  run.domain_folder = r.at("domain_folder").get<std::string>();
  run.domain = r.at("domain_file").get<std::string>();
  run.problem = r.at("problem_file").get<std::string>();
  run.search = r.at("planner").get<std::string>();
  run.solved = r.at("solved").get<bool>();
  run.valid = r.at("valid").get<bool>();
  run.reason = r.at("reason").get<std::string>();
  run.cost = number(r, "cost");
  run.length = r.at("plan_length").get<std::size_t>();
  run.expanded = r.at("expanded").get<std::uint64_t>();
  run.evaluated = r.at("evaluated").get<std::uint64_t>();
  run.ground_s = number(r, "ground_s");
  run.search_s = number(r, "search_s");
  run.total_s = number(r, "time_s");
  run.runs = r.at("runs").get<int>();
  return run;
}

std::vector<std::string> searches_of(const BenchArgs& args) {
  return args.searches.empty() ? std::vector<std::string>{"lama-first", "astar-lmcut"} : args.searches;
}

// The instances of the tree with a domain file; a .pddl file with no domain file beside
// it is no problem of this tree (a domain under another name, a stream file): said,
// and left out.
std::vector<Pair> pairs_of(const BenchArgs& args) {
  std::vector<Pair> pairs = instances(args.pddl_instances, args.per_domain);
  const auto lone = std::stable_partition(pairs.begin(), pairs.end(), [](const Pair& p) { return !p.domain.empty(); });
  for (auto it = lone; it != pairs.end(); ++it) {
    if (args.verbosity != Verbosity::quiet) std::cerr << "skipped " << it->problem.string() << ": no domain file found beside it\n";
  }
  pairs.erase(lone, pairs.end());
  if (pairs.empty()) throw InputError({args.pddl_instances.string(), 0, 0}, "no PDDL problem files found here or in its folders");
  return pairs;
}

// Runs run i: instance i / searches with search i % searches, parsing each instance once.
class PddlRunner {
 public:
  PddlRunner(const BenchArgs& args, std::vector<Pair> pairs) : args_(args), pairs_(std::move(pairs)), searches_(searches_of(args)) {}

  Record run(std::size_t i) {
    const Pair& pair = pairs_.at(i / searches_.size());
    if (parsed_ != i / searches_.size()) parse(i / searches_.size());
    Run row;
    if (error_.empty()) {
      row = measure(pair, *domain_, *problem_, searches_[i % searches_.size()], args_, parse_s_);
    } else {
      row.reason = "input refused: " + error_.substr(0, error_.find('\n'));  // the located line, not the excerpt
    }
    row.instance = pair.domain_folder + "/" + pair.problem.stem().string();
    row.domain_folder = pair.domain_folder;
    row.search = searches_[i % searches_.size()];
    row.domain = pair.domain;
    row.problem = pair.problem;
    return record_of(row, error_);
  }

 private:
  void parse(std::size_t k) {
    parsed_ = k;
    domain_.reset();
    problem_.reset();
    error_.clear();
    const auto t0 = std::chrono::steady_clock::now();
    try {
      domain_ = pddl::load_domain(pairs_[k].domain);
      problem_ = pddl::load_problem(pairs_[k].problem, *domain_);
    } catch (const InputError& e) {
      error_ = e.what();
    }
    parse_s_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }

  const BenchArgs& args_;
  std::vector<Pair> pairs_;
  std::vector<std::string> searches_;
  std::size_t parsed_ = static_cast<std::size_t>(-1);
  std::optional<pddl::Domain> domain_;
  std::optional<pddl::Problem> problem_;
  std::string error_;
  double parse_s_ = 0;
};

// Per domain folder: the share of instances each search solved with a valid plan, and
// the total times of those as box plots (unsolved instances as red crosses).
void write_svg(const fs::path& file, const std::vector<Run>& rows, const std::vector<std::string>& searches) {
  std::vector<std::string> folders;
  for (const Run& r : rows) {
    if (std::find(folders.begin(), folders.end(), r.domain_folder) == folders.end()) folders.push_back(r.domain_folder);
  }
  const double left = 70, slot = std::max(40.0, 24.0 * double(searches.size())), panel_h = 170, top = 40;
  const double panel_w = std::max(400.0, slot * double(folders.size()));
  SvgPlot plot(std::max(left + panel_w + 30, left + 130 * double(searches.size() + 1) + 30), top + 2 * (panel_h + 75) + 20);
  std::vector<double> times;
  for (const Run& r : rows) {
    if (r.valid) times.push_back(r.total_s);
  }
  const SvgPlot::Panel coverage = plot.panel(left, top, panel_w, panel_h, 100, "instances solved, valid plans", "%");
  const SvgPlot::Panel time = plot.panel_for(left, top + panel_h + 75, panel_w, panel_h, times, "time of solved instances (parse, ground, search), s");
  for (std::size_t f = 0; f < folders.size(); ++f) {
    const double x0 = left + slot * double(f), bar = slot * 0.8 / double(searches.size());
    for (std::size_t s = 0; s < searches.size(); ++s) {
      int total = 0, solved = 0;
      std::vector<double> seconds;
      for (const Run& r : rows) {
        if (r.domain_folder != folders[f] || r.search != searches[s]) continue;
        ++total;
        if (r.valid) {
          ++solved;
          seconds.push_back(r.total_s);
        }
      }
      const double x = x0 + slot * 0.1 + bar * (double(s) + 0.5);
      plot.bar(coverage, x - bar * 0.4, bar * 0.8, total ? 100.0 * solved / total : 0.0, series_colour(s));
      plot.box(time, x, bar * 0.8, seconds, series_colour(s));
      plot.unsolved(time, x, total - solved);
    }
    const std::string name = folders[f].size() > 9 ? folders[f].substr(0, 8) + "~" : folders[f];
    for (const SvgPlot::Panel* p : {&coverage, &time}) plot.x_label(*p, x0 + slot / 2, name);
  }
  for (std::size_t s = 0; s < searches.size(); ++s) plot.legend(left + 130 * double(s), top + 2 * (panel_h + 75) + 5, series_colour(s), searches[s]);
  plot.legend(left + 130 * double(searches.size()), top + 2 * (panel_h + 75) + 5, "cross", "unsolved (count)");
  plot.write(file);
}

}  // namespace

int pddl(const BenchArgs& given) {
  const BenchArgs args = with_absolute_paths(given);
  std::vector<Pair> pairs = pairs_of(args);
  reference_costs(args.reference_costs);  // a bad file is bad input before any run
  const std::vector<std::string> searches = searches_of(args);
  const SweepPlan plan{"pddl", settings_of(args), pairs.size() * searches.size(), [&](std::size_t i) {
                         const Pair& pair = pairs[i / searches.size()];
                         return pair.domain_folder + "/" + pair.problem.stem().string() + ", " + searches[i % searches.size()];
                       }};
  return run_and_report(
      plan, args, [&] { return std::make_unique<PddlRunner>(args, pairs); },
      [](PddlRunner& runner, std::size_t i) { return runner.run(i); }, report_pddl);
}

int report_pddl(const BenchArgs& args, const std::vector<Record>& records) {
  std::vector<Run> rows;
  std::vector<std::string> refused;  // files that are not read: bad input
  for (const Record& r : records) {
    rows.push_back(run_of(r));
    const std::string error = r.at("refused").get<std::string>();
    if (!error.empty() && std::find(refused.begin(), refused.end(), error) == refused.end()) {
      refused.push_back(error);
      std::cerr << error << "\n";
    }
  }
  std::cout << std::left << std::setw(30) << "instance" << std::setw(13) << "search" << std::right << std::setw(8) << "solved"
            << std::setw(7) << "cost" << std::setw(10) << "expanded" << std::setw(10) << "ground s" << std::setw(10) << "search s"
            << std::setw(10) << "total s" << "\n";
  for (const Run& row : rows) {
    const std::string cell = first_cell(row.instance, 30);
    std::cout << std::left << std::setw(30) << cell << std::setw(13) << row.search << std::right << std::setw(8)
              << (row.valid ? "yes" : row.solved ? "INVALID" : "no") << std::setw(7)
              << (row.solved ? std::to_string(static_cast<long>(row.cost)) : "-") << std::setw(10) << row.expanded << std::setw(10)
              << fixed(row.ground_s, 4) << std::setw(10) << fixed(row.search_s, 4) << std::setw(10) << fixed(row.total_s, 4) << "\n";
  }
  score(rows, reference_costs(args.reference_costs));
  const std::vector<std::string> searches = searches_of(args);
  nlohmann::ordered_json runs = nlohmann::ordered_json::array(), summary = nlohmann::ordered_json::array();
  for (const Run& r : rows) {
    runs.push_back({{"instance", r.instance},
                    {"domain_folder", r.domain_folder},
                    {"domain", r.domain.string()},
                    {"problem", r.problem.string()},
                    {"search", r.search},
                    {"solved", r.solved},
                    {"valid", r.valid},
                    {"reason", r.reason},
                    {"cost", r.cost},
                    {"plan_length", r.length},
                    {"expanded", r.expanded},
                    {"evaluated", r.evaluated},
                    {"grounding_seconds_median", r.ground_s},
                    {"search_seconds_median", r.search_s},
                    {"total_seconds_median", r.total_s},
                    {"runs", r.runs},
                    {"score", r.score}});
  }
  print_summary(rows, searches, summary);
  nlohmann::ordered_json out{{"runs", runs}, {"per_domain", summary}};
  if (args.parse_objects > 0) {
    const double seconds = parse_seconds(args.parse_objects, args.runs);
    std::cout << "\nparsing a generated Blocksworld problem of " << args.parse_objects << " objects: " << std::fixed
              << std::setprecision(3) << seconds << " s (median of " << args.runs << ")\n";
    std::cout.unsetf(std::ios::floatfield);
    out["parse"] = {{"parse_objects", args.parse_objects}, {"parse_seconds_median", seconds}};
  }
  if (!args.json.empty()) {
    write_json_file(args.json, out);
    std::cout << "\nwrote " << args.json.string() << "\n";
  }
  if (!args.csv.empty()) {
    write_csv(args.csv, rows);
    std::cout << "wrote " << args.csv.string() << "\n";
  }
  if (!args.svg.empty()) write_svg(args.svg, rows, searches);
  if (!args.ompl_log.empty()) {
    std::vector<OmplLogPlanner> planners;
    for (const std::string& search : searches) {
      OmplLogPlanner p{search, {}};
      for (const Record& r : records) {
        if (r.at("planner") == search) p.runs.push_back(&r);
      }
      planners.push_back(std::move(p));
    }
    write_ompl_log(args.ompl_log, {"cluttertamp_bench_pddl", settings_of(args).dump(2), 0, args.time_limit}, planners);
  }
  const bool invalid = std::any_of(rows.begin(), rows.end(), [](const Run& r) { return r.solved && !r.valid; });
  if (!refused.empty()) {
    std::cerr << refused.size() << " problem file(s) refused (bad input, listed above)\n";
    return run::ExitCode::bad_input;
  }
  return invalid ? run::ExitCode::internal_error : run::ExitCode::solved;
}

}  // namespace cluttertamp::bench
