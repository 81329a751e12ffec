#pragma once
// Internal: states as bit sets, successor generation, operator application and axiom
// evaluation of a grounded task.

#include <cstdint>
#include <vector>

#include "cluttertamp/search/task.hpp"

namespace cluttertamp::search::detail {

using State = std::vector<std::uint64_t>;

inline bool holds(const State& s, FactId f) { return (s[f >> 6] >> (f & 63)) & 1u; }
inline void set(State& s, FactId f) { s[f >> 6] |= std::uint64_t{1} << (f & 63); }
inline void clear(State& s, FactId f) { s[f >> 6] &= ~(std::uint64_t{1} << (f & 63)); }

/// Orders a search follows where ties are broken; each may be empty (then an order of
/// ids is used).
struct TieOrder {
  std::vector<std::uint32_t> successor_rank;  ///< per operator: its place among a state's successors
  std::vector<std::uint32_t> initial_rank;    ///< per fact: when the relaxation takes it, if true
  std::vector<std::uint32_t> effect_rank;     ///< per fact: its place among an operator's effects
};

class StateSpace {
 public:
  /// `left_out`: per operator, nonzero for one the search never applies (its
  /// preconditions are mutex, or it changes nothing the goal depends on); empty when the
  /// search may apply all. Heuristics built over this space leave them out too.
  explicit StateSpace(const Task& task, TieOrder order = {}, std::vector<char> left_out = {});

  const Task& task() const { return task_; }
  const std::vector<char>& left_out() const { return left_out_; }
  /// Operator op's cost, from a flat array (searches read it per successor).
  double cost(OperatorId op) const { return cost_[op]; }
  State initial() const;
  bool satisfied(const State& s, const Condition& c) const;
  bool applicable(const State& s, OperatorId op) const {
    const FactId* f = precondition_facts_.data() + precondition_start_[op];
    const FactId* const negative = precondition_facts_.data() + negative_start_[op];
    const FactId* const end = precondition_facts_.data() + precondition_start_[op + 1];
    for (; f != negative; ++f) {
      if (!holds(s, *f)) return false;
    }
    for (; f != end; ++f) {
      if (holds(s, *f)) return false;
    }
    return true;
  }
  bool is_goal(const State& s) const;
  /// The successor of s under an applicable operator, derived facts included.
  State apply(const State& s, OperatorId op) const;
  /// The same into `next` (any size before; no allocation once it has grown).
  void apply(const State& s, OperatorId op, State& next) const;
  const TieOrder& tie_order() const { return order_; }
  /// The operators applicable in s, in successor order, into `out` (cleared first).
  void applicable_operators(const State& s, std::vector<OperatorId>& out) const;
  /// Recomputes the derived facts of s from its fluent facts.
  void evaluate_axioms(State& s) const;
  /// Facts true in s, in increasing order.
  std::vector<FactId> facts(const State& s) const;

 private:
  template <class F>
  void for_each_applicable(const State& s, const F& f) const;

  const Task& task_;
  std::size_t words_;
  // Every operator's precondition in one array (its positive facts, then its negative
  // ones): successor generation tests thousands per state.
  std::vector<FactId> precondition_facts_;
  std::vector<std::uint32_t> precondition_start_, negative_start_;  // per operator (and one past the last)
  std::vector<std::uint32_t> trigger_start_;  // per fact (and one past the last): into triggered_
  std::vector<OperatorId> triggered_;         // per fact: operators whose first precondition it is
  std::vector<OperatorId> always_;                     // operators without positive preconditions
  std::vector<FactId> derived_facts_;
  std::vector<double> cost_;
  TieOrder order_;
  std::vector<char> left_out_;
};

}  // namespace cluttertamp::search::detail
