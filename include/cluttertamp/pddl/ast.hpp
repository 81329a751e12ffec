#pragma once

#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "cluttertamp/core/diagnostics.hpp"

namespace cluttertamp::pddl {

/// A typed name: a parameter, a quantified variable, an object or a constant.
/// `types` holds one type, or several for (either ...); "object" when untyped.
struct TypedName {
  std::string name;
  std::vector<std::string> types{"object"};
  SourceLocation where;
};

/// A variable (?x) or a constant / object name.
struct Term {
  std::string name;
  bool variable = false;
  SourceLocation where;
};

/// (predicate term...), also (= a b).
struct Atom {
  std::string predicate;
  std::vector<Term> args;
  SourceLocation where;
};

/// A goal description.
struct Formula {
  enum class Kind { atom, negation, conjunction, disjunction, implication, exists, forall, truth };
  Kind kind = Kind::truth;
  Atom atom;                      ///< atom
  std::vector<Formula> children;  ///< negation: 1; implication: 2 (if, then); quantifiers: 1
  std::vector<TypedName> variables;  ///< quantifiers
  SourceLocation where;
};

/// A numeric expression of a cost: a number or a function term.
struct CostExpression {
  std::optional<double> number;
  Atom function;  ///< when not a number: (f args)
  SourceLocation where;
};

/// An effect: literals, conjunctions, (forall ...), (when ...), (increase (total-cost) ...).
struct Effect {
  enum class Kind { add, remove, conjunction, forall, when, increase };
  Kind kind = Kind::conjunction;
  Atom atom;                      ///< add, remove
  std::vector<Effect> children;   ///< conjunction; forall and when: 1
  std::vector<TypedName> variables;  ///< forall
  Formula condition;              ///< when
  CostExpression cost;            ///< increase
  SourceLocation where;
};

struct PredicateDecl {
  std::string name;
  std::vector<TypedName> parameters;
  SourceLocation where;
};

struct Action {
  std::string name;
  std::vector<TypedName> parameters;
  Formula precondition;  ///< truth when absent
  Effect effect;
  SourceLocation where;
};

/// (:derived (head ?x...) body): the head's predicate is derived, never changed by actions.
struct DerivedRule {
  PredicateDecl head;
  Formula body;
  SourceLocation where;
};

struct Domain {
  std::string name;
  std::string file;
  std::set<std::string> requirements;
  std::map<std::string, std::vector<std::string>> types;  ///< type -> parent types ("object" is the root)
  std::vector<TypedName> constants;
  std::map<std::string, PredicateDecl> predicates;
  std::map<std::string, PredicateDecl> functions;  ///< cost functions, incl. total-cost
  std::vector<Action> actions;
  std::vector<DerivedRule> derived;
  SourceLocation where;
  /// What was suspect but accepted (a predicate declared twice, a cost function used
  /// without a declaration), located; the caller decides whether to show them.
  std::vector<Diagnostic> warnings;

  const Action* find_action(const std::string& name) const;
  /// True when `type` equals `ancestor` or descends from it.
  bool is_subtype(const std::string& type, const std::string& ancestor) const;
};

struct NumericFact {
  Atom function;
  double value = 0;
};

struct Problem {
  std::string name;
  std::string domain_name;
  std::string file;
  std::vector<TypedName> objects;
  std::vector<Atom> init;
  std::vector<NumericFact> numeric_init;
  Formula goal;
  bool minimize_total_cost = false;
  SourceLocation where;
};

}  // namespace cluttertamp::pddl
