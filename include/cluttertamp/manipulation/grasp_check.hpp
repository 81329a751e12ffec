#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include <Eigen/Geometry>

#include "cluttertamp/core/result.hpp"
#include "cluttertamp/export.hpp"
#include "cluttertamp/manipulation/base_placement.hpp"
#include "cluttertamp/plugin/context.hpp"
#include "cluttertamp/plugin/grasp_sampler.hpp"
#include "cluttertamp/plugin/world_view.hpp"

namespace cluttertamp::manipulation {

/// How densely GraspChecker checks a grasp's motions.
struct GraspCheckSettings {
  std::int64_t approach_steps = 5;  ///< collision checks along the approach and the lift, at the least
  double resolution = 0.02;         ///< rad between collision checks along a straight joint-space segment
  /// m behind each grasp a mobile base is first placed, the arm solved alone (0: the
  /// whole robot's IK from where it stands only).
  double base_distance = 0.0;
};

/// Decides whether proposed grasps of one object can be used, as every grasp sampler
/// must: per IK branch through the grasp (at most two of the robot's, plus one with a
/// mobile base placed behind it), the pre-grasp and the lift nearest to it, then the
/// approach (fingers open, the object itself ignored), the grasp and the lift (fingers
/// closed, the object held) checked along straight joint-space segments every
/// `resolution` rad, and again every 0.01 rad (pick's own check) when they look free.
/// A usable grasp gets its motions; a rejected one the objects in the way of its least
/// blocked branch and whether removing them would free it.
///
/// The world is the view the checker was made with: the object stands where it stands
/// there and the hand is empty (a held object is not carried).
class CLUTTERTAMP_API GraspChecker {
 public:
  /// `world`: the scene at the state of the query with nothing in the hand; `seed`: the
  /// robot configuration IK starts from (rad, m; robot joint order). Both must outlive
  /// the checker. Precondition: the context's problem has a robot.
  GraspChecker(plugin::PlanningContext& context, const plugin::WorldView& world, ObjectIndex object,
               Eigen::VectorXd seed, GraspCheckSettings settings = {});

  /// Checks `grasp` (its poses in the world frame, its finger values in m) and files it
  /// in `answer.usable` (with its IK solutions and motions) or `answer.blocked`. Counts
  /// collision checks in the context.
  void check(plugin::Grasp grasp, plugin::GraspAnswer& answer) const;

  /// The failure of an answer without a usable grasp: "no usable grasp of 'id'", with
  /// the blocking objects of its least blocked freeable grasp, or, when moving objects
  /// frees none, the reason of the first grasp rejected.
  static Failure no_usable_grasp(const std::string& object_id, const plugin::GraspAnswer& answer);

 private:
  struct Branch;
  std::vector<Branch> ik_branches(const Eigen::VectorXd& open_seed, const plugin::Grasp& grasp) const;

  plugin::PlanningContext& context_;
  const plugin::WorldView& world_;
  ObjectIndex object_;
  Eigen::VectorXd seed_;
  GraspCheckSettings settings_;
  std::optional<BasePlacement> mobile_;
  Eigen::Isometry3d base_T_world_;
};

/// A grasp of `object` standing at `world_T_object` with the tool at `world_T_gripper`:
/// the pre-grasp `approach` m back along the tool's z axis (the approach direction),
/// the lift `lift` m up (world z), the fingers open to the object's half width plus
/// `clearance` (at most half the gripper's stroke) and closed to its half width. The
/// half width of an upright cylinder is its radius, of a box half its narrower side in
/// the plane, of a sphere its radius.
CLUTTERTAMP_API plugin::Grasp grasp_at(const SceneObject& object, const Eigen::Isometry3d& world_T_object,
                                       const Eigen::Isometry3d& world_T_gripper, double gripper_stroke,
                                       double approach = 0.10, double lift = 0.03, double clearance = 0.008);

}  // namespace cluttertamp::manipulation
