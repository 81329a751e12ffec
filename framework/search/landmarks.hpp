#pragma once
// Internal: fact landmarks of the delete relaxation and LAMA's landmark-count heuristic.

#include <chrono>
#include <cstdint>
#include <vector>

#include "cluttertamp/search/task.hpp"
#include "search/heuristics.hpp"

namespace cluttertamp::search::detail {

struct MutexGroups;

/// Fact landmarks: facts (or disjunctions of facts) true at some point of every plan
/// from the initial state, with orders between them. Two ways to find them:
///
/// - Zhu & Givan 2003 (the constructor): label propagation through the relaxed task; a
///   fact's label is the set of facts every relaxed path to it passes through. Every
///   causal fact landmark of the delete relaxation is found. Orders: natural (l' is in
///   l's label) and greedy-necessary (l' is a precondition of every operator that can
///   first achieve l).
/// - Richter, Helmert & Westphal 2008 (`rhw`, LAMA's): back-chaining from the goal. A
///   landmark's first achievers are its achievers applicable in the relaxed task without
///   it; their shared preconditions are landmarks (greedy-necessary), and so are the
///   disjunctions of one precondition of each achiever from one predicate (at most 4
///   facts). In the domain transition graph of a finite-domain variable (the mutex
///   groups of `find_mutex_groups`), a value every path from the initial value to the
///   landmark's passes through is one too (natural). A fact that is not reachable
///   without a landmark, and no operator achieves together with it, is ordered after it.
///   Orders that close a cycle are dropped. Then Hoffmann, Porteous & Sebastia's (2004)
///   reasonable orders: x before landmark l when achieving x undoes l (x is mutex with
///   l, or every achiever of x has an effect mutex with l), for x any landmark if l is a
///   goal, else for the parents (and their ancestors) of a landmark l is greedy-necessary
///   for.
class Landmarks {
 public:
  /// Zhu & Givan. `relaxed` must outlive this. `work_budget` bounds the label operations
  /// (set elements merged). On a task too large for it, the landmarks are the goal facts
  /// only, unordered: still landmarks, found the same way on every machine.
  Landmarks(const RelaxedTask& relaxed, const State& initial, std::uint64_t work_budget);
  /// Richter, Helmert & Westphal on `relaxed`, the relaxation of `task`; both must outlive
  /// the result. `work_budget` bounds the operators and facts visited; past it, the
  /// landmarks found so far are kept and back-chaining stops, the same on every machine.
  /// Throws TimeLimit past `deadline` (the search's outer limit).
  /// `mutexes`, when given, are `task`'s mutex groups (found otherwise).
  static Landmarks rhw(const RelaxedTask& relaxed, const Task& task, const State& initial, std::uint64_t work_budget,
                       std::chrono::steady_clock::time_point deadline = std::chrono::steady_clock::time_point::max(),
                       const MutexGroups* mutexes = nullptr);

  std::size_t size() const { return atoms_.size(); }
  /// Landmark i's first fact in the relaxed task (a task fact, or a complement).
  FactId fact(int i) const { return atoms_[i].front(); }
  /// Landmark i's facts: one, or several for a disjunctive landmark (any one will do).
  const std::vector<FactId>& atoms(int i) const { return atoms_[i]; }
  bool holds(int i, const State& s) const {
    for (FactId f : atoms_[i]) {
      if (relaxed_.holds_in(s, f)) return true;
    }
    return false;
  }
  /// Landmarks ordered before landmark i (natural or greedy-necessary orders).
  const std::vector<int>& parents(int i) const { return parents_[i]; }
  /// Landmarks that landmark i is greedy-necessarily ordered before.
  const std::vector<int>& needed_by(int i) const { return needed_by_[i]; }
  /// Landmarks reasonably ordered before landmark i (`rhw` only): achieving one of them
  /// undoes landmark i, so i is needed again until they are all accepted.
  const std::vector<int>& reasonable_parents(int i) const { return reasonable_[i]; }
  /// True when the fact is in every goal disjunct.
  bool is_goal(int i) const { return goal_[i]; }
  /// The cheapest operator (in the relaxed task's costs) that achieves landmark i.
  double cost(int i) const { return cost_[i]; }
  /// False when the work budget ran out before every landmark was found.
  bool complete() const { return complete_; }
  std::size_t order_count() const;
  std::size_t disjunctive_count() const;
  /// Finite-domain variables with more than one fact that `rhw` used (0 for Zhu & Givan).
  std::size_t variable_count() const { return variables_; }

 private:
  explicit Landmarks(const RelaxedTask& relaxed) : relaxed_(relaxed) {}
  friend class RhwFactory;

  const RelaxedTask& relaxed_;
  std::vector<std::vector<FactId>> atoms_;
  std::vector<std::vector<int>> parents_, needed_by_, reasonable_;
  std::vector<char> goal_;
  std::vector<double> cost_;
  bool complete_ = true;
  std::size_t variables_ = 0;
};

/// LAMA's landmark-count heuristic, with Fast Downward's landmark status: the cost of
/// the landmarks that are future in a state. A landmark is past once it held on the path
/// (intersected over the paths that reach the state) and future while it is not past,
/// and also when it is false and a goal, or false and greedy-necessarily ordered before
/// a landmark not past, or when a landmark reasonably ordered before it is not past. A
/// future landmark stays future until a transition makes it true (one that finds it
/// true already does not count), so a landmark undone by a reasonable order must be
/// achieved again. Future is united over the paths.
class LandmarkCount {
 public:
  explicit LandmarkCount(const Landmarks& landmarks);

  /// The initial state (state id `id`).
  void start(int id, const State& s);
  /// A transition from `parent` (in state `parent_state`) into state `child` (new or
  /// seen before).
  void reach(int parent, int child, const State& parent_state, const State& child_state, bool is_new);
  double value(int id, const State& s) const;

 private:
  std::uint64_t* bits(std::vector<std::uint64_t>& v, int id) { return &v[static_cast<std::size_t>(id) * words_]; }
  const std::uint64_t* bits(const std::vector<std::uint64_t>& v, int id) const {
    return &v[static_cast<std::size_t>(id) * words_];
  }
  static bool test(const std::uint64_t* a, int i) { return (a[i >> 6] >> (i & 63)) & 1u; }
  static void set(std::uint64_t* a, int i) { a[i >> 6] |= std::uint64_t{1} << (i & 63); }
  static void reset(std::uint64_t* a, int i) { a[i >> 6] &= ~(std::uint64_t{1} << (i & 63)); }
  void grow(int id);

  const Landmarks& landmarks_;
  std::size_t words_;
  std::vector<std::uint64_t> past_, future_;  // per state id, words_ words each
  std::vector<char> holds_;                     // per landmark: true in the state reached
};

}  // namespace cluttertamp::search::detail
