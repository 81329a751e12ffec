#include "cluttertamp/manipulation/base_placement.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace cluttertamp::manipulation {

namespace {

// Random restarts of the arm's IK after the seed's: the arm reaches from a placed base
// or it does not, and the default 20 made the IK most of a mobile plan's time (3.9 s
// against 0.65 s on a bench table, the same plan; with none at all, plans got worse).
constexpr int kArmRestarts = 3;
constexpr double kStep = 0.1;  // m between placements further back
constexpr int kSteps = 6;      // placements tried per turn: distance + 0 .. 0.5 m
// A tool whose approach axis is within 5 degrees of vertical has no direction to stand behind.
const double kLeastApproach = std::sin(5 * M_PI / 180);
// The base's turns from facing along the approach, rad: square to a table's edge where
// the approach meets its corner.
constexpr double kTurns[] = {0.0, M_PI / 6, -M_PI / 6};

}  // namespace

std::optional<BasePlacement> BasePlacement::of(const robot::RobotDescription& robot) {
  const robot::RobotModel& model = *robot.model();
  const auto& variables = model.variables();
  if (variables.size() < 4) return std::nullopt;
  // Each base joint at its parent's origin, unturned; the first at the root.
  auto is = [&](std::size_t v, robot::JointType type, const Eigen::Vector3d& axis) {
    const robot::Joint& j = model.joints()[static_cast<std::size_t>(variables[v])];
    const robot::LinkIndex parent = v == 0 ? model.topological_order().front() : model.joints()[static_cast<std::size_t>(variables[v - 1])].child;
    return j.type == type && j.axis.isApprox(axis) && j.parent_T_joint.isApprox(Eigen::Isometry3d::Identity(), 1e-12) &&
           j.parent == parent;
  };
  if (!is(0, robot::JointType::prismatic, Eigen::Vector3d::UnitX()) || !is(1, robot::JointType::prismatic, Eigen::Vector3d::UnitY()) ||
      !is(2, robot::JointType::revolute, Eigen::Vector3d::UnitZ())) {
    return std::nullopt;
  }
  const robot::LinkIndex turned = model.joints()[static_cast<std::size_t>(variables[2])].child;
  if (!model.descends_from(robot.tip_link(), turned)) return std::nullopt;
  BasePlacement p;
  p.model_ = robot.model();
  robot::NumericIk::Options options;
  options.restarts = kArmRestarts;
  try {
    p.arm_ = std::make_shared<const robot::NumericIk>(robot.model(), turned, robot.tip_link(), options);
  } catch (const std::invalid_argument&) {
    return std::nullopt;  // no chain IK can solve (a mimic joint on it)
  }
  if (p.arm_->chain().empty()) return std::nullopt;
  p.arm_root_ = model.joints()[static_cast<std::size_t>(p.arm_->chain().front())].child;
  return p;
}

std::vector<Eigen::VectorXd> BasePlacement::solve(const collision::CollisionWorld& world, collision::CollisionWorld::Context& checker,
                                                  const Eigen::Isometry3d& world_T_tool, const Eigen::VectorXd& seed,
                                                  double distance, std::size_t max) const {
  if (static_cast<std::size_t>(seed.size()) != model_->variable_count()) {
    throw std::invalid_argument("BasePlacement: the seed configuration has " + std::to_string(seed.size()) +
                                " values, the robot " + std::to_string(model_->variable_count()));
  }
  std::vector<Eigen::VectorXd> out;
  const Eigen::Vector2d approach = world_T_tool.linear().col(2).head<2>();
  if (approach.norm() < kLeastApproach || max == 0) return out;
  const Eigen::Vector2d a = approach.normalized();
  const Eigen::Isometry3d& world_T_root = world.scene().world_T_robot_base;
  // The base variables are in the root's frame.
  const Eigen::Vector3d root_p = world_T_root.inverse() * world_T_tool.translation();
  const Eigen::Vector3d root_a = world_T_root.linear().transpose() * Eigen::Vector3d(a.x(), a.y(), 0.0);
  const double approach_yaw = std::atan2(root_a.y(), root_a.x());
  for (double turn : kTurns) {
    // Further back until the body is clear; the first clear placement out of reach ends this turn.
    const double yaw = std::remainder(approach_yaw + turn, 2 * M_PI);  // a continuous joint's limits: [-pi, pi]
    for (int step = 0; step < kSteps && out.size() < max; ++step) {
      const double back = distance + step * kStep;
      const Eigen::Vector2d centre = root_p.head<2>() - back * root_a.head<2>();
      Eigen::VectorXd placed = seed;
      placed[base_[0]] = centre.x();
      placed[base_[1]] = centre.y();
      placed[base_[2]] = yaw;
      if (!base_within_limits(placed)) continue;
      const auto contacts = world.fixed_contacts(placed, checker);
      const bool body_clear = std::none_of(contacts.begin(), contacts.end(), [&](const collision::FixedContact& c) {
        return c.link && !model_->descends_from(*c.link, arm_root_);
      });
      if (!body_clear) continue;
      auto arm = solve_arm(world_T_root, world_T_tool, placed);
      if (arm.empty()) break;
      // An arm folded into its own body is no placement; another distance bends it otherwise.
      if (!world.self_contacts(arm.front(), checker).empty()) continue;
      out.push_back(std::move(arm.front()));
      break;  // one placement per turn
    }
    if (out.size() >= max) break;
  }
  return out;
}

bool BasePlacement::base_within_limits(const Eigen::VectorXd& q) const {
  return std::all_of(base_.begin(), base_.end(), [&](int v) {
    const robot::Joint& j = model_->joints()[static_cast<std::size_t>(model_->variables()[static_cast<std::size_t>(v)])];
    return q[v] >= j.lower - 1e-9 && q[v] <= j.upper + 1e-9;
  });
}

std::vector<Eigen::VectorXd> BasePlacement::solve_arm(const Eigen::Isometry3d& world_T_robot_base,
                                                      const Eigen::Isometry3d& world_T_tool, const Eigen::VectorXd& q) const {
  std::vector<Eigen::Isometry3d> root_T_links;
  model_->link_poses(q, root_T_links);
  const Eigen::Isometry3d& root_T_turned = root_T_links[static_cast<std::size_t>(arm_->base())];
  return arm_->solve((world_T_robot_base * root_T_turned).inverse() * world_T_tool, q);
}

std::vector<Eigen::VectorXd> reach(const robot::RobotDescription& robot, const std::optional<BasePlacement>& placement,
                                   const collision::CollisionWorld& world, collision::CollisionWorld::Context& checker,
                                   const Eigen::Isometry3d& world_T_tool, const Eigen::VectorXd& seed) {
  if (placement) return placement->solve(world, checker, world_T_tool, seed);
  return robot.ik().solve(robot.world_T_ik_base(world.scene().world_T_robot_base).inverse() * world_T_tool, seed);
}

}  // namespace cluttertamp::manipulation
