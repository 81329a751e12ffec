#include "search/universal.hpp"

#include <algorithm>
#include <functional>
#include <set>
#include <string>
#include <vector>

namespace cluttertamp::search::detail {

namespace {

using pddl::Formula;
using Kind = Formula::Kind;

std::set<std::string> fluent_predicates(const pddl::Domain& domain) {
  std::set<std::string> out;
  std::function<void(const pddl::Effect&)> visit = [&](const pddl::Effect& e) {
    if (e.kind == pddl::Effect::Kind::add || e.kind == pddl::Effect::Kind::remove) out.insert(e.atom.predicate);
    for (const pddl::Effect& c : e.children) visit(c);
  };
  for (const pddl::Action& a : domain.actions) visit(a.effect);
  for (const pddl::DerivedRule& r : domain.derived) out.insert(r.head.name);
  return out;
}

bool mentions_fluent(const Formula& f, const std::set<std::string>& fluents) {
  if (f.kind == Kind::atom) return fluents.count(f.atom.predicate) > 0;
  return std::any_of(f.children.begin(), f.children.end(), [&](const Formula& c) { return mentions_fluent(c, fluents); });
}

// True when the disjunctive normal form of `f` may multiply with the objects: a fluent
// under a disjunction, an implication or a negated compound. (Static atoms are decided
// while grounding and fold away.)
bool branches_on_fluents(const Formula& f, const std::set<std::string>& fluents) {
  switch (f.kind) {
    case Kind::atom:
    case Kind::truth: return false;
    case Kind::negation: return f.children[0].kind != Kind::atom && mentions_fluent(f.children[0], fluents);
    case Kind::disjunction:
    case Kind::implication: return mentions_fluent(f, fluents);
    default:
      return std::any_of(f.children.begin(), f.children.end(),
                         [&](const Formula& c) { return branches_on_fluents(c, fluents); });
  }
}

bool contains(const std::vector<std::string>& names, const std::string& name) {
  return std::find(names.begin(), names.end(), name) != names.end();
}

// The variables of `f` that no quantifier inside it binds, in order of appearance.
void free_variables(const Formula& f, std::vector<std::string>& bound, std::vector<std::string>& out) {
  if (f.kind == Kind::atom) {
    for (const pddl::Term& t : f.atom.args) {
      if (t.variable && !contains(bound, t.name) && !contains(out, t.name)) out.push_back(t.name);
    }
    return;
  }
  const std::size_t outer = bound.size();
  for (const pddl::TypedName& v : f.variables) bound.push_back(v.name);
  for (const Formula& c : f.children) free_variables(c, bound, out);
  bound.resize(outer);
}

Formula atom_formula(pddl::Atom atom) {
  Formula f;
  f.kind = Kind::atom;
  f.where = atom.where;
  f.atom = std::move(atom);
  return f;
}

Formula compound(Kind kind, std::vector<Formula> children, const SourceLocation& where) {
  Formula f;
  f.kind = kind;
  f.children = std::move(children);
  f.where = where;
  return f;
}

class Compiler {
 public:
  explicit Compiler(pddl::Domain& domain) : domain_(domain), fluents_(fluent_predicates(domain)) {}

  bool changed() const { return made_ > 0; }

  void compile(pddl::Action& action) {
    action_ = &action;
    scope_ = action.parameters;
    context_.clear();
    const Formula& pre = action.precondition;
    if (pre.kind == Kind::atom) context_.push_back(pre.atom);
    if (pre.kind == Kind::conjunction) {
      for (const Formula& c : pre.children) {
        if (c.kind == Kind::atom) context_.push_back(c.atom);
      }
    }
    rewrite(action.precondition, true);
  }

 private:
  void rewrite(Formula& f, bool positive) {
    switch (f.kind) {
      case Kind::negation: rewrite(f.children[0], !positive); return;
      case Kind::implication:
        rewrite(f.children[0], !positive);
        rewrite(f.children[1], positive);
        return;
      case Kind::conjunction:
      case Kind::disjunction:
        for (Formula& c : f.children) rewrite(c, positive);
        return;
      case Kind::exists:
      case Kind::forall: {
        const std::size_t outer = scope_.size();
        scope_.insert(scope_.end(), f.variables.begin(), f.variables.end());
        rewrite(f.children[0], positive);  // inner quantifiers first
        if (f.kind == Kind::forall && positive && branches_on_fluents(f.children[0], fluents_)) f = axiom_for(f);
        scope_.resize(outer);
        return;
      }
      default: return;
    }
  }

  const pddl::TypedName& variable(const std::string& name) const {
    for (auto it = scope_.rbegin(); it != scope_.rend(); ++it) {
      if (it->name == name) return *it;
    }
    static const pddl::TypedName untyped{};  // types {"object"}
    return untyped;  // a variable the parser let through unbound: any object
  }

  std::string fresh_name() {
    std::string name;
    do {
      name = "forall-" + action_->name + "-" + std::to_string(++made_);
    } while (domain_.predicates.count(name));
    return name;
  }

  // (forall (?x) (imply A_static (Q ?x ?free...))) with
  // (Q ?x ?free...) := (and <context atoms on ?free> A_static body), where A_static are
  // the static atoms of the body's antecedent (if it is an implication): the
  // precondition's normal form is then one conjunction of Q atoms, one per object its
  // static atoms admit, and the relaxed heuristics see each of them (a negated derived
  // predicate would leave them blind to the forall).
  Formula axiom_for(const Formula& forall) {
    const Formula& body = forall.children[0];
    std::vector<std::string> bound, free;
    free_variables(forall, bound, free);
    std::vector<std::string> head_variables;
    for (const pddl::TypedName& v : forall.variables) head_variables.push_back(v.name);
    head_variables.insert(head_variables.end(), free.begin(), free.end());

    pddl::DerivedRule rule;
    rule.head.name = fresh_name();
    rule.head.where = rule.where = forall.where;
    for (const std::string& v : head_variables) {
      pddl::TypedName p = variable(v);
      p.name = v;
      rule.head.parameters.push_back(p);
    }
    std::vector<Formula> conjuncts = context_on(free);
    std::vector<Formula> antecedent;
    if (body.kind == Kind::implication) antecedent = static_atoms(body.children[0]);
    conjuncts.insert(conjuncts.end(), antecedent.begin(), antecedent.end());
    conjuncts.push_back(body);
    rule.body = conjuncts.size() == 1 ? conjuncts[0] : compound(Kind::conjunction, std::move(conjuncts), forall.where);

    pddl::Atom head{rule.head.name, {}, forall.where};
    for (const std::string& v : head_variables) head.args.push_back({v, true, forall.where});
    domain_.predicates[rule.head.name] = rule.head;
    domain_.derived.push_back(std::move(rule));

    Formula replaced = forall;
    replaced.children[0] = atom_formula(std::move(head));
    if (!antecedent.empty()) {
      Formula condition = antecedent.size() == 1 ? antecedent[0] : compound(Kind::conjunction, antecedent, forall.where);
      replaced.children[0] = compound(Kind::implication, {condition, replaced.children[0]}, forall.where);
    }
    return replaced;
  }

  // The precondition's positive atoms that mention a free variable, the others of their
  // variables quantified: they hold wherever the new predicate is asked.
  std::vector<Formula> context_on(const std::vector<std::string>& free) const {
    std::vector<Formula> out;
    for (const pddl::Atom& a : context_) {
      if (a.predicate == "=" || shadowed(a)) continue;
      std::vector<pddl::TypedName> others;
      bool relevant = false;
      for (const pddl::Term& t : a.args) {
        if (!t.variable) continue;
        if (contains(free, t.name)) relevant = true;
        else if (std::none_of(others.begin(), others.end(), [&](const pddl::TypedName& o) { return o.name == t.name; })) {
          pddl::TypedName o = variable(t.name);
          o.name = t.name;
          others.push_back(o);
        }
      }
      if (!relevant) continue;
      Formula held = atom_formula(a);
      if (!others.empty()) {
        Formula some = compound(Kind::exists, {held}, a.where);
        some.variables = others;
        held = some;
      }
      out.push_back(std::move(held));
    }
    return out;
  }

  // True when a quantifier around the forall rebinds a variable of the action-level atom
  // `a`: there the name means another variable, and the atom says nothing about it.
  bool shadowed(const pddl::Atom& a) const {
    return std::any_of(a.args.begin(), a.args.end(), [&](const pddl::Term& t) {
      if (!t.variable) return false;
      return std::count_if(scope_.begin(), scope_.end(), [&](const pddl::TypedName& v) { return v.name == t.name; }) > 1;
    });
  }

  // The positive atoms of a conjunction (or an atom) that no action changes.
  std::vector<Formula> static_atoms(const Formula& f) const {
    std::vector<Formula> out;
    if (f.kind == Kind::atom && f.atom.predicate != "=" && !fluents_.count(f.atom.predicate)) out.push_back(f);
    if (f.kind == Kind::conjunction) {
      for (const Formula& c : f.children) {
        const std::vector<Formula> inner = static_atoms(c);
        out.insert(out.end(), inner.begin(), inner.end());
      }
    }
    return out;
  }

  pddl::Domain& domain_;
  std::set<std::string> fluents_;
  pddl::Action* action_ = nullptr;
  std::vector<pddl::TypedName> scope_;
  std::vector<pddl::Atom> context_;
  int made_ = 0;
};

}  // namespace

std::optional<pddl::Domain> with_universal_axioms(const pddl::Domain& domain) {
  const std::set<std::string> fluents = fluent_predicates(domain);
  std::function<bool(const Formula&)> needed = [&](const Formula& f) {
    if (f.kind == Kind::forall && branches_on_fluents(f.children[0], fluents)) return true;
    return std::any_of(f.children.begin(), f.children.end(), needed);
  };
  if (std::none_of(domain.actions.begin(), domain.actions.end(),
                   [&](const pddl::Action& a) { return needed(a.precondition); })) {
    return std::nullopt;
  }
  pddl::Domain compiled = domain;
  Compiler compiler(compiled);
  for (pddl::Action& a : compiled.actions) compiler.compile(a);
  if (!compiler.changed()) return std::nullopt;  // only under negation: left as it is
  return compiled;
}

}  // namespace cluttertamp::search::detail
