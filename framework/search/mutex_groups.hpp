#pragma once
// Internal: mutex groups of a grounded task, from invariants found by synthesis
// (Helmert 2009, "Concise finite-domain representations for PDDL planning tasks"),
// and the finite-domain variables they cover, as Fast Downward's translator chooses them.

#include <cstdint>
#include <vector>

#include "cluttertamp/search/task.hpp"

namespace cluttertamp::search::detail {

/// Sets of fluent facts of which at most one is true in every reachable state.
///
/// An invariant is a set of parts, each a predicate with its arguments split into the
/// invariant's parameters and at most one counted argument; an instance (a value for
/// every parameter) holds the facts whose arguments give those values. An invariant is
/// kept when every operator that adds a fact of an instance also deletes one of the same
/// instance that its precondition requires, and never adds two: then no operator raises
/// an instance's count. Candidates start as one part per predicate and counted argument
/// and are refined with the deletes of an operator that breaks them.
///
/// The check runs on the grounded operators, so it proves the invariant for the reachable
/// task the grounder found, which is what the groups are used on. Conditional effects are
/// treated conservatively: two adds of one instance in different effects break it.
///
/// A group is an instance with exactly one fact true initially (Fast Downward's
/// translator keeps the same ones). `work_budget` bounds the operator effects examined:
/// past it, the invariants proven so far are kept, the same on every machine.
struct MutexGroups {
  std::vector<std::vector<FactId>> groups;  ///< each sorted, no duplicates
  std::size_t invariants = 0;               ///< invariants proven
  std::size_t candidates = 0;               ///< candidates examined
  bool complete = true;                     ///< false when the work budget ran out
  /// choose_variables(task, groups): the successor order and the landmark factory both
  /// read them, and choosing them twice cost as much as finding the groups.
  std::vector<std::vector<FactId>> variables;
};
/// The groups, and the variables chosen from them.
MutexGroups find_mutex_groups(const Task& task, std::uint64_t work_budget);

/// Per operator: 1 when its precondition needs two facts of one mutex group, so that no
/// reachable state applies it (Fast Downward's translator drops these operators too).
/// Such operators still achieve their effects in the delete relaxation, where they
/// would give heuristics and landmarks ways that do not exist.
std::vector<char> never_applicable(const Task& task, const MutexGroups& mutexes);

/// Per fact: its place when facts are ordered as Fast Downward's translator orders
/// atoms, by predicate name and then argument names (byte-wise).
std::vector<std::uint32_t> atom_order(const Task& task);

/// Finite-domain variables as Fast Downward's translator chooses them: groups taken
/// greedily, largest first (of equal ones, the last in atom order), each taking only
/// the facts no earlier choice took, until no group has two uncovered facts; every
/// fluent fact left over is a variable of its own. Facts the goal needs false stay on
/// their own. Each returned variable lists its facts in atom order (the translator's
/// value order), and the variables come in the translator's order (by those lists). A
/// variable's value is also "none of those" when none of its facts holds.
std::vector<std::vector<FactId>> choose_variables(const Task& task, const MutexGroups& mutexes);

}  // namespace cluttertamp::search::detail
