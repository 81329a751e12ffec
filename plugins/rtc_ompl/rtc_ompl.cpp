// rtc_ompl: reaching through clutter (RTC) by pushing, Papallas & Dogar (ICRA 2020),
// Section IV — a kinodynamic planner of OMPL's control layer (RRT or KPIECE1) over the
// planar pushing physics (physics::PushWorld): the state is the gripper's planar pose
// and every object's planar pose and velocity, a control a planar gripper velocity held
// for a multiple of the propagation step. A state is valid while no object has left its
// support or the shelf and the gripper has not entered fixed geometry. The goal: the
// gripper in front of the target, facing it, within a tolerance.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include <ompl/base/ProblemDefinition.h>
#include <ompl/base/ProjectionEvaluator.h>
#include <ompl/base/goals/GoalSampleableRegion.h>
#include <ompl/base/spaces/RealVectorStateSpace.h>
#include <ompl/base/spaces/SE2StateSpace.h>
#include <ompl/control/PathControl.h>
#include <ompl/control/SpaceInformation.h>
#include <ompl/control/planners/kpiece/KPIECE1.h>
#include <ompl/control/planners/rrt/RRT.h>
#include <ompl/control/spaces/RealVectorControlSpace.h>
#include <ompl/util/Console.h>

#include "cluttertamp/physics/push_world.hpp"
#include "cluttertamp/plugin/export.hpp"
#include "cluttertamp/plugin/task_planner.hpp"

namespace {

using namespace cluttertamp;
namespace ob = ompl::base;
namespace oc = ompl::control;
using Clock = std::chrono::steady_clock;

struct Settings {
  std::string planner = "rrt";    // rrt or kpiece
  double step = 0.1;              // s: OMPL's propagation step size
  int max_steps = 10;             // a control lasts 1..max_steps steps
  double max_speed = 0.15;        // m/s along world +x (into the shelf); controls are world-frame
  double max_side_speed = 0.1;    // m/s along world y either way, and along -x (out of the shelf)
  double max_turn = 0.5;          // rad/s
  double goal_distance = 0.03;    // m: gripper face to target surface, at most
  double goal_heading = 0.5;      // rad: the target within this of the gripper's heading
  double goal_bias = 0.05;        // RRT

  void read(const Parameters& p) {
    planner = p.get_string("planner", planner);
    step = p.get_double("step", step);
    max_steps = static_cast<int>(p.get_int("max_steps", max_steps));
    max_speed = p.get_double("max_speed", max_speed);
    max_side_speed = p.get_double("max_side_speed", max_side_speed);
    max_turn = p.get_double("max_turn", max_turn);
    goal_distance = p.get_double("goal_distance", goal_distance);
    goal_heading = p.get_double("goal_heading", goal_heading);
    goal_bias = p.get_double("goal_bias", goal_bias);
    p.require(planner == "rrt" || planner == "kpiece", "planner", "must be rrt or kpiece");
    p.require(step > 0, "step", "must be positive (seconds)");
    p.require(max_steps >= 1, "max_steps", "must be at least 1");
    p.require(max_speed > 0 && max_side_speed > 0 && max_turn > 0, "max_speed", "speeds must be positive");
    p.require(goal_distance > 0 && goal_heading > 0, "goal_distance", "tolerances must be positive");
    p.require(goal_bias >= 0 && goal_bias <= 1, "goal_bias", "must be in [0, 1]");
  }
};

// The state layout: SE2 (gripper) then a real vector of the objects' planar poses and
// velocities (6 per object) and a last entry, 1 while the state is valid. Only the
// gripper counts for distances (the objects' subspace has weight 0).
class Layout {
 public:
  explicit Layout(std::size_t objects) : objects_(objects) {}
  std::size_t reals() const { return 6 * objects_ + 1; }

  void write(const physics::PushState& s, bool valid, ob::State* state) const {
    auto* c = state->as<ob::CompoundState>();
    auto* g = c->as<ob::SE2StateSpace::StateType>(0);
    g->setXY(s.gripper.x(), s.gripper.y());
    g->setYaw(s.gripper.z());
    double* v = c->as<ob::RealVectorStateSpace::StateType>(1)->values;
    for (std::size_t i = 0; i < objects_; ++i) {
      for (int k = 0; k < 3; ++k) {
        v[6 * i + k] = s.objects[i].pose[k];
        v[6 * i + 3 + k] = s.objects[i].velocity[k];
      }
    }
    v[6 * objects_] = valid ? 1.0 : 0.0;
  }

  physics::PushState read(const ob::State* state) const {
    const auto* c = state->as<ob::CompoundState>();
    const auto* g = c->as<ob::SE2StateSpace::StateType>(0);
    const double* v = c->as<ob::RealVectorStateSpace::StateType>(1)->values;
    physics::PushState s;
    s.gripper = {g->getX(), g->getY(), g->getYaw()};
    s.objects.resize(objects_);
    for (std::size_t i = 0; i < objects_; ++i) {
      s.objects[i].pose = {v[6 * i], v[6 * i + 1], v[6 * i + 2]};
      s.objects[i].velocity = {v[6 * i + 3], v[6 * i + 4], v[6 * i + 5]};
    }
    return s;
  }

  bool valid(const ob::State* state) const { return reals(state)[6 * objects_] > 0.5; }

  static Eigen::Vector2d gripper_xy(const ob::State* state) {
    const auto* g = state->as<ob::CompoundState>()->as<ob::SE2StateSpace::StateType>(0);
    return {g->getX(), g->getY()};
  }
  static double gripper_yaw(const ob::State* state) {
    return state->as<ob::CompoundState>()->as<ob::SE2StateSpace::StateType>(0)->getYaw();
  }
  static Eigen::Vector2d object_xy(const ob::State* state, std::size_t object) {
    const double* v = reals(state);
    return {v[6 * object], v[6 * object + 1]};
  }

 private:
  static const double* reals(const ob::State* state) {
    return state->as<ob::CompoundState>()->as<ob::RealVectorStateSpace::StateType>(1)->values;
  }

 private:
  std::size_t objects_;
};

// Where the gripper may be and objects may stay: the scene's workspace in the plane,
// and for objects the region their support covers (the target's support: the shelf).
struct Bounds {
  Eigen::AlignedBox2d gripper, objects;
};

class Propagator final : public oc::StatePropagator {
 public:
  /// `checked`: the objects that must stay on the support (present and movable).
  Propagator(const oc::SpaceInformationPtr& si, const physics::PushWorld& world, const Layout& layout,
             const Bounds& bounds, std::vector<ObjectIndex> checked, std::uint64_t& propagations)
      : oc::StatePropagator(si), world_(world), layout_(layout), bounds_(bounds), checked_(std::move(checked)),
        propagations_(propagations) {}

  void propagate(const ob::State* from, const oc::Control* control, double duration, ob::State* result) const override {
    if (!layout_.valid(from)) {  // nothing grows from an invalid state
      si_->copyState(result, from);
      return;
    }
    const double* u = control->as<oc::RealVectorControlSpace::ControlType>()->values;
    ++propagations_;
    const physics::PushOutcome out = world_.propagate(layout_.read(from), physics::PushControl{{u[0], u[1], u[2]}, duration});
    bool valid = !out.gripper_hit_fixed && out.fallen.empty() && bounds_.gripper.contains(out.state.gripper.head<2>());
    for (ObjectIndex i : checked_) valid = valid && bounds_.objects.contains(out.state.objects[i].pose.head<2>());
    physics::PushState s = out.state;
    s.gripper.z() = std::remainder(s.gripper.z(), 2 * M_PI);  // SE2's yaw bounds; x, y are checked, never clamped
    layout_.write(s, valid, result);
  }

  bool canPropagateBackward() const override { return false; }

 private:
  const physics::PushWorld& world_;
  const Layout& layout_;
  const Bounds& bounds_;
  std::vector<ObjectIndex> checked_;
  std::uint64_t& propagations_;
};

// The gripper's face within goal_distance of the target's surface, the target within
// goal_heading of its heading. Sampled: gripper poses in front of the target, facing it.
class ReachGoal final : public ob::GoalSampleableRegion {
 public:
  ReachGoal(const oc::SpaceInformationPtr& si, const Layout& layout, const physics::PushState& start,
            ObjectIndex target, double reach, const Settings& settings)
      : ob::GoalSampleableRegion(si), layout_(layout), start_(start), target_index_(target),
        target_(start.objects.at(target).pose.head<2>()), reach_(reach), settings_(settings) {
    setThreshold(settings.goal_distance);
  }

  // Relative to where the target is in `state`: pushes may have moved it.
  double distanceGoal(const ob::State* state) const override {
    const Eigen::Vector2d to = Layout::object_xy(state, target_index_) - Layout::gripper_xy(state);
    const double off = std::abs(std::remainder(std::atan2(to.y(), to.x()) - Layout::gripper_yaw(state), 2 * M_PI));
    return std::abs(to.norm() - reach_) + std::max(0.0, off - settings_.goal_heading);
  }

  void sampleGoal(ob::State* state) const override {
    const double yaw = rng_.uniformReal(-settings_.goal_heading, settings_.goal_heading);
    physics::PushState s = start_;  // the objects' part does not count for distances
    s.gripper = {target_.x() - reach_ * std::cos(yaw), target_.y() - reach_ * std::sin(yaw), yaw};
    layout_.write(s, true, state);
  }

  unsigned int maxSampleCount() const override { return std::numeric_limits<unsigned int>::max(); }

 private:
  const Layout& layout_;
  physics::PushState start_;
  std::size_t target_index_;
  Eigen::Vector2d target_;  // where it starts: goal samples face it there
  double reach_;  // gripper centre to target centre when the face touches it
  const Settings& settings_;
  mutable ompl::RNG rng_;
};

// KPIECE's projection: the gripper's position (set explicitly: OMPL 1.5.2's default
// projection has a size bug, dependencies.md pitfall 3).
class GripperProjection final : public ob::ProjectionEvaluator {
 public:
  explicit GripperProjection(const ob::StateSpacePtr& space) : ob::ProjectionEvaluator(space) {}
  unsigned int getDimension() const override { return 2; }
  void defaultCellSizes() override { cellSizes_ = {0.05, 0.05}; }
  void project(const ob::State* state, Eigen::Ref<Eigen::VectorXd> out) const override { out = Layout::gripper_xy(state); }
};

class RtcPlanner final : public plugin::TaskPlanner {
 public:
  RtcPlanner() { ompl::msg::setLogLevel(ompl::msg::LOG_NONE); }

  void configure(const Parameters& p) override { settings_.read(p); }

  Result solve(plugin::PlanningContext& context, const WorldState& initial) override {
    const auto start_time = Clock::now();
    Result result;
    const Scene& scene = context.scene();
    const auto* task = std::get_if<ReachTask>(&context.problem.task);
    if (!task) {
      result.reason = "rtc_ompl plans reach tasks only (task: {reach: <target>})";
      return result;
    }
    const physics::PushWorld world(scene, initial);
    const physics::PushSettings& ps = world.settings();
    const ObjectIndex target = scene.target;
    const Eigen::AlignedBox3d target_box = world_bounds(scene.objects[target].shape, initial.world_T_objects[target]);
    const double reach = ps.gripper_size.x() / 2 + (target_box.max().x() - target_box.min().x()) / 2;

    // The gripper starts at the exit x_s facing into the shelf (+x); the objects must
    // stay over the target's support, the gripper inside the workspace.
    const Eigen::Vector3d gripper_start(scene.world_T_exit.translation().x(), scene.world_T_exit.translation().y(), 0.0);
    Bounds bounds;
    bounds.gripper = Eigen::AlignedBox2d(scene.workspace.min().head<2>(), scene.workspace.max().head<2>());
    bounds.objects = support_region(scene, initial.world_T_objects[target].translation().head<2>(),
                                    world.plane_z() - ps.gripper_clearance);

    const Layout layout(scene.objects.size());
    auto se2 = std::make_shared<ob::SE2StateSpace>();
    ob::RealVectorBounds xy(2);
    xy.setLow(0, bounds.gripper.min().x());
    xy.setLow(1, bounds.gripper.min().y());
    xy.setHigh(0, bounds.gripper.max().x());
    xy.setHigh(1, bounds.gripper.max().y());
    se2->setBounds(xy);
    auto rest = std::make_shared<ob::RealVectorStateSpace>(static_cast<unsigned int>(layout.reals()));
    rest->setBounds(-1e3, 1e3);
    auto space = std::make_shared<ob::CompoundStateSpace>();
    space->addSubspace(se2, 1.0);
    space->addSubspace(rest, 0.0);
    auto controls = std::make_shared<oc::RealVectorControlSpace>(space, 3);
    ob::RealVectorBounds cb(3);
    cb.setLow(0, -settings_.max_side_speed);
    cb.setHigh(0, settings_.max_speed);
    cb.setLow(1, -settings_.max_side_speed);
    cb.setHigh(1, settings_.max_side_speed);
    cb.setLow(2, -settings_.max_turn);
    cb.setHigh(2, settings_.max_turn);
    controls->setBounds(cb);

    auto si = std::make_shared<oc::SpaceInformation>(space, controls);
    std::uint64_t propagations = 0;
    std::vector<ObjectIndex> checked;
    for (ObjectIndex i = 0; i < scene.objects.size(); ++i) {
      if (scene.objects[i].movable && !initial.removed[i]) checked.push_back(i);
    }
    si->setStatePropagator(std::make_shared<Propagator>(si, world, layout, bounds, std::move(checked), propagations));
    si->setStateValidityChecker([&](const ob::State* s) { return layout.valid(s); });  // set by the propagator
    si->setPropagationStepSize(settings_.step);
    si->setMinMaxControlDuration(1, static_cast<unsigned int>(settings_.max_steps));
    si->setup();

    const physics::PushState start = world.state_of(initial, gripper_start);
    auto pdef = std::make_shared<ob::ProblemDefinition>(si);
    ob::ScopedState<> start_state(space);
    layout.write(start, true, start_state.get());
    pdef->addStartState(start_state);
    pdef->setGoal(std::make_shared<ReachGoal>(si, layout, start, target, reach, settings_));

    ob::PlannerPtr planner;
    if (settings_.planner == "kpiece") {
      auto kpiece = std::make_shared<oc::KPIECE1>(si);
      kpiece->setProjectionEvaluator(std::make_shared<GripperProjection>(space));
      planner = kpiece;
    } else {
      auto rrt = std::make_shared<oc::RRT>(si);
      rrt->setGoalBias(settings_.goal_bias);
      planner = rrt;
    }
    planner->setProblemDefinition(pdef);
    planner->setup();
    const ob::PlannerStatus status = planner->solve(std::max(0.0, context.deadline.remaining()));
    result.counters["propagations"] = propagations;
    result.counters[counter::samples] = propagations;
    const bool exact = status == ob::PlannerStatus::EXACT_SOLUTION;
    if (!exact) {
      result.reason = context.deadline.expired() ? "time limit reached" : "no solution: " + status.asString();
    } else {
      write_plan(*pdef->getSolutionPath()->as<oc::PathControl>(), layout, initial, scene, settings_.step, result);
      result.solved = true;
    }
    result.time.total = std::chrono::duration<double>(Clock::now() - start_time).count();
    result.time.task_planning = result.time.total;  // the kinodynamic search is the whole task
    return result;
  }

 private:
  // The region the objects must stay in: the fixed bodies whose top is the plane
  // `bottom` the target (at `at`) stands on, in the plane; the workspace without any.
  static Eigen::AlignedBox2d support_region(const Scene& scene, const Eigen::Vector2d& at, double bottom) {
    Eigen::AlignedBox2d region;
    for (const FixedBody& f : scene.fixed) {
      const Eigen::AlignedBox3d b = world_bounds(f.shape, f.world_T_body);
      const Eigen::AlignedBox2d plane(b.min().head<2>(), b.max().head<2>());
      if (std::abs(b.max().z() - bottom) < 0.01 && plane.contains(at)) region.extend(plane);
    }
    if (region.isEmpty()) region = Eigen::AlignedBox2d(scene.workspace.min().head<2>(), scene.workspace.max().head<2>());
    return region;
  }

  // One "push" step: the gripper's planar path (joint names gripper_x, gripper_y,
  // gripper_yaw) at the start and the end of every control; the objects it moved, and
  // where they ended.
  static void write_plan(oc::PathControl path, const Layout& layout, const WorldState& initial, const Scene& scene,
                         double step_seconds, Result& result) {
    Trajectory t;
    t.joint_names = {"gripper_x", "gripper_y", "gripper_yaw"};
    for (std::size_t i = 0; i < path.getStateCount(); ++i) {  // a state before each control, and the last
      const ob::State* s = path.getState(i);
      t.positions.push_back(Eigen::Vector3d(Layout::gripper_xy(s).x(), Layout::gripper_xy(s).y(), Layout::gripper_yaw(s)));
      t.times.push_back(i == 0 ? 0.0 : t.times.back() + path.getControlDuration(i - 1));
    }
    const physics::PushState end = layout.read(path.getState(path.getStateCount() - 1));
    PlanStep step{"push", {}, {}, t};
    // The controls themselves (vx, vy, yaw rate, duration per control), and the step
    // they were propagated in (each step a fresh simulation): replaying them through the
    // physics from the start, step by step, checks the plan.
    step.values["step"] = {step_seconds};
    std::vector<double>& controls = step.values["controls"];
    for (std::size_t i = 0; i < path.getControlCount(); ++i) {
      const double* u = path.getControl(i)->as<oc::RealVectorControlSpace::ControlType>()->values;
      controls.insert(controls.end(), {u[0], u[1], u[2], path.getControlDuration(i)});
    }
    for (ObjectIndex i = 0; i < scene.objects.size(); ++i) {
      const Eigen::Vector2d from = initial.world_T_objects[i].translation().head<2>();
      if ((end.objects[i].pose.head<2>() - from).norm() > 0.01) {
        step.objects.push_back(i);
        result.moved_objects.push_back(i);
        step.values[scene.objects[i].id] = {end.objects[i].pose.x(), end.objects[i].pose.y(), end.objects[i].pose.z()};
      }
    }
    result.plan.push_back(std::move(step));
    result.counters["plan_controls"] = path.getControlCount();
  }

  Settings settings_;
};

}  // namespace

CLUTTERTAMP_EXPORT_TASK_PLANNER(RtcPlanner, rtc_ompl,
                                "Reaching through clutter by pushing: kinodynamic RRT or KPIECE1 over the pushing physics "
                                "(Papallas & Dogar 2020)",
                                "0.1.0")
