#include "cluttertamp/collision/shape_distance.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>

#include <fcl/geometry/shape/box.h>
#include <fcl/geometry/shape/cylinder.h>
#include <fcl/geometry/shape/sphere.h>
#include <fcl/narrowphase/collision.h>

#include "collision/footprint.hpp"

namespace cluttertamp::collision {

namespace {

std::shared_ptr<fcl::CollisionGeometryd> shrunk_geometry(const Shape& shape, double shrink) {
  if (const auto* box = std::get_if<Box>(&shape)) {
    return std::make_shared<fcl::Boxd>((box->size.array() - 2 * shrink).max(1e-6).matrix());
  }
  if (const auto* sphere = std::get_if<Sphere>(&shape)) return std::make_shared<fcl::Sphered>(std::max(sphere->radius - shrink, 1e-6));
  const auto& c = std::get<Cylinder>(shape);
  return std::make_shared<fcl::Cylinderd>(std::max(c.radius - shrink, 1e-6), std::max(c.height - 2 * shrink, 1e-6));
}

bool upright_prism(const Shape& shape, const Eigen::Isometry3d& pose) {
  return !std::holds_alternative<Sphere>(shape) && std::abs(pose.linear()(2, 2)) > 1.0 - 1e-9;
}

// Planar penetration depth of two outlines (positive when they overlap).
double planar_depth(const detail::Outline& a, const detail::Outline& b) {
  using Kind = detail::Outline::Kind;
  if (a.kind == Kind::disc && b.kind == Kind::disc) return a.radius + b.radius - (a.centre - b.centre).norm();
  if (a.kind == Kind::rectangle && b.kind == Kind::disc) return planar_depth(b, a);
  if (a.kind == Kind::disc) {
    const Eigen::Vector2d p = b.world_R_rect.transpose() * (a.centre - b.centre);
    const Eigen::Vector2d outside = (p.cwiseAbs() - b.half).cwiseMax(0.0);
    if (outside.norm() > 0) return a.radius - outside.norm();
    return a.radius + (b.half - p.cwiseAbs()).minCoeff();
  }
  // Two rectangles: separating axes are the four edge normals.
  double depth = std::numeric_limits<double>::infinity();
  const Eigen::Vector2d d = b.centre - a.centre;
  for (const detail::Outline* r : {&a, &b}) {
    for (int k = 0; k < 2; ++k) {
      const Eigen::Vector2d axis = r->world_R_rect.col(k);
      auto extent = [&](const detail::Outline& o) {
        return o.half.x() * std::abs(o.world_R_rect.col(0).dot(axis)) + o.half.y() * std::abs(o.world_R_rect.col(1).dot(axis));
      };
      depth = std::min(depth, extent(a) + extent(b) - std::abs(d.dot(axis)));
    }
  }
  return depth;
}

}  // namespace

Overlap overlap(const Shape& a, const Eigen::Isometry3d& world_T_a, const Shape& b, const Eigen::Isometry3d& world_T_b,
                double tolerance) {
  Overlap result;
  if (upright_prism(a, world_T_a) && upright_prism(b, world_T_b)) {
    const detail::Outline oa = detail::outline(a, world_T_a), ob = detail::outline(b, world_T_b);
    const double vertical = std::min(oa.z_max, ob.z_max) - std::max(oa.z_min, ob.z_min);
    const double depth = std::min(vertical, planar_depth(oa, ob));
    result.depth = depth;
    result.beyond_tolerance = depth > tolerance;
    return result;
  }
  const auto ga = shrunk_geometry(a, tolerance / 2), gb = shrunk_geometry(b, tolerance / 2);
  fcl::CollisionRequestd request;
  request.gjk_solver_type = fcl::GST_LIBCCD;  // boolean: no EPA
  fcl::CollisionResultd out;
  fcl::collide(ga.get(), fcl::Transform3d(world_T_a.matrix()), gb.get(), fcl::Transform3d(world_T_b.matrix()), request, out);
  result.beyond_tolerance = out.isCollision();
  return result;
}

}  // namespace cluttertamp::collision
