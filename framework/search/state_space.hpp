#pragma once
// Internal: states as bit sets, successor generation, operator application and axiom
// evaluation of a grounded task.

#include <cstdint>
#include <functional>
#include <vector>

#include "cluttertamp/search/task.hpp"

namespace cluttertamp::search::detail {

using State = std::vector<std::uint64_t>;

inline bool holds(const State& s, FactId f) { return (s[f >> 6] >> (f & 63)) & 1u; }
inline void set(State& s, FactId f) { s[f >> 6] |= std::uint64_t{1} << (f & 63); }
inline void clear(State& s, FactId f) { s[f >> 6] &= ~(std::uint64_t{1} << (f & 63)); }

struct StateHash {
  std::size_t operator()(const State& s) const {
    std::uint64_t h = 1469598103934665603ull;
    for (std::uint64_t w : s) {
      h ^= w + 0x9e3779b97f4a7c15ull + (h << 6) + (h >> 2);
    }
    return static_cast<std::size_t>(h);
  }
};

class StateSpace {
 public:
  explicit StateSpace(const Task& task);

  const Task& task() const { return task_; }
  State initial() const;
  bool satisfied(const State& s, const Condition& c) const;
  bool applicable(const State& s, OperatorId op) const { return satisfied(s, task_.operators[op].precondition); }
  bool is_goal(const State& s) const;
  /// The successor of s under an applicable operator, derived facts included.
  State apply(const State& s, OperatorId op) const;
  /// Calls f(op) for every operator applicable in s.
  void applicable_operators(const State& s, const std::function<void(OperatorId)>& f) const;
  /// Recomputes the derived facts of s from its fluent facts.
  void evaluate_axioms(State& s) const;
  /// Facts true in s, in increasing order.
  std::vector<FactId> facts(const State& s) const;

 private:
  const Task& task_;
  std::size_t words_;
  std::vector<std::vector<OperatorId>> triggered_by_;  // per fact: operators whose first precondition it is
  std::vector<OperatorId> always_;                     // operators without positive preconditions
  std::vector<FactId> derived_facts_;
};

}  // namespace cluttertamp::search::detail
