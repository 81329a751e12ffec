#pragma once
// Internal: what a search takes from Fast Downward's finite-domain encoding of a task
// (Helmert 2009, "Concise finite-domain representations for PDDL planning tasks"): the
// operators that cannot matter for the goal, and the order in which its successor
// generator lists a state's applicable operators. Greedy searches break ties by the
// order successors are generated in, so this order keeps our expansions close to its.

#include <cstdint>
#include <vector>

#include "cluttertamp/search/task.hpp"
#include "search/mutex_groups.hpp"

namespace cluttertamp::search::detail {

struct SuccessorOrder {
  /// Per operator: 1 when it changes a variable the goal depends on in the causal graph
  /// (an ancestor of a goal variable, or one). The others can be left out of every
  /// search: no plan needs them.
  std::vector<char> relevant;
  /// Per operator: its place in the order successors are listed in. Operators are
  /// ordered by their preconditions as (variable, value) pairs sorted, compared
  /// lexicographically (a prefix first); ties by name, then by id.
  std::vector<std::uint32_t> rank;
  /// Per fact: its variable's place in the search's variable order (variables the goal
  /// does not depend on after all others), and its variable's place before that order
  /// was applied (the translator's: by facts in atom order), which orders an operator's
  /// effects. The delete relaxation takes the initial facts and each operator's effects
  /// in these orders, as Fast Downward's does, so that its supporters tie-break alike.
  std::vector<std::uint32_t> search_variable;
  std::vector<std::uint32_t> translator_variable;
  std::size_t variables = 0;           ///< finite-domain variables, constant ones excluded
  std::size_t relevant_variables = 0;  ///< of those, the ones the goal depends on
};

/// The variables are `mutexes.variables` (derived facts one each), without those whose
/// transition graph reaches no second value. They are ordered as Fast Downward's
/// translator orders them: strongly connected components of the causal graph (edges
/// from precondition and effect-condition variables to effect variables, weighted by
/// how many operators give them) in topological order, each component ordered by
/// greedily taking the variable with the least weight of incoming edges inside it, goal
/// variables last. A variable's values are its facts in atom order, then "none of those".
///
/// Operators marked in `left_out` are neither ranked nor counted in the causal graph
/// (their rank is past every other). Negative preconditions on a variable of several
/// facts do not enter the order (the translator splits such operators).
SuccessorOrder successor_order(const Task& task, const MutexGroups& mutexes, const std::vector<char>& left_out);

}  // namespace cluttertamp::search::detail
