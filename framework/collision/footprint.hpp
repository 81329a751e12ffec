#pragma once
// Internal: exact 2-D footprint geometry in the shelf plane (no FCL), for the
// roadmap's Col and EdgeCol queries.

#include <Eigen/Geometry>

#include "cluttertamp/core/geometry.hpp"

namespace cluttertamp::collision::detail {

/// An object's outline in the plane: a disc or an oriented rectangle, and its height band.
struct Outline {
  enum class Kind { disc, rectangle } kind = Kind::disc;
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
  double radius = 0.0;                                   ///< disc
  Eigen::Matrix2d world_R_rect = Eigen::Matrix2d::Identity();  ///< rectangle axes
  Eigen::Vector2d half = Eigen::Vector2d::Zero();        ///< rectangle half sizes
  double z_min = 0.0;
  double z_max = 0.0;
};

/// Exact for upright cylinders, spheres and boxes rotated about z; anything else gets
/// its world-aligned bounding rectangle (conservative).
Outline outline(const Shape& shape, const Eigen::Isometry3d& world_T_shape);

/// Distance from the segment [a, b] to the outline in the plane (0 when they meet).
double segment_distance(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Outline& outline);

/// Whether the outline may come within `distance` of the segment [a, b]: a test of
/// the segment's bounding box against the outline's bounding circle, much cheaper
/// than segment_distance and false only when segment_distance >= distance.
bool maybe_within(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Outline& outline, double distance);

/// True when the height bands overlap by more than a touch.
inline bool bands_overlap(const Outline& outline, double z_min, double z_max) {
  // Bands overlapping less than scene validation accepts as resting contact do not
  // count (a target standing 10 um into its shelf board is standing on it).
  constexpr double touch = kContactTolerance;
  return outline.z_min < z_max - touch && outline.z_max > z_min + touch;
}

}  // namespace cluttertamp::collision::detail
