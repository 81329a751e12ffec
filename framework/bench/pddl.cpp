// `cluttertamp bench pddl`: time, expansions and plan cost per instance and search, so
// runs can be compared with other planners.
#include <algorithm>
#include <chrono>
#include <fstream>
#include <iomanip>
#include <iostream>

#include <nlohmann/json.hpp>

#include "bench/json_file.hpp"
#include "cluttertamp/bench/bench.hpp"
#include "bench/statistics.hpp"
#include "cluttertamp/pddl/parser.hpp"
#include "cluttertamp/run/runner.hpp"
#include "cluttertamp/search/grounding.hpp"
#include "cluttertamp/search/planner.hpp"

namespace cluttertamp::bench {

namespace fs = std::filesystem;

namespace {

struct Pair {
  fs::path domain, problem;
};

// Every <dir>/<family>/p*.pddl with that family's domain*.pddl (typed-p* with domain-typed).
std::vector<Pair> instances(const fs::path& root) {
  std::vector<Pair> out;
  std::vector<fs::path> families;
  for (const auto& e : fs::directory_iterator(root)) {
    if (e.is_directory()) families.push_back(e.path());
  }
  std::sort(families.begin(), families.end());
  for (const fs::path& family : families) {
    std::vector<fs::path> problems;
    for (const auto& e : fs::directory_iterator(family)) {
      const std::string name = e.path().filename().string();
      if (e.is_regular_file() && name.ends_with(".pddl") && name.rfind("domain", 0) != 0) problems.push_back(e.path());
    }
    std::sort(problems.begin(), problems.end(), [](const fs::path& a, const fs::path& b) {
      // p4 before p10: by length, then by name.
      const std::string x = a.filename().string(), y = b.filename().string();
      return x.size() != y.size() ? x.size() < y.size() : x < y;
    });
    for (const fs::path& p : problems) {
      const std::string name = p.filename().string();
      fs::path domain = family / "domain.pddl";
      if (!fs::exists(domain)) domain = family / (name.rfind("typed-", 0) == 0 ? "domain-typed.pddl" : "domain-untyped.pddl");
      if (fs::exists(domain)) out.push_back({domain, p});
    }
  }
  return out;
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

int pddl(const BenchArgs& args) {
  const std::vector<Pair> pairs = instances(args.pddl_instances);
  if (pairs.empty()) throw InputError({args.pddl_instances.string(), 0, 0}, "no PDDL instances found here");
  const std::vector<std::string> searches = args.searches.empty() ? std::vector<std::string>{"lazy-gbfs-ff", "astar-lmcut"} : args.searches;
  nlohmann::ordered_json rows = nlohmann::ordered_json::array();
  std::cout << std::left << std::setw(26) << "instance" << std::setw(14) << "search" << std::right << std::setw(8)
            << "solved" << std::setw(8) << "cost" << std::setw(11) << "expanded" << std::setw(12) << "ground s"
            << std::setw(12) << "search s" << std::setw(12) << "total s" << "\n";
  for (const Pair& pair : pairs) {
    const pddl::Domain domain = pddl::load_domain(pair.domain);
    const pddl::Problem problem = pddl::load_problem(pair.problem, domain);
    const std::string name = pair.problem.parent_path().filename().string() + "/" + pair.problem.stem().string();
    for (const std::string& algorithm : searches) {
      std::vector<double> ground_s, search_s, total_s;
      search::SearchResult last;
      for (int run = 0; run < args.runs; ++run) {
        const auto t0 = std::chrono::steady_clock::now();
        search::GroundingStats stats;
        search::Task task;
        const auto stopped = [&](std::string reason) {  // grounding's failure is this instance's result
          last = {};
          last.reason = std::move(reason);
          ground_s.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
          search_s.push_back(0.0);
          total_s.push_back(ground_s.back());
        };
        try {
          task = search::ground(domain, problem, &stats, args.time_limit);  // the limit holds grounding too
        } catch (const search::TimeLimit&) {
          stopped("time limit (grounding)");
          break;
        } catch (const search::TooLarge& e) {
          stopped(std::string("grounding: ") + e.what());
          break;
        }
        search::SearchOptions options;
        options.algorithm = algorithm;
        options.time_limit =
            std::max(0.0, args.time_limit - std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
        last = search::plan(task, options);
        ground_s.push_back(stats.seconds);
        search_s.push_back(last.statistics.seconds);
        total_s.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
        if (!last.solved) break;  // a time-out does not get faster
      }
      std::cout << std::left << std::setw(26) << name << std::setw(14) << algorithm << std::right << std::setw(8)
                << (last.solved ? "yes" : "no") << std::setw(8) << (last.solved ? std::to_string(static_cast<long>(last.cost)) : "-")
                << std::setw(11) << last.statistics.expanded << std::fixed << std::setprecision(4) << std::setw(12)
                << median(ground_s) << std::setw(12) << median(search_s) << std::setw(12) << median(total_s) << "\n";
      std::cout.unsetf(std::ios::floatfield);
      rows.push_back({{"instance", name},
                      {"domain", pair.domain.string()},
                      {"problem", pair.problem.string()},
                      {"search", algorithm},
                      {"solved", last.solved},
                      {"reason", last.solved ? "" : last.reason},
                      {"cost", last.cost},
                      {"plan_length", last.plan.size()},
                      {"expanded", last.statistics.expanded},
                      {"evaluated", last.statistics.evaluated},
                      {"grounding_seconds_median", median(ground_s)},
                      {"search_seconds_median", median(search_s)},
                      {"total_seconds_median", median(total_s)},
                      {"runs", ground_s.size()}});
    }
  }
  if (args.parse_objects > 0) {
    const double seconds = parse_seconds(args.parse_objects, args.runs);
    std::cout << "\nparsing a generated Blocksworld problem of " << args.parse_objects << " objects: " << std::fixed
              << std::setprecision(3) << seconds << " s (median of " << args.runs << ")\n";
    std::cout.unsetf(std::ios::floatfield);
    rows.push_back({{"parse_objects", args.parse_objects}, {"parse_seconds_median", seconds}});
  }
  if (!args.json.empty()) {
    write_json_file(args.json, rows);
    std::cout << "\nwrote " << args.json.string() << "\n";
  }
  return run::ExitCode::solved;
}

}  // namespace cluttertamp::bench
