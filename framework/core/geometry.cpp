#include "cluttertamp/core/geometry.hpp"

namespace cluttertamp {

namespace {
// Half extents of the shape's own bounding box, in its frame.
Eigen::Vector3d half_extents(const Shape& shape) {
  if (const auto* box = std::get_if<Box>(&shape)) return box->size / 2.0;
  const auto& cylinder = std::get<Cylinder>(shape);
  return {cylinder.radius, cylinder.radius, cylinder.height / 2.0};
}
}  // namespace

Eigen::AlignedBox3d world_bounds(const Shape& shape, const Eigen::Isometry3d& world_T_shape) {
  const Eigen::Matrix3d& R = world_T_shape.linear();
  const Eigen::Vector3d centre = world_T_shape.translation();
  if (const auto* cylinder = std::get_if<Cylinder>(&shape)) {
    // Exact for a cylinder: its axis contributes |a_i| h/2 and its rim r sqrt(1 - a_i^2).
    const Eigen::Vector3d axis = R.col(2);
    Eigen::Vector3d half;
    for (int i = 0; i < 3; ++i) {
      half[i] = std::abs(axis[i]) * cylinder->height / 2.0 +
                cylinder->radius * std::sqrt(std::max(0.0, 1.0 - axis[i] * axis[i]));
    }
    return {centre - half, centre + half};
  }
  const Eigen::Vector3d half = R.cwiseAbs() * half_extents(shape);
  return {centre - half, centre + half};
}

const char* shape_name(const Shape& shape) { return std::holds_alternative<Box>(shape) ? "box" : "cylinder"; }

}  // namespace cluttertamp
