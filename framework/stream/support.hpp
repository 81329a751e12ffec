#pragma once
// Internal: which stream-certified facts an action plan relies on (PDDLStream's
// "preimage"), found by evaluating the plan's preconditions, derived predicates and
// goal on the facts of a FactBase.

#include <optional>
#include <set>
#include <string>

#include "cluttertamp/pddl/ast.hpp"
#include "stream/fact_base.hpp"

namespace cluttertamp::stream::detail {

/// The facts a formula's truth value rests on.
struct Support {
  std::set<FactKey> facts;    ///< static facts that must hold (optimistic ones need streams)
  std::set<FactKey> negated;  ///< facts of negated tests that must come out false

  std::size_t optimistic_size(const FactBase& base) const;
  void merge(const Support& other);
};

class SupportEvaluator {
 public:
  /// `negated_tests`: predicates certified by tests that the domain uses negated; they
  /// are false unless a test certified them. Without `optimistic`, optimistic facts
  /// and objects count as absent (to check a plan with real facts only).
  SupportEvaluator(const pddl::Domain& domain, FactBase& base, std::set<std::string> negated_tests, bool optimistic);

  /// The support of `formula` having truth value `polarity`, or nothing when it has the
  /// other value. Of several ways to hold, the one needing fewest optimistic facts.
  std::optional<Support> support(const pddl::Formula& formula, const Env& env, const State& state, bool polarity);

  /// Applies an action's effect to `before` into `after` (deletes first, then adds;
  /// conditions read `before`), adding the
  /// support of each condition's truth value to `support`. False when a condition has
  /// no defined value (a derived predicate recursing too deeply).
  bool apply(const pddl::Effect& effect, const Env& env, const State& before, State& after, Support& support);

  bool is_fluent(const std::string& predicate) const { return changed_.count(predicate) > 0; }

 private:
  std::optional<Support> atom(const pddl::Atom& atom, const Env& env, const State& state, bool polarity);
  std::optional<Support> quantified(const pddl::Formula& f, const Env& env, const State& state, bool polarity);
  template <class Visit>
  bool each_fluent_witness(const pddl::Formula& f, Env& local, const State& state, Visit&& visit);
  bool collect(const pddl::Effect& effect, const Env& env, const State& before, State& adds, State& deletes,
               Support& support);
  std::optional<Support> best(std::optional<Support> a, std::optional<Support> b) const;

  const pddl::Domain& domain_;
  FactBase& base_;
  std::set<std::string> negated_tests_;
  bool optimistic_;
  std::set<std::string> changed_;
  int depth_ = 0;
};

}  // namespace cluttertamp::stream::detail
