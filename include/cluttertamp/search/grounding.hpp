#pragma once

#include <cstddef>
#include <memory>
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
  std::size_t reused_instances = 0;  ///< Grounding: action and axiom instances taken from an earlier problem
  double seconds = 0;
};

/// Grounds a checked domain and problem by relaxed reachability: only action and
/// axiom instances whose preconditions can hold in the delete relaxation are made
/// (never the cross product of all objects). Static facts are folded away, quantifiers
/// expanded over the objects of their types, preconditions and goals put in
/// disjunctive normal form (a disjunctive precondition splits an operator). Operators
/// come by action name, then by the names of their objects: the order of their names
/// in which Fast Downward's translator sorts them, for names of letters, digits, '-' and
/// '_'. The operators of one split action stay together.
/// Throws InputError (located) for a cost function without a value when costs count or
/// derived predicates that are not stratified; TooLarge for a formula whose normal form
/// exceeds 10000 disjuncts; TimeLimit when grounding takes longer than `time_limit`
/// seconds.
CLUTTERTAMP_API Task ground(const pddl::Domain& domain, const pddl::Problem& problem, GroundingStats* stats = nullptr,
                            double time_limit = 1e9);

/// Grounds a sequence of problems of one domain whose objects only grow (each lists
/// the last one's objects first, in the same order; stream searches ground such a
/// problem each iteration), re-using the work of the earlier ones: reachability is
/// extended from the new initial atoms instead of found again, and an action or axiom
/// instance is grounded again only when an atom its formulas looked at, the witnesses
/// of its quantifiers, the objects of a quantified type or a cost it read changed.
/// A problem that does not extend the last one is grounded afresh.
///
/// The task equals ground()'s up to fact and operator numbering, except that it may
/// hold operators, axioms and facts that only an earlier problem could reach (reachability
/// only grows): they are never applicable, because static preconditions are decided by
/// the current problem's initial state. Same exceptions as ground(); after one, the next
/// problem is grounded afresh. `domain` must outlive this object.
class CLUTTERTAMP_API Grounding {
 public:
  explicit Grounding(const pddl::Domain& domain);
  ~Grounding();
  Grounding(const Grounding&) = delete;
  Grounding& operator=(const Grounding&) = delete;

  Task ground(const pddl::Problem& problem, GroundingStats* stats = nullptr, double time_limit = 1e9);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

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
