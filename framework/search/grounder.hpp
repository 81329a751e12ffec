#pragma once
// Internal: the grounder behind search::ground and search::Grounding. Its work is in
// four files: grounder_compile.cpp (the lifted domain compiled to variable slots, the
// objects and types), grounder_explore.cpp (relaxed reachability: which atoms and
// action instances can be reached), grounder_output.cpp (reached instances to ground
// operators and axioms, conditions in disjunctive normal form, strata of derived
// predicates) and grounding.cpp (a run, and sessions that reuse earlier runs).

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "cluttertamp/core/diagnostics.hpp"
#include "cluttertamp/pddl/ast.hpp"
#include "cluttertamp/search/grounding.hpp"
#include "search/tuple_index.hpp"

namespace cluttertamp::search::detail {

using Effect = pddl::Effect;
using Formula = pddl::Formula;

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
  std::vector<const std::vector<int>*> slot_domain;  // per slot: its parameter's objects, null for a quantified variable
  CFormula precondition;
  CEffect effect;
  CAtom head;  // axioms
  std::vector<CAtom> core;  // positive top-level atoms, to enumerate bindings
  std::vector<int> mentioned;  // predicates anywhere in the precondition, sorted, once each
  bool literal_precondition = false;  // a conjunction of literals (the STRIPS case)
  // A conjunction of positive atoms, all in `core`: a binding enumerate() finds satisfies
  // the relaxed precondition, which need not be tested again.
  bool joined_precondition = false;
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

  /// Empties what was recorded (keeping the vectors' capacity), but for the operators
  /// and axioms, which the grounder fills where its caller chooses.
  void restart(std::uint64_t at_generation) {
    computed = false;
    reusable = true;
    generation = at_generation;
    atoms.clear();
    witnesses.clear();
    objects = kNoObjects;
    costs.clear();
  }
};

// Atoms an instance may look up and still be kept for reuse: an (exists ...) over every
// pose looks at thousands, and checking them would cost what grounding it again does.
constexpr std::size_t kMaxDependencies = 256;

// The reached tuples of each predicate, in the order reached, and per argument position
// the tuples with a given object there: a join looks up the tuples that agree with what
// it has bound instead of scanning them all.
class __attribute__((visibility("hidden"))) ReachedTuples {
 public:
  void resize(std::size_t predicates) {
    tuples_.resize(predicates);
    index_.resize(predicates);
  }
  void add(int predicate, const std::vector<int>& tuple) {
    auto& positions = index_[predicate];
    positions.resize(tuple.size());
    const auto id = static_cast<std::uint32_t>(tuples_[predicate].size());
    for (std::size_t i = 0; i < tuple.size(); ++i) {
      auto& by_object = positions[i];
      if (static_cast<std::size_t>(tuple[i]) >= by_object.size()) by_object.resize(static_cast<std::size_t>(tuple[i]) + 1);
      by_object[tuple[i]].push_back(id);
    }
    tuples_[predicate].push_back(tuple);
  }
  const std::vector<std::vector<int>>& of(int predicate) const { return tuples_[predicate]; }
  /// Indices into of(predicate), ascending, of the tuples with `object` at `position`.
  const std::vector<std::uint32_t>& with(int predicate, std::size_t position, int object) const {
    static const std::vector<std::uint32_t> none;
    const auto& positions = index_[predicate];
    if (position >= positions.size() || static_cast<std::size_t>(object) >= positions[position].size()) return none;
    return positions[position][object];
  }

 private:
  std::vector<std::vector<std::vector<int>>> tuples_;
  // [predicate][position][object]: objects are dense indices, and a position admits few
  std::vector<std::vector<std::vector<std::vector<std::uint32_t>>>> index_;
};

// The parameter bindings found for one schema, in the order found (a grounding finds
// thousands; a map node and a vector each were a third of the relaxed exploration). In
// a session each binding also keeps what it grounded to.
class __attribute__((visibility("hidden"))) InstanceSet {
 public:
  explicit InstanceSet(std::size_t arity) : bindings_(arity) {}
  std::size_t size() const { return bindings_.size(); }
  std::span<const int> operator[](std::size_t k) const { return bindings_[k]; }
  bool contains(std::span<const int> p) const { return bindings_.contains(p); }
  void insert(std::span<const int> p) { bindings_.insert(p); }
  /// The bindings (of objects, indices from 0) in the order of their objects' indices,
  /// lexicographically (a map's).
  std::vector<std::uint32_t> sorted() const;
  /// What binding k grounded to, in a session (null until grounded).
  std::unique_ptr<Cached>& cached(std::size_t k) {
    if (cached_.size() < size()) cached_.resize(size());
    return cached_[k];
  }

 private:
  TupleIndex<int> bindings_;
  std::vector<std::unique_ptr<Cached>> cached_;
};

// Hidden: the library exports its symbols by default, and the grounder is none of its
// interface (nor may another library interpose its functions).
class __attribute__((visibility("hidden"))) Grounder {
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
  void order_joins(std::vector<CAtom>& core) const;
  void add_objects(const pddl::Problem& problem);
  /// The operators (or axioms) of one instance, appended to `operators` (`axioms`);
  /// `record` receives what they rest on (in a session).
  void ground_instance(std::size_t schema, std::span<const int> parameters, Cached& record,
                       std::vector<Operator>& operators, std::vector<Axiom>& axioms);
  bool still_valid(const Cached& c) const;
  std::uint8_t state(int atom) const { return static_cast<std::uint8_t>((reached_[atom] ? 1 : 0) | (initially_[atom] ? 2 : 0)); }
  // The recording of the instance being grounded, if any.
  void note_atom(int atom) const {
    if (!rec_ || !rec_->reusable) return;
    rec_->atoms.emplace_back(atom, state(atom));
    if (rec_->atoms.size() > kMaxDependencies) rec_->reusable = false;
  }
  void note_witness(int predicate) const {
    if (rec_) rec_->witnesses.emplace_back(predicate, reached_tuples_.of(predicate).size());
  }
  void note_objects() const {
    if (rec_) rec_->objects = object_names_.size();
  }

  // -- objects and types
  int object_index(const std::string& name) const { return object_ids_.at(name); }
  const std::vector<int>* objects_of(const std::vector<std::string>& types);

  // -- atoms
  int atom_id(int predicate, const std::vector<int>& args);
  /// atom_id() of `a` under `binding`, building no key when it is interned already.
  int intern(const CAtom& a, const std::vector<int>& binding) {
    const int found = find_ground(a, binding);
    return found >= 0 ? found : atom_id(a.predicate, ground_args(a, binding));
  }
  std::vector<int> ground_args(const CAtom& a, const std::vector<int>& binding) const;
  /// The object a term stands for under `binding`.
  static int object_of(const CTerm& t, const std::vector<int>& binding) { return t.variable ? binding[t.value] : t.value; }

  // -- compilation
  CTerm term(const pddl::Term& t, const std::map<std::string, int>& scope) const;
  CAtom atom(const pddl::Atom& a, const std::map<std::string, int>& scope) const;
  CFormula formula(const Formula& f, const std::map<std::string, int>& scope, int& slots);
  CEffect effect(const Effect& e, const std::map<std::string, int>& scope, int& slots);
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
  bool core_complete(const CFormula& f, std::vector<int> quantified = {}) const;
  void explore();

  // -- ground output
  struct Lit {
    int atom;
    bool positive;
  };
  using Dnf = std::vector<std::vector<Lit>>;  // disjunction of conjunctions; {} = false; {{}} = true
  Dnf dnf(const CFormula& f, std::vector<int>& binding, bool negated) const;
  // A literal's value where known in every reachable state, else the literal itself.
  enum class Known { no, truth, falsity };
  Known literal(const CAtom& a, std::vector<int>& binding, bool negated, Lit& out) const;
  /// Whether `f` is a conjunction of literals (atoms, negated atoms, equalities): then
  /// literals() grounds it as one conjunction, without the DNF's nested vectors.
  static bool is_literal_conjunction(const CFormula& f);
  /// Whether `f` is a conjunction of positive atoms (no equality).
  static bool is_atom_conjunction(const CFormula& f);
  /// The conjunction of the literals of `f` (is_literal_conjunction) into `out`, each
  /// atom once, as dnf() would give it; false when it is false in every reachable state.
  bool literals(const CFormula& f, std::vector<int>& binding, bool negated, std::vector<Lit>& out) const;
  static Dnf conjoin(const Dnf& a, const Dnf& b);
  static bool is_true(const Dnf& d) {
    return std::any_of(d.begin(), d.end(), [](const std::vector<Lit>& c) { return c.empty(); });
  }
  void ground_effect(const CEffect& e, std::vector<int>& binding, const Dnf& condition, Operator& op,
                     std::vector<std::pair<Dnf, std::pair<std::vector<Lit>, bool>>>& conditional, double& cost);
  FactId fact(int atom);
  Condition condition(const std::vector<Lit>& conjunction);
  std::vector<int> stratify();
  // Where one instance's operators lie in the output.
  struct Span {
    std::size_t schema;
    const int* parameters;  // as many as the schema has
    std::size_t begin, end;
  };
  void in_name_order(std::vector<Span>& spans, std::vector<Operator>& operators) const;
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
    const std::size_t place = dense_place(a.predicate, a.args.size(), [&](std::size_t i) { return object_of(a.args[i], binding); });
    if (place != kNoPlace) return dense_[a.predicate].ids[place];
    key_scratch_.resize(a.args.size() + 1);
    key_scratch_[0] = a.predicate;
    for (std::size_t i = 0; i < a.args.size(); ++i) {
      key_scratch_[i + 1] = object_of(a.args[i], binding);
    }
    const auto it = atom_ids_.find(key_scratch_);
    return it == atom_ids_.end() ? -1 : it->second;
  }
  mutable std::vector<int> key_scratch_;  // find_ground's key, reused

  // Per predicate, outside a session: the ids of its atoms in a table indexed by their
  // arguments' places in the predicate's declared types, when that table is small. A
  // lookup there is a few multiplications where the hash index hashes a key and follows
  // two pointers. The hash index holds every atom besides: a parameter of a wider type
  // can put an object outside the declared one, and such an atom has no place here.
  struct DenseAtoms {
    std::vector<const std::vector<int>*> place_of;  // per argument: object -> place in its type, -1 outside
    std::vector<std::size_t> stride;
    std::vector<int> ids;  // -1: not interned; empty: no table
  };
  static constexpr std::size_t kNoPlace = std::numeric_limits<std::size_t>::max();
  static constexpr std::size_t kMaxDenseAtoms = std::size_t{1} << 14;  // per predicate
  std::vector<DenseAtoms> dense_;
  std::map<const std::vector<int>*, std::vector<int>> dense_places_;  // per type's objects: their places
  /// After the objects are known: the tables of the predicates small enough for one.
  void index_atoms_densely();
  /// The place of the atom whose i-th argument is `arg(i)` in its predicate's table, or
  /// kNoPlace when there is no table or an argument lies outside the declared type.
  template <class Arg>
  std::size_t dense_place(int predicate, std::size_t arity, const Arg& arg) const {
    if (predicate < 0 || static_cast<std::size_t>(predicate) >= dense_.size()) return kNoPlace;
    const DenseAtoms& d = dense_[predicate];
    if (d.ids.empty() || arity != d.place_of.size()) return kNoPlace;
    std::size_t place = 0;
    for (std::size_t i = 0; i < arity; ++i) {
      const int o = arg(i);
      const std::vector<int>& places = *d.place_of[i];
      if (o < 0 || static_cast<std::size_t>(o) >= places.size() || places[o] < 0) return kNoPlace;
      place += static_cast<std::size_t>(places[o]) * d.stride[i];
    }
    return place;
  }
  std::vector<std::pair<int, std::vector<int>>> atoms_;  // predicate, args
  std::vector<bool> reached_;
  std::vector<bool> initially_;  // atoms true in the initial state (static or not)
  ReachedTuples reached_tuples_;

  std::vector<Schema> schemas_;
  std::vector<bool> by_type_;  // per schema: a parameter or quantifier ranges over a type
  std::vector<bool> effect_by_type_;  // per schema: an effect ranges over a type (forall)
  // Per schema: the parameter bindings found, and in a session what each grounded to
  // (null outside a session: a one-shot grounding of millions of instances keeps none).
  std::vector<InstanceSet> instances_;
  // explore(): per schema, the reached atoms of its predicates and the objects at its last pass
  std::vector<std::size_t> seen_, seen_objects_;
  std::vector<std::vector<std::size_t>> joined_;  // per schema and core atom: tuples joined at its last pass
  std::vector<bool> core_complete_;  // per schema: its relaxed precondition holds iff its core atoms are reached
  std::vector<int> init_atoms_;  // of the last run()
  std::vector<int> strata_;  // per predicate
  mutable Cached* rec_ = nullptr;
  // ground_instance()'s scratch, reused: a grounding makes thousands of operators.
  std::vector<int> binding_;
  std::vector<Lit> conjunction_;
  std::vector<FactId> add_, del_;
  std::uint64_t generation_ = 0;  // changes when every cached instance is stale
  std::optional<bool> unit_cost_;
  std::vector<FactId> fact_ids_;  // per atom, -1: not a fact of the task yet
  Task task_;  // the facts (names, derived) of every run so far
  std::chrono::steady_clock::time_point deadline_;
  mutable std::uint64_t ticks_ = 0;
};

// Binds f's variables from each reached tuple of `witness` that agrees with the
// variables bound outside f and with f's domains, and calls visit() until it returns
// true. The variables are left bound to the last tuple tried.
template <class Visit>
void Grounder::each_witness(const CFormula& f, const CAtom& witness, std::vector<int>& b, Visit&& visit) const {
  auto quantified = [&](int slot) { return std::find(f.slots.begin(), f.slots.end(), slot) - f.slots.begin(); };
  note_witness(witness.predicate);
  for (const std::vector<int>& tuple : reached_tuples_.of(witness.predicate)) {
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

// Inline: the relaxed exploration and the output call these millions of times.
inline int Grounder::atom_id(int predicate, const std::vector<int>& args) {
  std::vector<int> key{predicate};
  key.insert(key.end(), args.begin(), args.end());
  auto [it, inserted] = atom_ids_.emplace(std::move(key), static_cast<int>(atoms_.size()));
  if (inserted) {
    const std::size_t place = dense_place(predicate, args.size(), [&](std::size_t i) { return args[i]; });
    if (place != kNoPlace) dense_[predicate].ids[place] = it->second;
    atoms_.emplace_back(predicate, args);
    reached_.push_back(false);
    initially_.push_back(false);
  }
  return it->second;
}

inline std::vector<int> Grounder::ground_args(const CAtom& a, const std::vector<int>& binding) const {
  std::vector<int> args(a.args.size());
  for (std::size_t i = 0; i < a.args.size(); ++i) args[i] = object_of(a.args[i], binding);
  return args;
}

}  // namespace cluttertamp::search::detail
