#pragma once
// Internal to the grounder: universally quantified preconditions as derived predicates.

#include <optional>

#include "cluttertamp/pddl/ast.hpp"

namespace cluttertamp::search::detail {

/// The domain with each (forall (?x) body) of an action's precondition whose body puts a
/// fluent (a predicate an action changes, or a derived one) under a disjunction, an
/// implication or a negated compound replaced by (forall (?x) (imply S (Q ?x ?free...))),
/// Q a new derived predicate holding where the body holds and S the static atoms of the
/// body's antecedent. Expanded to disjunctive normal form, the forall over k objects had
/// up to 2^k disjuncts; now it is a conjunction of k derived atoms that the relaxed
/// heuristics see. Q's rule also requires S and the precondition's positive atoms that
/// mention its free variables (they hold wherever Q is asked), so its instances come
/// from them rather than from every tuple of objects. The names are
/// "forall-<action>-<n>", made unique against the domain's predicates.
/// nullopt when no precondition needs it.
std::optional<pddl::Domain> with_universal_axioms(const pddl::Domain& domain);

}  // namespace cluttertamp::search::detail
