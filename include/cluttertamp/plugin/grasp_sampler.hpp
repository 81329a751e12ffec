#pragma once

#include <vector>

#include <Eigen/Geometry>

#include "cluttertamp/core/result.hpp"
#include "cluttertamp/plugin/context.hpp"
#include "cluttertamp/plugin/plugin.hpp"

namespace cluttertamp::plugin {

/// Robot configurations of one IK branch through a grasp: before the approach, at the
/// grasp (fingers open) and lifted (fingers closed, object held).
struct GraspMotion {
  Eigen::VectorXd pregrasp;
  Eigen::VectorXd grasp;
  Eigen::VectorXd lift;
};

/// A way to hold an object. Poses of the robot's tool (TCP) in the world frame.
struct Grasp {
  Eigen::Isometry3d world_T_gripper = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d world_T_pregrasp = Eigen::Isometry3d::Identity();  ///< approach pose
  Eigen::Isometry3d world_T_lift = Eigen::Isometry3d::Identity();      ///< after lifting
  Eigen::Isometry3d gripper_T_object = Eigen::Isometry3d::Identity();  ///< the held object in the tool frame
  double finger_open = 0.0;    ///< finger variable while approaching (m)
  double finger_closed = 0.0;  ///< finger variable while holding (m)
  std::vector<Eigen::VectorXd> ik_solutions;  ///< robot configurations reaching world_T_gripper
  std::vector<GraspMotion> motions;  ///< branches whose approach, grasp and lift are collision-free
};

/// A grasp that cannot be used, with the objects that make it unusable.
struct BlockedGrasp {
  Grasp grasp;
  std::vector<ObjectIndex> blocking_objects;
  std::string reason;
  /// True when removing `blocking_objects` would free the grasp; false when it is
  /// unreachable or blocked by fixed geometry or the arm itself.
  bool freeable = true;
};

struct GraspQuery {
  ObjectIndex object = 0;
  const WorldState& state;  ///< the world the grasp is for; views: PlanningContext::world_at
};

struct GraspAnswer {
  std::vector<Grasp> usable;          ///< approach, grasp and lift are collision-free
  std::vector<BlockedGrasp> blocked;  ///< every rejected grasp and why
  std::optional<Failure> failure;     ///< set when `usable` is empty

  /// The freeable blocked grasp with the fewest blocking objects, or null.
  const BlockedGrasp* least_blocked() const;
};

/// Proposes grasps of an object and says which objects block the ones it rejects.
class CLUTTERTAMP_API GraspSampler : public Plugin {
 public:
  ~GraspSampler() override;
  virtual GraspAnswer sample(PlanningContext& context, const GraspQuery& query) = 0;
};

}  // namespace cluttertamp::plugin

CLUTTERTAMP_PLUGIN_KIND(::cluttertamp::plugin::GraspSampler, grasp_sampler)

/// Exports CLASS as the grasp_sampler NAME (see CLUTTERTAMP_EXPORT_PLUGIN in export.hpp).
#define CLUTTERTAMP_EXPORT_GRASP_SAMPLER(CLASS, NAME, DESCRIPTION, VERSION) \
  CLUTTERTAMP_EXPORT_PLUGIN(grasp_sampler, CLASS, NAME, DESCRIPTION, VERSION)
