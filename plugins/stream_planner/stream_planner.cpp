// stream_planner: solves a problem file's `task: pddl: {domain, problem, streams}` with
// the stream search (adaptive or incremental), the streams bound to the stream_sampler
// plugins of `plugins: streams:`. Without a PDDL problem the facts come from the scene
// (stream::scene_problem). With `prune` and an object_pruner plugin (e.g. the
// retrieval graph), only the objects of the pruner's candidate removal sequences are
// movable; all others stay where they are as obstacles (Tian et al., Section V-C).

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <optional>

#include "cluttertamp/core/problem.hpp"
#include "cluttertamp/core/geometry.hpp"
#include "cluttertamp/pddl/parser.hpp"
#include "cluttertamp/pddl/sexpr.hpp"
#include "cluttertamp/plugin/export.hpp"
#include "cluttertamp/plugin/object_pruner.hpp"
#include "cluttertamp/plugin/task_planner.hpp"
#include "cluttertamp/stream/scene_facts.hpp"
#include "cluttertamp/stream/stream_file.hpp"
#include "cluttertamp/stream/stream_search.hpp"

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

class StreamPlanner final : public plugin::TaskPlanner {
 public:
  void configure(const Parameters& p) override {
    const std::string algorithm = p.get_string("algorithm", "adaptive");
    const auto a = stream::algorithm_from_name(algorithm);
    p.require(a.has_value(), "algorithm", "must be adaptive or incremental");
    if (a) options_.algorithm = *a;
    options_.search = p.get_string("search", options_.search);
    options_.sampling_ratio = p.get_double("sampling_ratio", options_.sampling_ratio);
    options_.call_cost = p.get_double("call_cost", options_.call_cost);
    options_.search_cost = p.get_double("search_cost", options_.search_cost);
    options_.min_sampling = p.get_double("min_sampling", options_.min_sampling);
    p.require(options_.sampling_ratio > 0, "sampling_ratio", "must be positive");
    p.require(options_.call_cost >= 0, "call_cost", "must not be negative (work units per stream call)");
    p.require(options_.search_cost >= 0, "search_cost", "must not be negative (work units per search)");
    p.require(options_.min_sampling > 0, "min_sampling", "must be positive (work units per sampling pass)");
    const std::int64_t growth = p.get_int("plan_growth", options_.plan_growth);
    p.require(growth >= 1 && growth <= 1000, "plan_growth", "must be in [1, 1000] (actions per level)");
    options_.plan_growth = static_cast<int>(growth);
    prune_ = p.get_bool("prune", prune_);
    if (p.get_bool("trace", false)) {
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
    const pddl::Domain domain = pddl::load_domain(task->domain);
    const stream::StreamFile streams = stream::load_stream_file(*task->streams, &domain);

    // The facts: the PDDL problem, or the scene with the movable objects chosen.
    pddl::Problem problem;
    stream::StreamProblem sp;
    std::map<std::string, ObjectIndex> scene_objects;
    bool pruned_to_nothing = false;  // the pruner's sequences named no object to move
    // The problem with the pruner's obstacles not movable, and a context over it.
    std::optional<Problem> pruned_problem;
    std::optional<plugin::PlanningContext> pruned_context;
    if (task->problem) {
      problem = pddl::load_problem(*task->problem, domain);
    } else {
      std::vector<bool> movable;
      for (const SceneObject& o : context.scene().objects) movable.push_back(o.movable);
      if (prune_ && context.samplers.object_pruner) {
        const plugin::PruneAnswer pruned = context.samplers.object_pruner->prune(context, initial);
        if (pruned.failure) result.failures.push_back(*pruned.failure);
        if (!pruned.removal_sequences.empty()) {
          std::fill(movable.begin(), movable.end(), false);
          for (ObjectIndex o : pruned.movable_objects()) movable[o] = true;
          context.scene().mark_what_rests_on(movable);  // it has to go first
        }
        std::uint64_t n = 0;
        for (bool m : movable) n += m;
        result.counters["movable_objects"] = n;
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
                                                        context.samplers, context.world, context.checks_until, context.phases});
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
    for (const stream::StreamPlanStep& step : s.plan) result.plan.push_back(plan_step(step, s, scene_objects, result));
    const auto& st = s.statistics;
    result.counters["stream_calls"] = st.stream_calls;
    result.counters["stream_instances"] = st.stream_instances;
    result.counters["searches"] = st.searches;
    result.counters["skeletons"] = st.skeletons;
    result.counters["level"] = st.level;
    result.counters["plan_length"] = s.plan.size();
    for (const auto& [stream_name, calls] : st.calls_per_stream) result.counters["calls_" + stream_name] = calls;
    result.time.total = since(start);
    result.time.motion_planning = st.stream_seconds;
    result.time.task_planning = st.search_seconds + pruning_seconds;
    return result;
  }

 private:
  PlanStep plan_step(const stream::StreamPlanStep& step, const stream::StreamSolution& s,
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
      const auto v = s.values.find(arg);
      if (v == s.values.end()) continue;
      const std::vector<double> numbers = numbers_of(v->second);
      if (!numbers.empty()) out.values[arg] = numbers;
      if (const auto* payload = std::get_if<std::shared_ptr<const plugin::StreamPayload>>(&v->second)) {
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
