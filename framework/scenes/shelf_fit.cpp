#include "cluttertamp/scenes/shelf_fit.hpp"

#include <algorithm>
#include <cmath>
#include <memory>

#include "cluttertamp/collision/collision_world.hpp"
#include "cluttertamp/robot/ik.hpp"

namespace cluttertamp::scenes {

namespace {

Eigen::Isometry3d side_grasp(const Eigen::Vector3d& at, double up) {
  const Eigen::Vector3d approach = Eigen::Vector3d(at.x(), at.y(), 0).normalized();
  Eigen::Isometry3d tool = Eigen::Isometry3d::Identity();
  tool.linear().col(0) = up * Eigen::Vector3d::UnitZ();
  tool.linear().col(1) = approach.cross(tool.linear().col(0));
  tool.linear().col(2) = approach;
  tool.translation() = at;
  return tool;
}

// The grasp poses a placement is judged by, in the robot's base frame (at the origin).
std::vector<Eigen::Isometry3d> test_grasps(const ShelfSpec& spec, const Scene& scene) {
  const Eigen::Vector3d size = cabinet_size(spec);
  const double z = spec.floor_height + 0.5 * (spec.height_min + spec.height_max) / 2;
  std::vector<Eigen::Vector3d> points;
  for (const double x : {spec.front + 0.1, spec.front + size.x() / 2, spec.front + size.x() - 0.08}) {
    for (const double y : {-size.y() / 2 + 0.08, 0.0, size.y() / 2 - 0.08}) points.emplace_back(x, y, z);
  }
  points.push_back(scene.world_T_exit.translation());
  for (const Region& r : scene.regions) {
    points.push_back(r.world_T_region.translation() + Eigen::Vector3d(0, 0, z - spec.floor_height - r.size.z() / 2));
  }
  std::vector<Eigen::Isometry3d> out;
  for (const Eigen::Vector3d& p : points) {
    for (const double up : {-1.0, 1.0}) out.push_back(side_grasp(p, up));
  }
  return out;
}

}  // namespace

ShelfFit fit_shelf_to_robot(const ShelfSpec& spec, std::shared_ptr<const robot::RobotDescription> robot) {
  // A closed form answers at once; a numeric solver gets fewer restarts than planning
  // does (a few hundred placements are tried, most poses out of reach).
  std::unique_ptr<robot::NumericIk> numeric;
  const robot::IkSolver* ik = &robot->ik();
  if (!dynamic_cast<const robot::UrAnalyticIk*>(ik)) {
    robot::NumericIk::Options options;
    options.restarts = 4;
    options.max_solutions = 3;
    numeric = std::make_unique<robot::NumericIk>(robot->model(), robot->base_link(), robot->tip_link(), options);
    ik = numeric.get();
  }
  auto judge = [&](const ShelfSpec& candidate) {
    ShelfSpec boards = candidate;  // the furniture alone, at the size the objects give it
    const Eigen::Vector3d size = cabinet_size(candidate);
    boards.depth = size.x();
    boards.width = size.y();
    boards.objects = 0;
    ShelfFit fit{candidate, 0, 0};
    Scene scene = generate_shelf_scene(boards, 0);
    const collision::CollisionWorld world(scene, robot);
    auto context = world.make_context();
    const std::vector<Eigen::Isometry3d> grasps = test_grasps(candidate, scene);
    fit.tried = static_cast<int>(grasps.size());
    if (!world.is_valid(robot->home(), *context)) return fit;  // the robot starts inside the furniture
    std::uint64_t seed = 0;
    for (const Eigen::Isometry3d& grasp : grasps) {
      const auto solutions = ik->solve(grasp, robot->home(), seed++);
      fit.reached += std::any_of(solutions.begin(), solutions.end(), [&](const Eigen::VectorXd& q) { return world.is_valid(q, *context); });
    }
    return fit;
  };
  const ShelfFit as_given = judge(spec);
  ShelfFit best = as_given;
  if (best.reached == best.tried) {
    best.reached_as_given = best.reached;
    return best;
  }
  auto distance = [&](const ShelfSpec& s) { return std::hypot(s.front - spec.front, s.floor_height - spec.floor_height); };
  for (int f = 0; f <= 14; ++f) {
    for (int h = 0; h <= 18; ++h) {
      ShelfSpec candidate = spec;
      candidate.front = 0.2 + 0.05 * f;
      candidate.floor_height = 0.05 * h;
      const ShelfFit fit = judge(candidate);
      if (fit.reached > best.reached || (fit.reached == best.reached && distance(fit.spec) < distance(best.spec))) best = fit;
    }
  }
  best.reached_as_given = as_given.reached;
  return best;
}

}  // namespace cluttertamp::scenes
