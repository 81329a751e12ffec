#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace cluttertamp::search {

using FactId = std::int32_t;
using OperatorId = std::int32_t;

/// Facts that must be true and facts that must be false.
struct Condition {
  std::vector<FactId> positive;
  std::vector<FactId> negative;
};

/// An effect that applies when its condition holds in the state the operator is
/// applied in.
struct ConditionalEffect {
  Condition condition;
  std::vector<FactId> add;
  std::vector<FactId> del;
};

/// A ground action. Several operators may share a name when a disjunctive
/// precondition was split.
struct Operator {
  std::string name;  ///< "(action arg ...)"
  Condition precondition;
  std::vector<FactId> add;  ///< unconditional; never also in `del`
  std::vector<FactId> del;
  std::vector<ConditionalEffect> conditional;
  double cost = 1.0;
};

/// A ground derived-predicate rule: head holds when the body does. Rules of a
/// stratum are evaluated to a fixpoint after all lower strata.
struct Axiom {
  FactId head;
  Condition body;
  int stratum = 0;
};

/// A grounded planning task: fluent and derived facts only (static facts are folded
/// away), operators, axioms and a goal in disjunctive normal form.
struct Task {
  std::vector<std::string> fact_names;  ///< "(predicate arg ...)"
  std::vector<bool> derived;            ///< per fact: computed by axioms
  std::vector<FactId> initial;          ///< fluent facts true initially
  std::vector<Operator> operators;
  std::vector<Axiom> axioms;            ///< sorted by stratum
  std::vector<Condition> goal;          ///< satisfied when any disjunct holds; empty: unsatisfiable
  bool unit_cost = true;                ///< no (:metric minimize (total-cost)): every operator costs 1

  std::size_t fact_count() const { return fact_names.size(); }
};

}  // namespace cluttertamp::search
