#pragma once

#include <optional>

#include <Eigen/Core>

#include "cluttertamp/core/result.hpp"
#include "cluttertamp/plugin/context.hpp"
#include "cluttertamp/plugin/plugin.hpp"

namespace cluttertamp::plugin {

/// Push `object` until its centre lies within `goal_radius` of `goal_xy` (world
/// frame, metres, in the plane of its support).
struct PushQuery {
  ObjectIndex object = 0;
  Eigen::Vector2d goal_xy = Eigen::Vector2d::Zero();
  double goal_radius = 0.0;
  const WorldState* state = nullptr;  ///< not null
};

struct PushAnswer {
  std::optional<Trajectory> trajectory;  ///< the executed gripper motion
  std::optional<WorldState> resulting_state;
  std::optional<Failure> failure;
};

/// Moves objects without grasping them.
class CLUTTERTAMP_API PushSampler : public Plugin {
 public:
  ~PushSampler() override;
  virtual PushAnswer push(PlanningContext& context, const PushQuery& query) = 0;
};

template <>
struct KindOf<PushSampler> {
  static constexpr Kind value = Kind::push_sampler;
};

}  // namespace cluttertamp::plugin
