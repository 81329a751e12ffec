#pragma once

#include <optional>

#include <Eigen/Geometry>

#include "cluttertamp/core/scene.hpp"
#include "cluttertamp/export.hpp"
#include "cluttertamp/manipulation/base_placement.hpp"
#include "cluttertamp/plugin/context.hpp"
#include "cluttertamp/plugin/world_view.hpp"

namespace cluttertamp::manipulation {

/// What PlacementChecker found for one pose.
struct PlacementCheck {
  enum class Verdict {
    ok,           ///< `configuration` holds the object there, touching nothing
    touches,      ///< the object there touches `contacts` (fixed bodies, objects)
    unreachable,  ///< no IK solution holds it there without a collision
  };
  Verdict verdict = Verdict::unreachable;
  Eigen::VectorXd configuration;  ///< when ok: rad, m, the robot's joint order
  plugin::Contacts contacts;      ///< when touches
};

/// Decides whether one object can be put down at proposed poses, as every placement
/// sampler must: lifted 1 mm off its support the object touches nothing (the robot is
/// not looked at), and one of the first two IK solutions for the tool holding it (a
/// mobile base first placed behind the tool) is collision-free with it in the hand.
/// Whether the pose is inside a region, or stable, is the sampler's to decide.
class CLUTTERTAMP_API PlacementChecker {
 public:
  /// `world`: the scene at the query's state with the hand empty (the object is placed
  /// anew); `seed`: where IK starts. Both must outlive the checker. Precondition: the
  /// context's problem has a robot.
  PlacementChecker(plugin::PlanningContext& context, const plugin::WorldView& world, ObjectIndex object,
                   Eigen::VectorXd seed);

  /// Checks the object at `world_T_object` (world frame, m) held at `gripper_T_object`
  /// (tool frame). Counts collision checks in the context.
  PlacementCheck check(const Eigen::Isometry3d& world_T_object, const Eigen::Isometry3d& gripper_T_object) const;

  /// A side grip facing the robot at the object's centre (tool z along the horizontal
  /// from the robot's base to the object, tool x down): the tool frame in the object's.
  static Eigen::Isometry3d facing_grip(const Scene& scene, const Eigen::Isometry3d& world_T_object);

 private:
  plugin::PlanningContext& context_;
  const plugin::WorldView& world_;
  ObjectIndex object_;
  Eigen::VectorXd seed_;
  std::optional<BasePlacement> mobile_;
};

}  // namespace cluttertamp::manipulation
