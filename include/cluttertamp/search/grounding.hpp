#pragma once

#include <cstddef>
#include <stdexcept>

#include "cluttertamp/export.hpp"
#include "cluttertamp/pddl/ast.hpp"
#include "cluttertamp/search/task.hpp"

namespace cluttertamp::search {

struct GroundingStats {
  std::size_t reachable_facts = 0;  ///< relaxed-reachable atoms, static ones included
  std::size_t operators = 0;
  std::size_t axioms = 0;
  std::size_t static_facts = 0;
  double seconds = 0;
};

/// Grounds a checked domain and problem by relaxed reachability: only action and
/// axiom instances whose preconditions can hold in the delete relaxation are made
/// (never the cross product of all objects). Static facts are folded away, quantifiers
/// expanded over the objects of their types, preconditions and goals put in
/// disjunctive normal form (a disjunctive precondition splits an operator).
/// Throws InputError (located) for a cost function without a value when costs count or
/// derived predicates that are not stratified; TooLarge for a formula whose normal form
/// exceeds 10000 disjuncts; TimeLimit when grounding takes longer than `time_limit`
/// seconds.
CLUTTERTAMP_API Task ground(const pddl::Domain& domain, const pddl::Problem& problem, GroundingStats* stats = nullptr,
                            double time_limit = 1e9);

/// Grounding ran out of time: a planning failure, not bad input.
class CLUTTERTAMP_API TimeLimit : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A formula's disjunctive normal form outgrew the grounder ("file:line:column: the
/// precondition of 'a' has more than 10000 disjuncts ..."): a planning failure with its
/// location, not bad input — the file is valid PDDL.
class CLUTTERTAMP_API TooLarge : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace cluttertamp::search
