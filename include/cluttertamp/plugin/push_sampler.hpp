#pragma once

#include <optional>

#include <Eigen/Core>

#include "cluttertamp/core/result.hpp"
#include "cluttertamp/plugin/context.hpp"
#include "cluttertamp/plugin/plugin.hpp"

namespace cluttertamp::plugin {

/// Push `object` until its centre lies within `goal_radius` of `goal_xy` (world
/// frame, metres, in the plane of its support), the gripper moving in the plane of the
/// target's support from its planar pose `gripper` (x, y in m, yaw in rad, world frame;
/// yaw 0 faces +x).
struct PushQuery {
  ObjectIndex object = 0;
  Eigen::Vector2d goal_xy = Eigen::Vector2d::Zero();
  double goal_radius = 0.0;
  const WorldState& state;  ///< every object where it stands before the push
  Eigen::Vector3d gripper = Eigen::Vector3d::Zero();
  /// At most this many physics propagations for the whole query (0: the sampler's own
  /// budget). Work, not time, so that a push's outcome is the same on any machine.
  std::uint64_t max_propagations = 0;
};

/// Either a push that was executed in simulation, or why none was found.
struct PushAnswer {
  /// The executed push: action "push", the gripper's trajectory and its controls
  /// (physics::push_step describes the values).
  std::optional<PlanStep> step;
  std::optional<WorldState> resulting_state;  ///< every object where the push left it
  Eigen::Vector3d gripper_end = Eigen::Vector3d::Zero();  ///< where the gripper stopped (x, y, yaw)
  std::optional<Failure> failure;  ///< set when `step` is not
};

/// Moves objects without grasping them.
class CLUTTERTAMP_API PushSampler : public Plugin {
 public:
  ~PushSampler() override;
  virtual PushAnswer push(PlanningContext& context, const PushQuery& query) = 0;
};

}  // namespace cluttertamp::plugin

CLUTTERTAMP_PLUGIN_KIND(::cluttertamp::plugin::PushSampler, push_sampler)

/// Exports CLASS as the push_sampler NAME (see CLUTTERTAMP_EXPORT_PLUGIN in export.hpp).
#define CLUTTERTAMP_EXPORT_PUSH_SAMPLER(CLASS, NAME, DESCRIPTION, VERSION) \
  CLUTTERTAMP_EXPORT_PLUGIN(push_sampler, CLASS, NAME, DESCRIPTION, VERSION)
