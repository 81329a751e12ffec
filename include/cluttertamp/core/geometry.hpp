#pragma once

#include <variant>
#include <vector>

#include <Eigen/Geometry>

namespace cluttertamp {

/// Overlaps of two bodies up to this depth are resting contact, deeper ones
/// interpenetration, m: what a scene file may hold (an object standing a rounding error
/// into its shelf board) and what the planners' planar tests therefore ignore.
inline constexpr double kContactTolerance = 1e-3;

/// A box centred at its frame's origin. `size` holds the full edge lengths along the
/// frame's x, y and z axes, in metres.
struct Box {
  Eigen::Vector3d size = Eigen::Vector3d::Zero();
};

/// A cylinder centred at its frame's origin with its axis along the frame's z axis.
/// Radius and height in metres.
struct Cylinder {
  double radius = 0.0;
  double height = 0.0;
};

/// A sphere centred at its frame's origin. Radius in metres.
struct Sphere {
  double radius = 0.0;
};

/// The primitive shapes scenes and robot links are made of.
using Shape = std::variant<Box, Cylinder, Sphere>;

/// The world-frame axis-aligned bounding box of `shape` placed at `world_T_shape`.
Eigen::AlignedBox3d world_bounds(const Shape& shape, const Eigen::Isometry3d& world_T_shape);

/// Radius (m) of a disc in the world x-y plane, about the shape's centre, that covers
/// its footprint: exact for an upright cylinder or box and a sphere, conservative (half
/// the diagonal of its world bounding box) for anything tilted.
double footprint_radius(const Shape& shape, const Eigen::Isometry3d& world_T_shape);

/// Distance from `p` to the segment from `a` to `b` (to `a` when they coincide).
double distance_to_segment(const Eigen::Vector2d& p, const Eigen::Vector2d& a, const Eigen::Vector2d& b);

/// "box", "cylinder" or "sphere".
const char* shape_name(const Shape& shape);

/// The heading of the pose's x axis in the world x-y plane (rad, from +x towards +y).
double yaw_of(const Eigen::Isometry3d& pose);

/// `pose` moved in the world x-y plane to (x, y) and turned about the world z axis until
/// its yaw is `x_y_yaw.z()` (m, m, rad); its height and tilt stay.
Eigen::Isometry3d with_planar_pose(const Eigen::Isometry3d& pose, const Eigen::Vector3d& x_y_yaw);

/// A pose as result.json writes it: [x y z qx qy qz qw] (metres, unit quaternion).
std::vector<double> pose_values(const Eigen::Isometry3d& pose);

}  // namespace cluttertamp
