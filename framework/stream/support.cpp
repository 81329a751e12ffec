#include "stream/support.hpp"

#include <functional>

namespace cluttertamp::stream::detail {

namespace {
constexpr int kMaxDerivedDepth = 64;  // derived predicates nest no deeper in practice

using pddl::Formula;
}  // namespace

std::size_t Support::optimistic_size(const FactBase& base) const {
  std::size_t n = negated.size();
  for (const FactKey& f : facts) {
    const FactInfo* info = base.fact(f);
    if (info && info->optimistic) ++n;
  }
  return n;
}

void Support::merge(const Support& other) {
  facts.insert(other.facts.begin(), other.facts.end());
  negated.insert(other.negated.begin(), other.negated.end());
}

SupportEvaluator::SupportEvaluator(const pddl::Domain& domain, FactBase& base, std::set<std::string> negated_tests,
                                   bool optimistic)
    : domain_(domain), base_(base), negated_tests_(std::move(negated_tests)), optimistic_(optimistic),
      changed_(changed_predicates(domain)) {}

std::optional<Support> SupportEvaluator::best(std::optional<Support> a, std::optional<Support> b) const {
  if (!a) return b;
  if (!b) return a;
  return b->optimistic_size(base_) < a->optimistic_size(base_) ? b : a;
}

std::optional<Support> SupportEvaluator::support(const Formula& f, const Env& env, const State& state, bool polarity) {
  switch (f.kind) {
    case Formula::Kind::truth:
      return polarity ? std::optional<Support>(Support{}) : std::nullopt;
    case Formula::Kind::atom:
      return atom(f.atom, env, state, polarity);
    case Formula::Kind::negation:
      return support(f.children.at(0), env, state, !polarity);
    case Formula::Kind::conjunction:
    case Formula::Kind::disjunction: {
      // All children must agree when a conjunction holds or a disjunction fails;
      // otherwise one child decides, the cheapest.
      const bool all = (f.kind == Formula::Kind::conjunction) == polarity;
      std::optional<Support> out = all ? std::optional<Support>(Support{}) : std::nullopt;
      for (const Formula& child : f.children) {
        auto s = support(child, env, state, polarity);
        if (all) {
          if (!s) return std::nullopt;
          out->merge(*s);
        } else {
          out = best(out, s);
          if (out && out->optimistic_size(base_) == 0) break;
        }
      }
      return out;
    }
    case Formula::Kind::implication: {
      const Formula& premise = f.children.at(0);
      const Formula& conclusion = f.children.at(1);
      if (polarity) return best(support(premise, env, state, false), support(conclusion, env, state, true));
      auto p = support(premise, env, state, true);
      auto c = support(conclusion, env, state, false);
      if (!p || !c) return std::nullopt;
      p->merge(*c);
      return p;
    }
    case Formula::Kind::exists:
    case Formula::Kind::forall:
      return quantified(f, env, state, polarity);
  }
  return std::nullopt;
}

std::optional<Support> SupportEvaluator::quantified(const Formula& f, const Env& env, const State& state, bool polarity) {
  // exists holding or forall failing: one witness decides; otherwise every binding.
  const bool all = (f.kind == Formula::Kind::forall) == polarity;
  std::optional<Support> out = all ? std::optional<Support>(Support{}) : std::nullopt;
  Env local = env;
  bool stop = false;
  auto visit = [&] {
    auto s = support(f.children.at(0), local, state, polarity);
    if (all) {
      if (!s) {
        out.reset();
        stop = true;
      } else {
        out->merge(*s);
      }
    } else {
      out = best(out, s);
      stop = out && out->optimistic_size(base_) == 0;
    }
  };
  if (f.kind == Formula::Kind::exists && each_fluent_witness(f, local, state, [&] {
        visit();
        return stop;
      })) {
    return out;
  }
  std::function<void(std::size_t)> each = [&](std::size_t k) {
    if (stop) return;
    if (k == f.variables.size()) {
      visit();
      return;
    }
    for (ObjectId o : base_.objects_of(f.variables[k].types, optimistic_)) {
      local[f.variables[k].name] = o;
      each(k + 1);
      if (stop) return;
    }
  };
  each(0);
  return out;
}

// An (exists ...) whose body requires a fluent atom naming every quantified variable:
// a binding without that atom in `state` makes the body false with nothing to support
// (no binding of it can make the exists hold, and each keeps it from holding for free),
// so only the state's facts of that predicate need visiting — not every object for
// every variable (thousands of pose and trajectory pairs per derived atom). Binds the
// variables in `local` and calls visit() until it returns true; false when the body
// has no such atom.
template <class Visit>
bool SupportEvaluator::each_fluent_witness(const Formula& f, Env& local, const State& state, Visit&& visit) {
  auto names_all = [&](const Formula& c) {
    if (c.kind != Formula::Kind::atom || c.atom.predicate == "=" || !changed_.count(c.atom.predicate)) return false;
    return std::all_of(f.variables.begin(), f.variables.end(), [&](const pddl::TypedName& v) {
      return std::any_of(c.atom.args.begin(), c.atom.args.end(), [&](const pddl::Term& t) { return t.variable && t.name == v.name; });
    });
  };
  const Formula& body = f.children.at(0);
  const Formula* witness = names_all(body) ? &body : nullptr;
  if (!witness && body.kind == Formula::Kind::conjunction) {
    for (const Formula& c : body.children) {
      if (names_all(c)) {
        witness = &c;
        break;
      }
    }
  }
  if (!witness) return false;
  std::map<std::string, std::set<ObjectId>> domains;
  for (const pddl::TypedName& v : f.variables) {
    const std::vector<ObjectId> objects = base_.objects_of(v.types, optimistic_);
    domains[v.name] = std::set<ObjectId>(objects.begin(), objects.end());
  }
  const pddl::Atom& a = witness->atom;
  const int predicate = base_.predicate_id(a.predicate);
  for (auto it = state.lower_bound(FactKey{predicate}); it != state.end() && (*it)[0] == predicate; ++it) {
    const FactKey& fact = *it;
    for (const pddl::TypedName& v : f.variables) local.erase(v.name);
    bool fits = fact.size() == a.args.size() + 1;
    for (std::size_t i = 0; i < a.args.size() && fits; ++i) {
      const pddl::Term& t = a.args[i];
      const ObjectId value = fact[i + 1];
      if (!t.variable) {
        const auto id = base_.find(t.name);
        fits = id && *id == value;
      } else if (const auto bound = local.find(t.name); bound != local.end()) {
        fits = bound->second == value;  // bound outside, or the variable appears twice
      } else {
        const auto domain = domains.find(t.name);
        fits = domain == domains.end() || domain->second.count(value) > 0;
        local[t.name] = value;
      }
    }
    if (fits && visit()) break;
  }
  return true;
}

std::optional<Support> SupportEvaluator::atom(const pddl::Atom& a, const Env& env, const State& state, bool polarity) {
  const std::optional<FactKey> fact = base_.ground(a, env);
  if (!fact) return std::nullopt;  // an unknown constant: never happens in a checked domain
  if (a.predicate == "=") {
    return ((*fact)[1] == (*fact)[2]) == polarity ? std::optional<Support>(Support{}) : std::nullopt;
  }
  if (changed_.count(a.predicate)) {
    return (state.count(*fact) > 0) == polarity ? std::optional<Support>(Support{}) : std::nullopt;
  }
  // Derived: the rules' bodies with the head's arguments bound.
  std::optional<Support> derived;
  bool is_derived = false;
  for (const pddl::DerivedRule& rule : domain_.derived) {
    if (rule.head.name != a.predicate) continue;
    is_derived = true;
    if (depth_ >= kMaxDerivedDepth) return std::nullopt;
    Env local;
    for (std::size_t i = 0; i < rule.head.parameters.size(); ++i) local[rule.head.parameters[i].name] = (*fact)[i + 1];
    ++depth_;
    auto s = support(rule.body, local, state, polarity);
    --depth_;
    if (polarity) {
      derived = best(derived, s);
    } else {  // false only when every rule's body is
      if (!s) return std::nullopt;
      if (!derived) derived = Support{};
      derived->merge(*s);
    }
  }
  if (is_derived) return derived;
  // Static: certified by a stream or given initially.
  const FactInfo* info = base_.fact(*fact);
  // A fact certified in a state (by a stream with :fluents) holds only where the
  // state's fluents agree; the optimistic search uses its state-free optimistic version.
  const bool holds = (info && (optimistic_ || !info->optimistic)) || (!optimistic_ && base_.holds_in_state(*fact, state));
  if (holds != polarity) return std::nullopt;
  Support s;
  if (polarity) s.facts.insert(*fact);
  else if (negated_tests_.count(a.predicate)) s.negated.insert(*fact);
  return s;
}

bool SupportEvaluator::apply(const pddl::Effect& effect, const Env& env, const State& before, State& after,
                             Support& support) {
  // Deletes first, then adds, as PDDL has it.
  State adds, deletes;
  if (!collect(effect, env, before, adds, deletes, support)) return false;
  after = before;
  for (const FactKey& f : deletes) after.erase(f);
  after.insert(adds.begin(), adds.end());
  return true;
}

bool SupportEvaluator::collect(const pddl::Effect& e, const Env& env, const State& before, State& adds, State& deletes,
                               Support& support) {
  using Kind = pddl::Effect::Kind;
  switch (e.kind) {
    case Kind::add:
    case Kind::remove: {
      const auto fact = base_.ground(e.atom, env);
      if (!fact) return false;
      (e.kind == Kind::add ? adds : deletes).insert(*fact);
      return true;
    }
    case Kind::conjunction:
      for (const pddl::Effect& c : e.children) {
        if (!collect(c, env, before, adds, deletes, support)) return false;
      }
      return true;
    case Kind::when: {
      auto yes = this->support(e.condition, env, before, true);
      if (yes) {
        support.merge(*yes);
        return collect(e.children.at(0), env, before, adds, deletes, support);
      }
      auto no = this->support(e.condition, env, before, false);
      if (!no) return false;
      support.merge(*no);
      return true;
    }
    case Kind::forall: {
      Env local = env;
      bool ok = true;
      std::function<void(std::size_t)> each = [&](std::size_t k) {
        if (!ok) return;
        if (k == e.variables.size()) {
          ok = collect(e.children.at(0), local, before, adds, deletes, support);
          return;
        }
        for (ObjectId o : base_.objects_of(e.variables[k].types, optimistic_)) {
          local[e.variables[k].name] = o;
          each(k + 1);
        }
      };
      each(0);
      return ok;
    }
    case Kind::increase:
      return true;
  }
  return true;
}

}  // namespace cluttertamp::stream::detail
