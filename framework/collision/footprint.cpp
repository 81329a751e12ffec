#include "collision/footprint.hpp"

#include <algorithm>
#include <cmath>

namespace cluttertamp::collision::detail {

namespace {

constexpr double kUpright = 1.0 - 1e-9;  // |z axis . world z| above this: upright

double point_segment_distance(const Eigen::Vector2d& p, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const Eigen::Vector2d ab = b - a;
  const double length2 = ab.squaredNorm();
  const double t = length2 > 0 ? std::clamp((p - a).dot(ab) / length2, 0.0, 1.0) : 0.0;
  return (a + t * ab - p).norm();
}

double point_box_distance(const Eigen::Vector2d& p, const Eigen::Vector2d& half) {
  return (p.cwiseAbs() - half).cwiseMax(0.0).norm();
}

// Liang-Barsky: does the segment [a, b] meet the box [-half, half]?
bool segment_meets_box(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& half) {
  double t0 = 0.0, t1 = 1.0;
  const Eigen::Vector2d d = b - a;
  for (int axis = 0; axis < 2; ++axis) {
    for (double side : {-1.0, 1.0}) {
      // Inside where side * (a + t d)[axis] <= half[axis].
      const double p = side * d[axis];
      const double q = half[axis] - side * a[axis];
      if (p == 0.0) {
        if (q < 0) return false;
      } else {
        const double t = q / p;
        if (p < 0) t0 = std::max(t0, t); else t1 = std::min(t1, t);
        if (t0 > t1) return false;
      }
    }
  }
  return true;
}

}  // namespace

Outline outline(const Shape& shape, const Eigen::Isometry3d& world_T_shape) {
  const Eigen::AlignedBox3d bounds = world_bounds(shape, world_T_shape);
  Outline o;
  o.z_min = bounds.min().z();
  o.z_max = bounds.max().z();
  const bool upright = std::abs(world_T_shape.linear()(2, 2)) > kUpright;
  if (const auto* sphere = std::get_if<Sphere>(&shape)) {
    o.kind = Outline::Kind::disc;
    o.centre = world_T_shape.translation().head<2>();
    o.radius = sphere->radius;
  } else if (const auto* cylinder = std::get_if<Cylinder>(&shape); cylinder && upright) {
    o.kind = Outline::Kind::disc;
    o.centre = world_T_shape.translation().head<2>();
    o.radius = cylinder->radius;
  } else if (const auto* box = std::get_if<Box>(&shape); box && upright) {
    o.kind = Outline::Kind::rectangle;
    o.centre = world_T_shape.translation().head<2>();
    o.world_R_rect = world_T_shape.linear().topLeftCorner<2, 2>();
    o.half = box->size.head<2>() / 2.0;
  } else {
    o.kind = Outline::Kind::rectangle;
    o.centre = bounds.center().head<2>();
    o.half = bounds.sizes().head<2>() / 2.0;
  }
  return o;
}

bool maybe_within(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Outline& o, double distance) {
  const double reach = distance + (o.kind == Outline::Kind::disc ? o.radius : o.half.norm());
  const Eigen::Vector2d lo = a.cwiseMin(b).array() - reach, hi = a.cwiseMax(b).array() + reach;
  return (o.centre.array() >= lo.array()).all() && (o.centre.array() <= hi.array()).all();
}

double segment_distance(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Outline& o) {
  if (o.kind == Outline::Kind::disc) return std::max(0.0, point_segment_distance(o.centre, a, b) - o.radius);
  // Into the rectangle's frame, where it is the box [-half, half].
  const Eigen::Vector2d la = o.world_R_rect.transpose() * (a - o.centre);
  const Eigen::Vector2d lb = o.world_R_rect.transpose() * (b - o.centre);
  if (segment_meets_box(la, lb, o.half)) return 0.0;
  // Apart, the closest points include an endpoint of the segment or a corner of the box.
  double d = std::min(point_box_distance(la, o.half), point_box_distance(lb, o.half));
  for (double sx : {-1.0, 1.0}) {
    for (double sy : {-1.0, 1.0}) {
      d = std::min(d, point_segment_distance(Eigen::Vector2d(sx * o.half.x(), sy * o.half.y()), la, lb));
    }
  }
  return d;
}

}  // namespace cluttertamp::collision::detail
