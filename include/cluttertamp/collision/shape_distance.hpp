#pragma once
// Whether two placed primitive shapes interpenetrate, and by how much, for scene
// validation. FCL stays behind this header, in the geometry library.
//
// FCL 0.7's signed distance (libccd EPA) aborts on an internal assertion for some
// touching shapes, so depths here are exact geometry for upright prisms and a
// boolean GJK test on shrunk shapes otherwise; EPA is never called.

#include <optional>

#include <Eigen/Geometry>

#include "cluttertamp/core/geometry.hpp"
#include "cluttertamp/export.hpp"

namespace cluttertamp::collision {

struct Overlap {
  bool beyond_tolerance = false;  ///< they overlap by more than the tolerance
  std::optional<double> depth;    ///< penetration depth (m) when it is known exactly
};

/// Exact for upright cylinders and boxes rotated about z (penetration depth is the
/// smaller of the vertical and the planar overlap). For other shapes: whether the
/// shapes, each shrunk by tolerance / 2 on every side, still intersect.
CLUTTERTAMP_API Overlap overlap(const Shape& a, const Eigen::Isometry3d& world_T_a, const Shape& b, const Eigen::Isometry3d& world_T_b,
                double tolerance);

}  // namespace cluttertamp::collision
