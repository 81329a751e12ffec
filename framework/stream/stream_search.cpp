#include "cluttertamp/stream/stream_search.hpp"

#include "cluttertamp/core/free_beside.hpp"

#include <algorithm>
#include <cmath>
#include <chrono>
#include <deque>
#include <functional>
#include <limits>
#include <utility>
#include <sstream>

#include "cluttertamp/search/grounding.hpp"
#include "cluttertamp/search/planner.hpp"
#include "cluttertamp/stream/stream_task.hpp"
#include "stream/evaluator.hpp"
#include "stream/fact_base.hpp"
#include "stream/support.hpp"

namespace cluttertamp::stream {

const char* algorithm_name(Algorithm algorithm) {
  return algorithm == Algorithm::adaptive ? "adaptive" : "incremental";
}

std::optional<Algorithm> algorithm_from_name(std::string_view name) {
  if (name == "adaptive" || name == "focused") return Algorithm::adaptive;
  if (name == "incremental") return Algorithm::incremental;
  return std::nullopt;
}

namespace {

using namespace detail;
using Clock = std::chrono::steady_clock;

double since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

/// An action of a plan with its arguments as objects.
struct Step {
  const pddl::Action* action = nullptr;
  std::vector<ObjectId> args;
};

/// One stream instance of a stream plan; `negated`: a test that must come out false.
/// A stream with :fluents is evaluated in the state before action `step` (the goal's
/// state when it is the plan's length); -1 for the others.
struct PlannedInstance {
  int instance = 0;
  bool negated = false;
  int step = -1;
  auto operator<=>(const PlannedInstance&) const = default;
};

/// A node of the binding tree: optimistic objects bound so far, the next instance of
/// the stream plan to evaluate, and how many of that instance's values became children.
struct Binding {
  std::map<ObjectId, ObjectId> mapping;
  std::size_t index = 0;
  std::size_t consumed = 0;
};

/// An optimistic plan waiting for its streams: actions, stream plan, binding tree
/// (depth first: the last binding is the deepest).
struct Skeleton {
  std::string key;
  std::vector<Step> actions;
  std::vector<PlannedInstance> stream_plan;
  std::vector<Binding> stack;
  bool waiting = false;  ///< every binding waits for the level to rise
};

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

class StreamSearch {
 public:
  StreamSearch(const StreamProblem& problem, plugin::PlanningContext& context, const StreamSearchOptions& options)
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

  /// Destroys every generator (plugin code, which must not outlive its sampler).
  void release_generators() { evaluator_.release_generators(); }

  StreamSolution run() {
    try {
      if (options_.algorithm == Algorithm::incremental) incremental();
      else adaptive();
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

 private:
  // ---- setup ----------------------------------------------------------------

  void check_bindings() const {
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
    for (const auto& [name, unused] : options_.streams) {
      const auto& declared = problem_.streams->streams;
      if (std::none_of(declared.begin(), declared.end(), [&](const StreamDecl& s) { return s.name == name; })) {
        d.error(problem_.streams->where, "stream options name '" + name + "', which this stream file does not declare");
      }
    }
    d.throw_if_any();
  }

  void load_initial() {
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

  void add_named(const pddl::TypedName& named) {
    if (base_.find(named.name)) return;
    ObjectRecord r;
    r.name = named.name;
    r.types = named.types;
    if (const auto it = problem_.values.find(named.name); it != problem_.values.end()) r.value = it->second;
    base_.add_object(std::move(r));
  }

  bool certified_by_test(const std::string& predicate) const {
    for (const StreamDecl& s : problem_.streams->streams) {
      if (!s.is_test()) continue;
      for (const pddl::Atom& c : s.certified) {
        if (c.predicate == predicate) return true;
      }
    }
    return false;
  }

  // ---- symbolic search --------------------------------------------------------

  // Plans with the real facts, and the optimistic ones if asked.
  // The PDDL problem of the facts so far: the real ones, and the optimistic ones too
  // when `optimistic`.
  pddl::Problem symbolic_problem(bool optimistic) {
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

  std::optional<std::vector<Step>> plan_symbolic(bool optimistic) {
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

  // A plan and its cost on the real values, if it could be costed.
  struct Costed {
    std::vector<Step> steps;
    std::optional<double> cost;
  };

  // Once a plan is found: a cost-aware search (`polish_search`, within
  // `polish_expansions`) on the real facts, whose plan replaces it when cheaper (action
  // costs and function values; steps without a metric) and valid; then the steps whose
  // removal leaves a valid plan go. The first plan of a greedy search may take detours
  // (a pick and place to get the hand free, a value from an earlier skeleton) that cost
  // nothing to find and much to run. The cost is wanted only against `success_cost`.
  Costed polished(std::vector<Step> steps) {
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

  double cost_in(const std::map<std::string, double>& cost_of, const std::vector<Step>& steps) const {
    double total = 0;
    for (const Step& step : steps) {
      const auto it = cost_of.find(name_of(step));
      total += it == cost_of.end() ? std::numeric_limits<double>::infinity() : it->second;
    }
    return total;
  }

  std::vector<Step> cheaper_plan(const search::Task& task, const std::map<std::string, double>& cost_of, std::vector<Step> steps) {
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
  bool every_function_valued() {
    for (int s = 0; s < static_cast<int>(problem_.streams->streams.size()); ++s) {
      if (base_.decl(s).kind != StreamDecl::Kind::function) continue;
      for (int id : evaluator_.real_instances(s)) {
        if (!base_.instance_at(id).value) return false;
      }
    }
    return true;
  }

  std::string name_of(const Step& step) const {
    std::string name = "(" + step.action->name;
    for (ObjectId o : step.args) name += " " + base_.object(o).name;
    return name + ")";
  }


  // Function values: real ones where evaluated, 0 (a lower bound) where optimistic.
  void add_function_values(pddl::Problem& p, bool optimistic) {
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

  Step step_of(const std::string& name) {
    std::istringstream in(name.substr(1, name.size() - 2));
    std::string word;
    in >> word;
    Step step;
    step.action = domain_.find_action(word);
    while (in >> word) step.args.push_back(base_.find(word).value());
    return step;
  }

  // ---- checking plans ---------------------------------------------------------

  /// Where a plan needs its facts: the steps whose precondition or effect conditions
  /// rest on each fact (the plan's length for the goal), and the state before each step.
  struct Uses {
    std::map<FactKey, std::set<int>> steps;
    std::vector<State> states;  ///< before each step, then the final state
  };

  // The support of a plan: every precondition and the goal, state by state.
  std::optional<Support> plan_support(const std::vector<Step>& steps, bool optimistic, Uses* uses = nullptr) {
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

  static Env env_of(const Step& s) {
    Env env;
    for (std::size_t i = 0; i < s.action->parameters.size(); ++i) env[s.action->parameters[i].name] = s.args[i];
    return env;
  }

  // The state before step `k` of `steps` (the final state for k = steps.size()).
  State state_before(const std::vector<Step>& steps, std::size_t k) {
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
  bool verify(const std::vector<Step>& steps) {
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
  std::optional<int> test_instance(const FactKey& fact) {
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
  std::vector<Step> without_pointless_steps(std::vector<Step> steps) {
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
  bool accept(std::vector<Step> steps) {
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
  bool improved_enough() {
    if (!improve_from_ || work_ - *improve_from_ < options_.improve_work) return false;
    solved(std::move(*best_));
    return true;
  }

  // The search ends without a cheaper plan: the best one found, if any, is the solution.
  void settle() {
    if (best_ && !out_.solved) solved(std::move(*best_));
  }

  // The symbolic searches look only for plans cheaper than the best so far.
  double cost_bound() const {
    return best_ && best_->cost ? *best_->cost - 1e-9 : std::numeric_limits<double>::infinity();
  }

  void solved(Costed plan) {
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

  pddl::Atom atom_of(const FactKey& f) const {
    pddl::Atom a;
    a.predicate = base_.predicate_name(f[0]);
    for (std::size_t i = 1; i < f.size(); ++i) a.args.push_back({base_.object(f[i]).name, false, {}});
    return a;
  }

  // ---- incremental --------------------------------------------------------------

  void incremental() {
    for (;;) {
      evaluator_.close_real();
      if (context_.deadline.expired()) return;
      if (auto steps = plan_symbolic(false); steps && verify(*steps) && accept(std::move(*steps))) return;
      if (improved_enough()) return;  // checked after every search: improve_work 0 stops at once
      std::vector<int> open;
      for (int s = 0; s < static_cast<int>(problem_.streams->streams.size()); ++s) {
        const StreamDecl::Kind kind = base_.decl(s).kind;
        if (kind == StreamDecl::Kind::rule || kind == StreamDecl::Kind::function) continue;
        if (context_.deadline.expired()) return;
        for (int id : evaluator_.real_instances(s)) {
          if (!base_.instance_at(id).exhausted) open.push_back(id);
        }
      }
      if (open.empty()) {
        out_.reason = "no plan exists: every stream instance is exhausted";
        return settle();
      }
      ++out_.statistics.level;
      for (int id : open) {
        if (context_.deadline.expired()) return;
        const std::uint64_t checks_before = context_.checks_done();
        evaluator_.call(id);
        work_ += options_.call_cost + static_cast<double>(context_.checks_done() - checks_before);
      }
    }
  }

  // ---- adaptive -------------------------------------------------------------------

  // Throws TimeLimit once the run's time is up, looking at the clock every 256th call:
  // a stream whose inputs nothing binds ranges over every object, and each new
  // optimistic value multiplies its instances.
  void keep_time_limit() {
    if ((++ticks_ & 255) == 0 && context_.deadline.expired()) throw search::TimeLimit("time limit (optimistic instantiation)");
  }

  // Optimistic facts for every enabled instance within `level`; returns whether an
  // instance was left out for its complexity.
  bool instantiate_optimistic(int level) {
    base_.clear_optimistic();
    bool pruned = false;
    // A stream none of whose domain predicates gained facts since its last pass has no
    // new bindings (free inputs range over the real objects, which do not change here).
    const std::size_t streams = problem_.streams->streams.size();
    std::vector<std::size_t> seen(streams, std::numeric_limits<std::size_t>::max());
    for (bool changed = true; changed;) {
      changed = false;
      for (int s = 0; s < static_cast<int>(streams); ++s) {
        // High levels of a generative domain make many instances: keep the time limit.
        if (context_.deadline.expired()) throw search::TimeLimit("time limit (optimistic instantiation)");
        const StreamDecl& d = base_.decl(s);
        if (d.kind == StreamDecl::Kind::function) continue;
        if (d.is_test() && negated_tests_.count(d.certified.front().predicate)) continue;  // false until tested
        if (evaluator_.options_of(d).p_success == 0.0) continue;  // only real evaluations certify its facts
        std::size_t facts = 0;
        for (const pddl::Atom& a : d.domain) facts += base_.fact_count(a.predicate);
        if (std::exchange(seen[static_cast<std::size_t>(s)], facts) == facts) continue;
        // The bindings in one flat array (an input tuple per stride): millions of them
        // must not be millions of allocations to free when the time limit ends the pass.
        const std::size_t stride = d.inputs.size();
        std::vector<ObjectId> found;
        std::vector<int> found_complexity;
        base_.bindings(d.inputs, d.domain, true, [&](const std::vector<ObjectId>& inputs, int c) {
          keep_time_limit();
          found.insert(found.end(), inputs.begin(), inputs.end());
          found_complexity.push_back(c);
        });
        std::vector<ObjectId> inputs(stride);
        for (std::size_t k = 0; k < found_complexity.size(); ++k) {
          keep_time_limit();
          std::copy_n(found.begin() + static_cast<std::ptrdiff_t>(k * stride), stride, inputs.begin());
          const int domain_complexity = found_complexity[k];
          const int id = base_.instance(s, inputs);
          Instance& inst = base_.instance_at(id);
          if (inst.real && (inst.exhausted || inst.disabled)) continue;
          // Not counting calls here: a stream that keeps failing must not starve every
          // fact that depends on its next output (advance() bounds calls per level).
          const int complexity = domain_complexity + 1;
          if (complexity > level) {
            pruned = true;
            continue;
          }
          if (inst.optimistic_outputs.size() != d.outputs.size()) {
            for (const pddl::Term& o : d.outputs) {
              ObjectRecord r;
              r.name = o.name;  // "?p" -> "@p12" (assigned in steps: GCC 12 warns on "@" + string)
              r.name[0] = '@';
              r.name += std::to_string(id);
              r.optimistic = true;
              r.maker = id;
              inst.optimistic_outputs.push_back(base_.add_object(std::move(r)));
            }
          }
          const Env env = base_.env_of(inst, &inst.optimistic_outputs);
          for (const pddl::Atom& a : d.certified) {
            if (const auto fact = base_.ground(a, env)) changed |= base_.add_fact(*fact, FactInfo{true, complexity, id});
          }
        }
      }
    }
    return pruned;
  }

  // The stream plan behind the optimistic facts a plan relies on, in an order where
  // every instance comes after those making its inputs.
  //
  // An instance of a stream with :fluents is evaluated in the state before the first
  // step that needs it (a test: before each such step), after the instances whose
  // optimistic outputs that state holds; an instance it feeds needs it as early.
  std::optional<Skeleton> skeleton_of(const std::vector<Step>& steps) {
    Uses uses;
    const auto support = plan_support(steps, true, &uses);
    if (!support) return std::nullopt;
    Skeleton sk;
    sk.actions = steps;
    auto optimistic_certifiers = [&](const Instance& inst) {
      std::vector<int> out;
      const Env env = base_.env_of(inst);
      for (const pddl::Atom& a : base_.decl(inst.stream).domain) {
        const auto fact = base_.ground(a, env);
        const FactInfo* info = fact ? base_.fact(*fact) : nullptr;
        if (info && info->optimistic && info->certifier >= 0) out.push_back(info->certifier);
      }
      return out;
    };
    // The steps at which each needed instance's facts are used.
    std::map<int, std::set<int>> needed;
    std::function<void(int, int)> need = [&](int id, int step) {
      if (!needed[id].insert(step).second) return;
      for (int d : optimistic_certifiers(base_.instance_at(id))) need(d, step);
    };
    for (const FactKey& f : support->facts) {
      const FactInfo* info = base_.fact(f);
      if (!info || !info->optimistic) continue;
      for (int step : uses.steps[f]) need(info->certifier, step);
    }
    auto entries = [&](int id, bool negated) {
      const StreamDecl& d = base_.decl(base_.instance_at(id).stream);
      const std::set<int>& at = needed[id];
      if (d.fluents.empty() || at.empty()) return std::vector<PlannedInstance>{{id, negated, -1}};
      if (!d.outputs.empty()) return std::vector<PlannedInstance>{{id, negated, *at.begin()}};
      std::vector<PlannedInstance> out;
      for (int step : at) out.push_back({id, negated, step});
      return out;
    };
    std::set<PlannedInstance> placed;
    std::function<void(const PlannedInstance&)> place = [&](const PlannedInstance& p) {
      if (!placed.insert(p).second) return;
      for (int d : optimistic_certifiers(base_.instance_at(p.instance))) {
        for (const PlannedInstance& e : entries(d, false)) place(e);
      }
      if (p.step >= 0) {  // the makers of the optimistic objects in its state come first
        for (const FactKey& f : base_.fluent_state(uses.states[static_cast<std::size_t>(p.step)], base_.instance_at(p.instance).stream)) {
          for (std::size_t i = 1; i < f.size(); ++i) {
            const ObjectRecord& o = base_.object(f[i]);
            if (!o.optimistic || o.maker < 0) continue;
            if (needed[o.maker].empty()) need(o.maker, p.step);  // once: a maker placed stays put
            for (const PlannedInstance& e : entries(o.maker, false)) place(e);
          }
        }
      }
      sk.stream_plan.push_back(p);
    };
    // Deferred streams (expensive ones, e.g. motion planning) after the others, unless
    // another needs their outputs first: a skeleton that fails in a cheap stream then
    // never pays for them.
    // Negated tests come after the streams of their pass.
    // Within each, cheap streams likely to fail first (PDDLStream's p_success and
    // overhead: the expected cost of a sequence of independent tests is least in
    // increasing overhead / (1 - p_success)); a stream's inputs are placed before it.
    std::vector<int> ordered;
    for (const auto& [id, at] : needed) ordered.push_back(id);
    auto failure_cost = [&](int id) {
      const StreamOptions& o = evaluator_.options_of(base_.decl(base_.instance_at(id).stream));
      return o.p_success < 1.0 ? o.overhead / (1.0 - o.p_success) : std::numeric_limits<double>::infinity();
    };
    std::stable_sort(ordered.begin(), ordered.end(), [&](int a, int b) { return failure_cost(a) < failure_cost(b); });
    auto deferred_stream = [&](int id) { return evaluator_.options_of(base_.decl(base_.instance_at(id).stream)).defer; };
    for (const bool deferred : {false, true}) {
      for (const int id : ordered) {
        if (deferred_stream(id) != deferred) continue;
        for (const PlannedInstance& e : entries(id, false)) place(e);
      }
      for (const FactKey& f : support->negated) {
        const auto id = test_instance(f);
        if (id && deferred_stream(*id) == deferred) place({*id, true, -1});
      }
    }
    std::ostringstream key;
    for (const Step& s : steps) {
      key << s.action->name;
      for (ObjectId o : s.args) key << ' ' << o;
      key << ';';
    }
    sk.key = key.str();
    sk.stack.push_back({});
    return sk;
  }

  enum class Move { moved, called, waiting };

  static ObjectId bound(const Binding& b, ObjectId o) {
    const auto it = b.mapping.find(o);
    return it == b.mapping.end() ? o : it->second;
  }

  static std::vector<Step> bound_steps(std::vector<Step> steps, const Binding& b) {
    for (Step& s : steps) {
      for (ObjectId& o : s.args) o = bound(b, o);
    }
    return steps;
  }

  // Evaluates one step of a skeleton's binding tree (its deepest binding). Returns a
  // finished plan, if any. An instance whose next call would exceed the level's
  // complexity waits, at the bottom of the stack, for the level to rise.
  std::optional<std::vector<Step>> advance(Skeleton& sk, Move& move) {
    move = Move::moved;
    Binding& b = sk.stack.back();
    if (b.index == sk.stream_plan.size()) {
      std::vector<Step> steps = bound_steps(sk.actions, b);
      sk.stack.pop_back();
      if (verify(steps)) return steps;
      return std::nullopt;
    }
    const PlannedInstance planned = sk.stream_plan[b.index];
    const Instance& optimistic = base_.instance_at(planned.instance);
    std::vector<ObjectId> inputs;
    for (ObjectId o : optimistic.inputs) inputs.push_back(bound(b, o));
    std::optional<std::vector<FactKey>> fluent_state;
    if (planned.step < 0 && !base_.decl(optimistic.stream).fluents.empty()) {
      sk.stack.pop_back();  // no step needs it directly (only a negated test's domain): no state to run it in
      return std::nullopt;
    }
    if (planned.step >= 0) {
      const State state = state_before(bound_steps(sk.actions, b), static_cast<std::size_t>(planned.step));
      fluent_state = base_.fluent_state(state, optimistic.stream);
      for (const FactKey& f : *fluent_state) {
        if (std::any_of(f.begin() + 1, f.end(), [&](ObjectId o) { return base_.object(o).optimistic; })) {
          sk.stack.pop_back();  // its state is not known yet (makers ordered in a cycle)
          return std::nullopt;
        }
      }
    }
    const int id = base_.instance(optimistic.stream, inputs, fluent_state);
    Instance& inst = base_.instance_at(id);
    const std::optional<int> domain = inst.real ? evaluator_.real_domain(inst) : std::nullopt;
    if (!domain) {  // an earlier value broke this branch
      sk.stack.pop_back();
      return std::nullopt;
    }
    if (planned.negated) {
      if (inst.calls == 0 && !inst.exhausted) {
        evaluator_.call(id);
        move = Move::called;
      }
      if (!inst.results.empty()) sk.stack.pop_back();  // the test holds: this branch fails
      else ++b.index;
      return std::nullopt;
    }
    if (b.consumed < inst.results.size()) {
      Binding child = b;
      child.index = b.index + 1;
      child.consumed = 0;
      const std::vector<ObjectId>& values = inst.results[b.consumed++];
      for (std::size_t i = 0; i < values.size() && i < optimistic.optimistic_outputs.size(); ++i) {
        child.mapping[optimistic.optimistic_outputs[i]] = values[i];
      }
      sk.stack.push_back(std::move(child));
      return std::nullopt;
    }
    if (inst.exhausted) {
      sk.stack.pop_back();
    } else if (*domain + inst.calls > level_) {
      std::rotate(sk.stack.begin(), sk.stack.end() - 1, sk.stack.end());
      move = Move::waiting;
    } else {
      evaluator_.call(id);
      inst.disabled = true;
      move = Move::called;
    }
    return std::nullopt;
  }

  // Works through the skeleton queue for `budget` units of work (StreamSearchOptions),
  // shortest plan first: a skeleton is worked on until all its bindings wait. Returns a
  // plan, if one comes out; `progress` tells whether a stream was called.
  std::optional<std::vector<Step>> refine(double budget, bool& progress) {
    progress = false;
    for (Skeleton& sk : queue_) sk.waiting = false;
    std::size_t waits = 0;  // bindings in a row of the current skeleton that wait
    double spent = 0;
    while (spent < budget && !context_.deadline.expired()) {
      const std::uint64_t checks_before = context_.checks_done();
      const auto it = std::min_element(queue_.begin(), queue_.end(), [](const Skeleton& a, const Skeleton& b) {
        return std::make_pair(a.waiting, a.actions.size()) < std::make_pair(b.waiting, b.actions.size());
      });
      if (it == queue_.end() || it->waiting) break;
      Move move = Move::moved;
      if (auto steps = advance(*it, move)) return steps;
      progress |= move == Move::called;
      const double work = 1.0 + (move == Move::called ? options_.call_cost : 0.0) +
                          static_cast<double>(context_.checks_done() - checks_before);
      spent += work;
      work_ += work;
      if (it->stack.empty()) {
        queue_.erase(it);
        waits = 0;
      } else if (move != Move::waiting) {
        waits = 0;
      } else if (++waits >= it->stack.size()) {
        it->waiting = true;
        waits = 0;
      }
    }
    return std::nullopt;
  }

  void adaptive() {
    std::set<std::string> queued;
    while (!context_.deadline.expired()) {
      evaluator_.close_real();
      const bool pruned = instantiate_optimistic(level_);
      const auto steps = plan_symbolic(true);
      bool fresh = false, too_long = false;
      if (steps) {
        // Plans may grow by plan_growth actions per level above the one of the shortest
        // plan found: sampling the short skeletons again beats detours through real
        // values. (With one action per level, stacked4 spent four levels resampling the
        // target's blocked pick before the five-step plan that moves two objects.)
        if (!shortest_ || steps->size() < shortest_->first) shortest_ = {steps->size(), level_};
        too_long = steps->size() > shortest_->first + static_cast<std::size_t>(options_.plan_growth * (level_ - shortest_->second));
      }
      if (steps && !too_long) {
        auto sk = skeleton_of(*steps);
        if (!sk) {
          out_.reason = "internal error: an optimistic plan does not hold when checked";
          return;
        }
        if (sk->stream_plan.empty() && verify(*steps)) {
          if (accept(*steps) || improved_enough()) return;
          continue;  // the next search is bounded by the best cost
        }
        if (queued.insert(sk->key).second) {
          ++out_.statistics.skeletons;
          queue_.push_back(std::move(*sk));
          fresh = true;
        }
      }
      if (options_.trace) {
        std::ostringstream line;
        line << "level " << level_ << ": " << (steps ? "plan of " + std::to_string(steps->size()) + " steps" : "no plan")
             << (fresh ? " (queued)" : "") << (too_long ? " (too long)" : "") << ", queue " << queue_.size() << ", calls " << out_.statistics.stream_calls
             << ", objects " << base_.object_count() << ", facts " << base_.facts().size() << ", operators "
             << last_grounding_.operators << " (" << last_grounding_.reused_instances << " instances re-used)";
        if (steps) {
          line << ":";
          for (const Step& st : *steps) {
            line << " (" << st.action->name;
            for (ObjectId o : st.args) line << ' ' << base_.object(o).name;
            line << ')';
          }
        }
        options_.trace(line.str());
      }
      bool progress = false;
      const double budget = std::max(options_.min_sampling, last_search_work_ * options_.sampling_ratio);
      if (auto done = refine(budget, progress); done && accept(std::move(*done))) return;
      if (improved_enough()) return;
      if (!steps || too_long || (!fresh && !progress)) {
        bool any_disabled = false;
        for (std::size_t i = 0; i < base_.instance_count(); ++i) {
          Instance& inst = base_.instance_at(static_cast<int>(i));
          any_disabled |= inst.disabled;
          inst.disabled = false;
        }
        if (!steps && !pruned && !any_disabled && queue_.empty()) {
          out_.reason = "no plan exists: not even with optimistic stream outputs";
          return settle();
        }
        ++level_;
        out_.statistics.level = static_cast<std::uint64_t>(level_);
      }
    }
  }

  const StreamProblem& problem_;
  const pddl::Domain& domain_;
  plugin::PlanningContext& context_;
  const StreamSearchOptions& options_;
  FactBase base_;
  State initial_state_;
  std::set<std::string> negated_tests_;
  std::deque<Skeleton> queue_;
  double last_search_seconds_ = 0;
  double last_search_work_ = 0;  // of the last search, in StreamSearchOptions' units
  search::GroundingStats last_grounding_;
  std::uint64_t ticks_ = 0;  // keep_time_limit's calls
  std::optional<std::pair<std::size_t, int>> shortest_;  // adaptive: shortest plan, its level
  int level_ = 0;  // adaptive: the complexity bound of optimistic instances and calls
  double work_ = 0;  // of searches and stream evaluation so far, in StreamSearchOptions' units
  std::optional<Costed> best_;  // the cheapest plan found
  std::optional<double> improve_from_;  // work_ when the first plan above success_cost was found
  // Each iteration's problem holds the last one's objects and more: grounded on the
  // last one's work. The real facts' problems and the optimistic ones are two series.
  search::Grounding optimistic_grounding_{domain_};
  search::Grounding real_grounding_{domain_};
  StreamSolution out_;
  StreamEvaluator evaluator_{problem_, base_, context_, options_, out_};
};

}  // namespace

StreamSolution solve(const StreamProblem& problem, plugin::PlanningContext& context, const StreamSearchOptions& options) {
  if (!problem.domain || !problem.problem || !problem.streams) {
    throw std::invalid_argument("stream::solve: domain, problem and streams are required");
  }
  auto search = std::make_unique<StreamSearch>(problem, context, options);
  StreamSolution solution = search->run();
  // Ended by the time limit (solved or not: success_cost may keep it going to the
  // limit), it may hold millions of instances and two groundings: freed beside the
  // caller, but the generators first, here: they are the plugins' code.
  if (context.deadline.expired()) {
    search->release_generators();
    free_beside(std::move(search));
  }
  return solution;
}

pddl::Problem with_certified_facts(const pddl::Domain& domain, const pddl::Problem& problem,
                                   const StreamSolution& solution) {
  pddl::Problem out = problem;
  std::set<std::string> used;  // generated values the plan uses
  for (const StreamPlanStep& s : solution.plan) {
    for (const std::string& arg : s.arguments) {
      if (!arg.empty() && arg[0] == '#' && used.insert(arg).second) out.objects.push_back({arg, {"object"}, {}});
    }
  }
  for (const pddl::Atom& a : solution.certified) {
    const bool relevant = domain.predicates.count(a.predicate) &&
                          std::all_of(a.args.begin(), a.args.end(), [&](const pddl::Term& t) {
                            return t.name.empty() || t.name[0] != '#' || used.count(t.name);
                          });
    if (relevant) out.init.push_back(a);
  }
  return out;
}

std::vector<pddl::PlanStep> pddl_plan(const StreamSolution& solution) {
  std::vector<pddl::PlanStep> out;
  for (const StreamPlanStep& s : solution.plan) out.push_back({s.action, s.arguments, {}});
  return out;
}

}  // namespace cluttertamp::stream
