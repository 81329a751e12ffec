#pragma once

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "cluttertamp/core/result.hpp"
#include "cluttertamp/plugin/context.hpp"
#include "cluttertamp/plugin/plugin.hpp"

namespace cluttertamp::plugin {

struct PlacementQuery {
  ObjectIndex object = 0;
  std::string region;                 ///< a Scene::regions id
  const WorldState& state;  ///< the world to put it down in (it is held there)
  std::size_t max_placements = 1;
  /// How the object is held; reachability is checked for this grip. Absent: for a
  /// side grasp facing the robot.
  std::optional<Eigen::Isometry3d> gripper_T_object;
};

struct PlacementAnswer {
  std::vector<Eigen::Isometry3d> world_T_object;  ///< stable, collision-free, reachable
  std::vector<Eigen::VectorXd> configurations;    ///< a robot configuration holding it there, per placement
  std::optional<Failure> failure;                 ///< set when none was found
};

/// Finds where an object can be put down inside a region.
class CLUTTERTAMP_API PlacementSampler : public Plugin {
 public:
  ~PlacementSampler() override;
  virtual PlacementAnswer sample(PlanningContext& context, const PlacementQuery& query) = 0;
};

}  // namespace cluttertamp::plugin

CLUTTERTAMP_PLUGIN_KIND(::cluttertamp::plugin::PlacementSampler, placement_sampler)

/// Exports CLASS as the placement_sampler NAME (see CLUTTERTAMP_EXPORT_PLUGIN in export.hpp).
#define CLUTTERTAMP_EXPORT_PLACEMENT_SAMPLER(CLASS, NAME, DESCRIPTION, VERSION) \
  CLUTTERTAMP_EXPORT_PLUGIN(placement_sampler, CLASS, NAME, DESCRIPTION, VERSION)
