#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Geometry>

#include "cluttertamp/core/diagnostics.hpp"
#include "cluttertamp/core/geometry.hpp"
#include "cluttertamp/export.hpp"

namespace cluttertamp {

/// Index of an object in Scene::objects. Stable for the lifetime of a Scene.
using ObjectIndex = std::uint32_t;

/// Geometry that never moves: shelf boards, walls, tables.
struct FixedBody {
  std::string id;
  Shape shape;
  Eigen::Isometry3d world_T_body = Eigen::Isometry3d::Identity();
  /// Coulomb coefficient of its surface in the pushing physics (physics::PushSettings
  /// says how two bodies' coefficients combine). The default 1 leaves an object's own
  /// coefficient as the one against it under the default product rule.
  double friction = 1.0;
  SourceLocation where;  ///< where the scene file declares it
};

/// An object the robot may see, touch, and (if movable) pick, place or push.
struct SceneObject {
  std::string id;
  Shape shape;
  Eigen::Isometry3d world_T_object = Eigen::Isometry3d::Identity();
  double mass = 0.0;      ///< kg
  double friction = 0.0;  ///< Coulomb coefficient against its support
  bool movable = true;
  std::vector<ObjectIndex> supports;  ///< the objects it rests on (`on:`); empty: a fixed body
  SourceLocation where;
};

/// A box-shaped volume (buffer table top, free shelf space) where objects may be placed:
/// a placed object lies entirely inside it.
struct Region {
  std::string id;
  Eigen::Vector3d size = Eigen::Vector3d::Zero();  ///< full edge lengths, metres
  Eigen::Isometry3d world_T_region = Eigen::Isometry3d::Identity();  ///< centre of the volume
  SourceLocation where;
};

/// The immutable description of a workspace as read from a scene file.
/// All poses are in the world frame (z up), lengths in metres.
struct CLUTTERTAMP_API Scene {
  std::string name;
  std::string source_file;
  Eigen::AlignedBox3d workspace;  ///< every object and region lies inside it
  std::vector<FixedBody> fixed;
  std::vector<SceneObject> objects;
  ObjectIndex target = 0;  ///< the object to retrieve
  std::vector<Region> regions;
  /// x_s: where a retrieved target is carried to (Tian et al., Table of symbols).
  Eigen::Isometry3d world_T_exit = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d world_T_robot_base = Eigen::Isometry3d::Identity();
  /// The camera that observes the scene; absent when the scene declares none.
  std::optional<Eigen::Isometry3d> world_T_camera;

  std::optional<ObjectIndex> find_object(std::string_view id) const;
  const Region* find_region(std::string_view id) const;
  /// Marks every object that rests, directly or through others, on a marked one (what
  /// must go before them). Precondition: `marked` has one entry per object.
  void mark_what_rests_on(std::vector<bool>& marked) const;
};

}  // namespace cluttertamp
