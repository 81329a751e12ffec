#include "search/grounder.hpp"
#include "search/tuple_order.hpp"

#include <array>
#include <set>

namespace cluttertamp::search::detail {

std::vector<std::uint32_t> InstanceSet::sorted() const {
  int most = 0;
  for (std::size_t k = 0; k < size(); ++k) {
    for (int o : (*this)[k]) most = std::max(most, o);
  }
  return lexicographic_order(size(), bindings_.length(), static_cast<std::uint64_t>(most),
                             [&](std::uint32_t k, std::size_t i) { return static_cast<std::uint64_t>((*this)[k][i]); });
}

namespace {

// Tuples [first, second) of each core atom's predicate are joined.
using Ranges = std::vector<std::pair<std::size_t, std::size_t>>;
constexpr std::size_t kMaxInlineArgs = 16;

// The object a core atom's argument must be under the binding so far, or -1 when free.
int fixed_value(const CTerm& term, const std::vector<int>& binding, const std::vector<bool>& bound) {
  if (!term.variable) return term.value;
  if (term.value == kWildcard || !bound[term.value]) return -1;
  return binding[term.value];
}

// Binds the free arguments of `a` to `tuple` if it agrees with the binding so far and
// the parameters' types; the slots it bound are appended to `newly` (also on failure).
bool bind_tuple(const Schema& s, const CAtom& a, const std::vector<int>& tuple, std::vector<int>& binding,
                std::vector<bool>& bound, int* newly, std::size_t& newly_count) {
  for (std::size_t i = 0; i < a.args.size(); ++i) {
    const CTerm& term = a.args[i];
    if (!term.variable) {
      if (term.value != tuple[i]) return false;
    } else if (term.value == kWildcard) {
      continue;
    } else if (bound[term.value]) {
      if (binding[term.value] != tuple[i]) return false;
    } else {
      // The parameter's type must admit the object.
      if (const std::vector<int>* domain = s.slot_domain[static_cast<std::size_t>(term.value)]) {
        if (!std::binary_search(domain->begin(), domain->end(), tuple[i])) return false;
      }
      binding[term.value] = tuple[i];
      bound[term.value] = true;
      newly[newly_count++] = term.value;
    }
  }
  return true;
}

// Binds the schema's parameters by joining its positive precondition atoms with the
// facts reached so far, then the rest from their types. Where an argument of the next
// atom is already fixed, only the tuples with that object there are tried.
template <class Visit>
void enumerate(const Schema& s, const ReachedTuples& reached, std::size_t k, std::vector<int>& binding,
               std::vector<bool>& bound, const Ranges& ranges, const Visit& visit) {
  if (k < s.core.size()) {
    const CAtom& a = s.core[k];
    const auto& tuples = reached.of(a.predicate);
    // The slots one tuple binds, at most one per argument: on the stack, as this runs
    // for every reached tuple of every core atom.
    std::array<int, kMaxInlineArgs> newly_inline;
    std::vector<int> newly_heap;
    if (a.args.size() > kMaxInlineArgs) newly_heap.resize(a.args.size());
    int* newly = a.args.size() > kMaxInlineArgs ? newly_heap.data() : newly_inline.data();
    auto try_tuple = [&](std::size_t t) {
      std::size_t newly_count = 0;
      if (bind_tuple(s, a, tuples[t], binding, bound, newly, newly_count)) enumerate(s, reached, k + 1, binding, bound, ranges, visit);
      for (std::size_t n = 0; n < newly_count; ++n) bound[newly[n]] = false;
    };
    const std::vector<std::uint32_t>* candidates = nullptr;
    for (std::size_t i = 0; i < a.args.size(); ++i) {
      const int value = fixed_value(a.args[i], binding, bound);
      if (value < 0) continue;
      const std::vector<std::uint32_t>& with = reached.with(a.predicate, i, value);
      if (!candidates || with.size() < candidates->size()) candidates = &with;
    }
    if (!candidates) {
      for (std::size_t t = ranges[k].first; t < ranges[k].second; ++t) try_tuple(t);
      return;
    }
    for (auto it = std::lower_bound(candidates->begin(), candidates->end(), ranges[k].first);
         it != candidates->end() && *it < ranges[k].second; ++it) {
      try_tuple(*it);
    }
    return;
  }
  // Parameters no atom bound: every object of their type.
  for (std::size_t p = 0; p < s.parameters.size(); ++p) {
    const int slot = s.parameters[p];
    if (bound[slot]) continue;
    bound[slot] = true;
    for (int o : *s.parameter_domains[p]) {
      binding[slot] = o;
      enumerate(s, reached, k, binding, bound, ranges, visit);
    }
    bound[slot] = false;
    return;
  }
  visit();
}

}  // namespace

// Delete relaxation, optimistic about everything it cannot decide: negated fluents hold.
bool Grounder::relaxed(const CFormula& f, std::vector<int>& b) const {
  switch (f.kind) {
    case Formula::Kind::truth: return true;
    case Formula::Kind::atom: {
      if (f.atom.predicate < 0) return ground_args(f.atom, b)[0] == ground_args(f.atom, b)[1];
      const int id = find_ground(f.atom, b);
      return id >= 0 && reached_[id];
    }
    case Formula::Kind::negation: {
      const CFormula& c = f.children[0];
      if (c.kind != Formula::Kind::atom) return true;
      if (c.atom.predicate < 0) return ground_args(c.atom, b)[0] != ground_args(c.atom, b)[1];
      if (fluent_[c.atom.predicate]) return true;
      const int id = find_ground(c.atom, b);
      return id < 0 || !initially_[id];
    }
    case Formula::Kind::conjunction:
      return std::all_of(f.children.begin(), f.children.end(), [&](const CFormula& c) { return relaxed(c, b); });
    case Formula::Kind::disjunction:
      return std::any_of(f.children.begin(), f.children.end(), [&](const CFormula& c) { return relaxed(c, b); });
    case Formula::Kind::implication: return true;  // (not IF) may hold
    case Formula::Kind::exists:
    case Formula::Kind::forall: {
      const bool all = f.kind == Formula::Kind::forall;
      if (!all) {
        if (const CAtom* witness = covering_witness(f)) {
          bool holds = false;
          each_witness(f, *witness, b, [&] { return holds = relaxed(f.children[0], b); });
          return holds;
        }
      }
      std::function<bool(std::size_t)> quantify = [&](std::size_t k) -> bool {
        if (k == f.slots.size()) return relaxed(f.children[0], b);
        const std::vector<int>* objects = f.domains[k];
        std::vector<int> witnesses;
        if (!all && witness_values(f, k, b, witnesses)) objects = &witnesses;
        for (int o : *objects) {
          b[f.slots[k]] = o;
          const bool holds = quantify(k + 1);
          if (holds != all) return holds;
        }
        return all;
      };
      return quantify(0);
    }
  }
  return true;
}

// An (exists ...) holds in the relaxation only if its body's positive atoms were
// reached: the values of quantified variable k in reached atoms that agree with the
// variables bound so far are its only candidates. False when no top-level positive
// atom of the body mentions the variable (then every object of its type is tried).
bool Grounder::witness_values(const CFormula& f, std::size_t k, const std::vector<int>& b, std::vector<int>& out) const {
  const CFormula& body = f.children[0];
  const int slot = f.slots[k];
  auto later = [&](int s) { return std::find(f.slots.begin() + static_cast<long>(k) + 1, f.slots.end(), s) != f.slots.end(); };
  auto mentions = [&](const CFormula& c) {
    return c.kind == Formula::Kind::atom && c.atom.predicate >= 0 &&
           std::any_of(c.atom.args.begin(), c.atom.args.end(), [&](const CTerm& t) { return t.variable && t.value == slot; });
  };
  const CFormula* witness = nullptr;
  if (mentions(body)) witness = &body;
  else if (body.kind == Formula::Kind::conjunction) {
    for (const CFormula& c : body.children) {
      if (mentions(c)) {
        witness = &c;
        break;
      }
    }
  }
  if (!witness) return false;
  const CAtom& a = witness->atom;
  note_witness(a.predicate);
  for (const std::vector<int>& tuple : reached_tuples_.of(a.predicate)) {
    int value = -1;
    bool fits = true;
    for (std::size_t i = 0; i < a.args.size() && fits; ++i) {
      const CTerm& t = a.args[i];
      if (!t.variable) fits = t.value == tuple[i];
      else if (t.value == slot) {
        fits = value < 0 || value == tuple[i];  // the variable may appear twice
        value = tuple[i];
      }
      else if (!later(t.value)) fits = b[t.value] == tuple[i];
    }
    if (fits && std::binary_search(f.domains[k]->begin(), f.domains[k]->end(), value)) out.push_back(value);
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return true;
}

// A positive top-level atom of an (exists ...)'s body that mentions every quantified
// variable, or null: its reached tuples are all the bindings worth trying, found in
// one pass (variable by variable, witness_values scans the tuples once per value of
// the variables before).
const CAtom* Grounder::covering_witness(const CFormula& f) const {
  auto covers = [&](const CFormula& c) {
    if (c.kind != Formula::Kind::atom || c.atom.predicate < 0) return false;
    return std::all_of(f.slots.begin(), f.slots.end(), [&](int slot) {
      return std::any_of(c.atom.args.begin(), c.atom.args.end(), [&](const CTerm& t) { return t.variable && t.value == slot; });
    });
  };
  const CFormula& body = f.children[0];
  if (covers(body)) return &body.atom;
  if (body.kind == Formula::Kind::conjunction) {
    for (const CFormula& c : body.children) {
      if (covers(c)) return &c.atom;
    }
  }
  return nullptr;
}

void Grounder::relaxed_effects(const CEffect& e, std::vector<int>& b, std::vector<int>& out) const {
  switch (e.kind) {
    case Effect::Kind::add: {
      // Interning an atom changes only the atom table, not what the domain means.
      auto& self = const_cast<Grounder&>(*this);
      out.push_back(self.intern(e.atom, b));
      break;
    }
    case Effect::Kind::when:
      if (relaxed(e.condition, b)) relaxed_effects(e.children[0], b, out);
      break;
    case Effect::Kind::forall: {
      std::function<void(std::size_t)> each = [&](std::size_t k) {
        if (k == e.slots.size()) {
          relaxed_effects(e.children[0], b, out);
          return;
        }
        for (int o : *e.domains[k]) {
          b[e.slots[k]] = o;
          each(k + 1);
        }
      };
      each(0);
      break;
    }
    case Effect::Kind::conjunction:
      for (const CEffect& c : e.children) relaxed_effects(c, b, out);
      break;
    default: break;
  }
}


// Whether the relaxed test of `f` (relaxed()) holds exactly when the atoms
// collect_core() takes from it are reached, negated atoms aside (fluent ones hold in the
// relaxation; static ones are handled by the callers): conjunctions, atoms, negated
// atoms and (exists ...) whose variables each appear in a positive atom of the body's
// top level that also names a variable from outside (else no core atom holds it).
bool Grounder::core_complete(const CFormula& f, std::vector<int> quantified) const {
  auto is_quantified = [&](const CTerm& t) {
    return t.variable && std::find(quantified.begin(), quantified.end(), t.value) != quantified.end();
  };
  switch (f.kind) {
    case Formula::Kind::truth: return true;
    case Formula::Kind::atom:
      if (f.atom.predicate < 0) return true;
      // collect_core() leaves out an atom whose variables are all quantified.
      return std::none_of(f.atom.args.begin(), f.atom.args.end(), [](const CTerm& t) { return t.variable; }) ||
             std::any_of(f.atom.args.begin(), f.atom.args.end(), [&](const CTerm& t) { return t.variable && !is_quantified(t); });
    case Formula::Kind::negation: return f.children[0].kind == Formula::Kind::atom;
    case Formula::Kind::conjunction:
      return std::all_of(f.children.begin(), f.children.end(), [&](const CFormula& c) { return core_complete(c, quantified); });
    case Formula::Kind::exists: {
      const CFormula& body = f.children[0];
      std::vector<const CFormula*> top;
      if (body.kind == Formula::Kind::conjunction) {
        for (const CFormula& c : body.children) top.push_back(&c);
      } else {
        top.push_back(&body);
      }
      for (int slot : f.slots) {
        const bool witnessed = std::any_of(top.begin(), top.end(), [&](const CFormula* c) {
          return c->kind == Formula::Kind::atom && c->atom.predicate >= 0 &&
                 std::any_of(c->atom.args.begin(), c->atom.args.end(), [&](const CTerm& t) { return t.variable && t.value == slot; });
        });
        if (!witnessed) return false;
      }
      quantified.insert(quantified.end(), f.slots.begin(), f.slots.end());
      return core_complete(body, quantified);
    }
    default: return false;
  }
}

// Reachability accumulates over a session's problems: an atom reached for an earlier
// problem stays reached (the operators it lets in are harmless where it cannot hold:
// their static preconditions fold to false, or the search never reaches them). Only
// what holds initially is the current problem's alone.
void Grounder::explore() {
  auto reach = [&](int a) {
    if (reached_[a]) return;
    reached_[a] = true;
    reached_tuples_.add(atoms_[a].first, atoms_[a].second);
  };
  std::vector<int> now;
  now.reserve(problem_->init.size());
  std::vector<int> key;  // (predicate, args...): most atoms were interned by an earlier problem
  for (const pddl::Atom& a : problem_->init) {
    check_deadline();  // a stream search's optimistic problem has millions of facts
    key.assign(1, predicate_ids_.at(a.predicate));
    for (const pddl::Term& t : a.args) key.push_back(object_index(t.name));
    const auto known = atom_ids_.find(key);
    now.push_back(known != atom_ids_.end() ? known->second : atom_id(key[0], std::vector<int>(key.begin() + 1, key.end())));
  }
  for (int id : init_atoms_) initially_[id] = false;
  for (int id : now) initially_[id] = true;
  // A static atom that no longer holds initially may let in what its negation blocked:
  // the schemas that mention its predicate are looked at again.
  std::vector<bool> gone(predicate_names_.size(), false);
  for (int id : init_atoms_) gone[atoms_[id].first] = gone[atoms_[id].first] || !initially_[id];
  init_atoms_ = std::move(now);
  for (int id : init_atoms_) reach(id);
  // A binding's relaxed precondition can turn true only when an atom of a predicate it
  // mentions is reached: a schema none of whose predicates gained atoms since its last
  // pass has nothing new (stream problems re-derived every trajectory's UnsafeTraj on
  // every pass).
  auto reached_count = [&](const Schema& s) {
    std::size_t n = 0;
    for (int predicate : s.mentioned) n += reached_tuples_.of(predicate).size();
    return n;
  };
  seen_.resize(schemas_.size(), std::numeric_limits<std::size_t>::max());
  seen_objects_.resize(schemas_.size(), 0);
  joined_.resize(schemas_.size());
  for (std::size_t i = 0; i < schemas_.size(); ++i) {
    const auto& mentioned = schemas_[i].mentioned;
    if (std::any_of(mentioned.begin(), mentioned.end(), [&](int p) { return gone[p]; })) {
      seen_[i] = std::numeric_limits<std::size_t>::max();
      joined_[i].clear();  // a negation may hold again: every binding is looked at
    }
  }
  bool changed = true;
  while (changed) {
    changed = false;
    for (std::size_t i = 0; i < schemas_.size(); ++i) {
      const Schema& s = schemas_[i];
      // New objects bring new bindings where a parameter or a quantifier ranges over a type.
      const std::size_t objects = by_type_[i] ? object_names_.size() : 0;
      const bool objects_changed = objects != seen_objects_[i];
      if (!s.conditional) {
        const std::size_t now = reached_count(s);
        if (now == seen_[i] && !objects_changed) continue;
        seen_[i] = now;
      }
      seen_objects_[i] = objects;
      std::vector<int> binding(static_cast<std::size_t>(std::max(1, s.slot_count)), -1);
      std::vector<bool> bound(binding.size(), false);
      std::vector<int> added;
      if (s.conditional || (effect_by_type_[i] && objects_changed)) {
        // A (when ...) condition may have become reachable since an instance was found;
        // a (forall ...) effect reaches the new objects too.
        for (std::size_t k = 0; k < instances_[i].size(); ++k) {
          const std::span<const int> parameters = instances_[i][k];
          std::vector<int> b(binding.size(), -1);
          for (std::size_t p = 0; p < parameters.size(); ++p) b[s.parameters[p]] = parameters[p];
          relaxed_effects(s.effect, b, added);
        }
      }
      std::vector<int> parameters, b;  // visit()'s, reused
      auto visit = [&] {
        check_deadline();
        parameters.clear();
        for (int slot : s.parameters) parameters.push_back(binding[slot]);
        InstanceSet& known = instances_[i];
        if (known.contains(parameters)) return;
        b = binding;
        if (!s.joined_precondition && !relaxed(s.precondition, b)) return;
        known.insert(parameters);
        if (s.axiom) {
          added.push_back(intern(s.head, b));
        } else {
          relaxed_effects(s.effect, b, added);
        }
      };
      // Semi-naive: where only a core atom's new tuple can make a binding newly pass
      // (core_complete_), the bindings with at least one core atom on a tuple reached
      // since the schema's last pass are the new ones: the k-th atom on its new tuples,
      // those before it on their old ones, those after on all.
      std::vector<std::size_t>& last = joined_[i];
      const std::size_t n = s.core.size();
      Ranges ranges(n);
      std::vector<std::size_t> now(n);
      for (std::size_t k = 0; k < n; ++k) now[k] = reached_tuples_.of(s.core[k].predicate).size();
      const bool full = last.size() != n || !core_complete_[i] || objects_changed || s.conditional;
      if (full || n == 0) {
        for (std::size_t k = 0; k < n; ++k) ranges[k] = {0, now[k]};
        enumerate(s, reached_tuples_, 0, binding, bound, ranges, visit);
      } else {
        for (std::size_t delta = 0; delta < n; ++delta) {
          if (last[delta] == now[delta]) continue;
          for (std::size_t k = 0; k < n; ++k) ranges[k] = {k == delta ? last[k] : 0, k < delta ? last[k] : now[k]};
          enumerate(s, reached_tuples_, 0, binding, bound, ranges, visit);
        }
      }
      last = std::move(now);
      for (int a : added) {
        check_deadline();
        if (!reached_[a]) {
          reach(a);
          changed = true;
        }
      }
    }
  }
}

}  // namespace cluttertamp::search::detail
