#include "cluttertamp/pddl/validator.hpp"

#include <fstream>
#include <functional>
#include <map>
#include <set>
#include <sstream>

#include "cluttertamp/pddl/parser.hpp"
#include "cluttertamp/pddl/sexpr.hpp"

namespace cluttertamp::pddl {

namespace {

using Binding = std::map<std::string, std::string>;

class Simulator {
 public:
  Simulator(const Domain& domain, const Problem& problem) : domain_(domain), problem_(problem) {
    for (const TypedName& c : domain.constants) objects_.push_back(c);
    for (const TypedName& o : problem.objects) objects_.push_back(o);
    for (const Atom& a : problem.init) state_.insert(key(a, {}));
    for (const NumericFact& f : problem.numeric_init) values_[key(f.function, {})] = f.value;
    strata();
    derive();
  }

  bool holds(const Formula& f, Binding& b, std::string* failure) const {
    switch (f.kind) {
      case Formula::Kind::truth: return true;
      case Formula::Kind::atom: {
        bool value;
        if (f.atom.predicate == "=") value = resolve(f.atom.args[0], b) == resolve(f.atom.args[1], b);
        else value = state_.count(key(f.atom, b)) > 0;
        if (!value && failure) *failure = ground_text(f.atom, b) + " is false";
        return value;
      }
      case Formula::Kind::negation: {
        const bool value = !holds(f.children[0], b, nullptr);
        if (!value && failure) {
          *failure = f.children[0].kind == Formula::Kind::atom ? ground_text(f.children[0].atom, b) + " is true"
                                                               : "a negated condition holds";
        }
        return value;
      }
      case Formula::Kind::conjunction:
        for (const Formula& c : f.children) {
          if (!holds(c, b, failure)) return false;
        }
        return true;
      case Formula::Kind::disjunction:
        for (const Formula& c : f.children) {
          if (holds(c, b, nullptr)) return true;
        }
        if (failure) *failure = "no alternative of a disjunction holds";
        return false;
      case Formula::Kind::implication:
        return !holds(f.children[0], b, nullptr) || holds(f.children[1], b, failure);
      case Formula::Kind::exists:
      case Formula::Kind::forall: {
        const bool all = f.kind == Formula::Kind::forall;
        bool result = all;
        each(f.variables, b, [&](Binding& inner) {
          if (holds(f.children[0], inner, nullptr) != all) {
            result = !all;
            return false;  // decided
          }
          return true;
        });
        if (!result && failure) *failure = all ? "a universally quantified condition fails" : "no object satisfies an existential condition";
        return result;
      }
    }
    return true;
  }

  // Effects read in the current state, applied with deletes before adds.
  void apply(const Effect& e, Binding& b, std::set<std::string>& add, std::set<std::string>& del, double& cost) const {
    switch (e.kind) {
      case Effect::Kind::add: add.insert(key(e.atom, b)); break;
      case Effect::Kind::remove: del.insert(key(e.atom, b)); break;
      case Effect::Kind::conjunction:
        for (const Effect& c : e.children) apply(c, b, add, del, cost);
        break;
      case Effect::Kind::when:
        if (holds(e.condition, b, nullptr)) apply(e.children[0], b, add, del, cost);
        break;
      case Effect::Kind::forall:
        each(e.variables, b, [&](Binding& inner) {
          apply(e.children[0], inner, add, del, cost);
          return true;
        });
        break;
      case Effect::Kind::increase:
        if (!problem_.minimize_total_cost) break;  // without the metric costs do not count
        if (e.cost.number) {
          cost += *e.cost.number;
        } else {
          auto it = values_.find(key(e.cost.function, b));
          if (it == values_.end()) {
            throw InputError(e.cost.where, "the initial state of " + problem_.file + " gives no value for the cost " +
                                               ground_text(e.cost.function, b));
          }
          cost += it->second;
        }
        break;
    }
  }

  void step(const std::set<std::string>& add, const std::set<std::string>& del) {
    for (const std::string& a : del) state_.erase(a);
    for (const std::string& a : add) state_.insert(a);
    derive();
  }

  bool object_has_type(const std::string& object, const std::vector<std::string>& types) const {
    for (const TypedName& o : objects_) {
      if (o.name != object) continue;
      for (const std::string& own : o.types) {
        for (const std::string& t : types) {
          if (domain_.is_subtype(own, t)) return true;
        }
      }
    }
    return false;
  }

 private:
  std::string resolve(const Term& t, const Binding& b) const { return t.variable ? b.at(t.name) : t.name; }
  std::string key(const Atom& a, const Binding& b) const {
    std::string k = a.predicate;
    for (const Term& t : a.args) {
      k += ' ';
      k += resolve(t, b);
    }
    return k;
  }
  std::string ground_text(const Atom& a, const Binding& b) const {
    std::string text = "(";  // appended: g++ 12 warns falsely (-Wrestrict) on "(" + std::string
    text += key(a, b);
    return text + ")";
  }

  // Calls f for every typed binding of `variables` (extending b); f returns false to stop.
  void each(const std::vector<TypedName>& variables, const Binding& b, const std::function<bool(Binding&)>& f) const {
    Binding inner = b;
    std::function<bool(std::size_t)> rec = [&](std::size_t k) -> bool {
      if (k == variables.size()) return f(inner);
      for (const TypedName& o : objects_) {
        if (!object_has_type(o.name, variables[k].types)) continue;
        inner[variables[k].name] = o.name;
        if (!rec(k + 1)) return false;
      }
      return true;
    };
    rec(0);
  }

  void strata() {
    std::map<std::string, int> stratum;
    for (const DerivedRule& r : domain_.derived) stratum[r.head.name] = 0;
    std::function<void(const Formula&, bool, std::vector<std::pair<std::string, bool>>&)> uses =
        [&](const Formula& f, bool negated, std::vector<std::pair<std::string, bool>>& out) {
          if (f.kind == Formula::Kind::atom && stratum.count(f.atom.predicate)) out.push_back({f.atom.predicate, negated});
          const bool flips = f.kind == Formula::Kind::negation;  // quantifiers keep polarity
          for (std::size_t i = 0; i < f.children.size(); ++i) {
            uses(f.children[i], negated != (flips || (f.kind == Formula::Kind::implication && i == 0)), out);
          }
        };
    for (std::size_t round = 0; round <= domain_.derived.size() + 1; ++round) {
      bool changed = false;
      for (const DerivedRule& r : domain_.derived) {
        std::vector<std::pair<std::string, bool>> body;
        uses(r.body, false, body);
        for (const auto& [p, negated] : body) {
          if (stratum[r.head.name] < stratum[p] + (negated ? 1 : 0)) {
            stratum[r.head.name] = stratum[p] + (negated ? 1 : 0);
            changed = true;
          }
        }
      }
      if (!changed) break;
      if (round == domain_.derived.size() + 1) throw std::runtime_error("derived predicates are not stratified");
    }
    for (const DerivedRule& r : domain_.derived) rules_by_stratum_[stratum[r.head.name]].push_back(&r);
  }

  void derive() {
    if (domain_.derived.empty()) return;
    std::set<std::string> derived_names;
    for (const DerivedRule& r : domain_.derived) derived_names.insert(r.head.name);
    for (auto it = state_.begin(); it != state_.end();) {
      const std::string predicate = it->substr(0, it->find(' '));
      it = derived_names.count(predicate) ? state_.erase(it) : std::next(it);
    }
    for (const auto& [stratum, rules] : rules_by_stratum_) {
      bool changed = true;
      while (changed) {
        changed = false;
        for (const DerivedRule* r : rules) {
          each(r->head.parameters, {}, [&](Binding& b) {
            Atom head{r->head.name, {}, {}};
            for (const TypedName& p : r->head.parameters) head.args.push_back({p.name, true, {}});
            const std::string k = key(head, b);
            if (!state_.count(k) && holds(r->body, b, nullptr)) {
              state_.insert(k);
              changed = true;
            }
            return true;
          });
        }
      }
    }
  }

  const Domain& domain_;
  const Problem& problem_;
  std::vector<TypedName> objects_;
  std::set<std::string> state_;
  std::map<std::string, double> values_;
  std::map<int, std::vector<const DerivedRule*>> rules_by_stratum_;
};

}  // namespace

std::vector<PlanStep> parse_plan(const std::string& text, const std::string& file, const Domain& domain,
                                 const Problem& problem) {
  const SourceText source{file, text};
  Diagnostics diagnostics;
  std::map<std::string, std::vector<std::string>> objects;
  for (const TypedName& c : domain.constants) objects[c.name] = c.types;
  for (const TypedName& o : problem.objects) objects[o.name] = o.types;
  std::vector<PlanStep> plan;
  for (const SExpr& e : read_sexprs(source)) {
    if (!e.is_list || e.items.empty() || !e.items[0].is_atom()) {
      diagnostics.error(e.where, source.with_excerpt(e.where, "expected (action arg ...)"));
      continue;
    }
    PlanStep step{e.items[0].text, {}, e.where};
    const Action* action = domain.find_action(step.action);
    if (!action) {
      diagnostics.error(e.where, source.with_excerpt(e.where, "unknown action '" + step.action + "'"));
      continue;
    }
    if (e.items.size() - 1 != action->parameters.size()) {
      diagnostics.error(e.where, source.with_excerpt(e.where, "'" + step.action + "' takes " +
                                                                  std::to_string(action->parameters.size()) +
                                                                  " arguments, not " + std::to_string(e.items.size() - 1)));
      continue;
    }
    for (std::size_t i = 1; i < e.items.size(); ++i) {
      const SExpr& arg = e.items[i];
      auto it = arg.is_atom() ? objects.find(arg.text) : objects.end();
      if (it == objects.end()) {
        diagnostics.error(arg.where, source.with_excerpt(arg.where, "unknown object '" + (arg.is_atom() ? arg.text : std::string("(...)")) + "'"));
        continue;
      }
      bool fits = false;
      for (const std::string& own : it->second) {
        for (const std::string& t : action->parameters[i - 1].types) fits = fits || domain.is_subtype(own, t);
      }
      if (!fits) {
        diagnostics.error(arg.where, source.with_excerpt(arg.where, "'" + arg.text + "' does not have the type of parameter " +
                                                                        action->parameters[i - 1].name));
      }
      step.args.push_back(arg.text);
    }
    plan.push_back(std::move(step));
  }
  diagnostics.throw_if_any();
  return plan;
}

std::vector<PlanStep> load_plan(const std::filesystem::path& file, const Domain& domain, const Problem& problem) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(file, ec)) throw InputError({file.string(), 0, 0}, "no such plan file");
  std::ifstream in(file);
  std::stringstream text;
  text << in.rdbuf();
  return parse_plan(text.str(), file.string(), domain, problem);
}

PlanValidation validate_plan(const Domain& domain, const Problem& problem, const std::vector<PlanStep>& plan) {
  PlanValidation result;
  Simulator sim(domain, problem);
  for (std::size_t i = 0; i < plan.size(); ++i) {
    const PlanStep& step = plan[i];
    const Action* action = domain.find_action(step.action);
    std::string text = "(" + step.action;
    for (const std::string& a : step.args) text += " " + a;
    text += ")";
    if (!action || action->parameters.size() != step.args.size()) {
      result.step = i + 1;
      result.reason = "step " + std::to_string(i + 1) + " " + text + ": no such action with this many arguments";
      return result;
    }
    Binding b;
    for (std::size_t k = 0; k < step.args.size(); ++k) {
      if (!sim.object_has_type(step.args[k], action->parameters[k].types)) {
        result.step = i + 1;
        result.reason = "step " + std::to_string(i + 1) + " " + text + ": '" + step.args[k] + "' has the wrong type";
        return result;
      }
      b[action->parameters[k].name] = step.args[k];
    }
    std::string failure;
    if (!sim.holds(action->precondition, b, &failure)) {
      result.step = i + 1;
      result.reason = "step " + std::to_string(i + 1) + " " + text + ": precondition not satisfied: " + failure;
      return result;
    }
    std::set<std::string> add, del;
    double cost = 0;
    sim.apply(action->effect, b, add, del, cost);
    result.cost += problem.minimize_total_cost ? cost : 1.0;
    sim.step(add, del);
  }
  Binding none;
  std::string failure;
  if (!sim.holds(problem.goal, none, &failure)) {
    result.reason = "the goal does not hold after the plan: " + failure;
    return result;
  }
  result.valid = true;
  return result;
}

}  // namespace cluttertamp::pddl
