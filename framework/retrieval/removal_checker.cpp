#include "cluttertamp/retrieval/removal_checker.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <set>

#include "cluttertamp/collision/shared_world.hpp"
#include "cluttertamp/core/geometry.hpp"
#include "cluttertamp/manipulation/actions.hpp"
#include "cluttertamp/plugin/grasp_sampler.hpp"
#include "cluttertamp/plugin/motion_sampler.hpp"
#include "cluttertamp/plugin/placement_sampler.hpp"
#include "cluttertamp/robot/robot_description.hpp"

namespace cluttertamp::retrieval {

namespace {

// One trajectory through an action's motions (they share their endpoints).
Trajectory join(const std::vector<manipulation::Segment>& segments) {
  Trajectory t;
  double offset = 0.0;
  for (const manipulation::Segment& s : segments) {
    t.joint_names = s.trajectory.joint_names;
    for (std::size_t k = 0; k < s.trajectory.positions.size(); ++k) {
      if (!t.positions.empty() && k == 0) continue;
      t.times.push_back(offset + s.trajectory.times[k]);
      t.positions.push_back(s.trajectory.positions[k]);
    }
    offset = t.times.empty() ? 0.0 : t.times.back();
  }
  return t;
}

// The segments of `out` from index `from` up to (not including) `to`, joined.
Trajectory join_range(const std::vector<manipulation::Segment>& segments, std::size_t from, std::size_t to) {
  return join({segments.begin() + static_cast<std::ptrdiff_t>(from), segments.begin() + static_cast<std::ptrdiff_t>(to)});
}

// Index of the first segment named `name`, or the number of segments.
std::size_t segment_index(const std::vector<manipulation::Segment>& segments, const std::string& name) {
  std::size_t i = 0;
  while (i < segments.size() && segments[i].name != name) ++i;
  return i;
}

// The motions of a pick (or retrieve) of `object` from `before`: empty-handed up to the
// lift, then holding the object as it stood when the fingers closed. (A template: the
// step's motions are a private type of RemovalChecker.)
template <class StepT>
void add_taking_motions(StepT& s, const WorldState& before, ObjectIndex object, const manipulation::ActionOutcome& out) {
  const std::size_t lift = segment_index(out.segments, "lift");
  s.motions.push_back({before, join_range(out.segments, 0, lift)});
  if (lift == out.segments.size()) return;
  WorldState holding = before;
  holding.held = object;
  holding.robot_configuration = out.segments[lift].trajectory.positions.front();
  s.motions.push_back({holding, join_range(out.segments, lift, out.segments.size())});
}

PlanStep plan_step(const std::string& action, ObjectIndex object, const manipulation::ActionOutcome& out) {
  PlanStep step;
  step.action = action;
  step.objects = {object};
  step.trajectory = join(out.segments);
  return step;
}

// Why a check stopped before its next action: the run's time, or its work budget.
Failure out_of_budget(const plugin::PlanningContext& context) {
  return {"plan", context.deadline.expired() ? "time limit reached" : "work budget (collision checks) used up", {}};
}

}  // namespace

RemovalChecker::RemovalChecker(plugin::PlanningContext& context, const WorldState& initial, std::string placement_region)
    : context_(context), initial_(initial), region_(std::move(placement_region)) {}

plugin::PlanningContext RemovalChecker::attempt(std::uint64_t salt) const {
  return context_.with_seed(context_.seed + 0x9e3779b97f4a7c15ull * salt);
}

const RemovalChecker::Step& RemovalChecker::step(std::span<const ObjectIndex> prefix, ObjectIndex object,
                                                 std::uint64_t salt) {
  Key key{{prefix.begin(), prefix.end()}, salt};
  key.first.push_back(object);
  if (const auto it = steps_.find(key); it != steps_.end()) return it->second;
  const WorldState& before = prefix.empty() ? initial_ : step(prefix.first(prefix.size() - 1), prefix.back(), salt).after;

  ++actions_planned_;
  plugin::PlanningContext context = attempt(salt);
  const auto t0 = std::chrono::steady_clock::now();
  Step s;
  if (object == context_.scene().target) {
    plugin::Phase phase(context, "check.retrieve");
    const std::vector<Eigen::Vector2d> way = way_out_ ? way_out_(before) : std::vector<Eigen::Vector2d>{};
    const manipulation::ActionOutcome out = manipulation::retrieve(context, before, way);
    s.ok = out.ok;
    s.failure = out.failure;
    if (out.ok) {
      s.after = out.after;
      s.steps.push_back(plan_step("retrieve", object, out));
      add_taking_motions(s, before, object, out);
    }
  } else {
    std::optional<plugin::Phase> phase(std::in_place, context, "check.pick");
    const manipulation::ActionOutcome picked = manipulation::pick(context, before, object);
    phase.reset();
    s.ok = picked.ok;
    s.failure = picked.failure;
    if (picked.ok) {
      s.steps.push_back(plan_step("pick", object, picked));
      add_taking_motions(s, before, object, picked);
      s.after = picked.after;
      phase.emplace(context, "check.place");
      const manipulation::ActionOutcome placed = manipulation::place(context, picked.after, region_);
      phase.reset();
      if (placed.ok) {
        s.steps.push_back(plan_step("place", object, placed));
        const std::size_t release = segment_index(placed.segments, "release");
        s.motions.push_back({picked.after, join_range(placed.segments, 0, release)});
        s.motions.push_back({placed.after, join_range(placed.segments, release, placed.segments.size())});
        s.after = placed.after;
      } else {
        s.note = Failure{"place", "'" + context_.scene().objects[object].id + "' could not be placed in '" + region_ +
                                      "' and was taken out of the workspace: " +
                                      (placed.failure ? placed.failure->reason : ""),
                         {}};
        s.after.held.reset();
      }
      s.after.removed[object] = true;
    }
  }
  motion_seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return steps_.emplace(std::move(key), std::move(s)).first->second;
}

RemovalCheck RemovalChecker::remove(std::span<const ObjectIndex> order, std::uint64_t salt) {
  RemovalCheck check;
  check.state = initial_;
  for (std::size_t i = 0; i < order.size(); ++i) {
    if (context_.stopped()) {
      check.failed_object = order[i];
      check.failure = out_of_budget(context_);
      return check;
    }
    const Step& s = step(order.first(i), order[i], salt);
    if (!s.ok) {
      check.failed_object = order[i];
      check.failure = s.failure;
      return check;
    }
    check.state = s.after;
    check.removed = i + 1;
  }
  check.ok = true;
  return check;
}

RemovalCheck RemovalChecker::retrieve(std::span<const ObjectIndex> order, std::uint64_t salt) {
  RemovalCheck check = remove(order, salt);
  if (!check.ok) return check;
  check.ok = false;
  const ObjectIndex target = context_.scene().target;
  if (context_.stopped()) {
    check.failed_object = target;
    check.failure = out_of_budget(context_);
    return check;
  }
  const Step& s = step(order, target, salt);
  check.ok = s.ok;
  if (!s.ok) {
    check.failed_object = target;
    check.failure = s.failure;
  } else {
    check.state = s.after;
  }
  return check;
}

void RemovalChecker::record_times(Result& result, std::chrono::steady_clock::time_point start) const {
  const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  result.time.motion_planning = motion_seconds_;
  result.time.task_planning = std::max(0.0, total - motion_seconds_);
  result.counters[counter::actions_planned] = actions_planned_;
}

void RemovalChecker::write_steps(std::span<const ObjectIndex> order, std::uint64_t salt, Result& result) const {
  std::vector<ObjectIndex> key{};
  for (ObjectIndex object : order) {
    key.push_back(object);
    const Step& s = steps_.at({key, salt});
    result.plan.insert(result.plan.end(), s.steps.begin(), s.steps.end());
    if (s.note) result.failures.push_back(*s.note);
    result.moved_objects.push_back(object);
  }
}

std::vector<ObjectIndex> RemovalChecker::met_by_plan(std::span<const ObjectIndex> order, std::uint64_t salt,
                                                     bool with_target, std::span<const ObjectIndex> restored,
                                                     const WorldState& where) const {
  std::vector<ObjectIndex> key, steps(order.begin(), order.end());
  if (with_target) steps.push_back(context_.scene().target);
  std::set<ObjectIndex> met;
  collision::CollisionWorld& world = *collision::shared_world(context_);
  auto checker = world.make_context();
  for (ObjectIndex object : steps) {
    key.push_back(object);
    for (const Motion& m : steps_.at({key, salt}).motions) {
      // Only the restored objects stand in this world: any touch is one of them.
      WorldState state = m.start;
      std::fill(state.removed.begin(), state.removed.end(), true);
      if (state.held) state.removed[*state.held] = false;
      for (ObjectIndex r : restored) {
        if (r == object || r == state.held) continue;
        state.removed[r] = false;
        state.world_T_objects[r] = where.world_T_objects[r];
      }
      world.sync(state);
      const std::vector<Eigen::VectorXd>& qs = m.trajectory.positions;
      for (std::size_t i = 0; i < qs.size(); ++i) {
        const Eigen::VectorXd& b = qs[i];
        const Eigen::VectorXd& a = i ? qs[i - 1] : b;
        const int n = std::max(1, static_cast<int>(std::ceil((b - a).cwiseAbs().maxCoeff() / 0.01)));
        for (int k = i ? 1 : 0; k <= n; ++k) {
          const Eigen::VectorXd q = a + (b - a) * (double(k) / n);
          if (!world.touches_object(q, *checker)) continue;
          for (ObjectIndex o : world.check(q, *checker).objects) met.insert(o);
        }
      }
    }
  }
  return {met.begin(), met.end()};
}

void RemovalChecker::write_plan(std::span<const ObjectIndex> order, std::uint64_t salt, Result& result) const {
  std::vector<ObjectIndex> with_target(order.begin(), order.end());
  with_target.push_back(context_.scene().target);
  write_steps(with_target, salt, result);
}

collision::Footprint held_footprint(const plugin::PlanningContext& context, const WorldState& state, ObjectIndex object) {
  const SceneObject& o = context.scene().objects[object];
  const double radius = std::holds_alternative<Cylinder>(o.shape) ? std::get<Cylinder>(o.shape).radius
                                                                   : std::get<Box>(o.shape).size.head<2>().norm() / 2;
  const Eigen::AlignedBox3d bounds = world_bounds(o.shape, state.world_T_objects[object]);
  return {context.robot().gripper().footprint_radius(radius), bounds.min().z(), bounds.max().z()};
}

void record_failure_once(Result& result, const Failure& failure) {
  for (const Failure& f : result.failures) {
    if (f.stage == failure.stage && f.reason == failure.reason && f.blocking_objects == failure.blocking_objects) return;
  }
  result.failures.push_back(failure);
}

std::vector<std::string> retrieval_sampler_kinds() {
  return {plugin::KindOf<plugin::GraspSampler>::name, plugin::KindOf<plugin::MotionSampler>::name,
          plugin::KindOf<plugin::PlacementSampler>::name};
}

std::optional<std::string> retrieval_inputs_missing(const plugin::PlanningContext& context, const std::string& planner) {
  if (!context.worlds || !context.problem.robot.loaded) return "the problem has no robot";
  if (!std::holds_alternative<RetrievalTask>(context.problem.task)) return planner + " plans retrieve tasks only";
  if (!context.samplers.get<plugin::GraspSampler>() || !context.samplers.get<plugin::MotionSampler>() || !context.samplers.get<plugin::PlacementSampler>()) {
    return planner + " needs a grasp_sampler, a motion_sampler and a placement_sampler in the problem's plugins block";
  }
  return std::nullopt;
}

}  // namespace cluttertamp::retrieval
