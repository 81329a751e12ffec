// stream_planner: solves a problem file's `task: pddl: {domain, problem, streams}` with
// the stream search (adaptive or incremental), the streams bound to the stream_sampler
// plugins of `plugins: streams:`. Without a PDDL problem the facts come from the scene
// (stream::scene_problem). With `prune` and an object_pruner plugin (e.g. the
// retrieval graph), only the objects of the pruner's candidate removal sequences are
// movable; all others stay where they are as obstacles (Tian et al., Section V-C).

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <optional>
#include <set>

#include "cluttertamp/core/problem.hpp"
#include "cluttertamp/core/geometry.hpp"
#include "cluttertamp/pddl/parser.hpp"
#include "cluttertamp/pddl/sexpr.hpp"
#include "cluttertamp/search/planner.hpp"
#include "cluttertamp/plugin/export.hpp"
#include "cluttertamp/plugin/object_pruner.hpp"
#include "cluttertamp/plugin/task_planner.hpp"
#include "cluttertamp/stream/scene_facts.hpp"
#include "cluttertamp/stream/stream_file.hpp"
#include "cluttertamp/stream/stream_search.hpp"
#include "cluttertamp/stream/stream_task.hpp"

namespace {

using namespace cluttertamp;
using Clock = std::chrono::steady_clock;

double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

std::vector<double> numbers_of(const plugin::StreamValue& v) {
  if (const auto* x = std::get_if<double>(&v)) return {*x};
  if (const auto* q = std::get_if<Eigen::VectorXd>(&v)) return {q->data(), q->data() + q->size()};
  if (const auto* p = std::get_if<Eigen::Isometry3d>(&v)) return pose_values(*p);
  if (const auto* payload = std::get_if<std::shared_ptr<const plugin::StreamPayload>>(&v)) {
    return *payload ? (*payload)->numbers() : std::vector<double>{};
  }
  return {};
}

const plugin::StreamValue* find_value(const std::map<std::string, plugin::StreamValue>& values, const std::string& name) {
  const auto it = values.find(name);
  return it == values.end() ? nullptr : &it->second;
}

class StreamPlanner final : public plugin::TaskPlanner {
 public:
  void configure(const Parameters& p) override {
    const std::string algorithm = p.get_string("algorithm", "adaptive", "adaptive (focused) or incremental");
    const auto a = stream::algorithm_from_name(algorithm);
    p.require(a.has_value(), "algorithm", "must be adaptive or incremental");
    if (a) options_.algorithm = *a;
    options_.search = p.get_string("search", options_.search, "the symbolic search (cluttertamp pddl --help lists them)");
    options_.sampling_ratio = p.get_double("sampling_ratio", options_.sampling_ratio, "adaptive: stream work per unit of search work");
    options_.call_cost = p.get_double("call_cost", options_.call_cost, "work units per stream call");
    options_.search_cost = p.get_double("search_cost", options_.search_cost, "work units per search");
    options_.min_sampling = p.get_double("min_sampling", options_.min_sampling, "adaptive: work units of sampling at least, each time");
    p.require(options_.sampling_ratio > 0, "sampling_ratio", "must be positive");
    p.require(options_.call_cost >= 0, "call_cost", "must not be negative (work units per stream call)");
    p.require(options_.search_cost >= 0, "search_cost", "must not be negative (work units per search)");
    p.require(options_.min_sampling > 0, "min_sampling", "must be positive (work units per sampling pass)");
    const std::int64_t growth = p.get_int("plan_growth", options_.plan_growth, "adaptive: actions a plan may grow per level");
    p.require(growth >= 1 && growth <= 1000, "plan_growth", "must be in [1, 1000] (actions per level)");
    options_.plan_growth = static_cast<int>(growth);
    options_.polish_search = p.get_string("polish_search", options_.polish_search,
                                          "once solved, a cost-aware search for a cheaper plan (\"\": none)");
    const std::int64_t polish = p.get_int("polish_expansions", static_cast<std::int64_t>(options_.polish_expansions),
                                          "expansions of that search at most");
    p.require(polish >= 0, "polish_expansions", "must not be negative");
    const auto& names = search::search_names();
    std::string known;
    for (const std::string& n : names) known += (known.empty() ? "" : ", ") + n;
    for (const auto& [key, value] : {std::pair{"search", options_.search}, std::pair{"polish_search", options_.polish_search}}) {
      const bool ok = std::find(names.begin(), names.end(), value) != names.end() || (value.empty() && key == std::string("polish_search"));
      p.require(ok, key, "must be one of " + known);
    }
    options_.polish_expansions = static_cast<std::uint64_t>(polish);
    options_.success_cost = p.get_double("success_cost", options_.success_cost,
                                         "return a plan once it costs at most this (unset: the first plan)");
    p.require(options_.success_cost >= 0, "success_cost", "must be a number >= 0 (leave it out for the first plan)");
    options_.improve_work = p.get_double("improve_work", options_.improve_work,
                                         "work units spent on cheaper plans after the first above success_cost");
    p.require(options_.improve_work >= 0 && std::isfinite(options_.improve_work), "improve_work",
              "must be a finite number >= 0 (work units)");
    if (const Value* streams = p.get("streams", "per stream: {NAME: {eager: bool, defer: bool, optimistic: number, p_success: [0, 1], overhead: number}}")) {
      options_.streams = stream_options(*streams);
    }
    prune_ = p.get_bool("prune", prune_, "scene facts: only the object pruner's objects are movable");
    if (p.get_bool("trace", false, "a line per search iteration on stderr")) {
      options_.trace = [](const std::string& line) { std::fprintf(stderr, "stream search: %s\n", line.c_str()); };
    }
  }

  Result solve(plugin::PlanningContext& context, const WorldState& initial) override {
    const auto start = Clock::now();
    Result result;
    const auto* task = std::get_if<PddlTask>(&context.problem.task);
    if (!task || !task->streams) {
      result.reason = "stream_planner needs task: pddl: {domain, streams[, problem]} in the problem file";
      return result;
    }
    // Parsed once, when the problem was loaded.
    const std::shared_ptr<const stream::ParsedTask> parsed = stream::parsed_task(*task);
    const pddl::Domain& domain = parsed->domain;
    const stream::StreamFile& streams = *parsed->streams;

    // The facts: the PDDL problem, or the scene with the movable objects chosen.
    pddl::Problem problem;
    stream::StreamProblem sp;
    std::map<std::string, ObjectIndex> scene_objects;
    bool pruned_to_nothing = false;  // the pruner's sequences named no object to move
    // The problem with the pruner's obstacles not movable, and a context over it.
    std::optional<Problem> pruned_problem;
    std::optional<plugin::PlanningContext> pruned_context;
    if (task->problem) {
      problem = *parsed->problem;
      sp.values = object_values(*task, domain, problem);
    } else {
      std::vector<bool> movable;
      for (const SceneObject& o : context.scene().objects) movable.push_back(o.movable);
      if (const auto pruner = context.samplers.get<plugin::ObjectPruner>(); prune_ && pruner) {
        const plugin::PruneAnswer pruned = pruner->prune(context, initial);
        if (pruned.failure) result.failures.push_back(*pruned.failure);
        if (!pruned.removal_sequences.empty()) {
          std::fill(movable.begin(), movable.end(), false);
          for (ObjectIndex o : pruned.movable_objects()) movable[o] = true;
          context.scene().mark_what_rests_on(movable);  // it has to go first
        }
        std::uint64_t n = 0;
        for (bool m : movable) n += m;
        result.counters[counter::movable_objects] = n;
        pruned_to_nothing = n == 0;
      }
      if (std::find(movable.begin(), movable.end(), false) != movable.end()) {
        // The obstacles stay where they stand: the streams see them as not movable, so
        // they plan around them instead of asking a test about each.
        pruned_problem.emplace(context.problem);
        for (ObjectIndex o = 0; o < movable.size(); ++o) {
          if (!movable[o] && o != context.scene().target) pruned_problem->scene.objects[o].movable = false;
        }
        pruned_context.emplace(plugin::PlanningContext{*pruned_problem, context.deadline, context.seed, context.counters,
                                                        context.samplers, context.worlds, context.checks_until, context.phases});
      }
      stream::SceneProblem derived = stream::scene_problem(context.scene(), movable, domain.name);
      problem = std::move(derived.problem);
      sp.values = std::move(derived.values);
      scene_objects = std::move(derived.objects);
    }
    const double pruning_seconds = since(start);
    sp.domain = &domain;
    sp.problem = &problem;
    sp.streams = &streams;
    for (const auto& [name, sampler] : context.samplers.streams) sp.bindings[pddl::lower_name(name)] = sampler.get();

    const stream::StreamSolution s = stream::solve(sp, pruned_context ? *pruned_context : context, options_);
    result.solved = s.solved;
    result.reason = s.reason;
    result.failures.insert(result.failures.end(), s.failures.begin(), s.failures.end());
    if (!s.solved && pruned_to_nothing) {
      // The search cannot tell that no obstacle may move; the user should hear it.
      result.failures.push_back({"object_pruner",
                                 "the object pruner's sequences named no object to move, so every obstacle stayed fixed "
                                 "(with parameter prune: false every object is movable)",
                                 {}});
    }
    for (const stream::StreamPlanStep& step : s.plan) result.plan.push_back(plan_step(step, s, sp.values, scene_objects, result));
    const auto& st = s.statistics;
    result.counters[counter::stream_calls] = st.stream_calls;
    result.counters[counter::stream_instances] = st.stream_instances;
    result.counters[counter::searches] = st.searches;
    result.counters[counter::skeletons] = st.skeletons;
    result.counters[counter::level] = st.level;
    result.counters[counter::plan_length] = s.plan.size();
    result.counters[counter::plans_found] = st.plans;
    result.cost = s.cost;
    for (const auto& [stream_name, calls] : st.calls_per_stream) result.counters["calls_" + stream_name] = calls;
    result.time.total = since(start);
    result.time.motion_planning = st.stream_seconds;
    result.time.task_planning = st.search_seconds + pruning_seconds;
    return result;
  }

 private:
  // `streams: {test-region: {eager: true}, dist: {optimistic: 10}}`, each error at its value.
  static std::map<std::string, stream::StreamOptions> stream_options(const Value& streams) {
    const Value::Map* entries = streams.map();
    if (!entries) throw InputError(streams.where(), "parameter 'streams' must map stream names to {eager, defer, optimistic, p_success, overhead}, not " + std::string(streams.kind_name()));
    std::map<std::string, stream::StreamOptions> out;
    Diagnostics d;
    for (const auto& [name, settings] : *entries) {
      if (out.count(pddl::lower_name(name))) {
        d.error(settings.where(), "stream '" + name + "' is named twice (stream names are case-insensitive)");
        continue;
      }
      stream::StreamOptions& o = out[pddl::lower_name(name)];
      if (!settings.map()) {
        d.error(settings.where(), "stream '" + name + "': options must be a map {eager: bool, defer: bool, optimistic: number, p_success: number, overhead: number}");
        continue;
      }
      for (const auto& [key, value] : *settings.map()) {
        const std::optional<double> number = value.number();
        const bool finite = number && std::isfinite(*number);
        if ((key == "eager" || key == "defer") && value.boolean()) (key == "eager" ? o.eager : o.defer) = *value.boolean();
        else if (key == "optimistic" && finite && *number >= 0) o.optimistic_value = *number;
        else if (key == "p_success" && finite && *number >= 0 && *number <= 1) o.p_success = *number;
        else if (key == "overhead" && finite && *number >= 0) o.overhead = *number;
        else if (key == "eager" || key == "defer") d.error(value.where(), "stream '" + name + "': '" + key + "' must be a boolean, not " + value.to_yaml());
        else if (key == "optimistic") d.error(value.where(), "stream '" + name + "': 'optimistic' must be a number >= 0 (a cost's lower bound), not " + value.to_yaml());
        else if (key == "overhead") d.error(value.where(), "stream '" + name + "': 'overhead' must be a number >= 0, not " + value.to_yaml());
        else if (key == "p_success") d.error(value.where(), "stream '" + name + "': 'p_success' must be a probability in [0, 1], not " + value.to_yaml());
        else d.error(value.where(), "stream '" + name + "': unknown option '" + key + "' (eager, defer, optimistic, p_success, overhead)");
      }
    }
    d.throw_if_any();
    return out;
  }

  // The problem file's `values:`, checked against the PDDL problem's objects and the
  // domain's constants (case-insensitive, as PDDL names are).
  static std::map<std::string, plugin::StreamValue> object_values(const PddlTask& task, const pddl::Domain& domain,
                                                                  const pddl::Problem& problem) {
    std::set<std::string> names;
    for (const pddl::TypedName& o : problem.objects) names.insert(pddl::lower_name(o.name));
    for (const pddl::TypedName& c : domain.constants) names.insert(pddl::lower_name(c.name));
    Diagnostics diagnostics;
    std::map<std::string, plugin::StreamValue> values;
    for (const auto& [object, value] : task.values) {
      const std::string name = pddl::lower_name(object);
      if (values.count(name)) {
        diagnostics.error(value.where(), "values: '" + object + "' is given twice (PDDL names are case-insensitive)");
        continue;
      }
      if (!names.count(name)) {
        diagnostics.error(value.where(), "values: '" + object + "' is not an object of PDDL problem " + problem.file +
                                             " nor a constant of its domain");
        continue;
      }
      values[name] = plugin::stream_value(value);
    }
    diagnostics.throw_if_any();
    return values;
  }

  PlanStep plan_step(const stream::StreamPlanStep& step, const stream::StreamSolution& s,
                     const std::map<std::string, plugin::StreamValue>& given,
                     const std::map<std::string, ObjectIndex>& scene_objects, Result& result) const {
    PlanStep out;
    out.action = step.action;
    out.arguments = step.arguments;
    for (std::size_t i = 0; i < step.arguments.size(); ++i) {
      const std::string& arg = step.arguments[i];
      if (const auto o = scene_objects.find(arg); o != scene_objects.end()) {
        out.objects.push_back(o->second);
        if (i == 0 && step.action == "pick") result.moved_objects.push_back(o->second);
        continue;
      }
      const plugin::StreamValue* value = find_value(s.values, arg);
      if (!value) value = find_value(given, pddl::lower_name(arg));
      if (!value) continue;
      const std::vector<double> numbers = numbers_of(*value);
      if (!numbers.empty()) out.values[arg] = numbers;
      if (const auto* payload = std::get_if<std::shared_ptr<const plugin::StreamPayload>>(value)) {
        if (*payload && (*payload)->trajectory()) out.trajectory = *(*payload)->trajectory();
      }
    }
    return out;
  }

  stream::StreamSearchOptions options_;
  bool prune_ = true;
};

}  // namespace

CLUTTERTAMP_EXPORT_TASK_PLANNER(StreamPlanner, stream_planner,
                                "PDDL with streams: adaptive (focused) or incremental search, optionally on pruned objects",
                                "1.0.0")
