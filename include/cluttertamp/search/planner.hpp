#pragma once

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "cluttertamp/export.hpp"
#include "cluttertamp/search/task.hpp"

namespace cluttertamp::search {

/// Search algorithms by name (`cluttertamp pddl --search NAME`):
///   lazy-gbfs-ff   greedy best-first, lazy evaluation, h_FF with preferred operators
///                  (the default; like LAMA's first iteration without landmarks)
///   eager-gbfs-ff  greedy best-first, eager evaluation, h_FF, preferred operators
///   gbfs-add       greedy best-first, eager, h_add
///   wastar-ff      weighted A* (weight 5 unless SearchOptions::weight), h_FF
///   astar-hmax     A* with h_max: optimal
///   astar-lmcut    A* with LM-cut: optimal, much better informed than h_max
///   astar-blind    A* with h = 0 (uniform cost): optimal
CLUTTERTAMP_API const std::vector<std::string>& search_names();

struct SearchOptions {
  std::string algorithm = "lazy-gbfs-ff";
  double time_limit = 1e9;              ///< seconds
  std::uint64_t max_expansions = ~0ull;
  double weight = 5.0;                  ///< wastar only
  /// Only plans cheaper than this (in the task's action costs): a path that reaches it
  /// is not followed. The greedy searches may then miss a cheaper plan that reaches a
  /// state first found by a dearer path; the A* searches and wastar do not.
  double cost_bound = std::numeric_limits<double>::infinity();
};

struct SearchStatistics {
  std::uint64_t expanded = 0;
  std::uint64_t generated = 0;
  std::uint64_t evaluated = 0;
  double seconds = 0;
};

struct SearchResult {
  bool solved = false;
  std::string reason;             ///< why not solved: "time limit", "expansion limit", "no plan exists"
  std::vector<OperatorId> plan;
  double cost = 0;
  SearchStatistics statistics;
};

/// Runs a search on a grounded task. Throws std::invalid_argument for an unknown
/// algorithm. Every returned plan is applicable from the initial state and reaches the
/// goal (the search checks it again before returning).
CLUTTERTAMP_API SearchResult plan(const Task& task, const SearchOptions& options);

/// Heuristic value of the initial state, for tests: "hmax", "hadd", "hff", "lmcut".
/// Returns infinity for a dead end.
CLUTTERTAMP_API double initial_heuristic(const Task& task, const std::string& heuristic);

}  // namespace cluttertamp::search
