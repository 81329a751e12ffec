#include "cluttertamp/search/grounding.hpp"

#include <algorithm>
#include <chrono>
#include <functional>
#include <iterator>
#include <limits>
#include <map>
#include <memory>
#include <set>
#include <unordered_map>

#include "cluttertamp/core/diagnostics.hpp"
#include "cluttertamp/pddl/parser.hpp"
#include "cluttertamp/core/free_beside.hpp"
#include "search/universal.hpp"

namespace cluttertamp::search {

namespace {

using pddl::Effect;
using pddl::Formula;

constexpr std::size_t kMaxDisjuncts = 10000;

// Thrown while grounding one formula; turned into an InputError at its location.
struct TooManyDisjuncts {};

// ---- compiled (variable-slot) form of the lifted domain ----------------------------------

struct CTerm {
  bool variable = false;
  int value = 0;  // slot or object
};

// A variable term of a Schema::core atom that matches any object: a variable
// quantified inside the precondition, which enumerate() does not bind.
constexpr int kWildcard = -1;

struct CAtom {
  int predicate = -1;  // -1: equality
  std::vector<CTerm> args;
};

struct CFormula {
  Formula::Kind kind = Formula::Kind::truth;
  CAtom atom;
  std::vector<CFormula> children;
  std::vector<int> slots;                  // quantified variables
  std::vector<const std::vector<int>*> domains;  // their objects
};

struct CEffect {
  Effect::Kind kind = Effect::Kind::conjunction;
  CAtom atom;
  std::vector<CEffect> children;
  std::vector<int> slots;
  std::vector<const std::vector<int>*> domains;
  CFormula condition;
  std::optional<double> cost_number;
  CAtom cost_function;  // predicate indexes the function table
  bool has_cost = false;
  SourceLocation cost_where;
};

struct Schema {
  std::string name;
  SourceLocation where;
  bool axiom = false;
  bool conditional = false;  // has (when ...) effects: re-examined as atoms are reached
  int slot_count = 0;
  std::vector<int> parameters;  // slots
  std::vector<const std::vector<int>*> parameter_domains;
  CFormula precondition;
  CEffect effect;
  CAtom head;  // axioms
  std::vector<CAtom> core;  // positive top-level atoms, to enumerate bindings
  std::vector<int> mentioned;  // predicates anywhere in the precondition, sorted, once each
};

constexpr std::size_t kNoObjects = std::numeric_limits<std::size_t>::max();

// What one action or axiom instance grounded to, and what that rested on: the state of
// every atom its formulas looked up, the reached tuples of the predicates its
// quantifiers drew witnesses from, the objects when a quantifier ranged over a type, and
// the cost functions' values. While all are as they were, a later problem of the same
// session grounds the instance to the same operators (fact ids are kept).
struct Cached {
  bool computed = false;
  bool reusable = true;  // false: it looked at too much to be worth checking
  std::uint64_t generation = 0;
  std::vector<std::pair<int, std::uint8_t>> atoms;
  std::vector<std::pair<int, std::size_t>> witnesses;
  std::size_t objects = kNoObjects;  // the object count, if a quantifier ranged over a type
  std::vector<std::pair<std::vector<int>, double>> costs;
  std::vector<Operator> operators;
  std::vector<Axiom> axioms;
};

// Atoms an instance may look up and still be kept for reuse: an (exists ...) over every
// pose looks at thousands, and checking them would cost what grounding it again does.
constexpr std::size_t kMaxDependencies = 256;

class Grounder {
 public:
  /// `keep`: record what each instance rests on, for later problems (a session).
  Grounder(const pddl::Domain& domain, bool keep) : domain_(domain), keep_(keep) {}

  Task run(const pddl::Problem& problem, GroundingStats* stats, double time_limit);
  /// Whether `problem` lists the objects of the last one first, in the same order and
  /// with the same types: then it can be grounded on what this grounder holds.
  bool extends(const pddl::Problem& problem) const;
  /// No problem grounded yet.
  bool fresh() const { return !compiled_; }

 private:
  void compile();
  void add_objects(const pddl::Problem& problem);
  void ground_instance(std::size_t schema, const std::vector<int>& parameters, Cached& out);
  bool still_valid(const Cached& c) const;
  std::uint8_t state(int atom) const { return static_cast<std::uint8_t>((reached_[atom] ? 1 : 0) | (initially_[atom] ? 2 : 0)); }
  // The recording of the instance being grounded, if any.
  void note_atom(int atom) const {
    if (!rec_ || !rec_->reusable) return;
    rec_->atoms.emplace_back(atom, state(atom));
    if (rec_->atoms.size() > kMaxDependencies) rec_->reusable = false;
  }
  void note_witness(int predicate) const {
    if (rec_) rec_->witnesses.emplace_back(predicate, reached_by_predicate_[predicate].size());
  }
  void note_objects() const {
    if (rec_) rec_->objects = object_names_.size();
  }

  // -- objects and types
  int object_index(const std::string& name) const { return object_ids_.at(name); }
  const std::vector<int>* objects_of(const std::vector<std::string>& types);

  // -- atoms
  int atom_id(int predicate, const std::vector<int>& args);
  std::vector<int> ground_args(const CAtom& a, const std::vector<int>& binding) const;

  // -- compilation
  CTerm term(const pddl::Term& t, const std::map<std::string, int>& scope) const;
  CAtom atom(const pddl::Atom& a, const std::map<std::string, int>& scope) const;
  CFormula formula(const Formula& f, std::map<std::string, int> scope, int& slots);
  CEffect effect(const Effect& e, std::map<std::string, int> scope, int& slots);
  void collect_core(const CFormula& f, std::vector<CAtom>& core, std::vector<int> quantified = {}) const;
  static void collect_predicates(const CFormula& f, std::vector<int>& out);
  static bool has_when(const CEffect& e) {
    if (e.kind == Effect::Kind::when) return true;
    return std::any_of(e.children.begin(), e.children.end(), [](const CEffect& c) { return has_when(c); });
  }
  void check_deadline() const {
    if ((++ticks_ & 1023) == 0 && std::chrono::steady_clock::now() >= deadline_) throw TimeLimit("time limit (grounding)");
  }
  void mark_fluents(const Effect& e);

  // -- relaxed exploration
  bool relaxed(const CFormula& f, std::vector<int>& binding) const;
  bool witness_values(const CFormula& f, std::size_t k, const std::vector<int>& binding, std::vector<int>& out) const;
  const CAtom* covering_witness(const CFormula& f) const;
  template <class Visit>
  void each_witness(const CFormula& f, const CAtom& witness, std::vector<int>& binding, Visit&& visit) const;
  void relaxed_effects(const CEffect& e, std::vector<int>& binding, std::vector<int>& out) const;
  // Tuples [first, second) of each core atom's predicate are joined.
  using Ranges = std::vector<std::pair<std::size_t, std::size_t>>;
  void enumerate(const Schema& s, std::size_t k, std::vector<int>& binding, std::vector<bool>& bound,
                 const Ranges& ranges, const std::function<void()>& visit);
  bool core_complete(const CFormula& f, std::vector<int> quantified = {}) const;
  void explore();

  // -- ground output
  struct Lit {
    int atom;
    bool positive;
  };
  using Dnf = std::vector<std::vector<Lit>>;  // disjunction of conjunctions; {} = false; {{}} = true
  Dnf dnf(const CFormula& f, std::vector<int>& binding, bool negated) const;
  static Dnf conjoin(const Dnf& a, const Dnf& b);
  static bool is_true(const Dnf& d) {
    return std::any_of(d.begin(), d.end(), [](const std::vector<Lit>& c) { return c.empty(); });
  }
  void ground_effect(const CEffect& e, std::vector<int>& binding, const Dnf& condition, Operator& op,
                     std::vector<std::pair<Dnf, std::pair<std::vector<Lit>, bool>>>& conditional, double& cost);
  FactId fact(int atom);
  Condition condition(const std::vector<Lit>& conjunction);
  std::vector<int> stratify();
  [[noreturn]] void too_many(const SourceLocation& where, const std::string& what) const {
    throw TooLarge(where.str() + ": " + what + " has more than 10000 disjuncts in disjunctive normal form");
  }

  const pddl::Domain& domain_;
  const bool keep_;
  const pddl::Problem* problem_ = nullptr;  // of the current run()
  bool compiled_ = false;
  std::size_t constant_count_ = 0;
  std::vector<std::string> object_names_;
  std::unordered_map<std::string, int> object_ids_;
  std::vector<std::vector<std::string>> object_types_;
  std::map<std::vector<std::string>, std::vector<int>> type_objects_;
  std::vector<std::string> predicate_names_;
  std::map<std::string, int> predicate_ids_;
  std::vector<bool> fluent_;   // per predicate: changed by an action or derived
  std::vector<bool> derived_;  // per predicate
  std::map<std::string, int> function_ids_;
  std::map<std::vector<int>, double> function_values_;  // (function, args...) -> value

  // (predicate, args...) -> atom id.
  struct KeyHash {
    std::size_t operator()(const std::vector<int>& key) const noexcept {
      std::size_t h = key.size();
      for (int v : key) h ^= static_cast<std::size_t>(v) + 0x9e3779b97f4a7c15ull + (h << 6) + (h >> 2);
      return h;
    }
  };
  std::unordered_map<std::vector<int>, int, KeyHash> atom_ids_;
  /// The id of atom `a` under `binding` if already interned, or -1, without building
  /// an argument vector (the relaxed tests and DNF ask this millions of times).
  int find_ground(const CAtom& a, const std::vector<int>& binding) const {
    key_scratch_.resize(a.args.size() + 1);
    key_scratch_[0] = a.predicate;
    for (std::size_t i = 0; i < a.args.size(); ++i) {
      key_scratch_[i + 1] = a.args[i].variable ? binding[a.args[i].value] : a.args[i].value;
    }
    const auto it = atom_ids_.find(key_scratch_);
    return it == atom_ids_.end() ? -1 : it->second;
  }
  mutable std::vector<int> key_scratch_;  // find_ground's key, reused
  std::vector<std::pair<int, std::vector<int>>> atoms_;  // predicate, args
  std::vector<bool> reached_;
  std::vector<bool> initially_;  // atoms true in the initial state (static or not)
  std::vector<std::vector<std::vector<int>>> reached_by_predicate_;

  std::vector<Schema> schemas_;
  std::vector<bool> by_type_;  // per schema: a parameter or quantifier ranges over a type
  std::vector<bool> effect_by_type_;  // per schema: an effect ranges over a type (forall)
  // Per schema: the parameter bindings found, and in a session what each grounded to
  // (null outside a session: a one-shot grounding of millions of instances keeps none).
  std::vector<std::map<std::vector<int>, std::unique_ptr<Cached>>> instances_;
  // explore(): per schema, the reached atoms of its predicates and the objects at its last pass
  std::vector<std::size_t> seen_, seen_objects_;
  std::vector<std::vector<std::size_t>> joined_;  // per schema and core atom: tuples joined at its last pass
  std::vector<bool> core_complete_;  // per schema: its relaxed precondition holds iff its core atoms are reached
  std::vector<int> init_atoms_;  // of the last run()
  std::vector<int> strata_;  // per predicate
  mutable Cached* rec_ = nullptr;
  std::uint64_t generation_ = 0;  // changes when every cached instance is stale
  std::optional<bool> unit_cost_;
  std::map<int, FactId> fact_ids_;
  Task task_;  // the facts (names, derived) of every run so far
  std::chrono::steady_clock::time_point deadline_;
  mutable std::uint64_t ticks_ = 0;
};

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

int Grounder::atom_id(int predicate, const std::vector<int>& args) {
  std::vector<int> key{predicate};
  key.insert(key.end(), args.begin(), args.end());
  auto [it, inserted] = atom_ids_.emplace(std::move(key), static_cast<int>(atoms_.size()));
  if (inserted) {
    atoms_.emplace_back(predicate, args);
    reached_.push_back(false);
    initially_.push_back(false);
  }
  return it->second;
}

std::vector<int> Grounder::ground_args(const CAtom& a, const std::vector<int>& binding) const {
  std::vector<int> args(a.args.size());
  for (std::size_t i = 0; i < a.args.size(); ++i) args[i] = a.args[i].variable ? binding[a.args[i].value] : a.args[i].value;
  return args;
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

CFormula Grounder::formula(const Formula& f, std::map<std::string, int> scope, int& slots) {
  CFormula out;
  out.kind = f.kind;
  if (f.kind == Formula::Kind::atom) out.atom = atom(f.atom, scope);
  for (const pddl::TypedName& v : f.variables) {
    scope[v.name] = slots;
    out.slots.push_back(slots++);
    out.domains.push_back(objects_of(v.types));
  }
  for (const Formula& c : f.children) out.children.push_back(formula(c, scope, slots));
  return out;
}

CEffect Grounder::effect(const Effect& e, std::map<std::string, int> scope, int& slots) {
  CEffect out;
  out.kind = e.kind;
  if (e.kind == Effect::Kind::add || e.kind == Effect::Kind::remove) out.atom = atom(e.atom, scope);
  for (const pddl::TypedName& v : e.variables) {
    scope[v.name] = slots;
    out.slots.push_back(slots++);
    out.domains.push_back(objects_of(v.types));
  }
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
  for (const std::vector<int>& tuple : reached_by_predicate_[a.predicate]) {
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

// Binds f's variables from each reached tuple of `witness` that agrees with the
// variables bound outside f and with f's domains, and calls visit() until it returns
// true. The variables are left bound to the last tuple tried.
template <class Visit>
void Grounder::each_witness(const CFormula& f, const CAtom& witness, std::vector<int>& b, Visit&& visit) const {
  auto quantified = [&](int slot) { return std::find(f.slots.begin(), f.slots.end(), slot) - f.slots.begin(); };
  note_witness(witness.predicate);
  for (const std::vector<int>& tuple : reached_by_predicate_[witness.predicate]) {
    for (int slot : f.slots) b[slot] = -1;
    bool fits = true;
    for (std::size_t i = 0; i < witness.args.size() && fits; ++i) {
      const CTerm& t = witness.args[i];
      if (!t.variable) {
        fits = t.value == tuple[i];
        continue;
      }
      const auto k = quantified(t.value);
      if (k == static_cast<long>(f.slots.size())) {
        fits = b[t.value] == tuple[i];  // bound outside
      } else if (b[t.value] >= 0) {
        fits = b[t.value] == tuple[i];  // the variable appears twice
      } else {
        const std::vector<int>& domain = *f.domains[static_cast<std::size_t>(k)];
        fits = std::binary_search(domain.begin(), domain.end(), tuple[i]);
        b[t.value] = tuple[i];
      }
    }
    if (fits && visit()) return;
  }
}

void Grounder::relaxed_effects(const CEffect& e, std::vector<int>& b, std::vector<int>& out) const {
  switch (e.kind) {
    case Effect::Kind::add: {
      // Interning an atom changes only the atom table, not what the domain means.
      auto& self = const_cast<Grounder&>(*this);
      out.push_back(self.atom_id(e.atom.predicate, ground_args(e.atom, b)));
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

// Binds the schema's parameters by joining its positive precondition atoms with the
// facts reached so far, then the rest from their types.
void Grounder::enumerate(const Schema& s, std::size_t k, std::vector<int>& binding, std::vector<bool>& bound,
                         const Ranges& ranges, const std::function<void()>& visit) {
  if (k < s.core.size()) {
    const CAtom& a = s.core[k];
    const auto& tuples = reached_by_predicate_[a.predicate];
    for (std::size_t t = ranges[k].first; t < ranges[k].second; ++t) {
      const std::vector<int>& tuple = tuples[t];
      std::vector<int> newly;
      bool ok = true;
      for (std::size_t i = 0; i < a.args.size() && ok; ++i) {
        const CTerm& term = a.args[i];
        if (!term.variable) {
          ok = term.value == tuple[i];
        } else if (term.value == kWildcard) {
          continue;
        } else if (bound[term.value]) {
          ok = binding[term.value] == tuple[i];
        } else {
          // The parameter's type must admit the object.
          const auto param = std::find(s.parameters.begin(), s.parameters.end(), term.value);
          if (param != s.parameters.end()) {
            const auto* domain = s.parameter_domains[param - s.parameters.begin()];
            ok = std::binary_search(domain->begin(), domain->end(), tuple[i]);
          }
          if (ok) {
            binding[term.value] = tuple[i];
            bound[term.value] = true;
            newly.push_back(term.value);
          }
        }
      }
      if (ok) enumerate(s, k + 1, binding, bound, ranges, visit);
      for (int slot : newly) bound[slot] = false;
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
      enumerate(s, k, binding, bound, ranges, visit);
    }
    bound[slot] = false;
    return;
  }
  visit();
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
    reached_by_predicate_[atoms_[a].first].push_back(atoms_[a].second);
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
    for (int predicate : s.mentioned) n += reached_by_predicate_[predicate].size();
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
        for (const auto& [parameters, unused] : instances_[i]) {
          std::vector<int> b(binding.size(), -1);
          for (std::size_t p = 0; p < parameters.size(); ++p) b[s.parameters[p]] = parameters[p];
          relaxed_effects(s.effect, b, added);
        }
      }
      auto visit = [&] {
        check_deadline();
        std::vector<int> parameters;
        for (int slot : s.parameters) parameters.push_back(binding[slot]);
        if (instances_[i].count(parameters)) return;
        std::vector<int> b = binding;
        if (!relaxed(s.precondition, b)) return;
        instances_[i].emplace(std::move(parameters), nullptr);
        if (s.axiom) {
          added.push_back(atom_id(s.head.predicate, ground_args(s.head, b)));
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
      for (std::size_t k = 0; k < n; ++k) now[k] = reached_by_predicate_[s.core[k].predicate].size();
      const bool full = last.size() != n || !core_complete_[i] || objects_changed || s.conditional;
      if (full || n == 0) {
        for (std::size_t k = 0; k < n; ++k) ranges[k] = {0, now[k]};
        enumerate(s, 0, binding, bound, ranges, visit);
      } else {
        for (std::size_t delta = 0; delta < n; ++delta) {
          if (last[delta] == now[delta]) continue;
          for (std::size_t k = 0; k < n; ++k) ranges[k] = {k == delta ? last[k] : 0, k < delta ? last[k] : now[k]};
          enumerate(s, 0, binding, bound, ranges, visit);
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

Grounder::Dnf Grounder::dnf(const CFormula& f, std::vector<int>& b, bool negated) const {
  const Dnf truth{{}}, falsity{};
  switch (f.kind) {
    case Formula::Kind::truth: return negated ? falsity : truth;
    case Formula::Kind::atom: {
      bool value_known = false, value = false;
      int id = -1;
      if (f.atom.predicate < 0) {
        const std::vector<int> args = ground_args(f.atom, b);
        value_known = true;
        value = args[0] == args[1];
      } else {
        int found = find_ground(f.atom, b);
        if (rec_ && rec_->reusable) {
          // An atom not interned yet may be reached later: interned, its state is noted.
          if (found < 0) found = const_cast<Grounder&>(*this).atom_id(f.atom.predicate, ground_args(f.atom, b));
          note_atom(found);
        }
        if (found < 0 || !reached_[found]) {
          value_known = true;  // unreachable: false in every reachable state
        } else if (!fluent_[f.atom.predicate]) {
          value_known = true;
          value = initially_[found];
        } else {
          id = found;
        }
      }
      if (value_known) return (value != negated) ? truth : falsity;
      return Dnf{{Lit{id, !negated}}};
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
  auto [it, inserted] = fact_ids_.emplace(atom, static_cast<FactId>(task_.fact_names.size()));
  if (inserted) {
    std::string name = "(" + predicate_names_[atoms_[atom].first];
    for (int o : atoms_[atom].second) name += " " + object_names_[o];
    task_.fact_names.push_back(name + ")");
    task_.derived.push_back(derived_[atoms_[atom].first]);
  }
  return it->second;
}

Condition Grounder::condition(const std::vector<Lit>& conjunction) {
  Condition c;
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
      const int a = atom_id(e.atom.predicate, ground_args(e.atom, b));
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

bool Grounder::extends(const pddl::Problem& problem) const {
  const std::size_t known = object_names_.size() - constant_count_;
  if (!compiled_ || problem.objects.size() < known) return false;
  for (std::size_t k = 0; k < known; ++k) {
    const pddl::TypedName& o = problem.objects[k];
    if (o.name != object_names_[constant_count_ + k] || o.types != object_types_[constant_count_ + k]) return false;
  }
  return true;
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
  reached_by_predicate_.resize(predicate_names_.size());
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
    // Join static atoms first: they are complete from the start and most selective.
    std::stable_sort(s.core.begin(), s.core.end(), [&](const CAtom& x, const CAtom& y) {
      return !fluent_[x.predicate] && fluent_[y.predicate];
    });
    schemas_.push_back(std::move(s));
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
  instances_.resize(schemas_.size());
  if (!domain_.derived.empty()) strata_ = stratify();
}

bool Grounder::still_valid(const Cached& c) const {
  if (!c.computed || !c.reusable || c.generation != generation_) return false;
  if (c.objects != kNoObjects && c.objects != object_names_.size()) return false;
  for (const auto& [atom, was] : c.atoms) {
    if (state(atom) != was) return false;
  }
  for (const auto& [predicate, count] : c.witnesses) {
    if (reached_by_predicate_[predicate].size() != count) return false;
  }
  for (const auto& [key, value] : c.costs) {
    const auto it = function_values_.find(key);
    if (it == function_values_.end() || it->second != value) return false;
  }
  return true;
}

// The operators (or axioms) of one instance, with what they rest on when kept.
void Grounder::ground_instance(std::size_t schema, const std::vector<int>& parameters, Cached& out) {
  const Schema& s = schemas_[schema];
  out = Cached{};
  out.generation = generation_;
  rec_ = keep_ ? &out : nullptr;
  struct Stop {
    Cached*& rec;
    ~Stop() { rec = nullptr; }
  } stop{rec_};
  std::vector<int> b(static_cast<std::size_t>(std::max(1, s.slot_count)), -1);
  for (std::size_t p = 0; p < parameters.size(); ++p) b[s.parameters[p]] = parameters[p];
  Dnf pre;
  try {
    pre = dnf(s.precondition, b, false);
  } catch (const TooManyDisjuncts&) {
    too_many(s.where, s.axiom ? "the body of derived predicate '" + s.name + "'" : "the precondition of '" + s.name + "'");
  }
  out.computed = true;
  if (s.axiom) {
    const int head = atom_id(s.head.predicate, ground_args(s.head, b));
    for (const auto& conjunction : pre) out.axioms.push_back({fact(head), condition(conjunction), strata_.empty() ? 0 : strata_[s.head.predicate]});
    return;
  }
  if (pre.empty()) return;
  Operator op;
  op.name = "(" + s.name;
  for (int o : parameters) op.name += " " + object_names_[o];
  op.name += ")";
  std::vector<std::pair<Dnf, std::pair<std::vector<Lit>, bool>>> conditional;
  double cost = 0;
  ground_effect(s.effect, b, Dnf{{}}, op, conditional, cost);
  op.cost = task_.unit_cost ? 1.0 : cost;
  // Add after delete: an atom both added and deleted ends up true.
  std::sort(op.add.begin(), op.add.end());
  op.add.erase(std::unique(op.add.begin(), op.add.end()), op.add.end());
  std::sort(op.del.begin(), op.del.end());
  op.del.erase(std::unique(op.del.begin(), op.del.end()), op.del.end());
  std::erase_if(op.del, [&](FactId f) { return std::binary_search(op.add.begin(), op.add.end(), f); });
  for (const auto& [cond, lit] : conditional) {
    for (const auto& conjunction : cond) {
      ConditionalEffect ce;
      ce.condition = condition(conjunction);
      (lit.second ? ce.add : ce.del).push_back(fact(lit.first[0].atom));
      op.conditional.push_back(std::move(ce));
    }
  }
  for (const auto& conjunction : pre) {
    Operator copy = op;
    copy.precondition = condition(conjunction);
    out.operators.push_back(std::move(copy));
  }
}

Task Grounder::run(const pddl::Problem& problem, GroundingStats* stats, double time_limit) {
  const auto start = std::chrono::steady_clock::now();
  problem_ = &problem;
  deadline_ = start + std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::duration<double>(std::min(time_limit, 1e9)));
  if (!compiled_) compile();
  add_objects(problem);
  function_values_.clear();
  for (const pddl::NumericFact& f : problem.numeric_init) {
    std::vector<int> key{function_ids_.at(f.function.predicate)};
    for (const pddl::Term& t : f.function.args) key.push_back(object_index(t.name));
    function_values_[key] = f.value;
  }
  const bool unit_cost = !problem.minimize_total_cost;
  if (unit_cost_ != unit_cost) ++generation_;  // every cost changes meaning
  unit_cost_ = unit_cost;
  task_.unit_cost = unit_cost;
  explore();

  Task out;
  out.unit_cost = unit_cost;
  std::size_t reused = 0;
  for (std::size_t i = 0; i < schemas_.size(); ++i) {
    for (auto& [parameters, cached] : instances_[i]) {
      check_deadline();  // millions of operators are made here too
      if (!keep_) {
        Cached once;
        ground_instance(i, parameters, once);
        std::move(once.operators.begin(), once.operators.end(), std::back_inserter(out.operators));
        std::move(once.axioms.begin(), once.axioms.end(), std::back_inserter(out.axioms));
        continue;
      }
      if (!cached) cached = std::make_unique<Cached>();
      if (still_valid(*cached)) ++reused;
      else ground_instance(i, parameters, *cached);
      out.operators.insert(out.operators.end(), cached->operators.begin(), cached->operators.end());
      out.axioms.insert(out.axioms.end(), cached->axioms.begin(), cached->axioms.end());
    }
  }
  std::stable_sort(out.axioms.begin(), out.axioms.end(), [](const Axiom& a, const Axiom& b) { return a.stratum < b.stratum; });
  for (int id : init_atoms_) {
    if (fluent_[atoms_[id].first]) out.initial.push_back(fact(id));
  }
  std::sort(out.initial.begin(), out.initial.end());
  out.initial.erase(std::unique(out.initial.begin(), out.initial.end()), out.initial.end());
  int goal_slots = 0;
  const CFormula goal = formula(problem.goal, {}, goal_slots);
  std::vector<int> goal_binding(static_cast<std::size_t>(std::max(1, goal_slots)), -1);
  Dnf goal_dnf;
  try {
    goal_dnf = dnf(goal, goal_binding, false);
  } catch (const TooManyDisjuncts&) {
    too_many(problem.goal.where, "the goal");
  }
  for (const auto& conjunction : goal_dnf) out.goal.push_back(condition(conjunction));
  out.fact_names = task_.fact_names;
  out.derived = task_.derived;

  if (stats) {
    stats->reachable_facts = static_cast<std::size_t>(std::count(reached_.begin(), reached_.end(), true));
    stats->operators = out.operators.size();
    stats->axioms = out.axioms.size();
    stats->reused_instances = reused;
    std::size_t statics = 0;
    for (std::size_t a = 0; a < atoms_.size(); ++a) statics += reached_[a] && !fluent_[atoms_[a].first];
    stats->static_facts = statics;
    stats->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  return out;
}

}  // namespace

Task ground(const pddl::Domain& domain, const pddl::Problem& problem, GroundingStats* stats, double time_limit) {
  // Foralls that would multiply out in disjunctive normal form become derived predicates.
  const std::optional<pddl::Domain> compiled = detail::with_universal_axioms(domain);
  auto grounder = std::make_unique<Grounder>(compiled ? *compiled : domain, false);
  try {
    return grounder->run(problem, stats, time_limit);
  } catch (const TimeLimit&) {
    free_beside(std::move(grounder));
    throw;
  }
}

struct Grounding::Impl {
  explicit Impl(const pddl::Domain& d) : domain(d), compiled(detail::with_universal_axioms(d)) {}
  const pddl::Domain& domain;
  const std::optional<pddl::Domain> compiled;
  std::unique_ptr<Grounder> grounder;
};

Grounding::Grounding(const pddl::Domain& domain) : impl_(std::make_unique<Impl>(domain)) {}
Grounding::~Grounding() = default;

Task Grounding::ground(const pddl::Problem& problem, GroundingStats* stats, double time_limit) {
  if (!impl_->grounder || !impl_->grounder->extends(problem)) {
    if (impl_->grounder) free_beside(std::move(impl_->grounder));
    impl_->grounder = std::make_unique<Grounder>(impl_->compiled ? *impl_->compiled : impl_->domain, true);
  }
  const bool incremental = !impl_->grounder->fresh();
  const auto start = std::chrono::steady_clock::now();
  try {
    return impl_->grounder->run(problem, stats, time_limit);
  } catch (const InputError&) {
    // An instance only an earlier problem reached may read a cost this problem does not
    // give (ground() would not make it): grounded afresh, the problem decides alone.
    free_beside(std::move(impl_->grounder));
    if (!incremental) throw;
    return ground(problem, stats, time_limit - std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  } catch (...) {
    // Half-updated: the next problem starts afresh.
    free_beside(std::move(impl_->grounder));
    throw;
  }
}

}  // namespace cluttertamp::search
