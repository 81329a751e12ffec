#pragma once

#include <vector>

#include <Eigen/Geometry>

#include "cluttertamp/core/result.hpp"
#include "cluttertamp/plugin/context.hpp"
#include "cluttertamp/plugin/plugin.hpp"

namespace cluttertamp::plugin {

/// A way to hold an object. Poses in the world frame.
struct Grasp {
  Eigen::Isometry3d world_T_gripper = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d world_T_pregrasp = Eigen::Isometry3d::Identity();  ///< approach pose
  std::vector<Eigen::VectorXd> ik_solutions;  ///< robot configurations reaching world_T_gripper
};

/// A grasp that cannot be used, with the objects that make it unusable.
struct BlockedGrasp {
  Grasp grasp;
  std::vector<ObjectIndex> blocking_objects;
  std::string reason;
};

struct GraspQuery {
  ObjectIndex object = 0;
  const WorldState* state = nullptr;  ///< not null
};

struct GraspAnswer {
  std::vector<Grasp> usable;          ///< approach, grasp and lift are collision-free
  std::vector<BlockedGrasp> blocked;  ///< every rejected grasp and why
  std::optional<Failure> failure;     ///< set when `usable` is empty

  /// The blocked grasp with the fewest blocking objects, or null.
  const BlockedGrasp* least_blocked() const;
};

/// Proposes grasps of an object and says which objects block the ones it rejects.
class CLUTTERTAMP_API GraspSampler : public Plugin {
 public:
  ~GraspSampler() override;
  virtual GraspAnswer sample(PlanningContext& context, const GraspQuery& query) = 0;
};

template <>
struct KindOf<GraspSampler> {
  static constexpr Kind value = Kind::grasp_sampler;
};

}  // namespace cluttertamp::plugin
