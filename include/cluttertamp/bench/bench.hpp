#pragma once
// The benchmarks of `cluttertamp bench` and `cluttertamp compare`: the papers'
// experiments and the speed goals, each a function from its arguments to an exit code
// (0: the goal it checks met; see each). Tables go to stdout, progress to stderr.

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "cluttertamp/export.hpp"

namespace cluttertamp::bench {

/// How much a command prints: errors only, the default, or also why each step went.
enum class Verbosity { quiet, normal, verbose };

struct BenchArgs {
  std::string what;  ///< "collision", "pddl", "samplers", "retrieval", "physics" or "push"
  std::uint64_t seed = 1;
  std::size_t samples = 5000;
  int objects = 20;
  std::filesystem::path json;  ///< empty: no JSON file
  std::filesystem::path robot;  ///< robot description file
  std::filesystem::path pddl_instances;  ///< bench pddl: a folder of problems, or of such folders (IPC layout)
  int per_domain = 0;                    ///< bench pddl: the first N problems of each folder; 0: all
  std::filesystem::path reference_costs; ///< bench pddl: "folder/problem cost" lines for the quality score
  std::vector<std::string> searches;     ///< bench pddl
  int parse_objects = 200000;            ///< bench pddl: objects of the generated problem it parses (0: none)
  double time_limit = 60;                ///< bench pddl, per search; bench retrieval, per run
  int instances = 5;                     ///< bench retrieval: scenes per object count
  std::vector<int> sizes;                ///< bench retrieval: object counts (default 12 16 20)
  std::filesystem::path csv;             ///< bench pddl, retrieval, push
  std::filesystem::path svg;             ///< bench push
  std::filesystem::path push_scenes;     ///< bench push: directory of reach problems
  double goal_distance = 0.005;          ///< bench push: ReachTolerances::distance for every planner, m
  double goal_heading = 0.5;             ///< bench push: ReachTolerances::heading for every planner, rad
  double steer = 0.0;                    ///< bench push: KinodynamicSettings::steer for every planner's reach
  std::vector<std::string> tables;       ///< bench retrieval: "I", "V", "VI" (default I)
  std::vector<std::string> planners;     ///< bench retrieval: only these rows' planners (default all)
  std::filesystem::path table_vi_scenes; ///< bench retrieval: shelf16-min{2,3,4}.yaml
  double min_gap = 0.0;                  ///< bench retrieval: m between generated cylinders (0: the paper's)
  /// bench retrieval: --robot given, so generated shelves go where that robot reaches
  /// them (scenes::fit_shelf_to_robot, as `generate --robot` places them)
  bool fit_to_robot = false;
  double table_v_width = 0.0;            ///< bench retrieval: Table V cabinet width, m; 0: ShelfSpec's
  std::string mobile_tables = "fig9";    ///< bench mobile: "fig9" (Tian et al.'s Fig. 9 tables) or "random"
  std::vector<std::string> occlusion_layouts;  ///< bench occlusion: "columns", "random" (default both)
  Verbosity verbosity = Verbosity::normal;
  int runs = 3;                          ///< bench pddl
};
struct CompareArgs {
  std::vector<std::filesystem::path> problems;  ///< stream problems (task: pddl)
  int runs = 5;
  std::uint64_t seed = 0;
  std::optional<double> time_limit;  ///< per run; default: each problem's
  std::optional<std::filesystem::path> json, csv, svg;
  std::vector<std::filesystem::path> plugin_paths;
  Verbosity verbosity = Verbosity::normal;
};
/// {adaptive, incremental} x {pruned, all movable} on each problem, `runs` seeds each:
/// a table beside Tian et al.'s Table IV; exit code 0 when every run solved, else 1.
CLUTTERTAMP_API int compare(const CompareArgs& args);

/// FK, IK, collision and sweep query times; exit code 0 when every speed goal is met, 1 when one is missed.
CLUTTERTAMP_API int collision(const BenchArgs& args);
/// The occlusion planner on generated occlusion shelves (Table II of Tian et al.);
/// exit code 0 when success >= 95 % and the median time <= 1 s for every size, else 1.
CLUTTERTAMP_API int occlusion(const BenchArgs& args);
/// retrieval_graph with a mobile manipulator on generated tables, initial L = 1,
/// |n_g.NodeCol| and |O| (Table III of Tian et al.); exit code 0 when L = 1 moves at
/// most 2.2 objects on average with a median <= 1 s, else 1.
CLUTTERTAMP_API int mobile(const BenchArgs& args);
/// Pushing physics speed (times real time) on a generated shelf; exit code 0 when the
/// 10-object goal (>= 20) is met or another size was asked for, 1 otherwise.
CLUTTERTAMP_API int physics(const BenchArgs& args);
/// Every problem of a folder tree in the IPC layout with each search: a table per
/// instance (each plan checked by the validator) and per domain folder (coverage, IPC
/// quality score, median plan length and time). Exit code 0; 1 when a plan failed
/// validation; 2 when a file was refused (after all the rest ran).
CLUTTERTAMP_API int pddl(const BenchArgs& args);
/// Grasp, motion and pick-and-place medians; exit code 0 when every goal is met.
CLUTTERTAMP_API int samplers(const BenchArgs& args);
/// Tables I, V and VI of Tian et al.; exit code 0.
CLUTTERTAMP_API int retrieval(const BenchArgs& args);
/// RRT, KPIECE and guided reaching through clutter on shelf scenes, beside Papallas &
/// Dogar's Fig. 6; exit code 0 when guided beats both on success rate, 1 otherwise.
CLUTTERTAMP_API int push(const BenchArgs& args);

}  // namespace cluttertamp::bench
