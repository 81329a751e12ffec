#include "search/grounder.hpp"

#include <set>

namespace cluttertamp::search::detail {

Grounder::Dnf Grounder::conjoin(const Dnf& a, const Dnf& b) {
  // A disjunction holding the empty conjunction is true whatever else it holds: the
  // other side alone (a forall of implications with statically true consequents would
  // otherwise multiply out to 2^k disjuncts).
  if (is_true(a)) return b;
  if (is_true(b)) return a;
  Dnf out;
  for (const auto& x : a) {
    for (const auto& y : b) {
      std::vector<Lit> c = x;
      bool contradiction = false;
      for (const Lit& l : y) {
        bool present = false;
        for (const Lit& m : c) {
          if (m.atom == l.atom) {
            present = true;
            contradiction = contradiction || m.positive != l.positive;
          }
        }
        if (!present) c.push_back(l);
      }
      if (!contradiction) out.push_back(std::move(c));
      if (out.size() > kMaxDisjuncts) throw TooManyDisjuncts();
    }
  }
  return out;
}

Grounder::Known Grounder::literal(const CAtom& a, std::vector<int>& b, bool negated, Lit& out) const {
  bool value = false;
  if (a.predicate < 0) {
    value = object_of(a.args[0], b) == object_of(a.args[1], b);
  } else {
    int found = find_ground(a, b);
    if (rec_ && rec_->reusable) {
      // An atom not interned yet may be reached later: interned, its state is noted.
      if (found < 0) found = const_cast<Grounder&>(*this).intern(a, b);
      note_atom(found);
    }
    if (found >= 0 && reached_[found]) {
      if (fluent_[a.predicate]) {
        out = Lit{found, !negated};
        return Known::no;
      }
      value = initially_[found];
    }  // else unreachable: false in every reachable state
  }
  return value != negated ? Known::truth : Known::falsity;
}

bool Grounder::is_literal_conjunction(const CFormula& f) {
  switch (f.kind) {
    case Formula::Kind::truth:
    case Formula::Kind::atom: return true;
    case Formula::Kind::negation: return f.children[0].kind == Formula::Kind::atom;
    case Formula::Kind::conjunction:
      return std::all_of(f.children.begin(), f.children.end(), [](const CFormula& c) { return is_literal_conjunction(c); });
    default: return false;
  }
}

bool Grounder::is_atom_conjunction(const CFormula& f) {
  switch (f.kind) {
    case Formula::Kind::truth: return true;
    case Formula::Kind::atom: return f.atom.predicate >= 0;
    case Formula::Kind::conjunction:
      return std::all_of(f.children.begin(), f.children.end(), [](const CFormula& c) { return is_atom_conjunction(c); });
    default: return false;
  }
}

bool Grounder::literals(const CFormula& f, std::vector<int>& b, bool negated, std::vector<Lit>& out) const {
  switch (f.kind) {
    case Formula::Kind::truth: return true;
    case Formula::Kind::negation: return literals(f.children[0], b, !negated, out);
    case Formula::Kind::conjunction:
      for (const CFormula& c : f.children) {
        if (!literals(c, b, negated, out)) return false;
      }
      return true;
    default: break;
  }
  Lit l{};
  const Known known = literal(f.atom, b, negated, l);
  if (known != Known::no) return known == Known::truth;
  // As conjoin(): an atom once, and both of its values contradict.
  for (const Lit& m : out) {
    if (m.atom == l.atom) return m.positive == l.positive;
  }
  out.push_back(l);
  return true;
}

Grounder::Dnf Grounder::dnf(const CFormula& f, std::vector<int>& b, bool negated) const {
  const Dnf truth{{}}, falsity{};
  switch (f.kind) {
    case Formula::Kind::truth: return negated ? falsity : truth;
    case Formula::Kind::atom: {
      Lit l{};
      switch (literal(f.atom, b, negated, l)) {
        case Known::truth: return truth;
        case Known::falsity: return falsity;
        case Known::no: return Dnf{{l}};
      }
      return truth;
    }
    case Formula::Kind::negation: return dnf(f.children[0], b, !negated);
    case Formula::Kind::conjunction:
    case Formula::Kind::disjunction: {
      const bool conjunction = (f.kind == Formula::Kind::conjunction) != negated;
      Dnf out = conjunction ? truth : falsity;
      for (const CFormula& c : f.children) {
        Dnf part = dnf(c, b, negated);
        if (conjunction) {
          out = conjoin(out, part);
          if (out.empty()) return out;  // false
        } else {
          if (is_true(part)) return truth;
          out.insert(out.end(), part.begin(), part.end());
          if (out.size() > kMaxDisjuncts) throw TooManyDisjuncts();
        }
      }
      return out;
    }
    case Formula::Kind::implication: {
      // (imply A B) = (or (not A) B); negated: (and A (not B)).
      if (negated) return conjoin(dnf(f.children[0], b, false), dnf(f.children[1], b, true));
      Dnf out = dnf(f.children[0], b, true);
      if (is_true(out)) return truth;  // the condition is statically false
      Dnf then = dnf(f.children[1], b, false);
      if (is_true(then)) return truth;  // the consequent is statically true
      out.insert(out.end(), then.begin(), then.end());
      if (out.size() > kMaxDisjuncts) throw TooManyDisjuncts();
      return out;
    }
    case Formula::Kind::exists:
    case Formula::Kind::forall: {
      const bool conjunction = (f.kind == Formula::Kind::forall) != negated;
      Dnf out = conjunction ? truth : falsity;
      bool decided = false;  // the quantifier's value is known: stop expanding
      // An (exists ...) is false for values that make a positive top-level atom of its
      // body unreachable: only the witnesses need expanding (stream problems quantify
      // over every pose and trajectory, thousands of pairs per derived atom).
      const bool existential = f.kind == Formula::Kind::exists && !negated;
      if (const CAtom* witness = existential ? covering_witness(f) : nullptr) {
        each_witness(f, *witness, b, [&] {
          check_deadline();
          Dnf part = dnf(f.children[0], b, false);
          if (is_true(part)) {
            out = truth;
            return true;
          }
          out.insert(out.end(), part.begin(), part.end());
          if (out.size() > kMaxDisjuncts) throw TooManyDisjuncts();
          return false;
        });
        return out;
      }
      std::function<void(std::size_t)> each = [&](std::size_t k) {
        if (k == f.slots.size()) {
          check_deadline();
          Dnf part = dnf(f.children[0], b, negated);
          if (conjunction) {
            out = conjoin(out, part);
            decided = out.empty();  // false
          } else if (is_true(part)) {
            out = truth;
            decided = true;
          } else {
            out.insert(out.end(), part.begin(), part.end());
          }
          if (out.size() > kMaxDisjuncts) throw TooManyDisjuncts();
          return;
        }
        const std::vector<int>* objects = f.domains[k];
        std::vector<int> witnesses;
        if (existential && witness_values(f, k, b, witnesses)) objects = &witnesses;
        else note_objects();
        for (int o : *objects) {
          b[f.slots[k]] = o;
          each(k + 1);
          if (decided) return;
        }
      };
      each(0);
      return out;
    }
  }
  return truth;
}

FactId Grounder::fact(int atom) {
  if (static_cast<std::size_t>(atom) >= fact_ids_.size()) fact_ids_.resize(atoms_.size(), -1);
  FactId& id = fact_ids_[atom];
  if (id < 0) {
    id = static_cast<FactId>(task_.fact_names.size());
    std::string name = "(" + predicate_names_[atoms_[atom].first];
    for (int o : atoms_[atom].second) (name += ' ') += object_names_[o];
    task_.fact_names.push_back(name + ")");
    task_.derived.push_back(derived_[atoms_[atom].first]);
  }
  return id;
}

Condition Grounder::condition(const std::vector<Lit>& conjunction) {
  Condition c;
  const auto positives = static_cast<std::size_t>(std::count_if(conjunction.begin(), conjunction.end(), [](const Lit& l) { return l.positive; }));
  c.positive.reserve(positives);
  c.negative.reserve(conjunction.size() - positives);
  for (const Lit& l : conjunction) (l.positive ? c.positive : c.negative).push_back(fact(l.atom));
  std::sort(c.positive.begin(), c.positive.end());
  std::sort(c.negative.begin(), c.negative.end());
  return c;
}

void Grounder::ground_effect(const CEffect& e, std::vector<int>& b, const Dnf& cond, Operator& op,
                             std::vector<std::pair<Dnf, std::pair<std::vector<Lit>, bool>>>& conditional, double& cost) {
  switch (e.kind) {
    case Effect::Kind::add:
    case Effect::Kind::remove: {
      const int a = intern(e.atom, b);
      const bool add = e.kind == Effect::Kind::add;
      if (!add) note_atom(a);
      if (!add && !reached_[a]) return;  // deleting what never holds changes nothing
      if (cond.size() == 1 && cond[0].empty()) {
        (add ? op.add : op.del).push_back(fact(a));
      } else if (!cond.empty()) {
        conditional.push_back({cond, {{Lit{a, true}}, add}});
      }
      return;
    }
    case Effect::Kind::when:
      ground_effect(e.children[0], b, conjoin(cond, dnf(e.condition, b, false)), op, conditional, cost);
      return;
    case Effect::Kind::forall: {
      note_objects();
      std::function<void(std::size_t)> each = [&](std::size_t k) {
        if (k == e.slots.size()) {
          ground_effect(e.children[0], b, cond, op, conditional, cost);
          return;
        }
        for (int o : *e.domains[k]) {
          b[e.slots[k]] = o;
          each(k + 1);
        }
      };
      each(0);
      return;
    }
    case Effect::Kind::increase: {
      if (task_.unit_cost) return;  // without (:metric minimize (total-cost)) costs do not count
      if (e.cost_number) {
        cost += *e.cost_number;
      } else {
        std::vector<int> key{e.cost_function.predicate};
        for (int a : ground_args(e.cost_function, b)) key.push_back(a);
        auto it = function_values_.find(key);
        if (it == function_values_.end()) {
          std::string name = "(";
          for (const auto& [fn, id] : function_ids_) {
            if (id == key[0]) name += fn;
          }
          for (std::size_t i = 1; i < key.size(); ++i) name += " " + object_names_[key[i]];
          throw InputError(e.cost_where, "the initial state of " + problem_->file + " gives no value for the cost " + name + ")");
        }
        cost += it->second;
        if (rec_) rec_->costs.emplace_back(key, it->second);
      }
      return;
    }
    case Effect::Kind::conjunction:
      for (const CEffect& c : e.children) ground_effect(c, b, cond, op, conditional, cost);
      return;
  }
}

// Strata of derived predicates: a rule's head lies above every derived predicate its
// body negates, and no lower than those it uses positively.
std::vector<int> Grounder::stratify() {
  const std::size_t n = predicate_names_.size();
  std::vector<int> stratum(n, 0);
  std::function<void(const Formula&, bool, std::vector<std::pair<int, bool>>&)> uses =
      [&](const Formula& f, bool negated, std::vector<std::pair<int, bool>>& out) {
        if (f.kind == Formula::Kind::atom && f.atom.predicate != "=") {
          const int p = predicate_ids_.at(f.atom.predicate);
          if (derived_[p]) out.push_back({p, negated});
        }
        const bool flips = f.kind == Formula::Kind::negation;  // quantifiers keep polarity
        for (std::size_t i = 0; i < f.children.size(); ++i) {
          const bool antecedent = f.kind == Formula::Kind::implication && i == 0;
          uses(f.children[i], negated != (flips || antecedent), out);
        }
      };
  std::vector<std::pair<int, std::vector<std::pair<int, bool>>>> rules;
  for (const pddl::DerivedRule& r : domain_.derived) {
    rules.push_back({predicate_ids_.at(r.head.name), {}});
    uses(r.body, false, rules.back().second);
  }
  for (std::size_t round = 0; round <= n + 1; ++round) {
    bool changed = false;
    for (const auto& [head, body] : rules) {
      for (const auto& [p, negated] : body) {
        const int need = stratum[p] + (negated ? 1 : 0);
        if (stratum[head] < need) {
          stratum[head] = need;
          changed = true;
        }
      }
    }
    if (!changed) return stratum;
    if (round == n + 1) break;
  }
  throw InputError({domain_.file, 0, 0}, "derived predicates are not stratified (a predicate depends on its own negation)");
}

bool Grounder::still_valid(const Cached& c) const {
  if (!c.computed || !c.reusable || c.generation != generation_) return false;
  if (c.objects != kNoObjects && c.objects != object_names_.size()) return false;
  for (const auto& [atom, was] : c.atoms) {
    if (state(atom) != was) return false;
  }
  for (const auto& [predicate, count] : c.witnesses) {
    if (reached_tuples_.of(predicate).size() != count) return false;
  }
  for (const auto& [key, value] : c.costs) {
    const auto it = function_values_.find(key);
    if (it == function_values_.end() || it->second != value) return false;
  }
  return true;
}

void Grounder::ground_instance(std::size_t schema, std::span<const int> parameters, Cached& record,
                               std::vector<Operator>& operators, std::vector<Axiom>& axioms) {
  const Schema& s = schemas_[schema];
  record.restart(generation_);
  rec_ = keep_ ? &record : nullptr;
  struct Stop {
    Cached*& rec;
    ~Stop() { rec = nullptr; }
  } stop{rec_};
  std::vector<int>& b = binding_;
  b.assign(static_cast<std::size_t>(std::max(1, s.slot_count)), -1);
  for (std::size_t p = 0; p < parameters.size(); ++p) b[s.parameters[p]] = parameters[p];
  // The precondition's disjuncts: of a conjunction of literals, the one conjunction_
  // holds, or none when it is false (no DNF's nested vectors for the STRIPS case).
  Dnf pre;
  std::size_t disjuncts = 0;
  conjunction_.clear();
  try {
    if (!s.literal_precondition) {
      pre = dnf(s.precondition, b, false);
      disjuncts = pre.size();
    } else {
      disjuncts = literals(s.precondition, b, false, conjunction_) ? 1 : 0;
    }
  } catch (const TooManyDisjuncts&) {
    too_many(s.where, s.axiom ? "the body of derived predicate '" + s.name + "'" : "the precondition of '" + s.name + "'");
  }
  const auto disjunct = [&](std::size_t k) -> const std::vector<Lit>& { return s.literal_precondition ? conjunction_ : pre[k]; };
  record.computed = true;
  if (s.axiom) {
    const int head = intern(s.head, b);
    for (std::size_t k = 0; k < disjuncts; ++k) {
      axioms.push_back({fact(head), condition(disjunct(k)), strata_.empty() ? 0 : strata_[s.head.predicate]});
    }
    return;
  }
  if (disjuncts == 0) return;
  Operator op;
  std::size_t length = s.name.size() + 2;
  for (int o : parameters) length += object_names_[o].size() + 1;
  op.name.reserve(length);
  op.name += '(';
  op.name += s.name;
  for (int o : parameters) (op.name += ' ') += object_names_[o];
  op.name += ')';
  std::vector<std::pair<Dnf, std::pair<std::vector<Lit>, bool>>> conditional;
  double cost = 0;
  // Effects go to the scratch vectors first, then to vectors of their exact size.
  add_.clear();
  del_.clear();
  op.add.swap(add_);
  op.del.swap(del_);
  static const Dnf kTruth{{}};
  ground_effect(s.effect, b, kTruth, op, conditional, cost);
  op.cost = task_.unit_cost ? 1.0 : cost;
  // Add after delete: an atom both added and deleted ends up true.
  std::sort(op.add.begin(), op.add.end());
  op.add.erase(std::unique(op.add.begin(), op.add.end()), op.add.end());
  std::sort(op.del.begin(), op.del.end());
  op.del.erase(std::unique(op.del.begin(), op.del.end()), op.del.end());
  std::erase_if(op.del, [&](FactId f) { return std::binary_search(op.add.begin(), op.add.end(), f); });
  add_.swap(op.add);
  del_.swap(op.del);
  op.add.assign(add_.begin(), add_.end());
  op.del.assign(del_.begin(), del_.end());
  for (const auto& [cond, lit] : conditional) {
    for (const auto& conjunction : cond) {
      ConditionalEffect ce;
      ce.condition = condition(conjunction);
      (lit.second ? ce.add : ce.del).push_back(fact(lit.first[0].atom));
      op.conditional.push_back(std::move(ce));
    }
  }
  for (std::size_t k = 0; k < disjuncts; ++k) {
    Operator& o = operators.emplace_back(k + 1 < disjuncts ? op : std::move(op));
    o.precondition = condition(disjunct(k));
  }
}

}  // namespace cluttertamp::search::detail
