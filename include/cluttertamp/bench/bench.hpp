#pragma once
// The benchmarks of `cluttertamp bench` and `cluttertamp compare`: the papers'
// experiments and the speed goals, each a function from its arguments to an exit code:
// 0 when it ran, 2 on bad input, 3 on a fault; with check_goals, 1 when a goal it
// reports (see each) was missed. Tables go to stdout, progress to stderr.

#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "cluttertamp/export.hpp"

namespace cluttertamp::bench {

/// How much a command prints: errors only, the default, or also why each step went.
enum class Verbosity { quiet, normal, verbose };

/// Which runs of a bench one process does: run i when i % count == index (a
/// deterministic partition, interleaved so that every shard gets its share of each
/// table's rows).
struct Shard {
  std::size_t index = 0, count = 1;
  bool holds(std::size_t run) const { return run % count == index; }
};

/// "K/N" as the command line gives it: 0 <= K < N. Throws InputError naming `option`.
CLUTTERTAMP_API Shard parse_shard(const std::string& text, const std::string& option = "--shard");

/// How a bench's runs are spread and recorded: --shard K/N, -j N, --records FILE.
struct SweepOptions {
  Shard shard;
  /// Child processes sharing this shard's runs (each run single-threaded, results as
  /// with 1); 1: the runs run in this process.
  int jobs = 1;
  /// JSON Lines file of this shard's runs (written as FILE.partial while they run,
  /// renamed when all are done); empty: none.
  std::filesystem::path records;
  /// As the command line gave them, for the child processes.
  std::vector<std::filesystem::path> package_paths;
  std::size_t memory_limit_mib = 0;
  /// The cluttertamp program the child processes run; empty: this process's own.
  std::filesystem::path executable;
};

/// A child process of -j failed; its output has the reason. `exit_code` is its own
/// (2: bad input, 3: a fault), for the parent to exit with.
class CLUTTERTAMP_API WorkerFailed : public std::runtime_error {
 public:
  WorkerFailed(int exit_code, const std::string& message);
  ~WorkerFailed() override;
  int exit_code;
};

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
  std::string landmarks = "rhw";         ///< bench pddl: lama-first's landmarks
  int parse_objects = 200000;            ///< bench pddl: objects of the generated problem it parses (0: none)
  double time_limit = 60;                ///< bench pddl, per search; bench retrieval, per run
  int instances = 5;                     ///< bench retrieval: scenes per object count
  std::vector<int> sizes;                ///< bench retrieval: object counts (default 12 16 20)
  std::filesystem::path csv;             ///< bench pddl, retrieval, push
  std::filesystem::path svg;             ///< bench push
  std::filesystem::path push_scenes;     ///< bench push: directory of reach problems
  /// bench push: planner parameters every run takes over its problem file's own (from
  /// --goal-distance, --goal-heading, --steer and --param KEY=VALUE), values as written
  std::map<std::string, std::string> push_overrides;
  std::string pusher = "gripper";        ///< bench physics: "gripper" or "arm" (the robot's, on a planar base)
  std::vector<std::string> tables;       ///< bench retrieval: "I", "V", "VI" (default I)
  std::vector<std::string> planners;     ///< bench retrieval: only these rows' planners; bench push: rrt, kpiece, guided (default all)
  std::filesystem::path table_vi_scenes; ///< bench retrieval: shelf16-min{2,3,4}.yaml
  double min_gap = 0.0;                  ///< bench retrieval: m between generated cylinders (0: the paper's)
  /// bench retrieval: --robot given, so generated shelves go where that robot reaches
  /// them (scenes::fit_shelf_to_robot, as `generate --robot` places them)
  bool fit_to_robot = false;
  double table_v_width = 0.0;            ///< bench retrieval: Table V cabinet width, m; 0: ShelfSpec's
  std::string mobile_tables = "fig9";    ///< bench mobile: "fig9" (Tian et al.'s Fig. 9 tables) or "random"
  /// bench mobile: the seeds of the tables chosen (by mobile_tables); empty: not chosen
  /// yet (the bench chooses them first and hands them to its shards' child processes)
  std::vector<std::uint64_t> mobile_table_seeds;
  std::filesystem::path sweep_file;      ///< bench sweep: the sweep file (io::load_sweep_file)
  std::vector<std::filesystem::path> problems;      ///< compare: its stream problems
  std::vector<std::filesystem::path> plugin_paths;  ///< compare: searched before each problem's own
  std::vector<std::string> occlusion_layouts;  ///< bench occlusion: "columns", "random" (default both)
  Verbosity verbosity = Verbosity::normal;
  int runs = 3;                          ///< runs per instance (seeds seed, seed + 1, ...)
  /// Exit code 1 when a goal the bench reports is missed; otherwise 0 whenever it ran.
  bool check_goals = false;
  SweepOptions sweep;  ///< bench retrieval
  /// OMPL's benchmark log of the runs (for ompl_benchmark_statistics, Planner Arena); empty: none.
  std::filesystem::path ompl_log;
  /// false: only run the runs and write the records (a child process of -j).
  bool report = true;
};
struct CompareArgs {
  std::vector<std::filesystem::path> problems;  ///< stream problems (task: pddl)
  int runs = 5;
  std::uint64_t seed = 0;
  std::optional<double> time_limit;  ///< per run; default: each problem's
  std::optional<std::filesystem::path> json, csv, svg;
  std::vector<std::filesystem::path> plugin_paths;
  Verbosity verbosity = Verbosity::normal;
  bool check_goals = false;  ///< exit code 1 when a run was not solved
  SweepOptions sweep;        ///< --shard, -j, --records: compare runs as a sweep
  std::filesystem::path ompl_log;  ///< OMPL's benchmark log of the runs; empty: none
};
/// {adaptive, incremental} x {pruned, all movable} on each problem, `runs` seeds each:
/// a table beside Tian et al.'s Table IV; goal: every run solved.
CLUTTERTAMP_API int compare(const CompareArgs& args);

/// `cluttertamp bench merge`: records files of one sweep's shards reported as one run.
struct MergeArgs {
  std::vector<std::filesystem::path> files;
  std::filesystem::path json, csv, svg, records;  ///< empty: not written; records: the merged records file
  std::filesystem::path ompl_log;                 ///< OMPL's benchmark log; empty: not written
  bool check_goals = false;
  Verbosity verbosity = Verbosity::normal;
};
/// The tables, CSV, JSON and plots of the records in `args.files`, as the bench that
/// wrote them reports an unsharded run of the same runs; the exit code is that report's.
CLUTTERTAMP_API int merge(const MergeArgs& args);

/// A child process of `-j`: runs the shard `sweep.shard` of the sweep whose bench and
/// settings `settings_file` holds (written by the parent) and writes its records.
CLUTTERTAMP_API int sweep_worker(const std::filesystem::path& settings_file, const SweepOptions& sweep);

/// The exit code of a bench that ran: 1 when `goals_met` is false and the user asked
/// for --check-goals, else 0.
CLUTTERTAMP_API int goal_exit_code(bool check_goals, bool goals_met);

/// Every problem of a sweep file (args.sweep_file) with every planner of its grid and
/// every seed: a row per problem and planner (success, median time, |O_r|, steps);
/// goal: every run solved.
CLUTTERTAMP_API int file_sweep(const BenchArgs& args);

/// FK, IK, collision and sweep query times; goals: the speed goals it prints.
CLUTTERTAMP_API int collision(const BenchArgs& args);
/// The occlusion planner on generated occlusion shelves (Table II of Tian et al.);
/// goal: success >= 95 % and the median time <= 1 s for every size.
CLUTTERTAMP_API int occlusion(const BenchArgs& args);
/// retrieval_graph with a mobile manipulator on generated tables, initial L = 1,
/// |n_g.NodeCol| and |O| (Table III of Tian et al.); goal: L = 1 moves at most 2.2
/// objects on average with a median <= 1 s. A table check that the time limit ends
/// stops it: exit code 1.
CLUTTERTAMP_API int mobile(const BenchArgs& args);
/// Pushing physics speed (times real time) on a generated shelf; goal: >= 20 times
/// real time with 10 objects (none for another size).
CLUTTERTAMP_API int physics(const BenchArgs& args);
/// Every problem of a folder tree in the IPC layout with each search: a table per
/// instance (each plan checked by the validator) and per domain folder (coverage, IPC
/// quality score, median plan length and time). Exit code 3 when a plan failed
/// validation; 2 when a file was refused (after all the rest ran).
CLUTTERTAMP_API int pddl(const BenchArgs& args);
/// Grasp, motion and pick-and-place medians; goals: the speed goals it prints.
CLUTTERTAMP_API int samplers(const BenchArgs& args);
/// Tables I, V and VI of Tian et al.; no goal.
CLUTTERTAMP_API int retrieval(const BenchArgs& args);
/// RRT, KPIECE and guided reaching through clutter on shelf scenes, beside Papallas &
/// Dogar's Fig. 6; goal: guided beats both on success rate.
CLUTTERTAMP_API int push(const BenchArgs& args);

}  // namespace cluttertamp::bench
