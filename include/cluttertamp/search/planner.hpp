#pragma once

#include <cstdint>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "cluttertamp/export.hpp"
#include "cluttertamp/search/task.hpp"

namespace cluttertamp::search {

/// Search algorithms by name (`cluttertamp pddl --search NAME`):
///   lama-first     LAMA's first iteration (the default): lazy greedy best-first search
///                  alternating h_FF and the landmark count (both counting plan length),
///                  preferred operators of h_FF, boosted on progress
///   lazy-gbfs-ff   greedy best-first, lazy evaluation, h_FF (in the task's costs) with
///                  preferred operators
///   eager-gbfs-ff  greedy best-first, eager evaluation, h_FF, preferred operators
///   gbfs-add       greedy best-first, eager, h_add
///   wastar-ff      weighted A* (weight 5 unless SearchOptions::weight), h_FF
///   astar-hmax     A* with h_max: optimal
///   astar-lmcut    A* with LM-cut: optimal, much better informed than h_max
///   astar-blind    A* with h = 0 (uniform cost): optimal
CLUTTERTAMP_API const std::vector<std::string>& search_names();

struct SearchResult;

/// A search's heuristic value: the initial one, then each lower one (as Fast Downward's
/// "New best heuristic value" lines).
struct SearchProgress {
  std::string heuristic;        ///< "ff", "landmark count", "add", "hmax", "lmcut" or "blind"
  double value = 0;
  std::uint64_t expanded = 0;   ///< expansions before the state was evaluated
  std::uint64_t evaluated = 0;  ///< evaluations, this one included
};

struct SearchOptions {
  std::string algorithm = "lama-first";
  double time_limit = 1e9;              ///< seconds
  std::uint64_t max_expansions = ~0ull;
  double weight = 5.0;                  ///< wastar only
  /// How lama-first and the anytime mode find landmarks: "rhw" (Richter, Helmert &
  /// Westphal, as LAMA) or "zhu-givan" (label propagation). Throws std::invalid_argument
  /// from `plan` for another name.
  std::string landmarks = "rhw";
  /// Only plans cheaper than this (in the task's action costs): a path that reaches it
  /// is not followed. The greedy searches may then miss a cheaper plan that reaches a
  /// state first found by a dearer path; the A* searches and wastar do not.
  double cost_bound = std::numeric_limits<double>::infinity();
  /// After the first plan, search on for cheaper ones as LAMA does (lazy weighted A*
  /// with h_FF and the landmark count, weights 5, 3, 2, 1, then 1 again, each under the
  /// best cost so far) until the time or expansion limit, or until a search proves that
  /// no cheaper plan exists. The limits count over all searches: with a time limit only,
  /// the last plan depends on the machine's speed; with `max_expansions` it does not.
  bool anytime = false;
  /// Called with each plan the anytime mode finds (the first one included), cheapest last.
  std::function<void(const SearchResult&)> on_plan;
  /// Called with each heuristic's initial value and each lower value a search finds
  /// (not during the anytime mode's restarts, which on_plan reports); on the caller's
  /// thread, between expansions.
  std::function<void(const SearchProgress&)> on_progress;
};

struct SearchStatistics {
  std::uint64_t expanded = 0;
  std::uint64_t generated = 0;
  std::uint64_t evaluated = 0;
  double seconds = 0;
  /// The landmarks of lama-first and the anytime mode (0 for other searches).
  std::size_t landmarks = 0;
  std::size_t disjunctive_landmarks = 0;
  std::size_t landmark_orders = 0;
  std::size_t variables = 0;  ///< finite-domain variables of several facts rhw used
  /// Operators left out because their precondition needs two facts of one mutex group.
  std::size_t never_applicable = 0;
  /// Operators left out because they change no variable the goal depends on (in the
  /// causal graph of the finite-domain encoding, as Fast Downward's translator finds them).
  std::size_t irrelevant = 0;
};

struct SearchResult {
  bool solved = false;
  std::string reason;             ///< why not solved: "time limit", "expansion limit", "no plan exists"
  std::vector<OperatorId> plan;
  double cost = 0;
  SearchStatistics statistics;  ///< over all searches of the anytime mode
  int plans_found = 0;          ///< plans found, each cheaper than the one before
  /// Anytime mode: why it stopped looking for cheaper plans ("no cheaper plan exists",
  /// "time limit", "expansion limit"); empty otherwise.
  std::string anytime_end;
};

/// Runs a search on a grounded task. Throws std::invalid_argument for an unknown
/// algorithm. Every returned plan is applicable from the initial state and reaches the
/// goal (the search checks it again before returning).
CLUTTERTAMP_API SearchResult plan(const Task& task, const SearchOptions& options);

/// Heuristic value of the initial state, for tests: "hmax", "hadd", "hff", "lmcut".
/// Returns infinity for a dead end.
CLUTTERTAMP_API double initial_heuristic(const Task& task, const std::string& heuristic);

}  // namespace cluttertamp::search
