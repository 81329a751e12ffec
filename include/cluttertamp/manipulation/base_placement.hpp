#pragma once

#include <array>
#include <cstddef>
#include <memory>
#include <optional>
#include <vector>

#include <Eigen/Geometry>

#include "cluttertamp/collision/collision_world.hpp"
#include "cluttertamp/export.hpp"
#include "cluttertamp/robot/ik.hpp"
#include "cluttertamp/robot/robot_description.hpp"

namespace cluttertamp::manipulation {

/// Where a mobile manipulator's base stands to put its tool at a pose (Tian et al.,
/// Section V-B: base placements around the clutter), and the arm's IK from there.
///
/// For robots whose first three configuration variables are a planar base at the root:
/// prismatic along x, prismatic along y, then a turn about z (pr2_mobile's base_x,
/// base_y, base_yaw). Their whole-robot IK moves the base as readily as the arm, so
/// the base ends wherever the least-squares steps leave it — often inside the table
/// the arm reaches into. Here the base is placed first and the arm solved alone.
class CLUTTERTAMP_API BasePlacement {
 public:
  /// How far behind the tool the base first stands, m: the PR2 reaches a 0.7 m table's
  /// middle from outside it.
  static constexpr double kDefaultDistance = 0.6;

  /// The placement model of `robot`, or nothing when its root is no planar base (the
  /// three joints at the root, each at its parent's origin) or no IK solves its arm.
  static std::optional<BasePlacement> of(const robot::RobotDescription& robot);

  /// Configurations with the tool at `world_T_tool` (world frame), at most `max`, one
  /// per base turn. The base's centre stands on the tool's approach axis (its z, made
  /// horizontal), `distance` m behind the tool, facing along the approach — then, for
  /// more solutions or where that finds none, turned 30 degrees either way (square to a
  /// table's edge where the approach meets its corner). Where the body (every link the
  /// arm does not move) would touch fixed geometry of `world`, or the arm would touch
  /// the robot itself, further back in 0.1 m steps, up to 0.5 m more; the first clear
  /// placement the arm cannot reach ends that turn; placements outside the base joints'
  /// limits are passed over. The arm is solved alone from `seed`'s arm joints; it is not
  /// checked against fixed geometry or objects, nor is the held object. A tool whose
  /// approach is within 5 degrees of vertical has no direction to stand behind: no
  /// solutions. Throws std::invalid_argument for a seed of the wrong size.
  std::vector<Eigen::VectorXd> solve(const collision::CollisionWorld& world, collision::CollisionWorld::Context& checker,
                                     const Eigen::Isometry3d& world_T_tool, const Eigen::VectorXd& seed,
                                     double distance = kDefaultDistance, std::size_t max = 2) const;

  /// The arm's IK for the tool at `world_T_tool` with the base where `q` has it (every
  /// solution keeps q's base variables); nearest q first, as IkSolver::solve.
  /// `world_T_robot_base`: the scene's pose of the robot's root.
  std::vector<Eigen::VectorXd> solve_arm(const Eigen::Isometry3d& world_T_robot_base, const Eigen::Isometry3d& world_T_tool,
                                         const Eigen::VectorXd& q) const;

  /// The configuration variables of the base: x, y, yaw.
  const std::array<int, 3>& base_variables() const { return base_; }

 private:
  BasePlacement() = default;
  bool base_within_limits(const Eigen::VectorXd& q) const;
  std::shared_ptr<const robot::RobotModel> model_;
  std::shared_ptr<const robot::NumericIk> arm_;  ///< from the link the turn carries to the tool
  robot::LinkIndex arm_root_ = -1;               ///< the first link the arm moves
  std::array<int, 3> base_{0, 1, 2};
};

/// Configurations with the tool at `world_T_tool` (world frame): with a `placement`,
/// its solve(world, checker, world_T_tool, seed), in its order; without, the robot's
/// own IK (RobotDescription::ik) seeded by `seed`, nearest the seed first.
CLUTTERTAMP_API std::vector<Eigen::VectorXd> reach(const robot::RobotDescription& robot,
                                                   const std::optional<BasePlacement>& placement,
                                                   const collision::CollisionWorld& world,
                                                   collision::CollisionWorld::Context& checker,
                                                   const Eigen::Isometry3d& world_T_tool, const Eigen::VectorXd& seed);

}  // namespace cluttertamp::manipulation
