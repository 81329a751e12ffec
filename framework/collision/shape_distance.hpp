#pragma once
// Internal: exact distances between two primitive shapes, over FCL. Kept behind this
// header so that FCL stays out of every other translation unit.

#include <Eigen/Geometry>

#include "cluttertamp/core/geometry.hpp"

namespace cluttertamp::collision {

/// Signed distance in metres between two placed shapes: the gap when apart, minus
/// the penetration depth when they overlap (0 when they touch).
double signed_distance(const Shape& a, const Eigen::Isometry3d& world_T_a, const Shape& b,
                       const Eigen::Isometry3d& world_T_b);

}  // namespace cluttertamp::collision
