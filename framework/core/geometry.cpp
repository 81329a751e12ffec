#include "cluttertamp/core/geometry.hpp"

#include <algorithm>
#include <cmath>

namespace cluttertamp {

namespace {
}  // namespace

double footprint_radius(const Shape& shape, const Eigen::Isometry3d& world_T_shape) {
  if (const auto* sphere = std::get_if<Sphere>(&shape)) return sphere->radius;
  if (std::abs(world_T_shape.linear()(2, 2)) > 1.0 - 1e-9) {  // upright: its z along the world's
    if (const auto* cylinder = std::get_if<Cylinder>(&shape)) return cylinder->radius;
    if (const auto* box = std::get_if<Box>(&shape)) return box->size.head<2>().norm() / 2;
  }
  const Eigen::AlignedBox3d bounds = world_bounds(shape, world_T_shape);
  return 0.5 * (bounds.max() - bounds.min()).head<2>().norm();
}

double distance_to_segment(const Eigen::Vector2d& p, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const Eigen::Vector2d ab = b - a;
  const double length2 = ab.squaredNorm();
  const double t = length2 > 0 ? std::clamp((p - a).dot(ab) / length2, 0.0, 1.0) : 0.0;
  return (a + t * ab - p).norm();
}

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
  if (const auto* sphere = std::get_if<Sphere>(&shape)) {
    const Eigen::Vector3d half = Eigen::Vector3d::Constant(sphere->radius);
    return {centre - half, centre + half};
  }
  const Eigen::Vector3d half = R.cwiseAbs() * (std::get<Box>(shape).size / 2.0);
  return {centre - half, centre + half};
}

const char* shape_name(const Shape& shape) {
  switch (shape.index()) {
    case 0: return "box";
    case 1: return "cylinder";
    default: return "sphere";
  }
}

double yaw_of(const Eigen::Isometry3d& pose) {
  const Eigen::Vector3d x = pose.rotation().col(0);
  return std::atan2(x.y(), x.x());
}

Eigen::Isometry3d with_planar_pose(const Eigen::Isometry3d& pose, const Eigen::Vector3d& x_y_yaw) {
  Eigen::Isometry3d moved = pose;
  const double turn = x_y_yaw.z() - yaw_of(pose);
  moved.linear() = Eigen::AngleAxisd(turn, Eigen::Vector3d::UnitZ()).toRotationMatrix() * pose.linear();
  moved.translation().head<2>() = x_y_yaw.head<2>();
  return moved;
}

std::vector<double> pose_values(const Eigen::Isometry3d& pose) {
  const Eigen::Quaterniond q(pose.linear());
  const Eigen::Vector3d t = pose.translation();
  return {t.x(), t.y(), t.z(), q.x(), q.y(), q.z(), q.w()};
}

}  // namespace cluttertamp
