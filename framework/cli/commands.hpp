#pragma once
// The subcommands of the `cluttertamp` program. Each returns a process exit code
// (run::ExitCode) and lets InputError escape for main() to report with exit code 2.

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "cluttertamp/bench/bench.hpp"

namespace cluttertamp::cli {

using Verbosity = bench::Verbosity;
using bench::BenchArgs;
using bench::CompareArgs;

struct PlanArgs {
  std::filesystem::path problem;
  std::optional<std::int64_t> seed;  ///< validated >= 0 by the parser
  std::optional<double> time_limit;
  std::optional<std::string> planner;  ///< replaces the problem's planner.plugin
  std::filesystem::path output = "cluttertamp-out";
  std::vector<std::filesystem::path> plugin_paths;
  bool html = false;  ///< also write OUTPUT/plan.html (the replay page)
  int repeat = 1;     ///< plan this many times; more than one: compare the results (exit 3 when they differ)
  int load = 0;       ///< busy threads on the planner's CPU during every run
  std::optional<std::filesystem::path> expect;  ///< compare the result with this result.json
  Verbosity verbosity = Verbosity::normal;
};
int plan(const PlanArgs& args);

struct ViewArgs {
  std::filesystem::path result;
  std::optional<std::filesystem::path> problem;  ///< instead of the problem result.json names
  std::optional<std::filesystem::path> output;   ///< default: plan.html beside the result
  Verbosity verbosity = Verbosity::normal;
};
int view(const ViewArgs& args);

struct ValidateArgs {
  std::vector<std::filesystem::path> files;
  bool skip_plugins = false;
  std::vector<std::filesystem::path> plugin_paths;
  Verbosity verbosity = Verbosity::normal;
};
int validate(const ValidateArgs& args);

struct PluginsArgs {
  std::vector<std::string> names;  ///< only these plugins (any kind); empty: all
  std::vector<std::filesystem::path> plugin_paths;
  Verbosity verbosity = Verbosity::normal;
};
/// Exit code 2 when a name in `names` is no plugin found.
int plugins(const PluginsArgs& args);

struct PddlArgs {
  std::filesystem::path domain, problem;
  std::string search = "lama-first";
  std::string landmarks = "rhw";     ///< lama-first's and --anytime's landmarks
  double time_limit = 300;
  std::uint64_t max_expansions = ~0ull;
  double weight = 5;
  std::filesystem::path plan_file;  ///< also write the plan here
  bool anytime = false;              ///< search on for cheaper plans after the first
  Verbosity verbosity = Verbosity::normal;
};
/// Prints the plan (IPC format, then "; cost = N") on stdout, statistics on stderr.
int pddl(const PddlArgs& args);

struct ValidatePlanArgs {
  std::filesystem::path domain, problem, plan;
  Verbosity verbosity = Verbosity::normal;
};
/// Exit code 0 for a valid plan, 1 for an invalid one (with the reason), 2 bad input.
int validate_plan(const ValidatePlanArgs& args);

struct GenerateArgs {
  int objects = 12;
  std::uint64_t seed = 1;
  std::filesystem::path output;   ///< the scene file
  std::filesystem::path problem;  ///< also write a problem file here (optional)
  std::filesystem::path robot;
  bool require_removal = true;    ///< keep only scenes whose target needs a removal
  int min_removals = 0;           ///< keep only scenes whose optimal |O_r| (target included) is this; 0: any
  double check_time = 300;        ///< seconds for the exhaustive check of one scene
  double width = 0, depth = 0;    ///< cabinet interior, m; 0: from the object count
  /// m between cylinders and to the walls; unset: ShelfSpec's (0, the paper's recipe) or TableSpec's
  std::optional<double> min_gap;
  int max_attempts = 100;
  bool occlusion = false;  ///< an occlusion shelf (columns of 4 hidden behind a front row)
  std::string occlusion_layout = "columns";  ///< with occlusion: "columns" or "random"
  bool table = false;      ///< a table for a mobile manipulator, reachable from every side
  bool push = false;       ///< a pushing shelf like Papallas & Dogar's, with a reach problem
  bool fit_to_robot = false;  ///< --robot given: the shelf goes where that robot reaches it
  Verbosity verbosity = Verbosity::normal;
};
/// Exit code 0 when a scene was written, 1 when no attempt needed a removal.
int generate(const GenerateArgs& args);

struct GuideArgs {
  std::filesystem::path problem;  ///< a reach problem
  bool automatic = false;         ///< --auto: write the automatic guidance and exit
  /// --auto: the guidance file; serving: the directory the session is saved in.
  std::optional<std::filesystem::path> output;
  int max_guides = 1;
  double diameter = 0.1;  ///< m, every guide's region
  std::string host = "127.0.0.1";
  int port = 8080;        ///< 0: any free port
  double push_time = 10;  ///< s per guide
  std::optional<double> time_limit;     ///< overrides the problem's
  std::optional<std::uint64_t> seed;    ///< overrides the problem's
  Verbosity verbosity = Verbosity::normal;
};
/// --auto: writes the automatic guidance of a reach problem (exit code 0). Otherwise
/// serves the operator's page until stopped (exit code 0 when the session reached the
/// target, 1 when not).
int guide(const GuideArgs& args);

struct ObserveArgs {
  std::filesystem::path file;  ///< a scene or problem file
  std::vector<std::string> remove;
  double min_visible_fraction = 0.3;
  bool json = false;
};
/// Prints what the scene's camera sees; exit code 0.
int observe(const ObserveArgs& args);

struct SelfCollisionArgs {
  std::filesystem::path robot;  ///< robot description file
  std::size_t samples = 20000;
  std::uint64_t seed = 1;
  Verbosity verbosity = Verbosity::normal;
  std::filesystem::path srdf;  ///< --srdf: also write the disabled pairs as an SRDF
};
/// Counts self contacts per link pair over random configurations; exit code 0.
int self_collisions(const SelfCollisionArgs& args);

}  // namespace cluttertamp::cli
