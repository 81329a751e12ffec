#include "cluttertamp/manipulation/actions.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <span>

#include "cluttertamp/collision/shared_world.hpp"
#include "cluttertamp/manipulation/base_placement.hpp"
#include "cluttertamp/plugin/grasp_sampler.hpp"
#include "cluttertamp/plugin/motion_sampler.hpp"
#include "cluttertamp/plugin/placement_sampler.hpp"
#include "cluttertamp/robot/robot_description.hpp"

namespace cluttertamp::manipulation {

namespace {

ActionOutcome failed(const std::string& stage, const std::string& reason, std::vector<ObjectIndex> blocking = {}) {
  ActionOutcome out;
  out.failure = Failure{stage, reason, std::move(blocking)};
  return out;
}

// The held object follows the tool: its pose at configuration q.
Eigen::Isometry3d held_pose(plugin::PlanningContext& context, const Eigen::VectorXd& q, const Eigen::Isometry3d& gripper_T_object) {
  auto checker = collision::shared_world(context)->make_context();
  return collision::shared_world(context)->tool_pose(q, *checker) * gripper_T_object;
}

// Plans a collision-free motion in `state` (its held object included).
std::optional<Trajectory> move(plugin::PlanningContext& context, const WorldState& state, const Eigen::VectorXd& goal,
                               std::optional<Failure>& failure) {
  const auto answer = context.samplers.get<plugin::MotionSampler>()->plan(context, {state.robot_configuration, goal, state});
  if (!answer.trajectory) failure = answer.failure;
  return answer.trajectory;
}

// The contacts of the first state in collision on the straight segment a→b, checked
// every 0.01 rad; a valid report when the segment is free.
collision::CollisionReport straight_contacts(plugin::PlanningContext& context, const WorldState& state,
                                             const Eigen::VectorXd& a, const Eigen::VectorXd& b,
                                             std::span<const ObjectIndex> ignored) {
  collision::CollisionWorld& world = *collision::shared_world(context);
  world.sync(state);
  auto checker = world.make_context();
  const int steps = std::max(1, static_cast<int>(std::ceil((b - a).cwiseAbs().maxCoeff() / 0.01)));
  for (int s = 0; s <= steps; ++s) {
    context.count(counter::collision_checks);
    const Eigen::VectorXd q = a + (b - a) * (double(s) / steps);
    if (!world.is_valid(q, *checker, ignored)) return world.check(q, *checker, ignored);
  }
  return {};
}

// True when every configuration of the straight joint-space segment is free.
bool straight_free(plugin::PlanningContext& context, const WorldState& state, const Eigen::VectorXd& a,
                   const Eigen::VectorXd& b, std::span<const ObjectIndex> ignored) {
  return straight_contacts(context, state, a, b, ignored).valid();
}

// How far behind the pre-grasp the transfer into clutter aims first, m, and the
// shortest back-off worth a staging pose.
constexpr double kStagingDistance = 0.25;
constexpr double kShortestStaging = 0.08;
// Step of the straight tool line back from the pre-grasp, m, and the largest joint
// change between its waypoints, rad (more means the IK changed branch).
constexpr double kLineStep = 0.02;
constexpr double kLineJump = 0.3;
// The motion budget per grasp in pick's first, quick pass over the usable grasps, in
// collision checks (work, not time: the same seed picks the same grasp on any machine).
constexpr std::uint64_t kQuickTransferChecks = 60000;
// The motion budget of move_out's plan from the end of its straight line, collision checks.
constexpr std::uint64_t kQuickMoveOutChecks = 120000;

// Waypoints of the tool backing out of configuration `from` (tool pose world_T_tool)
// in a straight line along `back` (unit, world frame), up to kStagingDistance: IK
// seeded by the previous waypoint, each segment free in `state`. Stops where the line
// is blocked or leaves reach; the first waypoint is `from`.
std::vector<Eigen::VectorXd> back_off_line(plugin::PlanningContext& context, const WorldState& state,
                                           const Eigen::Isometry3d& world_T_tool, const Eigen::Vector3d& back,
                                           const Eigen::VectorXd& from) {
  const robot::RobotDescription& robot = context.robot();
  const Eigen::Isometry3d base_T_world = robot.world_T_ik_base(context.scene().world_T_robot_base).inverse();
  std::vector<Eigen::VectorXd> line{from};
  const int steps = static_cast<int>(std::round(kStagingDistance / kLineStep));
  for (int k = 1; k <= steps; ++k) {
    Eigen::Isometry3d tool = world_T_tool;
    tool.translation() += back * (k * kLineStep);
    const auto ik = robot.ik().solve(base_T_world * tool, line.back());
    if (ik.empty() || (ik[0] - line.back()).cwiseAbs().maxCoeff() > kLineJump ||
        !straight_free(context, state, line.back(), ik[0], {})) {
      break;
    }
    line.push_back(ik[0]);
  }
  return line;
}

// Whether a back-off line reaches far enough to be worth its staging pose.
bool long_enough(const std::vector<Eigen::VectorXd>& line) {
  return static_cast<double>(line.size() - 1) * kLineStep >= kShortestStaging - 1e-9;
}

// `rest` continued from the end of `t` (rest's first waypoint is t's last).
void append(Trajectory& t, const Trajectory& rest) {
  const double offset = t.times.back();
  for (std::size_t k = 1; k < rest.positions.size(); ++k) {
    t.times.push_back(offset + rest.times[k]);
    t.positions.push_back(rest.positions[k]);
  }
}

// The straight way out of the clutter from `from` (tool pose world_T_tool): back along
// `back`, or, when that line is blocked before kShortestStaging, towards the exit x_s
// if that line goes further (a diagonal approach can back the arm into a neighbour:
// the stacked8 target's approach line stopped at 4 cm, on side_1).
std::vector<Eigen::VectorXd> way_out(plugin::PlanningContext& context, const WorldState& state,
                                     const Eigen::Isometry3d& world_T_tool, const Eigen::Vector3d& back,
                                     const Eigen::VectorXd& from) {
  std::vector<Eigen::VectorXd> line = back_off_line(context, state, world_T_tool, back, from);
  Eigen::Vector3d to_exit = context.scene().world_T_exit.translation() - world_T_tool.translation();
  to_exit.z() = 0.0;
  if (!long_enough(line) && to_exit.norm() > 1e-6 && to_exit.normalized().dot(back) < 0.99) {
    std::vector<Eigen::VectorXd> straight = back_off_line(context, state, world_T_tool, to_exit.normalized(), from);
    if (straight.size() > line.size()) line = std::move(straight);
  }
  return line;
}

// A transfer to a grasp's pre-grasp `pregrasp` through a staging pose on the straight
// way out from it (way_out), reached by that tool line from there: a planned motion to
// the staging pose (usually in the open, in front of the clutter), then that line —
// the planner's trees find narrow ways into clutter slowly. Nothing without a free
// line of at least kShortestStaging: pick's second pass plans to the pre-grasp itself,
// and a first try at that here would only repeat the start of the same seeded search.
std::optional<Trajectory> staged_transfer(plugin::PlanningContext& context, const WorldState& state,
                                          const plugin::Grasp& grasp, const Eigen::VectorXd& pregrasp,
                                          std::optional<Failure>& failure) {
  const robot::RobotDescription& robot = context.robot();
  const Eigen::Vector3d back = grasp.world_T_pregrasp.translation() - grasp.world_T_gripper.translation();
  if (back.norm() > 1e-6) {
    std::vector<Eigen::VectorXd> line = way_out(context, state, grasp.world_T_pregrasp, back.normalized(), pregrasp);
    if (long_enough(line)) {
      auto to_staging = move(context, state, line.back(), failure);
      if (to_staging) {
        std::reverse(line.begin(), line.end());
        append(*to_staging, timed(robot, line));
      }
      return to_staging;
    }
  }
  return std::nullopt;
}

}  // namespace

Trajectory timed(const robot::RobotDescription& robot, const std::vector<Eigen::VectorXd>& waypoints, double scale) {
  Trajectory t;
  t.joint_names = robot.model()->variable_names();
  const Eigen::VectorXd limit = robot.model()->velocity_limits() * scale;
  double time = 0.0;
  for (std::size_t k = 0; k < waypoints.size(); ++k) {
    if (k > 0) time += std::max(1e-3, ((waypoints[k] - waypoints[k - 1]).cwiseAbs().array() / limit.array()).maxCoeff());
    t.times.push_back(time);
    t.positions.push_back(waypoints[k]);
  }
  return t;
}

std::optional<Trajectory> move_out(plugin::PlanningContext& context, const WorldState& state, const Eigen::VectorXd& goal,
                                   std::optional<Failure>& failure) {
  auto checker = collision::shared_world(context)->make_context();
  const Eigen::Isometry3d world_T_tool = collision::shared_world(context)->tool_pose(state.robot_configuration, *checker);
  Eigen::Vector3d back = -world_T_tool.linear().col(2);
  back.z() = 0.0;
  if (back.norm() > 0.5) {
    std::vector<Eigen::VectorXd> line = way_out(context, state, world_T_tool, back.normalized(), state.robot_configuration);
    if (long_enough(line)) {
      WorldState outside = state;
      outside.robot_configuration = line.back();
      if (state.held) {
        outside.world_T_objects[*state.held] = collision::shared_world(context)->tool_pose(line.back(), *checker) *
                                               world_T_tool.inverse() * state.world_T_objects[*state.held];
      }
      // A short budget: from outside the clutter the planner either finds its way at
      // once or the line led somewhere unhelpful.
      plugin::PlanningContext quick = context.with_checks(kQuickMoveOutChecks);
      std::optional<Failure> ignored;
      if (const auto rest = move(quick, outside, goal, ignored)) {
        Trajectory out = timed(context.robot(), line);
        append(out, *rest);
        return out;
      }
    }
  }
  return move(context, state, goal, failure);
}

namespace {

// The held object carried from where it is in `holding` through `corners` (its
// positions, world frame) in straight lines of kLineStep steps, its orientation kept:
// each configuration from IK seeded by the one before, joined by a segment free in
// `holding`; the first is holding's. Empty where a segment is blocked or the line
// leaves reach. No jump limit: near a wrist singularity the nearest IK branch turns
// the wrist half a turn within one step, which the dense check of the segment covers.
std::optional<std::vector<Eigen::VectorXd>> carry_through(plugin::PlanningContext& context, const WorldState& holding,
                                                          const Eigen::Isometry3d& gripper_T_object,
                                                          const std::vector<Eigen::Vector3d>& corners) {
  const robot::RobotDescription& robot = context.robot();
  const Eigen::Isometry3d base_T_world = robot.world_T_ik_base(context.scene().world_T_robot_base).inverse();
  const Eigen::Isometry3d object_T_tool = gripper_T_object.inverse();
  Eigen::Isometry3d object = holding.world_T_objects[*holding.held];
  std::vector<Eigen::VectorXd> waypoints{holding.robot_configuration};
  for (const Eigen::Vector3d& corner : corners) {
    const Eigen::Vector3d from = object.translation();
    const int steps = static_cast<int>(std::ceil((corner - from).norm() / kLineStep));
    for (int s = 1; s <= steps; ++s) {
      object.translation() = from + (corner - from) * (double(s) / steps);
      const auto ik = robot.ik().solve(base_T_world * object * object_T_tool, waypoints.back());
      if (ik.empty() || !straight_free(context, holding, waypoints.back(), ik[0], {})) return std::nullopt;
      waypoints.push_back(ik[0]);
    }
  }
  return waypoints;
}

// The rest of a pick once the transfer to `grasp`'s pre-grasp is planned: approach,
// close the fingers, lift, and retreat when the way back is free.
ActionOutcome grasped(plugin::PlanningContext& context, const WorldState& state, ObjectIndex object,
                      const plugin::Grasp& grasp, const Trajectory& transfer) {
  const robot::RobotDescription& robot = context.robot();
  const plugin::GraspMotion& m = grasp.motions.front();
  ActionOutcome out;
  out.grasp = grasp;
  out.segments.push_back({"transfer", transfer});
  out.segments.push_back({"approach", timed(robot, {m.pregrasp, m.grasp})});
  Eigen::VectorXd closed = m.grasp;
  if (robot.finger_variable()) closed[*robot.finger_variable()] = grasp.finger_closed;
  out.segments.push_back({"grasp", timed(robot, {m.grasp, closed})});
  out.segments.push_back({"lift", timed(robot, {closed, m.lift})});
  WorldState holding = state;
  holding.held = object;
  holding.robot_configuration = m.lift;
  holding.world_T_objects[object] = held_pose(context, m.lift, grasp.gripper_T_object);
  // Retreat: back out along the approach, as far as the pre-grasp was in front.
  Eigen::Isometry3d retreat_pose = grasp.world_T_lift;
  retreat_pose.translation() -= (grasp.world_T_gripper.translation() - grasp.world_T_pregrasp.translation());
  const auto retreat = robot.ik().solve(robot.world_T_ik_base(context.scene().world_T_robot_base).inverse() * retreat_pose, m.lift);
  if (!retreat.empty() && (retreat[0] - m.lift).cwiseAbs().maxCoeff() < 0.8 &&
      straight_free(context, holding, m.lift, retreat[0], {})) {
    out.segments.push_back({"retreat", timed(robot, {m.lift, retreat[0]})});
    holding.robot_configuration = retreat[0];
    holding.world_T_objects[object] = held_pose(context, retreat[0], grasp.gripper_T_object);
  }
  out.after = holding;
  out.ok = true;
  collision::shared_world(context)->sync(state);
  return out;
}

}  // namespace

ActionOutcome pick(plugin::PlanningContext& context, const WorldState& state, ObjectIndex object) {
  const auto grasp_sampler = context.samplers.get<plugin::GraspSampler>();
  if (!context.worlds || !grasp_sampler || !context.samplers.get<plugin::MotionSampler>()) {
    return failed("pick", "pick needs a robot, a grasp_sampler and a motion_sampler");
  }
  if (state.held) return failed("pick", "the hand already holds an object");
  const robot::RobotDescription& robot = context.robot();
  const plugin::GraspAnswer grasps = [&] {
    plugin::Phase phase(context, "pick.grasps");
    return grasp_sampler->sample(context, {object, state});
  }();
  if (grasps.usable.empty()) {
    return failed("grasp", grasps.failure ? grasps.failure->reason : "no usable grasp",
                  grasps.failure ? grasps.failure->blocking_objects : std::vector<ObjectIndex>{});
  }
  std::optional<Failure> last;
  const ObjectIndex self[] = {object};
  // Whatever the grasp sampler checked, the straight segments are checked densely here.
  std::vector<const plugin::Grasp*> free;
  std::optional<plugin::Phase> dense_phase(std::in_place, context, "pick.dense_check");
  for (const plugin::Grasp& grasp : grasps.usable) {
    const plugin::GraspMotion& m = grasp.motions.front();
    Eigen::VectorXd closed_check = m.grasp;
    if (robot.finger_variable()) closed_check[*robot.finger_variable()] = grasp.finger_closed;
    WorldState lifted = state;
    lifted.held = object;
    lifted.robot_configuration = closed_check;
    collision::CollisionReport contacts = straight_contacts(context, state, m.pregrasp, m.grasp, self);
    if (contacts.valid()) contacts = straight_contacts(context, lifted, closed_check, m.lift, {});
    if (!contacts.valid()) {
      // The sampler's coarser check missed a contact: say what it is, so it can be removed.
      last = Failure{"grasp",
                     std::string("the approach or lift of a usable grasp is not free when checked densely") +
                         (contacts.fixed ? " (fixed geometry)" : contacts.self ? " (the arm itself)" : ""),
                     contacts.self || contacts.fixed ? std::vector<ObjectIndex>{} : contacts.objects};
      continue;
    }
    free.push_back(&grasp);
  }
  dense_phase.reset();
  // Two passes over the grasps: a quick one (kQuickTransferChecks per transfer, to a staging
  // pose and along a straight tool line from there), so that one hard-to-reach grasp
  // does not take the motion planner's whole budget while another is easy; then each
  // with the full budget, straight to the pre-grasp, whose failure names the objects
  // in the way.
  for (const bool quick_pass : {true, false}) {
    for (const plugin::Grasp* grasp : free) {
      std::optional<Failure> why;
      const Eigen::VectorXd& pregrasp = grasp->motions.front().pregrasp;
      plugin::PlanningContext quick = context.with_checks(kQuickTransferChecks);
      plugin::Phase phase(context, quick_pass ? "pick.transfer_staged" : "pick.transfer");
      const auto transfer = quick_pass ? staged_transfer(quick, state, *grasp, pregrasp, why) : move(context, state, pregrasp, why);
      if (transfer) {
        plugin::Phase retreat(context, "pick.retreat");
        return grasped(context, state, object, *grasp, *transfer);
      }
      if (!quick_pass) last = why;
    }
  }
  collision::shared_world(context)->sync(state);
  return failed("motion", last ? "no motion reaches a usable grasp: " + last->reason : "no motion reaches a usable grasp",
                last ? last->blocking_objects : std::vector<ObjectIndex>{});
}

ActionOutcome place(plugin::PlanningContext& context, const WorldState& state, const std::string& region) {
  const auto placement_sampler = context.samplers.get<plugin::PlacementSampler>();
  if (!context.worlds || !placement_sampler || !context.samplers.get<plugin::MotionSampler>()) {
    return failed("place", "place needs a robot, a placement_sampler and a motion_sampler");
  }
  if (!state.held) return failed("place", "the hand holds nothing");
  const robot::RobotDescription& robot = context.robot();
  const ObjectIndex object = *state.held;
  auto checker = collision::shared_world(context)->make_context();
  collision::shared_world(context)->sync(state);
  const Eigen::Isometry3d gripper_T_object =
      collision::shared_world(context)->tool_pose(state.robot_configuration, *checker).inverse() * state.world_T_objects[object];
  plugin::PlacementQuery query{object, region, state, 8, gripper_T_object};
  const plugin::PlacementAnswer placements = [&] {
    plugin::Phase phase(context, "place.placements");
    return placement_sampler->sample(context, query);
  }();
  if (placements.world_T_object.empty()) {
    return failed("placement", placements.failure ? placements.failure->reason : "no placement",
                  placements.failure ? placements.failure->blocking_objects : std::vector<ObjectIndex>{});
  }
  std::optional<Failure> last;
  const Eigen::Isometry3d base_T_world = robot.world_T_ik_base(context.scene().world_T_robot_base).inverse();
  for (std::size_t i = 0; i < placements.world_T_object.size(); ++i) {
    const Eigen::VectorXd& q_place = placements.configurations[i];
    Eigen::Isometry3d above = placements.world_T_object[i] * gripper_T_object.inverse();
    above.translation().z() += 0.03;
    const auto pre = robot.ik().solve(base_T_world * above, q_place);
    if (pre.empty() || (pre[0] - q_place).cwiseAbs().maxCoeff() > 0.8 || !straight_free(context, state, pre[0], q_place, {})) continue;
    std::optional<Failure> why;
    const auto transfer = [&] {
      plugin::Phase phase(context, "place.transfer");
      return move_out(context, state, pre[0], why);
    }();
    if (!transfer) {
      last = why;
      continue;
    }
    ActionOutcome out;
    out.segments.push_back({"transfer", *transfer});
    out.segments.push_back({"place", timed(robot, {pre[0], q_place})});
    WorldState placed = state;
    placed.held.reset();
    placed.world_T_objects[object] = placements.world_T_object[i];
    placed.robot_configuration = q_place;
    Eigen::VectorXd open = q_place;
    if (robot.finger_variable()) {
      // Open by a grasp sampler's usual clearance, within the stroke.
      const int f = *robot.finger_variable();
      const auto& joint = robot.model()->joints()[robot.model()->variables()[f]];
      open[f] = std::min(joint.upper, q_place[f] + 0.008);
    }
    const ObjectIndex ignore[] = {object};
    if (!straight_free(context, placed, q_place, open, ignore)) {
      last = Failure{"place", "the fingers cannot open at the placement", {}};
      continue;
    }
    out.segments.push_back({"release", timed(robot, {q_place, open})});
    placed.robot_configuration = open;
    // Retreat: back out along the tool's approach axis.
    auto c = collision::shared_world(context)->make_context();
    Eigen::Isometry3d back = collision::shared_world(context)->tool_pose(placed.robot_configuration, *c);
    back.translation() -= 0.10 * back.linear().col(2);
    const auto retreat = robot.ik().solve(base_T_world * back, placed.robot_configuration);
    if (!retreat.empty() && (retreat[0] - placed.robot_configuration).cwiseAbs().maxCoeff() < 0.8 &&
        straight_free(context, placed, placed.robot_configuration, retreat[0], {})) {
      out.segments.push_back({"retreat", timed(robot, {placed.robot_configuration, retreat[0]})});
      placed.robot_configuration = retreat[0];
    }
    out.after = placed;
    out.ok = true;
    collision::shared_world(context)->sync(state);
    return out;
  }
  collision::shared_world(context)->sync(state);
  return failed("motion", last ? "no motion reaches a placement: " + last->reason : "no placement can be approached from above",
                last ? last->blocking_objects : std::vector<ObjectIndex>{});
}

namespace {

// A configuration holding the target at `exit` (object pose, world frame) and the pose
// it arrives in; an upright cylinder may arrive turned about its axis (the same solid)
// by 45 degree steps. A fixed arm takes the least turn it holds free; a mobile base
// stands behind the tool (BasePlacement), where no table is: of the free turns, the one
// leaving the base nearest to where it stands holding the target.
std::optional<std::pair<Eigen::VectorXd, Eigen::Isometry3d>> exit_configuration(plugin::PlanningContext& context,
                                                                                 const WorldState& holding,
                                                                                 const plugin::Grasp& grasp,
                                                                                 const Eigen::Isometry3d& exit) {
  const robot::RobotDescription& robot = context.robot();
  const Eigen::VectorXd& from = holding.robot_configuration;
  const auto mobile = BasePlacement::of(robot);
  collision::CollisionWorld& world = *collision::shared_world(context);
  world.sync(holding);
  auto checker = world.make_context();
  // An upright cylinder may arrive turned about its axis: the same target to the task,
  // and an arm that cannot hold it at x_s as it was grasped may hold it turned.
  const SceneObject& target = context.scene().objects.at(*holding.held);
  const bool turnable = std::holds_alternative<Cylinder>(target.shape) && std::abs(exit.linear()(2, 2)) > 1 - 1e-6;
  if (!mobile) {
    // The IK solutions nearest `from` first, the least turn first; one in collision (the
    // arm folded into itself, say) would make every carry fail at its goal.
    for (const int k : {0, 1, -1, 2, -2, 3, -3, 4}) {
      if (k != 0 && !turnable) break;
      const Eigen::Isometry3d arrived = exit * Eigen::AngleAxisd(k * M_PI / 4, Eigen::Vector3d::UnitZ());
      const Eigen::Isometry3d tool = arrived * grasp.gripper_T_object.inverse();
      for (const Eigen::VectorXd& q : robot.ik().solve(robot.world_T_ik_base(context.scene().world_T_robot_base).inverse() * tool, from)) {
        context.count(counter::collision_checks);
        if (world.is_valid(q, *checker, {})) return std::pair(q, arrived);
      }
    }
    return std::nullopt;
  }
  const auto& base = mobile->base_variables();
  std::optional<std::pair<Eigen::VectorXd, Eigen::Isometry3d>> best;
  double best_travel = 0.0;
  for (int k = 0; k < (turnable ? 8 : 1); ++k) {
    const Eigen::Isometry3d arrived = exit * Eigen::AngleAxisd(k * M_PI / 4, Eigen::Vector3d::UnitZ());
    for (const Eigen::VectorXd& q : mobile->solve(world, *checker, arrived * grasp.gripper_T_object.inverse(), from)) {
      context.count(counter::collision_checks);
      if (!world.is_valid(q, *checker, {})) continue;
      const double travel = std::hypot(q[base[0]] - from[base[0]], q[base[1]] - from[base[1]]);
      if (!best || travel < best_travel) {
        best = std::pair(q, arrived);
        best_travel = travel;
      }
    }
  }
  return best;
}

}  // namespace

ActionOutcome retrieve(plugin::PlanningContext& context, const WorldState& state, std::span<const Eigen::Vector2d> way) {
  const ObjectIndex target = context.scene().target;
  ActionOutcome picked = pick(context, state, target);
  if (!picked.ok) return picked;
  Eigen::Isometry3d exit = state.world_T_objects[target];
  exit.translation() = context.scene().world_T_exit.translation();
  const auto held_at_exit = exit_configuration(context, picked.after, *picked.grasp, exit);
  if (!held_at_exit) {
    collision::shared_world(context)->sync(state);  // as the other actions leave it
    return failed("retrieve", "the robot cannot hold the target at the exit pose x_s");
  }
  if (way.size() >= 2 && !BasePlacement::of(context.robot())) {
    // From the lift, where the target still stands over the way's first point (the
    // retreat backs it off the way): along the way at the lifted height, then to x_s.
    ActionOutcome lifted = picked;
    if (lifted.segments.back().name == "retreat") {
      lifted.segments.pop_back();
      lifted.after.robot_configuration = lifted.segments.back().trajectory.positions.back();
      lifted.after.world_T_objects[target] = held_pose(context, lifted.after.robot_configuration, lifted.grasp->gripper_T_object);
    }
    const double lifted_z = lifted.after.world_T_objects[target].translation().z();
    std::vector<Eigen::Vector3d> corners;
    for (const Eigen::Vector2d& x : way) corners.emplace_back(x.x(), x.y(), lifted_z);  // the first leg is empty
    corners.push_back(held_at_exit->second.translation());
    const auto along = [&] {
      plugin::Phase phase(context, "retrieve.carry_along");
      return carry_through(context, lifted.after, lifted.grasp->gripper_T_object, corners);
    }();
    collision::shared_world(context)->sync(state);  // as the other actions leave it
    if (along) {
      lifted.segments.push_back({"carry", timed(context.robot(), *along)});
      lifted.after.world_T_objects[target].translation() = held_at_exit->second.translation();
      lifted.after.robot_configuration = along->back();
      return lifted;
    }
  }
  std::optional<Failure> why;
  const auto carry = [&] {
    plugin::Phase phase(context, "retrieve.carry");
    return move_out(context, picked.after, held_at_exit->first, why);
  }();
  if (!carry) {
    return failed("carry", "no motion carries the target to x_s" + (why ? ": " + why->reason : std::string()),
                  why ? why->blocking_objects : std::vector<ObjectIndex>{});
  }
  picked.segments.push_back({"carry", *carry});
  picked.after.robot_configuration = held_at_exit->first;
  picked.after.world_T_objects[target] = held_at_exit->second;
  return picked;
}

}  // namespace cluttertamp::manipulation
