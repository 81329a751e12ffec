#include "stream/search_core.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <limits>
#include <sstream>
#include <utility>

#include "cluttertamp/core/free_beside.hpp"
#include "cluttertamp/search/planner.hpp"
#include "cluttertamp/stream/stream_task.hpp"

namespace cluttertamp::stream::detail {

namespace {

using Clock = std::chrono::steady_clock;

double since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

// Predicates used negated (through derived predicates too) and never positively.
std::set<std::string> negated_predicates(const pddl::Domain& domain, const pddl::Problem& problem) {
  std::map<std::string, std::set<bool>> uses;
  std::function<void(const pddl::Formula&, bool)> visit = [&](const pddl::Formula& f, bool polarity) {
    using K = pddl::Formula::Kind;
    if (f.kind == K::atom) uses[f.atom.predicate].insert(polarity);
    for (std::size_t i = 0; i < f.children.size(); ++i) {
      const bool flip = f.kind == K::negation || (f.kind == K::implication && i == 0);
      visit(f.children[i], flip ? !polarity : polarity);
    }
  };
  std::function<void(const pddl::Effect&)> conditions = [&](const pddl::Effect& e) {
    if (e.kind == pddl::Effect::Kind::when) {
      visit(e.condition, true);
      visit(e.condition, false);
    }
    for (const pddl::Effect& c : e.children) conditions(c);
  };
  for (const pddl::Action& a : domain.actions) {
    visit(a.precondition, true);
    conditions(a.effect);
  }
  visit(problem.goal, true);
  // Derived predicates pass the polarity of their uses on to their bodies.
  std::set<std::pair<std::string, bool>> done;
  for (bool changed = true; changed;) {
    changed = false;
    for (const pddl::DerivedRule& r : domain.derived) {
      for (bool polarity : {true, false}) {
        if (!uses[r.head.name].count(polarity) || !done.insert({r.head.name, polarity}).second) continue;
        visit(r.body, polarity);
        changed = true;
      }
    }
  }
  std::set<std::string> out;
  for (const auto& [predicate, polarities] : uses) {
    if (polarities.count(false) && !polarities.count(true)) out.insert(predicate);
  }
  return out;
}

}  // namespace

SearchCore::SearchCore(const StreamProblem& problem, plugin::PlanningContext& context, const StreamSearchOptions& options)
    : problem_(problem), domain_(*problem.domain), context_(context), options_(options),
      base_(*problem.domain, *problem.streams) {
  check_bindings();
  load_initial();
  std::set<std::string> negated;
  for (const std::string& p : negated_predicates(domain_, *problem.problem)) {
    if (certified_by_test(p)) negated.insert(p);
  }
  negated_tests_ = negated;
}

StreamSolution SearchCore::run(const std::function<void()>& search) {
  try {
    search();
  } catch (const search::TimeLimit&) {
    out_.reason = "time limit reached";
  } catch (const search::TooLarge& e) {
    out_.reason = std::string("grounding: ") + e.what();
  } catch (const InputError&) {
    // Looking for a cheaper plan, the real problem could not be costed any more (a
    // function call failed): the best plan found stands. Before any plan, it is bad input.
    if (!best_) throw;
  }
  settle();  // the time limit ended the search for a cheaper plan
  if (!out_.solved && out_.reason.empty()) out_.reason = "time limit reached";
  return std::move(out_);
}

void SearchCore::check_bindings() const {
  Diagnostics d;
  const std::set<std::string> negated = negated_predicates(domain_, *problem_.problem);
  for (const StreamDecl& s : problem_.streams->streams) {
    if (!s.fluents.empty() && options_.algorithm == Algorithm::incremental) {
      d.error(s.where, "'" + s.name + "' reads :fluents, which only the adaptive search supports (as in PDDLStream)");
    }
    if (!s.fluents.empty() && s.is_test()) {
      for (const pddl::Atom& c : s.certified) {
        if (negated.count(c.predicate)) {
          d.error(s.where, "test '" + s.name + "' reads :fluents and certifies '" + c.predicate +
                               "', which the domain uses negated: a state-dependent test cannot decide a negated fact");
        }
      }
    }
    if (const auto o = options_.streams.find(s.name); o != options_.streams.end()) {
      if (o->second.eager && s.kind == StreamDecl::Kind::function) {
        d.error(s.where, "'" + s.name + "' is a function: functions are evaluated at once anyway, 'eager' is for tests and generators");
      }
      if (o->second.defer && s.kind == StreamDecl::Kind::function) {
        d.error(s.where, "'" + s.name + "' is a function: functions are evaluated at once, 'defer' is for tests and generators");
      }
      if (o->second.optimistic_value != 0.0 && s.kind != StreamDecl::Kind::function) {
        d.error(s.where, "'" + s.name + "' is not a function: only a function has an optimistic value");
      }
      if (!(o->second.p_success >= 0.0 && o->second.p_success <= 1.0) || !(o->second.overhead >= 0.0) || !std::isfinite(o->second.overhead)) {
        d.error(s.where, "'" + s.name + "': p_success must be in [0, 1] and overhead a finite number >= 0");
      }
      if ((o->second.p_success != 1.0 || o->second.overhead != 1.0) && s.kind == StreamDecl::Kind::function) {
        d.error(s.where, "'" + s.name + "' is a function: functions are evaluated at once, 'p_success' and 'overhead' order tests and generators");
      }
      if (o->second.p_success == 0.0 && !o->second.eager && s.kind != StreamDecl::Kind::function &&
          s.kind != StreamDecl::Kind::rule && options_.algorithm == Algorithm::adaptive) {
        d.error(s.where, "'" + s.name + "' has p_success 0 (never assumed optimistically) and is not eager: the adaptive search would never evaluate it, so its facts could never hold");
      }
    }
  }
  check_streams_bound(*problem_.streams, [&](const std::string& name) {
    const auto it = problem_.bindings.find(name);
    return it != problem_.bindings.end() && it->second;
  }, d);
  for (const auto& entry : options_.streams) {
    const std::string& name = entry.first;  // not a structured binding: lambdas capture it
    const auto& declared = problem_.streams->streams;
    if (std::none_of(declared.begin(), declared.end(), [&](const StreamDecl& s) { return s.name == name; })) {
      d.error(problem_.streams->where, "stream options name '" + name + "', which this stream file does not declare");
    }
  }
  d.throw_if_any();
}

void SearchCore::load_initial() {
  for (const pddl::TypedName& c : domain_.constants) add_named(c);
  for (const pddl::TypedName& o : problem_.problem->objects) add_named(o);
  SupportEvaluator evaluator(domain_, base_, {}, false);
  for (const pddl::Atom& a : problem_.problem->init) {
    const auto fact = base_.ground(a, {});
    if (!fact) continue;
    if (evaluator.is_fluent(a.predicate)) initial_state_.insert(*fact);
    else base_.add_fact(*fact, FactInfo{});
  }
}

void SearchCore::add_named(const pddl::TypedName& named) {
  if (base_.find(named.name)) return;
  ObjectRecord r;
  r.name = named.name;
  r.types = named.types;
  if (const auto it = problem_.values.find(named.name); it != problem_.values.end()) r.value = it->second;
  base_.add_object(std::move(r));
}

bool SearchCore::certified_by_test(const std::string& predicate) const {
  for (const StreamDecl& s : problem_.streams->streams) {
    if (!s.is_test()) continue;
    for (const pddl::Atom& c : s.certified) {
      if (c.predicate == predicate) return true;
    }
  }
  return false;
}

// Plans with the real facts, and the optimistic ones if asked.
// The PDDL problem of the facts so far: the real ones, and the optimistic ones too
// when `optimistic`.
pddl::Problem SearchCore::symbolic_problem(bool optimistic) {
  pddl::Problem p = *problem_.problem;
  p.objects.clear();
  p.init.clear();
  std::set<std::string> constants;
  for (const pddl::TypedName& c : domain_.constants) constants.insert(c.name);
  for (std::size_t i = 0; i < base_.object_count(); ++i) {
    const ObjectRecord& o = base_.object(static_cast<ObjectId>(i));
    if ((o.optimistic && !optimistic) || constants.count(o.name)) continue;
    p.objects.push_back({o.name, o.types, {}});
  }
  for (const FactKey& f : initial_state_) p.init.push_back(atom_of(f));
  for (const auto& [fact, info] : base_.facts()) {
    keep_time_limit();
    // Predicates the domain does not declare are the streams' own: not for the search.
    if ((!info.optimistic || optimistic) && domain_.predicates.count(base_.predicate_name(fact[0]))) {
      p.init.push_back(atom_of(fact));
    }
  }
  add_function_values(p, optimistic);
  return p;
}

std::optional<std::vector<Step>> SearchCore::plan_symbolic(bool optimistic) {
  const auto start = Clock::now();
  pddl::Problem p;
  std::optional<std::vector<Step>> steps;
  // The optimistic problem may hold millions of facts: a time limit reached while it
  // is built or searched leaves it (and the grounded task) to be freed beside.
  try {
    p = symbolic_problem(optimistic);
    ++out_.statistics.searches;
    search::GroundingStats grounding;
    search::Task task = (optimistic ? optimistic_grounding_ : real_grounding_).ground(p, &grounding, context_.deadline.remaining());
    last_grounding_ = grounding;
    search::SearchOptions so;
    so.algorithm = options_.search;
    so.time_limit = context_.deadline.remaining();
    so.cost_bound = cost_bound();
    const search::SearchResult r = search::plan(task, so);
    last_search_work_ = options_.search_cost + 10.0 * static_cast<double>(grounding.operators + r.statistics.generated);
    work_ += last_search_work_;
    if (r.solved) {
      steps.emplace();
      for (search::OperatorId op : r.plan) steps->push_back(step_of(task.operators[static_cast<std::size_t>(op)].name));
    } else if (r.reason == "time limit") {
      free_beside(std::move(task));
      throw search::TimeLimit("time limit (search)");
    }
  } catch (const search::TimeLimit&) {
    last_search_seconds_ = since(start);
    out_.statistics.search_seconds += last_search_seconds_;
    free_beside(std::move(p));
    throw;
  }
  last_search_seconds_ = since(start);
  out_.statistics.search_seconds += last_search_seconds_;
  return steps;
}

// Once a plan is found: a cost-aware search (`polish_search`, within
// `polish_expansions`) on the real facts, whose plan replaces it when cheaper (action
// costs and function values; steps without a metric) and valid; then the steps whose
// removal leaves a valid plan go. The first plan of a greedy search may take detours
// (a pick and place to get the hand free, a value from an earlier skeleton) that cost
// nothing to find and much to run. The cost is wanted only against `success_cost`.
SearchCore::Costed SearchCore::polished(std::vector<Step> steps) {
  const bool costed = options_.success_cost < std::numeric_limits<double>::infinity();
  if ((options_.polish_search.empty() && !costed) || context_.deadline.expired()) {
    return {without_pointless_steps(std::move(steps)), std::nullopt};
  }
  const auto start = Clock::now();
  std::map<std::string, double> cost_of;  // of every real operator
  try {
    evaluator_.close_real();  // every cost function on the real values
    if (!context_.deadline.expired() && every_function_valued()) {
      const pddl::Problem p = symbolic_problem(false);
      search::Task task;
      try {
        task = real_grounding_.ground(p, nullptr, context_.deadline.remaining());
      } catch (const InputError&) {
        // A cost with no value: a function whose domain holds only optimistically for
        // some real values. The real problem cannot be costed; the plan in hand stands.
        return {without_pointless_steps(std::move(steps)), std::nullopt};
      }
      for (const search::Operator& op : task.operators) cost_of.emplace(op.name, op.cost);
      if (!options_.polish_search.empty()) steps = cheaper_plan(task, cost_of, std::move(steps));
    }
  } catch (const search::TimeLimit&) {
    // The plan in hand stands.
  }
  out_.statistics.search_seconds += since(start);
  steps = without_pointless_steps(std::move(steps));
  if (cost_of.empty()) return {std::move(steps), std::nullopt};
  return {steps, cost_in(cost_of, steps)};
}

double SearchCore::cost_in(const std::map<std::string, double>& cost_of, const std::vector<Step>& steps) const {
  double total = 0;
  for (const Step& step : steps) {
    const auto it = cost_of.find(name_of(step));
    total += it == cost_of.end() ? std::numeric_limits<double>::infinity() : it->second;
  }
  return total;
}

std::vector<Step> SearchCore::cheaper_plan(const search::Task& task, const std::map<std::string, double>& cost_of, std::vector<Step> steps) {
  search::SearchOptions so;
  so.algorithm = options_.polish_search;
  so.time_limit = context_.deadline.remaining();
  so.max_expansions = options_.polish_expansions;
  so.cost_bound = cost_in(cost_of, steps) - 1e-9;
  const search::SearchResult r = search::plan(task, so);
  ++out_.statistics.searches;
  if (r.solved) {
    std::vector<Step> cheaper;
    for (search::OperatorId op : r.plan) cheaper.push_back(step_of(task.operators[static_cast<std::size_t>(op)].name));
    if (verify(cheaper)) steps = std::move(cheaper);
  }
  return steps;
}

// False when a function on real values has none (its call failed): the real
// problem could not be costed.
bool SearchCore::every_function_valued() {
  for (int s = 0; s < static_cast<int>(problem_.streams->streams.size()); ++s) {
    if (base_.decl(s).kind != StreamDecl::Kind::function) continue;
    for (int id : evaluator_.real_instances(s)) {
      if (!base_.instance_at(id).value) return false;
    }
  }
  return true;
}

std::string SearchCore::name_of(const Step& step) const {
  std::string name = "(" + step.action->name;
  for (ObjectId o : step.args) name += " " + base_.object(o).name;
  return name + ")";
}

// Function values: real ones where evaluated, 0 (a lower bound) where optimistic.
void SearchCore::add_function_values(pddl::Problem& p, bool optimistic) {
  for (int s = 0; s < static_cast<int>(problem_.streams->streams.size()); ++s) {
    const StreamDecl& d = base_.decl(s);
    if (d.kind != StreamDecl::Kind::function) continue;
    base_.bindings(d.inputs, d.domain, optimistic, [&](const std::vector<ObjectId>& inputs, int) {
      const int id = base_.instance(s, inputs);
      const Instance& inst = base_.instance_at(id);
      if (!inst.value && !optimistic) return;
      pddl::NumericFact f;
      f.function.predicate = d.name;
      for (ObjectId o : inputs) f.function.args.push_back({base_.object(o).name, false, {}});
      f.value = inst.value.value_or(evaluator_.options_of(d).optimistic_value);
      p.numeric_init.push_back(f);
    });
  }
}

Step SearchCore::step_of(const std::string& name) {
  std::istringstream in(name.substr(1, name.size() - 2));
  std::string word;
  in >> word;
  Step step;
  step.action = domain_.find_action(word);
  while (in >> word) step.args.push_back(base_.find(word).value());
  return step;
}

// The support of a plan: every precondition and the goal, state by state.
std::optional<Support> SearchCore::plan_support(const std::vector<Step>& steps, bool optimistic, Uses* uses) {
  SupportEvaluator evaluator(domain_, base_, negated_tests_, optimistic);
  Support total;
  State state = initial_state_;
  auto use = [&](const Support& s, int step) {
    total.merge(s);
    if (!uses) return;
    for (const FactKey& f : s.facts) uses->steps[f].insert(step);
  };
  for (std::size_t k = 0; k < steps.size(); ++k) {
    if (uses) uses->states.push_back(state);
    Env env = env_of(steps[k]);
    auto pre = evaluator.support(steps[k].action->precondition, env, state, true);
    if (!pre) return std::nullopt;
    State next;
    Support conditions;
    if (!evaluator.apply(steps[k].action->effect, env, state, next, conditions)) return std::nullopt;
    use(*pre, static_cast<int>(k));
    use(conditions, static_cast<int>(k));
    state = std::move(next);
  }
  if (uses) uses->states.push_back(state);
  auto goal = evaluator.support(problem_.problem->goal, {}, state, true);
  if (!goal) return std::nullopt;
  use(*goal, static_cast<int>(steps.size()));
  return total;
}

Env SearchCore::env_of(const Step& s) {
  Env env;
  for (std::size_t i = 0; i < s.action->parameters.size(); ++i) env[s.action->parameters[i].name] = s.args[i];
  return env;
}

// The state before step `k` of `steps` (the final state for k = steps.size()).
State SearchCore::state_before(const std::vector<Step>& steps, std::size_t k) {
  SupportEvaluator evaluator(domain_, base_, negated_tests_, true);
  State state = initial_state_;
  Support ignored;
  for (std::size_t i = 0; i < k && i < steps.size(); ++i) {
    State next;
    evaluator.apply(steps[i].action->effect, env_of(steps[i]), state, next, ignored);
    state = std::move(next);
  }
  return state;
}

// True when the plan holds with real facts, every negated test it relies on
// evaluated (now, if need be) and false.
bool SearchCore::verify(const std::vector<Step>& steps) {
  const auto support = plan_support(steps, false);
  if (!support) return false;
  for (const FactKey& fact : support->negated) {
    const auto id = test_instance(fact);
    if (!id) continue;  // no test applies: false by the closed world
    Instance& inst = base_.instance_at(*id);
    if (!evaluator_.real_domain(inst)) continue;
    if (inst.calls == 0 && !inst.exhausted) evaluator_.call(*id);
    if (!inst.results.empty()) return false;
  }
  return true;
}

// The test instance that decides a negated fact.
std::optional<int> SearchCore::test_instance(const FactKey& fact) {
  for (int s = 0; s < static_cast<int>(problem_.streams->streams.size()); ++s) {
    const StreamDecl& d = base_.decl(s);
    if (!d.is_test()) continue;
    for (const pddl::Atom& c : d.certified) {
      if (c.predicate != base_.predicate_name(fact[0]) || c.args.size() + 1 != fact.size()) continue;
      Env env;
      for (std::size_t i = 0; i < c.args.size(); ++i) env[c.args[i].name] = fact[i + 1];
      std::vector<ObjectId> inputs;
      for (const pddl::Term& in : d.inputs) {
        const auto it = env.find(in.name);
        if (it == env.end()) break;
        inputs.push_back(it->second);
      }
      if (inputs.size() == d.inputs.size()) return base_.instance(s, inputs);
    }
  }
  return std::nullopt;
}

// Greedy action elimination: while dropping one action, or two (a place and the pick
// that undoes it need not be neighbours), leaves a plan that holds with real facts,
// drop them; singles before pairs, earliest first, so a plan always shortens the same
// way. The searches are not cost-optimal and the incremental one plans with every
// value it has, so such detours do occur.
std::vector<Step> SearchCore::without_pointless_steps(std::vector<Step> steps) {
  auto without = [&](std::size_t i, std::size_t j) {
    std::vector<Step> fewer;
    for (std::size_t k = 0; k < steps.size(); ++k) {
      if (k != i && k != j) fewer.push_back(steps[k]);
    }
    return fewer;
  };
  for (bool shorter = true; shorter && !context_.deadline.expired();) {
    shorter = false;
    // Gap 0: one action; then two, nearest pairs first.
    for (std::size_t gap = 0; gap < steps.size() && !shorter && !context_.deadline.expired(); ++gap) {
      for (std::size_t i = 0; i + gap < steps.size() && !shorter && !context_.deadline.expired(); ++i) {
        std::vector<Step> fewer = without(i, i + gap);
        if (verify(fewer)) {
          steps = std::move(fewer);
          shorter = true;
        }
      }
    }
  }
  return steps;
}

// A plan that holds with real facts: polished, kept if the cheapest so far. Returns
// whether the search is done (the best plan then is the solution): its cost is at
// most `success_cost` or 0 (nothing is cheaper), or the new plan cannot be costed
// to compare (a function without a value: the search would find it again and again).
bool SearchCore::accept(std::vector<Step> steps) {
  ++out_.statistics.plans;
  Costed c = polished(std::move(steps));
  const bool costed = c.cost.has_value();
  const double cost = c.cost.value_or(std::numeric_limits<double>::infinity());
  if (!best_ || cost < best_->cost.value_or(std::numeric_limits<double>::infinity()) - 1e-9) best_ = std::move(c);
  if (!costed || !best_->cost || *best_->cost <= options_.success_cost || *best_->cost <= 0) {
    solved(std::move(*best_));
    return true;
  }
  if (!improve_from_) improve_from_ = work_;
  if (options_.trace) options_.trace("plan of cost " + std::to_string(*best_->cost) + " above success_cost: looking for a cheaper one");
  return false;
}

// Whether the work allowed for cheaper plans after the first is spent; then the best
// plan is the solution.
bool SearchCore::improved_enough() {
  if (!improve_from_ || work_ - *improve_from_ < options_.improve_work) return false;
  solved(std::move(*best_));
  return true;
}

// The search ends without a cheaper plan: the best one found, if any, is the solution.
void SearchCore::settle() {
  if (best_ && !out_.solved) solved(std::move(*best_));
}

// The symbolic searches look only for plans cheaper than the best so far.
double SearchCore::cost_bound() const {
  return best_ && best_->cost ? *best_->cost - 1e-9 : std::numeric_limits<double>::infinity();
}

void SearchCore::solved(Costed plan) {
  const std::vector<Step>& steps = plan.steps;
  out_.cost = plan.cost;
  out_.solved = true;
  out_.reason.clear();
  for (const Step& s : steps) {
    StreamPlanStep out{s.action->name, {}};
    for (ObjectId o : s.args) {
      const ObjectRecord& r = base_.object(o);
      out.arguments.push_back(r.name);
      if (r.value && r.name[0] == '#') out_.values[r.name] = *r.value;
    }
    out_.plan.push_back(std::move(out));
  }
  for (const auto& [fact, info] : base_.facts()) {
    if (!info.optimistic && info.certifier >= 0) out_.certified.push_back(atom_of(fact));
  }
  // Of the facts certified in a state, those the plan relies on: verify() checked that
  // they hold where it uses them. Others (other states, failed skeletons) may not.
  if (const auto support = plan_support(steps, false)) {
    for (const FactKey& f : support->facts) {
      const FactInfo* info = base_.fact(f);
      if ((!info || info->optimistic) && base_.state_facts().count(f)) out_.certified.push_back(atom_of(f));
    }
  }
}

pddl::Atom SearchCore::atom_of(const FactKey& f) const {
  pddl::Atom a;
  a.predicate = base_.predicate_name(f[0]);
  for (std::size_t i = 1; i < f.size(); ++i) a.args.push_back({base_.object(f[i]).name, false, {}});
  return a;
}

// Throws TimeLimit once the run's time is up, looking at the clock every 256th call:
// a stream whose inputs nothing binds ranges over every object, and each new
// optimistic value multiplies its instances.
void SearchCore::keep_time_limit() {
  if ((++ticks_ & 255) == 0 && context_.deadline.expired()) throw search::TimeLimit("time limit (optimistic instantiation)");
}

}  // namespace cluttertamp::stream::detail
