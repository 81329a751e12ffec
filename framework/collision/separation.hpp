#pragma once
// Internal: a cheap, conservative test that two placed primitives cannot touch, run
// before FCL's narrow phase (libccd MPR), which costs far more. In a planner's
// validity checks most pairs whose world AABBs overlap (arm links, a held object
// beside its neighbours) are separated by one of these tests.

#include <Eigen/Geometry>

namespace cluttertamp::collision::detail {

/// A primitive in its own frame: a box of half extents `half`, a cylinder of radius
/// half.x() and half length half.z() along its z axis, or a sphere of radius half.x().
struct Solid {
  enum class Kind { box, cylinder, sphere } kind;
  Eigen::Vector3d half;
};

/// True only when the solids certainly do not intersect; false means "maybe"
/// (ask the narrow phase). Tests: the oriented bounding boxes' 15 separating axes,
/// and for two cylinders or spheres, the distance of their enclosing capsules.
/// Poses are world_T_solid (m).
bool separated(const Solid& a, const Eigen::Isometry3d& world_T_a, const Solid& b, const Eigen::Isometry3d& world_T_b);

}  // namespace cluttertamp::collision::detail
