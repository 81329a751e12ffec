#include "cluttertamp/physics/push_planning.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <optional>
#include <set>
#include <stdexcept>
#include <utility>
#include <variant>

#include <Eigen/Geometry>

#include <ompl/base/ProblemDefinition.h>
#include <ompl/base/ProjectionEvaluator.h>
#include <ompl/base/StateSampler.h>
#include <ompl/base/goals/GoalSampleableRegion.h>
#include <ompl/base/spaces/RealVectorStateSpace.h>
#include <ompl/base/spaces/SE2StateSpace.h>
#include <ompl/control/ControlSampler.h>
#include <ompl/control/PathControl.h>
#include <ompl/control/SpaceInformation.h>
#include <ompl/control/planners/kpiece/KPIECE1.h>
#include <ompl/control/planners/rrt/RRT.h>
#include <ompl/control/spaces/RealVectorControlSpace.h>
#include <ompl/datastructures/NearestNeighborsLinear.h>
#include <ompl/util/Console.h>

namespace cluttertamp::physics {

namespace ob = ompl::base;
namespace oc = ompl::control;

namespace {

double angle_between(double a, double b) { return std::abs(std::remainder(a - b, 2 * M_PI)); }

// One propagation, the gripper's yaw normalised to SE2's bounds (x, y are checked by
// valid_outcome, never clamped): the one step of the planner, simulate and replay.
PushOutcome step_once(const PushWorld& world, const PushState& from, const Eigen::Vector3d& velocity, double seconds) {
  PushOutcome out = world.propagate(from, {velocity, seconds});
  out.state.gripper.z() = std::remainder(out.state.gripper.z(), 2 * M_PI);
  return out;
}

// The state layout: SE2 (gripper) then a real vector of the objects' planar poses and
// velocities (6 per object) and a last entry, 1 while the state is valid. Only the
// gripper counts for distances (the objects' subspace has weight 0).
class Layout {
 public:
  explicit Layout(std::size_t objects) : objects_(objects) {}
  std::size_t reals() const { return 6 * objects_ + 1; }

  void write(const PushState& s, bool valid, ob::State* state) const {
    auto* g = gripper(state);
    g->setXY(s.gripper.x(), s.gripper.y());
    g->setYaw(s.gripper.z());
    double* v = values(state);
    for (std::size_t i = 0; i < objects_; ++i) {
      for (int k = 0; k < 3; ++k) {
        v[6 * i + k] = s.objects[i].pose[k];
        v[6 * i + 3 + k] = s.objects[i].velocity[k];
      }
    }
    v[6 * objects_] = valid ? 1.0 : 0.0;
  }

  PushState read(const ob::State* state) const {
    const auto* g = gripper(state);
    const double* v = values(state);
    PushState s;
    s.gripper = {g->getX(), g->getY(), g->getYaw()};
    s.objects.resize(objects_);
    for (std::size_t i = 0; i < objects_; ++i) {
      s.objects[i].pose = {v[6 * i], v[6 * i + 1], v[6 * i + 2]};
      s.objects[i].velocity = {v[6 * i + 3], v[6 * i + 4], v[6 * i + 5]};
    }
    return s;
  }

  bool valid(const ob::State* state) const { return values(state)[6 * objects_] > 0.5; }

  static Eigen::Vector3d gripper_pose(const ob::State* state) {
    const auto* g = gripper(state);
    return {g->getX(), g->getY(), g->getYaw()};
  }
  static Eigen::Vector2d gripper_xy(const ob::State* state) { return gripper_pose(state).head<2>(); }

 private:
  static const ob::SE2StateSpace::StateType* gripper(const ob::State* state) {
    return state->as<ob::CompoundState>()->as<ob::SE2StateSpace::StateType>(0);
  }
  static ob::SE2StateSpace::StateType* gripper(ob::State* state) {
    return state->as<ob::CompoundState>()->as<ob::SE2StateSpace::StateType>(0);
  }
  static const double* values(const ob::State* state) {
    return state->as<ob::CompoundState>()->as<ob::RealVectorStateSpace::StateType>(1)->values;
  }
  static double* values(ob::State* state) {
    return state->as<ob::CompoundState>()->as<ob::RealVectorStateSpace::StateType>(1)->values;
  }

  std::size_t objects_;
};

class Propagator final : public oc::StatePropagator {
 public:
  Propagator(const oc::SpaceInformationPtr& si, const PushWorld& world, const Layout& layout, std::uint64_t& propagations)
      : oc::StatePropagator(si), world_(world), layout_(layout), propagations_(propagations) {}

  void propagate(const ob::State* from, const oc::Control* control, double duration, ob::State* result) const override {
    if (!layout_.valid(from)) {  // nothing grows from an invalid state
      si_->copyState(result, from);
      return;
    }
    const double* u = control->as<oc::RealVectorControlSpace::ControlType>()->values;
    ++propagations_;
    const PushOutcome out = step_once(world_, layout_.read(from), {u[0], u[1], u[2]}, duration);
    layout_.write(out.state, valid_outcome(world_, out), result);
  }

  bool canPropagateBackward() const override { return false; }

 private:
  const PushWorld& world_;
  const Layout& layout_;
  std::uint64_t& propagations_;
};

// OMPL's view of a PushGoal; goal samples scatter about the goal's gripper target in
// the start state, drawn from our own seeded generator.
class OmplGoal final : public ob::GoalSampleableRegion {
 public:
  OmplGoal(const oc::SpaceInformationPtr& si, const Layout& layout, const PushWorld& world, const PushGoal& goal,
           const PushState& start, std::uint64_t seed)
      : ob::GoalSampleableRegion(si), layout_(layout), world_(world), goal_(goal), start_(start), rng_(seed) {
    setThreshold(goal.tolerance());
  }

  double distanceGoal(const ob::State* state) const override { return goal_.distance(layout_.read(state)); }

  void sampleGoal(ob::State* state) const override {
    const std::vector<Eigen::Vector3d> centres = goal_.goal_grippers(start_);
    const Eigen::Vector3d centre = centres[std::uniform_int_distribution<std::size_t>(0, centres.size() - 1)(rng_)];
    const Eigen::Vector3d spread = goal_.sample_spread();
    PushState s = start_;  // the objects' part does not count for distances
    // Scattered about the hand's pose: an arm's base turned about its own centre would
    // swing the hand on its lever.
    Eigen::Vector3d hand = world_.hand(centre);
    for (int k = 0; k < 3; ++k) hand[k] += std::uniform_real_distribution<double>(-1, 1)(rng_) * spread[k];
    s.gripper = world_.pose_for_hand(hand);
    layout_.write(s, true, state);
  }

  unsigned int maxSampleCount() const override { return std::numeric_limits<unsigned int>::max(); }

 private:
  const Layout& layout_;
  const PushWorld& world_;
  const PushGoal& goal_;
  PushState start_;
  mutable std::mt19937_64 rng_;
};

// Uniform pusher poses whose hand is in the hand's region, headed within the yaw limits
// (the objects' part is the start's: it does not count for distances), from a seeded
// generator.
class GripperSampler final : public ob::StateSampler {
 public:
  GripperSampler(const ob::StateSpace* space, const Layout& layout, const PushWorld& world, const PushState& start,
                 const std::vector<double>& bounds, std::uint64_t seed)
      : ob::StateSampler(space), layout_(layout), world_(world), start_(start), region_(world.gripper_region()),
        pusher_box_(bounds.size() == 4), rng_(seed) {
    if (pusher_box_) region_ = Eigen::AlignedBox2d(Eigen::Vector2d(bounds[0], bounds[1]), Eigen::Vector2d(bounds[2], bounds[3]));
    const Eigen::Vector2d& limits = world.settings().yaw_limits;
    yaw_low_ = std::isfinite(limits.x()) ? limits.x() : -M_PI;
    yaw_high_ = std::isfinite(limits.y()) ? limits.y() : M_PI;
  }

  // Drawn in the order x, y, yaw.
  void sampleUniform(ob::State* state) override {
    const double x = uniform(region_.min().x(), region_.max().x());
    const double y = uniform(region_.min().y(), region_.max().y());
    const double yaw = uniform(yaw_low_, yaw_high_);
    if (pusher_box_) return write({x, y, yaw}, state);
    write(world_.pose_for_hand({x, y, yaw + world_.hand({0, 0, 0}).z()}), state);
  }
  void sampleUniformNear(ob::State* state, const ob::State* near, double distance) override {
    if (pusher_box_) {
      const Eigen::Vector3d c = Layout::gripper_pose(near);
      const double x = std::clamp(c.x() + uniform(-distance, distance), region_.min().x(), region_.max().x());
      const double y = std::clamp(c.y() + uniform(-distance, distance), region_.min().y(), region_.max().y());
      return write({x, y, world_.clamp_yaw(c.z() + uniform(-distance, distance))}, state);
    }
    const Eigen::Vector3d c = world_.hand(Layout::gripper_pose(near));
    const double x = std::clamp(c.x() + uniform(-distance, distance), region_.min().x(), region_.max().x());
    const double y = std::clamp(c.y() + uniform(-distance, distance), region_.min().y(), region_.max().y());
    const double yaw = world_.clamp_yaw(Layout::gripper_pose(near).z() + uniform(-distance, distance));
    write(world_.pose_for_hand({x, y, yaw + world_.hand({0, 0, 0}).z()}), state);
  }
  void sampleGaussian(ob::State* state, const ob::State* mean, double stdDev) override {
    sampleUniformNear(state, mean, stdDev);
  }

 private:
  double uniform(double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng_); }
  void write(const Eigen::Vector3d& pose, ob::State* state) const {
    PushState s = start_;
    s.gripper = pose;
    s.gripper.z() = std::remainder(s.gripper.z(), 2 * M_PI);
    layout_.write(s, true, state);
  }

  const Layout& layout_;
  const PushWorld& world_;
  const PushState& start_;
  Eigen::AlignedBox2d region_;  // of the hand, or with pusher_box_ of the pusher's pose
  bool pusher_box_;
  double yaw_low_ = -M_PI, yaw_high_ = M_PI;
  std::mt19937_64 rng_;
};

// Controls uniform within their bounds or, a `steer` fraction of the time, heading
// from the state they extend towards the goal's gripper target. Seeded.
class PushControlSampler final : public oc::ControlSampler {
 public:
  PushControlSampler(const oc::ControlSpace* space, const Layout& layout, const PushGoal& goal,
                     const KinodynamicSettings& settings, std::uint64_t seed)
      : oc::ControlSampler(space), layout_(layout), goal_(goal), settings_(settings), rng_(seed) {}

  void sample(oc::Control* control) override {
    steered_steps_ = 0;
    double* u = control->as<oc::RealVectorControlSpace::ControlType>()->values;
    u[0] = uniform(-settings_.max_side_speed, settings_.max_speed);
    u[1] = uniform(-settings_.max_side_speed, settings_.max_side_speed);
    u[2] = uniform(-settings_.max_turn, settings_.max_turn);
  }

  void sample(oc::Control* control, const ob::State* state) override {
    steered_steps_ = 0;
    if (settings_.steer <= 0 || uniform(0, 1) >= settings_.steer || !layout_.valid(state)) return sample(control);
    const PushState s = layout_.read(state);
    const Eigen::Vector3d to = goal_.gripper_target(s) - s.gripper;
    if (to.head<2>().norm() < 1e-9) return sample(control);
    double* u = control->as<oc::RealVectorControlSpace::ControlType>()->values;
    // Headed for the target at a random fraction of the speed that stays in bounds.
    Eigen::Vector2d v = to.head<2>().normalized() * uniform(0.5, 1.0) * settings_.max_speed;
    const double x_bound = v.x() > 0    ? settings_.max_speed / v.x()
                           : v.x() < 0 ? settings_.max_side_speed / -v.x()
                                       : std::numeric_limits<double>::infinity();
    const double y_bound = v.y() != 0 ? settings_.max_side_speed / std::abs(v.y()) : std::numeric_limits<double>::infinity();
    v *= std::min({1.0, x_bound, y_bound});
    u[0] = v.x();
    u[1] = v.y();
    // Long enough to get there, not to overshoot (sampleStepCount is asked next).
    const double travel = to.head<2>().norm() / std::max(v.norm(), 1e-9);
    steered_steps_ = static_cast<unsigned int>(std::max(1.0, std::round(travel / settings_.step)));
    const double turn_time = std::max(travel, settings_.step);
    u[2] = std::clamp(std::remainder(to.z(), 2 * M_PI) / turn_time, -settings_.max_turn, settings_.max_turn);
  }

  void sampleNext(oc::Control* control, const oc::Control*, const ob::State* state) override { sample(control, state); }

  // OMPL's planners ask for a control, then for its step count: a steered control's
  // count is the one that reaches its target.
  unsigned int sampleStepCount(unsigned int min_steps, unsigned int max_steps) override {
    if (steered_steps_) return std::clamp(std::exchange(steered_steps_, 0u), min_steps, max_steps);
    return std::uniform_int_distribution<unsigned int>(min_steps, max_steps)(rng_);
  }

 private:
  double uniform(double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng_); }

  const Layout& layout_;
  const PushGoal& goal_;
  const KinodynamicSettings& settings_;
  std::mt19937_64 rng_;
  unsigned int steered_steps_ = 0;  // of the last steered control, until asked
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

// The planners with their own random generators seeded (OMPL's otherwise draw from one
// process-wide seed) and, for RRT, exact nearest neighbours (GNAT draws its own numbers).
class SeededRrt final : public oc::RRT {
 public:
  SeededRrt(const oc::SpaceInformationPtr& si, std::uint64_t seed) : oc::RRT(si) {
    rng_.setLocalSeed(static_cast<std::uint_fast32_t>(seed));
    setNearestNeighbors<ompl::NearestNeighborsLinear>();
  }
};
class SeededKpiece final : public oc::KPIECE1 {
 public:
  SeededKpiece(const oc::SpaceInformationPtr& si, std::uint64_t seed) : oc::KPIECE1(si) {
    rng_.setLocalSeed(static_cast<std::uint_fast32_t>(seed));
  }
};

// Why `s` cannot start a valid plan (the rules of valid_outcome), or nothing.
std::optional<std::string> invalid_start(const PushWorld& world, const PushState& s) {
  if (!world.gripper_region().contains(world.hand(s.gripper).head<2>())) return std::string("the hand is outside its region");
  if (!world.yaw_allowed(s.gripper.z())) return std::string("the pusher's heading is outside its yaw limits");
  if (world.propagate(s, {Eigen::Vector3d::Zero(), world.settings().time_step}).gripper_hit_fixed) {
    return std::string("the pusher starts inside fixed geometry (a wall or board): move its start, or the arm's posture or hand height");
  }
  for (ObjectIndex i : world.pushable()) {
    if (!world.support_region().contains(s.objects[i].pose.head<2>())) {
      return "'" + world.scene().objects[i].id + "' is not over the target's support";
    }
  }
  return std::nullopt;
}

std::uint64_t mix(std::uint64_t seed, std::uint64_t salt) {
  std::uint64_t h = seed ^ (0x9e3779b97f4a7c15ull * (salt + 1));
  h ^= h >> 31;
  h *= 0xbf58476d1ce4e5b9ull;
  return h ^ (h >> 29);
}

}  // namespace

void KinodynamicSettings::read(const Parameters& p) {
  planner = p.get_string("planner", planner, "OMPL control planner: rrt or kpiece");
  step = p.get_double("step", step, "s of one propagation step (each a fresh simulation)", Range::above(0));
  max_steps = static_cast<int>(
      p.get_int("max_steps", max_steps, "propagation steps a control lasts, at most", Range::at_least(1)));
  max_speed = p.get_double("max_speed", max_speed, "m/s of the gripper along +x (into the shelf)", Range::above(0));
  max_side_speed = p.get_double("max_side_speed", max_side_speed, "m/s of the gripper along y either way and along -x",
                                Range::above(0));
  max_turn = p.get_double("max_turn", max_turn, "rad/s of the gripper's turn, either way", Range::above(0));
  goal_bias = p.get_double("goal_bias", goal_bias, "rrt: fraction of samples drawn from the goal", Range::closed(0, 1));
  steer = p.get_double("steer", steer, "fraction of sampled controls steered towards the goal", Range::closed(0, 1));
  const std::int64_t propagations =
      p.get_int("max_propagations", static_cast<std::int64_t>(max_propagations),
                "physics propagations per search, the work budget (0: none but the time limit)", Range::at_least(0));
  max_propagations = static_cast<std::uint64_t>(propagations);
  sample_bounds = p.get_vector("sample_bounds", sample_bounds,
                               "[x_min, y_min, x_max, y_max] m where the pusher's pose is sampled (default: the hand over "
                               "its region)",
                               Range::closed(-1000, 1000));
  p.require(sample_bounds.empty() || (sample_bounds.size() == 4 && sample_bounds[0] < sample_bounds[2] && sample_bounds[1] < sample_bounds[3]),
            "sample_bounds", "must be [x_min, y_min, x_max, y_max] with min < max");
  p.require(planner == "rrt" || planner == "kpiece", "planner", "must be rrt or kpiece");
}

PushGoal::~PushGoal() = default;

void ReachTolerances::read(const Parameters& p) {
  const std::string name = p.get_string("goal", "pocket",
                                        "pocket (the target between the fingers, or at the hand's face) or point (the hand's "
                                        "reach point near the target's centre, as the paper's code)");
  p.require(name == "pocket" || name == "point", "goal", "must be pocket or point");
  kind = name == "point" ? Kind::point : Kind::pocket;
  distance = p.get_double("goal_distance", kind == Kind::point ? 0.07 : distance,
                          "m the target's centre may be from the pocket between the fingers (no fingers or an arm: the "
                          "hand's face from its surface; point: from the reach point)",
                          Range::above(0));
  const bool heading_given = p.contains("goal_heading");
  const double h = p.get_double("goal_heading", 0.5, "rad the target may be off the hand's heading (point: unchecked unless given)",
                                Range::above(0));
  heading = kind == Kind::pocket || heading_given ? std::optional<double>(h) : std::nullopt;
}

ReachGoal::ReachGoal(const PushWorld& world, ObjectIndex target, const ReachTolerances& tolerances)
    : PushGoal(tolerances.distance), world_(&world), target_(target), kind_(tolerances.kind), heading_(tolerances.heading) {
  const PushSettings& g = world.settings();
  const double r = world.footprint_radius(target);
  const bool fingers = !g.arm && g.finger_length > 0;
  pocket_near_ = world.hand_face();
  pocket_far_ = pocket_near_ + (fingers ? g.finger_length : 0.0);
  pocket_half_width_ = g.gripper_size.y() / 2 - g.finger_width - r;
  // A target too wide for the gap is reached as by a plain box: the face at its surface.
  if (pocket_half_width_ <= 0) pocket_far_ = pocket_near_;
  if (kind_ == ReachTolerances::Kind::point) {
    // The floating gripper's reach point: the pocket's middle; the arm's: its tool.
    ahead_ = g.arm ? 0.0 : (pocket_near_ + pocket_far_) / 2;
    reach_ = std::max(ahead_, pocket_near_ + r + 0.005);
    return;
  }
  // The palm's face at the target's surface, or the target's centre at the fingertips
  // when they are shorter than its radius.
  reach_ = pocket_near_ + (has_pocket() ? std::min(r, g.finger_length) : r);
}

Eigen::Vector3d ReachGoal::sample_spread() const {
  const double heading = heading_.value_or(0.3);
  // In the pocket, the target's bearing stays within what its width allows.
  const double yaw = kind_ == ReachTolerances::Kind::pocket && has_pocket() ? std::min(heading, std::atan2(pocket_half_width_, reach_)) : heading;
  return {0.0, 0.0, yaw};
}

double ReachGoal::heading_excess(const Eigen::Vector3d& hand, const Eigen::Vector2d& target) const {
  if (!heading_) return 0.0;
  const Eigen::Vector2d to = target - hand.head<2>();
  return std::max(0.0, angle_between(std::atan2(to.y(), to.x()), hand.z()) - *heading_);
}

double ReachGoal::distance(const PushState& s) const {
  const Eigen::Vector3d hand = world_->hand(s.gripper);
  const Eigen::Vector2d target = s.objects.at(target_).pose.head<2>();
  const Eigen::Vector2d to = target - hand.head<2>();
  if (kind_ == ReachTolerances::Kind::point) {
    const Eigen::Vector2d reach_point = hand.head<2>() + ahead_ * Eigen::Vector2d(std::cos(hand.z()), std::sin(hand.z()));
    return (target - reach_point).norm() + heading_excess(hand, target);
  }
  if (!has_pocket()) return std::abs(to.norm() - reach_) + heading_excess(hand, target);
  // The target's centre in the hand's frame, and how far it is from the pocket.
  const Eigen::Vector2d local = Eigen::Rotation2Dd(-hand.z()) * to;
  const double dx = std::max({0.0, pocket_near_ - local.x(), local.x() - pocket_far_});
  const double dy = std::max(0.0, std::abs(local.y()) - pocket_half_width_);
  return std::hypot(dx, dy) + heading_excess(hand, target);
}

Eigen::Vector3d ReachGoal::gripper_target(const PushState& s) const {
  const Eigen::Vector2d target = s.objects.at(target_).pose.head<2>();
  const Eigen::Vector3d hand = world_->hand(s.gripper);
  Eigen::Vector2d from = target - hand.head<2>();
  // Straight at the target from where the hand is; from the front (-x) when on it.
  const double yaw = from.norm() > 1e-6 ? std::atan2(from.y(), from.x()) : 0.0;
  return world_->pose_for_hand({target.x() - reach_ * std::cos(yaw), target.y() - reach_ * std::sin(yaw), yaw});
}

GripperPoseGoal::GripperPoseGoal(const PushWorld& world, std::vector<Eigen::Vector3d> poses, double position, double heading)
    : PushGoal(position), world_(&world), poses_(std::move(poses)), position_(position), heading_(heading) {
  if (poses_.empty()) throw std::invalid_argument("GripperPoseGoal: no pose");
}

double GripperPoseGoal::distance(const PushState& s) const {
  const Eigen::Vector3d hand = world_->hand(s.gripper);
  double best = std::numeric_limits<double>::infinity();
  for (const Eigen::Vector3d& p : poses_) {
    const double off = angle_between(hand.z(), p.z());
    best = std::min(best, (hand.head<2>() - p.head<2>()).norm() + std::max(0.0, off - heading_));
  }
  return best;
}

Eigen::Vector3d GripperPoseGoal::gripper_target(const PushState& s) const {
  const Eigen::Vector2d hand = world_->hand(s.gripper).head<2>();
  return world_->pose_for_hand(*std::min_element(poses_.begin(), poses_.end(), [&](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    return (a.head<2>() - hand).norm() < (b.head<2>() - hand).norm();
  }));
}

std::vector<Eigen::Vector3d> GripperPoseGoal::goal_grippers(const PushState&) const {
  std::vector<Eigen::Vector3d> poses;
  for (const Eigen::Vector3d& p : poses_) poses.push_back(world_->pose_for_hand(p));
  return poses;
}

ObjectInRegionGoal::ObjectInRegionGoal(const PushWorld& world, ObjectIndex object, const Eigen::Vector2d& centre,
                                       double radius)
    : PushGoal(radius), world_(&world), object_(object), centre_(centre),
      standoff_(world.hand_face() + world.footprint_radius(object)),
      approach_(standoff_ + (world.settings().arm ? 0.0 : world.settings().finger_length) + 0.01) {}

double ObjectInRegionGoal::distance(const PushState& s) const {
  return (s.objects.at(object_).pose.head<2>() - centre_).norm();
}

Eigen::Vector3d ObjectInRegionGoal::gripper_target(const PushState& s) const {
  const Eigen::Vector2d object = s.objects.at(object_).pose.head<2>();
  const Eigen::Vector3d hand = world_->hand(s.gripper);
  const Eigen::Vector2d along = centre_ - object;
  const double yaw = along.norm() > 1e-6 ? std::atan2(along.y(), along.x()) : hand.z();
  // Until lined up behind the object on the line that pushes it to the centre (its
  // fingertips short of it, or closer in on that line), head for the approach point;
  // once lined up, for where the hand's face leaves the object at the centre.
  const Eigen::Vector2d dir(std::cos(yaw), std::sin(yaw));
  const Eigen::Vector2d rel = hand.head<2>() - object;
  const double behind = -rel.dot(dir), aside = std::abs(rel.dot(Eigen::Vector2d(-dir.y(), dir.x())));
  const bool lined_up = aside < 0.02 && angle_between(hand.z(), yaw) < 0.3 && behind > standoff_ - 0.01 &&
                        behind < approach_ + 0.02;
  const Eigen::Vector2d at = lined_up ? Eigen::Vector2d(centre_ - standoff_ * dir) : Eigen::Vector2d(object - approach_ * dir);
  return world_->pose_for_hand({at.x(), at.y(), yaw});
}

std::vector<Eigen::Vector3d> ObjectInRegionGoal::goal_grippers(const PushState& start) const {
  const Eigen::Vector2d along = centre_ - start.objects.at(object_).pose.head<2>();
  const double yaw = along.norm() > 1e-6 ? std::atan2(along.y(), along.x()) : world_->hand(start.gripper).z();
  const Eigen::Vector2d at = centre_ - standoff_ * Eigen::Vector2d(std::cos(yaw), std::sin(yaw));
  return {world_->pose_for_hand({at.x(), at.y(), yaw})};
}

double PushPath::duration() const {
  double total = 0;
  for (const PushControl& c : controls) total += c.duration;
  return total;
}

bool valid_outcome(const PushWorld& world, const PushOutcome& out) {
  const double force_limit = world.settings().wall_force_limit.value_or(std::numeric_limits<double>::infinity());
  if (out.gripper_hit_fixed || !out.fallen.empty() || !out.tipped.empty() || out.wall_force > force_limit ||
      !world.yaw_allowed(out.state.gripper.z()) ||
      !world.gripper_region().contains(world.hand(out.state.gripper).head<2>())) {
    return false;
  }
  const Eigen::AlignedBox2d& support = world.support_region();
  return std::all_of(world.pushable().begin(), world.pushable().end(),
                     [&](ObjectIndex i) { return support.contains(out.state.objects[i].pose.head<2>()); });
}

KinodynamicOutcome plan_pushes(const PushWorld& world, const PushState& start, const PushGoal& goal,
                               const KinodynamicSettings& settings, const PushBudget& budget, std::uint64_t seed) {
  if (start.objects.size() != world.scene().objects.size()) {
    throw std::invalid_argument("plan_pushes: the start state needs one body per scene object");
  }
  ompl::msg::setLogLevel(ompl::msg::LOG_NONE);
  KinodynamicOutcome outcome;
  if (auto why = invalid_start(world, start)) {
    outcome.reason = "the start is not valid: " + *why;
    return outcome;
  }
  const double seconds = std::clamp(budget.seconds, 0.0, 1e7);  // no limit (Deadline::never) overflows OMPL's clock
  const Layout layout(start.objects.size());
  // The pusher's positions: the hand's region widened by the lever from pusher to hand.
  Eigen::AlignedBox2d region = world.gripper_region();
  const double lever = world.hand({0, 0, 0}).head<2>().norm();
  region.min().array() -= lever;
  region.max().array() += lever;
  if (settings.sample_bounds.size() == 4) {
    region.extend(Eigen::Vector2d(settings.sample_bounds[0], settings.sample_bounds[1]));
    region.extend(Eigen::Vector2d(settings.sample_bounds[2], settings.sample_bounds[3]));
  }

  auto se2 = std::make_shared<ob::SE2StateSpace>();
  ob::RealVectorBounds xy(2);
  xy.setLow(0, region.min().x());
  xy.setLow(1, region.min().y());
  xy.setHigh(0, region.max().x());
  xy.setHigh(1, region.max().y());
  se2->setBounds(xy);
  auto rest = std::make_shared<ob::RealVectorStateSpace>(static_cast<unsigned int>(layout.reals()));
  rest->setBounds(-1e3, 1e3);
  auto space = std::make_shared<ob::CompoundStateSpace>();
  space->addSubspace(se2, 1.0);
  space->addSubspace(rest, 0.0);
  space->setStateSamplerAllocator([&, s = mix(seed, 1)](const ob::StateSpace* sp) {
    return std::make_shared<GripperSampler>(sp, layout, world, start, settings.sample_bounds, s);
  });

  auto controls = std::make_shared<oc::RealVectorControlSpace>(space, 3);
  ob::RealVectorBounds cb(3);
  cb.setLow(0, -settings.max_side_speed);
  cb.setHigh(0, settings.max_speed);
  cb.setLow(1, -settings.max_side_speed);
  cb.setHigh(1, settings.max_side_speed);
  cb.setLow(2, -settings.max_turn);
  cb.setHigh(2, settings.max_turn);
  controls->setBounds(cb);
  std::uint64_t samplers = 0;  // each sampler its own stream
  controls->setControlSamplerAllocator([&](const oc::ControlSpace* cs) {
    return std::make_shared<PushControlSampler>(cs, layout, goal, settings, mix(seed, 2 + samplers++));
  });

  auto si = std::make_shared<oc::SpaceInformation>(space, controls);
  si->setStatePropagator(std::make_shared<Propagator>(si, world, layout, outcome.propagations));
  si->setStateValidityChecker([&](const ob::State* s) { return layout.valid(s); });  // set by the propagator
  si->setPropagationStepSize(settings.step);
  si->setMinMaxControlDuration(1, static_cast<unsigned int>(settings.max_steps));
  si->setup();

  auto pdef = std::make_shared<ob::ProblemDefinition>(si);
  ob::ScopedState<> start_state(space);
  layout.write(start, true, start_state.get());
  pdef->addStartState(start_state);
  pdef->setGoal(std::make_shared<OmplGoal>(si, layout, world, goal, start, mix(seed, 0)));

  ob::PlannerPtr planner;
  if (settings.planner == "kpiece") {
    auto kpiece = std::make_shared<SeededKpiece>(si, mix(seed, 100));
    kpiece->setProjectionEvaluator(std::make_shared<GripperProjection>(space));
    planner = kpiece;
  } else {
    auto rrt = std::make_shared<SeededRrt>(si, mix(seed, 100));
    rrt->setGoalBias(settings.goal_bias);
    planner = rrt;
  }
  planner->setProblemDefinition(pdef);
  planner->setup();
  const auto end = std::chrono::steady_clock::now() +
                   std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::duration<double>(seconds));
  const ob::PlannerStatus status = planner->solve(ob::PlannerTerminationCondition([&] {
    return outcome.propagations >= budget.propagations || std::chrono::steady_clock::now() >= end;
  }));
  if (status != ob::PlannerStatus::EXACT_SOLUTION) {
    outcome.budget_reached = outcome.propagations >= budget.propagations;
    outcome.time_limit_reached = !outcome.budget_reached && std::chrono::steady_clock::now() >= end;
    outcome.reason = outcome.budget_reached      ? "propagation budget (" + std::to_string(budget.propagations) + ") used up"
                     : outcome.time_limit_reached ? "time limit reached"
                                                  : "no solution: " + status.asString();
    return outcome;
  }
  const auto& path = *pdef->getSolutionPath()->as<oc::PathControl>();
  PushPath result;
  result.step = settings.step;
  for (std::size_t i = 0; i < path.getStateCount(); ++i) result.states.push_back(layout.read(path.getState(i)));
  for (std::size_t i = 0; i < path.getControlCount(); ++i) {
    const double* u = path.getControl(i)->as<oc::RealVectorControlSpace::ControlType>()->values;
    result.controls.push_back({{u[0], u[1], u[2]}, path.getControlDuration(i)});
  }
  result.states.front() = start;  // bit for bit: OMPL normalised nothing, but the yaw
  outcome.path = std::move(result);
  return outcome;
}

std::vector<PushControl> straight_controls(const Eigen::Vector3d& from, const Eigen::Vector3d& to,
                                           const KinodynamicSettings& settings) {
  Eigen::Vector3d delta = to - from;
  delta.z() = std::remainder(delta.z(), 2 * M_PI);
  const double seconds = std::max({std::abs(delta.x()) / (delta.x() > 0 ? settings.max_speed : settings.max_side_speed),
                                   std::abs(delta.y()) / settings.max_side_speed, std::abs(delta.z()) / settings.max_turn});
  if (delta.head<2>().norm() < 1e-9 && std::abs(delta.z()) < 1e-9) return {};
  const int steps = std::max(1, static_cast<int>(std::ceil(seconds / settings.step - 1e-9)));
  const Eigen::Vector3d velocity = delta / (steps * settings.step);
  std::vector<PushControl> controls;
  for (int done = 0; done < steps; done += settings.max_steps) {
    controls.push_back({velocity, std::min(settings.max_steps, steps - done) * settings.step});
  }
  return controls;
}

bool simulate(const PushWorld& world, PushPath& path, const std::vector<PushControl>& controls) {
  if (!(path.step > 0) || path.states.empty()) throw std::invalid_argument("simulate: a path with a start and a step");
  for (const PushControl& c : controls) {
    PushState s = path.states.back();
    const int steps = std::max(1, static_cast<int>(std::lround(c.duration / path.step)));
    for (int k = 0; k < steps; ++k) {
      const PushOutcome out = step_once(world, s, c.velocity, path.step);
      if (!valid_outcome(world, out)) return false;
      s = out.state;
    }
    path.states.push_back(std::move(s));
    path.controls.push_back(c);
  }
  return true;
}

Replay replay(const PushWorld& world, const PushState& start, const std::vector<PushControl>& controls, double step) {
  if (!(step > 0)) throw std::invalid_argument("replay: step must be positive");
  Replay r;
  r.end = start;
  std::set<ObjectIndex> touched;
  for (const PushControl& c : controls) {
    const int steps = std::max(1, static_cast<int>(std::lround(c.duration / step)));
    for (int k = 0; k < steps; ++k) {
      const PushOutcome out = step_once(world, r.end, c.velocity, step);
      touched.insert(out.touched.begin(), out.touched.end());
      r.valid = r.valid && valid_outcome(world, out);
      r.end = out.state;
    }
  }
  r.touched.assign(touched.begin(), touched.end());
  return r;
}

PlanStep push_step(const PushWorld& world, const PushPath& path, const WorldState& before) {
  const Scene& scene = world.scene();
  Trajectory t;
  if (world.settings().arm) t.joint_names = {"base_x", "base_y", "base_yaw"};
  else t.joint_names = {"gripper_x", "gripper_y", "gripper_yaw"};
  for (std::size_t i = 0; i < path.states.size(); ++i) {
    t.positions.push_back(path.states[i].gripper);
    t.times.push_back(i == 0 ? 0.0 : t.times.back() + path.controls[i - 1].duration);
  }
  for (ObjectIndex i = 0; i < scene.objects.size(); ++i) {
    const auto moves = [&](const PushState& s) { return (s.objects[i].pose - path.states.front().objects[i].pose).norm() > 1e-5; };
    if (!std::any_of(path.states.begin(), path.states.end(), moves)) continue;
    std::vector<Eigen::Vector3d>& poses = t.object_paths[i];
    for (const PushState& s : path.states) poses.push_back(s.objects[i].pose);
  }
  PlanStep step;
  step.action = "push";
  step.trajectory = t;
  // The controls themselves and the step they were propagated in: replaying them
  // through the physics from the start checks the plan (replay()).
  step.values["step"] = {path.step};
  std::vector<double>& controls = step.values["controls"];
  for (const PushControl& c : path.controls) controls.insert(controls.end(), {c.velocity.x(), c.velocity.y(), c.velocity.z(), c.duration});
  // The pusher as the physics moved it, so the replay draws it from the result alone:
  // the floating gripper's boxes (size x, y, z, then centre x, y in its own frame, m),
  // every part (pusher_parts: kind 0 box [x y z] / 1 cylinder [r h 0] / 2 sphere [r 0 0],
  // then its position x y z and quaternion x y z w in the pusher's frame; a hull as
  // its bounding box) and the frame's height.
  if (!world.settings().arm) {
    std::vector<double>& boxes = step.values["pusher_boxes"];
    for (const GripperBox& box : gripper_boxes(world.settings())) {
      boxes.insert(boxes.end(), {box.size.x(), box.size.y(), box.size.z(), box.offset.x(), box.offset.y()});
    }
  }
  std::vector<double>& parts = step.values["pusher_parts"];
  for (const PusherPart& part : world.pusher_parts()) {
    std::visit(
        [&](const auto& shape) {
          using T = std::decay_t<decltype(shape)>;
          if constexpr (std::is_same_v<T, Box>) parts.insert(parts.end(), {0.0, shape.size.x(), shape.size.y(), shape.size.z()});
          else if constexpr (std::is_same_v<T, Cylinder>) parts.insert(parts.end(), {1.0, shape.radius, shape.height, 0.0});
          else parts.insert(parts.end(), {2.0, shape.radius, 0.0, 0.0});
        },
        part.shape);
    const Eigen::Vector3d at = part.frame_T_part.translation();
    const Eigen::Quaterniond q(part.frame_T_part.rotation());
    parts.insert(parts.end(), {at.x(), at.y(), at.z(), q.x(), q.y(), q.z(), q.w()});
  }
  step.values["pusher_z"] = {world.pusher_z()};
  const PushState& end = path.states.back();
  for (ObjectIndex i = 0; i < scene.objects.size(); ++i) {
    if ((end.objects[i].pose.head<2>() - before.world_T_objects[i].translation().head<2>()).norm() > 0.01) {
      step.objects.push_back(i);
      step.values[scene.objects[i].id] = {end.objects[i].pose.x(), end.objects[i].pose.y(), end.objects[i].pose.z()};
    }
  }
  return step;
}

std::vector<PushControl> controls_of(const PlanStep& step) {
  std::vector<PushControl> controls;
  const auto it = step.values.find("controls");
  if (it == step.values.end()) return controls;
  const std::vector<double>& v = it->second;
  for (std::size_t i = 0; i + 3 < v.size(); i += 4) controls.push_back({{v[i], v[i + 1], v[i + 2]}, v[i + 3]});
  return controls;
}

WorldState world_state_of(const WorldState& before, const PushState& state) {
  WorldState after = before;
  for (std::size_t i = 0; i < after.world_T_objects.size() && i < state.objects.size(); ++i) {
    after.world_T_objects[i] = with_planar_pose(after.world_T_objects[i], state.objects[i].pose);
  }
  return after;
}

}  // namespace cluttertamp::physics
