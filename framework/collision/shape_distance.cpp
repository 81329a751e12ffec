#include "collision/shape_distance.hpp"

#include <memory>

#include <fcl/geometry/shape/box.h>
#include <fcl/geometry/shape/cylinder.h>
#include <fcl/geometry/shape/sphere.h>
#include <fcl/narrowphase/distance.h>

namespace cluttertamp::collision {

namespace {
std::shared_ptr<fcl::CollisionGeometryd> make_geometry(const Shape& shape) {
  if (const auto* box = std::get_if<Box>(&shape)) return std::make_shared<fcl::Boxd>(box->size);
  if (const auto* sphere = std::get_if<Sphere>(&shape)) return std::make_shared<fcl::Sphered>(sphere->radius);
  const auto& cylinder = std::get<Cylinder>(shape);
  return std::make_shared<fcl::Cylinderd>(cylinder.radius, cylinder.height);
}
}  // namespace

double signed_distance(const Shape& a, const Eigen::Isometry3d& world_T_a, const Shape& b,
                       const Eigen::Isometry3d& world_T_b) {
  const auto geometry_a = make_geometry(a);
  const auto geometry_b = make_geometry(b);
  fcl::DistanceRequestd request;
  request.enable_signed_distance = true;
  // libccd's EPA gives the right negative depth for overlapping cylinders; the
  // independent solver asserts on them (shared/notes/dependencies.md, pitfall 2).
  request.gjk_solver_type = fcl::GST_LIBCCD;
  fcl::DistanceResultd result;
  fcl::distance(geometry_a.get(), fcl::Transform3d(world_T_a.matrix()), geometry_b.get(),
                fcl::Transform3d(world_T_b.matrix()), request, result);
  return result.min_distance;
}

}  // namespace cluttertamp::collision
