#pragma once
// Sweep files: problems x planners (with a parameter grid) x seeds, the runs of
// `cluttertamp bench sweep` (format: docs/file-formats.md, "Sweep files").

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "cluttertamp/core/diagnostics.hpp"
#include "cluttertamp/core/parameters.hpp"
#include "cluttertamp/export.hpp"

namespace cluttertamp::io {

inline constexpr int kSweepFormatVersion = 1;

/// One planner of a sweep: a task_planner plugin with its parameters, one point of the
/// file's grid.
struct SweepPlanner {
  /// What the tables call it: the file's `name` (or the plugin's), then the grid's
  /// values, e.g. "retrieval_graph[initial_L=one]".
  std::string label;
  std::string plugin;
  /// The entry's `parameters` with this point's grid values over them.
  Parameters parameters;
  /// The grid's values of this point alone, as "key=value" (empty without a grid).
  std::vector<std::string> grid_values;
  SourceLocation where;
};

/// What a sweep file asks for: every problem with every planner and every seed.
struct SweepSpec {
  std::filesystem::path file;
  std::vector<std::filesystem::path> problems;  ///< absolute
  std::vector<SourceLocation> problem_where;    ///< where each is named
  std::vector<SweepPlanner> planners;           ///< grids expanded, in file order
  std::vector<std::uint64_t> seeds;
  /// Seconds per run (the outer limit); empty: each problem's own `time_limit`.
  std::optional<double> time_limit;
  std::size_t runs() const { return problems.size() * planners.size() * seeds.size(); }
};

/// Reads a sweep file:
///   version: 1
///   problems: [a.yaml, b.yaml]          # relative to the sweep file
///   planners:
///     - plugin: retrieval_graph
///       parameters: {grasp_orders: 3}   # fixed
///       grid: {initial_L: [one, nodecol, objects]}   # every combination one planner
///     - {plugin: exhaustive, name: exhaustive-2, parameters: {max_removals: 2}}
///   seeds: 3                            # 0, 1, 2; or a list [4, 8]
///   time_limit: 60                      # s per run; default: each problem's
/// Throws InputError listing every problem with file:line:column. The problems are
/// named only (each is read when the sweep runs); a missing file is an error here.
CLUTTERTAMP_API SweepSpec load_sweep_file(const std::filesystem::path& file);

}  // namespace cluttertamp::io
