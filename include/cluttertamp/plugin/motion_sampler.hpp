#pragma once

#include <optional>

#include <Eigen/Core>

#include "cluttertamp/core/result.hpp"
#include "cluttertamp/plugin/context.hpp"
#include "cluttertamp/plugin/plugin.hpp"

namespace cluttertamp::plugin {

struct MotionQuery {
  Eigen::VectorXd start;  ///< joint values, robot's joint order
  Eigen::VectorXd goal;
  const WorldState& state;  ///< the world to move through; state.held travels with the gripper
};

struct MotionAnswer {
  std::optional<Trajectory> trajectory;  ///< collision-free, time-parameterized
  std::optional<Failure> failure;        ///< set without a trajectory; names blockers
};

/// Plans collision-free robot motions.
class CLUTTERTAMP_API MotionSampler : public Plugin {
 public:
  ~MotionSampler() override;
  virtual MotionAnswer plan(PlanningContext& context, const MotionQuery& query) = 0;
};

}  // namespace cluttertamp::plugin

CLUTTERTAMP_PLUGIN_KIND(::cluttertamp::plugin::MotionSampler, motion_sampler)

/// Exports CLASS as the motion_sampler NAME (see CLUTTERTAMP_EXPORT_PLUGIN in export.hpp).
#define CLUTTERTAMP_EXPORT_MOTION_SAMPLER(CLASS, NAME, DESCRIPTION, VERSION) \
  CLUTTERTAMP_EXPORT_PLUGIN(motion_sampler, CLASS, NAME, DESCRIPTION, VERSION)
