#pragma once
// Internal: fact landmarks of the delete relaxation and LAMA's landmark-count heuristic.

#include <cstdint>
#include <vector>

#include "search/heuristics.hpp"

namespace cluttertamp::search::detail {

/// Fact landmarks: facts true at some point of every plan from the initial state.
/// Found by propagating labels through the relaxed task (Zhu & Givan 2003): a fact's
/// label is the set of facts every relaxed path to it passes through. Every causal
/// fact landmark of the delete relaxation is found. Orders between them:
/// - natural: l' is in l's label, so l' is true strictly before l first is;
/// - greedy-necessary: l' is a precondition of every operator that can first achieve l.
class Landmarks {
 public:
  /// `relaxed` must outlive this. `work_budget` bounds the label operations (set elements merged). On a task too
  /// large for it, the landmarks are the goal facts only, unordered: still landmarks,
  /// found the same way on every machine.
  Landmarks(const RelaxedTask& relaxed, const State& initial, std::uint64_t work_budget);

  std::size_t size() const { return facts_.size(); }
  /// Landmark i's fact in the relaxed task (a task fact, or a complement).
  FactId fact(int i) const { return facts_[i]; }
  bool holds(int i, const State& s) const { return relaxed_.holds_in(s, facts_[i]); }
  /// Landmarks naturally ordered before landmark i.
  const std::vector<int>& parents(int i) const { return parents_[i]; }
  /// Landmarks that landmark i is greedy-necessarily ordered before.
  const std::vector<int>& needed_by(int i) const { return needed_by_[i]; }
  /// True when the fact is in every goal disjunct.
  bool is_goal(int i) const { return goal_[i]; }
  /// The cheapest operator (in the relaxed task's costs) that achieves landmark i.
  double cost(int i) const { return cost_[i]; }
  /// False when the work budget ran out and only the goal facts were kept.
  bool complete() const { return complete_; }
  std::size_t order_count() const;

 private:
  const RelaxedTask& relaxed_;
  std::vector<FactId> facts_;
  std::vector<std::vector<int>> parents_, needed_by_;
  std::vector<char> goal_;
  std::vector<double> cost_;
  bool complete_ = true;
};

/// LAMA's landmark-count heuristic: the cost of the landmarks not yet accepted on the
/// path to a state, plus those accepted that are required again (false, and a goal or
/// greedy-necessarily ordered before one not accepted). A landmark is accepted when it
/// becomes true after all its natural parents were accepted. The accepted set is
/// path-dependent: it is kept per state, intersected over the paths that reach it.
class LandmarkCount {
 public:
  explicit LandmarkCount(const Landmarks& landmarks);

  /// The initial state (state id `id`): its true landmarks are accepted.
  void start(int id, const State& s);
  /// A transition into state `child` (new or seen before) from `parent`.
  void reach(int parent, int child, const State& child_state, bool is_new);
  double value(int id, const State& s) const;

 private:
  std::uint64_t* accepted(int id) { return &accepted_[static_cast<std::size_t>(id) * words_]; }
  const std::uint64_t* accepted(int id) const { return &accepted_[static_cast<std::size_t>(id) * words_]; }
  bool is_accepted(const std::uint64_t* a, int i) const { return (a[i >> 6] >> (i & 63)) & 1u; }

  const Landmarks& landmarks_;
  std::size_t words_;
  std::vector<std::uint64_t> accepted_;  // per state id, words_ words
  std::vector<std::uint64_t> scratch_;
};

}  // namespace cluttertamp::search::detail
