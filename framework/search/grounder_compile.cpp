#include "search/grounder.hpp"

#include <set>
#include <tuple>

#include "cluttertamp/pddl/parser.hpp"

namespace cluttertamp::search::detail {

const std::vector<int>* Grounder::objects_of(const std::vector<std::string>& types) {
  auto it = type_objects_.find(types);
  if (it != type_objects_.end()) return &it->second;
  std::vector<int>& objects = type_objects_[types];
  for (std::size_t o = 0; o < object_names_.size(); ++o) {
    bool fits = false;
    for (const std::string& own : object_types_[o]) {
      for (const std::string& t : types) fits = fits || domain_.is_subtype(own, t);
    }
    if (fits) objects.push_back(static_cast<int>(o));
  }
  return &objects;
}

CTerm Grounder::term(const pddl::Term& t, const std::map<std::string, int>& scope) const {
  if (t.variable) return {true, scope.at(t.name)};
  return {false, object_index(t.name)};
}

CAtom Grounder::atom(const pddl::Atom& a, const std::map<std::string, int>& scope) const {
  CAtom out;
  out.predicate = a.predicate == "=" ? -1 : predicate_ids_.at(a.predicate);
  for (const pddl::Term& t : a.args) out.args.push_back(term(t, scope));
  return out;
}

// The scope is copied only where a quantifier adds variables to it.
CFormula Grounder::formula(const Formula& f, const std::map<std::string, int>& outer, int& slots) {
  CFormula out;
  out.kind = f.kind;
  if (f.kind == Formula::Kind::atom) out.atom = atom(f.atom, outer);
  std::map<std::string, int> inner;
  if (!f.variables.empty()) inner = outer;
  for (const pddl::TypedName& v : f.variables) {
    inner[v.name] = slots;
    out.slots.push_back(slots++);
    out.domains.push_back(objects_of(v.types));
  }
  const std::map<std::string, int>& scope = f.variables.empty() ? outer : inner;
  for (const Formula& c : f.children) out.children.push_back(formula(c, scope, slots));
  return out;
}

CEffect Grounder::effect(const Effect& e, const std::map<std::string, int>& outer, int& slots) {
  CEffect out;
  out.kind = e.kind;
  if (e.kind == Effect::Kind::add || e.kind == Effect::Kind::remove) out.atom = atom(e.atom, outer);
  std::map<std::string, int> inner;
  if (!e.variables.empty()) inner = outer;
  for (const pddl::TypedName& v : e.variables) {
    inner[v.name] = slots;
    out.slots.push_back(slots++);
    out.domains.push_back(objects_of(v.types));
  }
  const std::map<std::string, int>& scope = e.variables.empty() ? outer : inner;
  if (e.kind == Effect::Kind::when) out.condition = formula(e.condition, scope, slots);
  if (e.kind == Effect::Kind::increase) {
    out.has_cost = true;
    out.cost_where = e.cost.where;
    out.cost_number = e.cost.number;
    if (!e.cost.number) {
      out.cost_function.predicate = function_ids_.at(e.cost.function.predicate);
      for (const pddl::Term& t : e.cost.function.args) out.cost_function.args.push_back(term(t, scope));
    }
  }
  for (const Effect& c : e.children) out.children.push_back(effect(c, scope, slots));
  return out;
}

// Positive atoms every binding that satisfies `f` has reached. An (exists ...) holds
// only with its body's atoms, so those among them that name none of its variables
// count too: (Pose ?o ?p) inside UnsafePose's exists binds the axiom's parameters from
// the poses instead of from every pair of objects.
void Grounder::collect_core(const CFormula& f, std::vector<CAtom>& core, std::vector<int> quantified) const {
  if (f.kind == Formula::Kind::conjunction) {
    for (const CFormula& c : f.children) collect_core(c, core, quantified);
  } else if (f.kind == Formula::Kind::exists) {
    quantified.insert(quantified.end(), f.slots.begin(), f.slots.end());
    collect_core(f.children.at(0), core, quantified);
  } else if (f.kind == Formula::Kind::atom && f.atom.predicate >= 0) {
    // A quantified variable matches any value (kWildcard): (Contained ?b ?p ?r) inside
    // In's (exists (?p) ...) still binds ?b and ?r from the reached Contained atoms,
    // instead of every pair of objects being tried.
    CAtom a = f.atom;
    bool binds = false, wild = false;
    for (CTerm& t : a.args) {
      if (!t.variable) continue;
      const bool q = std::find(quantified.begin(), quantified.end(), t.value) != quantified.end();
      if (q) t.value = kWildcard;
      binds = binds || !q;
      wild = wild || q;
    }
    if (binds || !wild) core.push_back(std::move(a));
  }
}

void Grounder::collect_predicates(const CFormula& f, std::vector<int>& out) {
  std::function<void(const CFormula&)> visit = [&](const CFormula& g) {
    if (g.kind == Formula::Kind::atom && g.atom.predicate >= 0) out.push_back(g.atom.predicate);
    for (const CFormula& c : g.children) visit(c);
  };
  visit(f);
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
}

void Grounder::mark_fluents(const Effect& e) {
  if (e.kind == Effect::Kind::add || e.kind == Effect::Kind::remove) fluent_[predicate_ids_.at(e.atom.predicate)] = true;
  for (const Effect& c : e.children) mark_fluents(c);
}

// The problem's objects beyond those of the last run, each added to the type domains.
void Grounder::add_objects(const pddl::Problem& problem) {
  for (std::size_t k = object_names_.size() - constant_count_; k < problem.objects.size(); ++k) {
    const pddl::TypedName& o = problem.objects[k];
    const int id = static_cast<int>(object_names_.size());
    object_ids_[o.name] = id;
    object_names_.push_back(o.name);
    object_types_.push_back(o.types);
    for (auto& [types, objects] : type_objects_) {
      bool fits = false;
      for (const std::string& own : o.types) {
        for (const std::string& t : types) fits = fits || domain_.is_subtype(own, t);
      }
      if (fits) objects.push_back(id);
    }
  }
  index_atoms_densely();
}

void Grounder::index_atoms_densely() {
  dense_.assign(predicate_names_.size(), {});
  dense_places_.clear();
  if (keep_) return;  // a session adds objects each problem: every table would be rebuilt
  for (const auto& [name, decl] : domain_.predicates) {
    std::vector<const std::vector<int>*> domains;
    std::size_t size = 1;
    for (const pddl::TypedName& parameter : decl.parameters) {
      domains.push_back(objects_of(parameter.types));
      size *= std::max<std::size_t>(domains.back()->size(), 1);
      if (size > kMaxDenseAtoms) break;
    }
    if (size > kMaxDenseAtoms) continue;
    DenseAtoms& d = dense_[predicate_ids_.at(name)];
    for (const std::vector<int>* objects : domains) {
      // One array of places per type, shared by the arguments of that type.
      auto [places, fresh] = dense_places_.try_emplace(objects);
      if (fresh) {
        places->second.assign(object_names_.size(), -1);
        for (std::size_t k = 0; k < objects->size(); ++k) places->second[(*objects)[k]] = static_cast<int>(k);
      }
      d.place_of.push_back(&places->second);
      d.stride.push_back(d.stride.empty() ? 1 : d.stride.back() * std::max<std::size_t>(domains[d.stride.size() - 1]->size(), 1));
    }
    d.ids.assign(size, -1);
  }
  for (std::size_t id = 0; id < atoms_.size(); ++id) {
    const auto& [predicate, args] = atoms_[id];
    const std::size_t place = dense_place(predicate, args.size(), [&](std::size_t i) { return args[i]; });
    if (place != kNoPlace) dense_[predicate].ids[place] = static_cast<int>(id);
  }
}

// The order the core atoms are joined in: next, an atom with an argument bound by those
// before (its tuples are looked up by that object, not scanned), static before fluent
// (static atoms are complete from the start and most selective), then the most bound
// arguments; on a tie, the order written.
void Grounder::order_joins(std::vector<CAtom>& core) const {
  std::vector<CAtom> ordered;
  std::vector<bool> bound;
  auto bound_args = [&](const CAtom& a) {
    int n = 0;
    for (const CTerm& t : a.args) n += !t.variable || (t.value != kWildcard && static_cast<std::size_t>(t.value) < bound.size() && bound[t.value]);
    return n;
  };
  while (!core.empty()) {
    auto best = core.begin();
    auto rank = [&](const CAtom& a) { return std::tuple(bound_args(a) > 0, !fluent_[a.predicate], bound_args(a)); };
    for (auto it = core.begin(); it != core.end(); ++it) {
      if (rank(*it) > rank(*best)) best = it;
    }
    for (const CTerm& t : best->args) {
      if (!t.variable || t.value == kWildcard) continue;
      if (static_cast<std::size_t>(t.value) >= bound.size()) bound.resize(static_cast<std::size_t>(t.value) + 1, false);
      bound[t.value] = true;
    }
    ordered.push_back(std::move(*best));
    core.erase(best);
  }
  core = std::move(ordered);
}

// What depends on the domain alone: predicates, functions, constants and the schemas.
void Grounder::compile() {
  compiled_ = true;
  for (const pddl::TypedName& c : domain_.constants) {
    object_ids_[c.name] = static_cast<int>(object_names_.size());
    object_names_.push_back(c.name);
    object_types_.push_back(c.types);
  }
  constant_count_ = object_names_.size();
  for (const auto& [name, decl] : domain_.predicates) {
    predicate_ids_[name] = static_cast<int>(predicate_names_.size());
    predicate_names_.push_back(name);
  }
  fluent_.assign(predicate_names_.size(), false);
  derived_.assign(predicate_names_.size(), false);
  reached_tuples_.resize(predicate_names_.size());
  for (const pddl::Action& a : domain_.actions) mark_fluents(a.effect);
  for (const pddl::DerivedRule& r : domain_.derived) {
    fluent_[predicate_ids_.at(r.head.name)] = true;
    derived_[predicate_ids_.at(r.head.name)] = true;
  }
  for (const auto& [name, decl] : domain_.functions) function_ids_[name] = static_cast<int>(function_ids_.size());

  for (const pddl::DerivedRule& r : domain_.derived) {
    Schema s;
    s.name = r.head.name;
    s.where = r.where;
    s.axiom = true;
    std::map<std::string, int> scope;
    for (const pddl::TypedName& p : r.head.parameters) {
      scope[p.name] = s.slot_count;
      s.parameters.push_back(s.slot_count++);
      s.parameter_domains.push_back(objects_of(p.types));
    }
    pddl::Atom head{r.head.name, {}, r.head.where};
    for (const pddl::TypedName& p : r.head.parameters) head.args.push_back({p.name, true, p.where});
    s.head = atom(head, scope);
    s.precondition = formula(r.body, scope, s.slot_count);
    collect_core(s.precondition, s.core);
    collect_predicates(s.precondition, s.mentioned);
    schemas_.push_back(std::move(s));
  }
  for (const pddl::Action& a : domain_.actions) {
    Schema s;
    s.name = a.name;
    s.where = a.where;
    std::map<std::string, int> scope;
    for (const pddl::TypedName& p : a.parameters) {
      scope[p.name] = s.slot_count;
      s.parameters.push_back(s.slot_count++);
      s.parameter_domains.push_back(objects_of(p.types));
    }
    s.precondition = formula(a.precondition, scope, s.slot_count);
    s.effect = effect(a.effect, scope, s.slot_count);
    s.conditional = has_when(s.effect);
    collect_core(s.precondition, s.core);
    collect_predicates(s.precondition, s.mentioned);
    order_joins(s.core);
    schemas_.push_back(std::move(s));
  }
  for (Schema& s : schemas_) {
    s.slot_domain.assign(static_cast<std::size_t>(std::max(1, s.slot_count)), nullptr);
    for (std::size_t p = 0; p < s.parameters.size(); ++p) s.slot_domain[s.parameters[p]] = s.parameter_domains[p];
    s.literal_precondition = is_literal_conjunction(s.precondition);
    s.joined_precondition = is_atom_conjunction(s.precondition);
  }
  for (const Schema& s : schemas_) {
    // A parameter no core atom binds is enumerated over its type; a quantifier ranges
    // over one (or its witnesses): new objects may then make new instances.
    bool by_type = false;
    for (int slot : s.parameters) {
      by_type = by_type || std::none_of(s.core.begin(), s.core.end(), [&](const CAtom& a) {
                  return std::any_of(a.args.begin(), a.args.end(), [&](const CTerm& t) { return t.variable && t.value == slot; });
                });
    }
    core_complete_.push_back(core_complete(s.precondition));
    std::function<bool(const CEffect&)> effect_forall = [&](const CEffect& e) {
      return e.kind == Effect::Kind::forall || std::any_of(e.children.begin(), e.children.end(), effect_forall);
    };
    effect_by_type_.push_back(!s.axiom && effect_forall(s.effect));
    by_type_.push_back(by_type || !core_complete_.back() || effect_by_type_.back());
  }
  for (const Schema& s : schemas_) instances_.emplace_back(s.parameters.size());
  if (!domain_.derived.empty()) strata_ = stratify();
}

}  // namespace cluttertamp::search::detail
