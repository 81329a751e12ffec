#pragma once

#include <optional>
#include <vector>

#include <Eigen/Geometry>

#include "cluttertamp/core/scene.hpp"

namespace cluttertamp {

/// What changes while a plan executes: where the objects are, which were taken
/// out of the workspace, what the gripper holds and the robot's joint values.
/// Indices refer to Scene::objects.
struct WorldState {
  std::vector<Eigen::Isometry3d> world_T_objects;
  std::vector<bool> removed;                ///< true once an object left the workspace
  std::optional<ObjectIndex> held;          ///< the object in the gripper, if any
  Eigen::VectorXd robot_configuration;      ///< joint values (rad, m), robot's joint order

  /// The state the scene file describes: objects at their poses, nothing held.
  static WorldState initial(const Scene& scene);
};

}  // namespace cluttertamp
