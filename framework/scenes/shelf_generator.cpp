#include "cluttertamp/scenes/shelf_generator.hpp"

#include <algorithm>
#include <cstdio>
#include <random>
#include <stdexcept>

namespace cluttertamp::scenes {

namespace {

Eigen::Isometry3d at(double x, double y, double z) {
  Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
  p.translation() << x, y, z;
  return p;
}

FixedBody board(const std::string& id, const Eigen::Vector3d& size, const Eigen::Vector3d& centre) {
  FixedBody body;
  body.id = id;
  body.shape = Box{size};
  body.world_T_body = at(centre.x(), centre.y(), centre.z());
  return body;
}

}  // namespace

Eigen::Vector3d cabinet_size(const ShelfSpec& spec) {
  const double t = std::clamp((spec.objects - 12) / 8.0, 0.0, 1.0);
  // Beyond 20 objects (Table V's 100) only the width grows, 2.25 cm per object: a deeper
  // cabinet would put its back out of a UR10's reach. At 1 cm per object (2.0 m for 100)
  // neighbours blocked each other's every grasp and no planner solved a scene; at 3.0 m
  // retrieval takes 6 to 15 removals, near the paper's "at least 10".
  const double wider = 0.0225 * std::max(0, spec.objects - 20);
  const double width = spec.width > 0 ? spec.width : 0.9 + t * 0.3 + wider;
  const double depth = spec.depth > 0 ? spec.depth : 0.6 + t * 0.1;
  return {depth, width, spec.height};
}

Scene generate_shelf_scene(const ShelfSpec& spec, std::uint64_t seed) {
  const Eigen::Vector3d size = cabinet_size(spec);
  const double depth = size.x(), width = size.y(), height = size.z();
  const double x0 = spec.front, x1 = spec.front + depth, z0 = spec.floor_height;
  constexpr double wall = 0.02;

  Scene scene;
  scene.name = "shelf" + std::to_string(spec.objects) + "-seed" + std::to_string(seed);
  const double cx = (x0 + x1) / 2;
  scene.fixed.push_back(board("cabinet_floor", {depth, width + 2 * wall, wall}, {cx, 0, z0 - wall / 2}));
  scene.fixed.push_back(board("cabinet_top", {depth, width + 2 * wall, wall}, {cx, 0, z0 + height + wall / 2}));
  scene.fixed.push_back(board("cabinet_back", {wall, width + 2 * wall, height + 2 * wall}, {x1 + wall / 2, 0, z0 + height / 2}));
  scene.fixed.push_back(board("cabinet_left", {depth, wall, height}, {cx, width / 2 + wall / 2, z0 + height / 2}));
  scene.fixed.push_back(board("cabinet_right", {depth, wall, height}, {cx, -width / 2 - wall / 2, z0 + height / 2}));
  // A buffer table to the robot's right, its top level with the cabinet floor.
  const Eigen::Vector3d table(0.5, 0.4, z0);
  const Eigen::Vector2d table_xy(0.2, -width / 2 - 0.25);
  scene.fixed.push_back(board("buffer_table", table, {table_xy.x(), table_xy.y(), z0 / 2}));
  Region buffer;
  buffer.id = "buffer";
  buffer.size = {table.x() - 0.04, table.y() - 0.04, 0.32};
  buffer.world_T_region = at(table_xy.x(), table_xy.y(), z0 + 0.16);
  scene.regions.push_back(buffer);

  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> radius(spec.radius_min, spec.radius_max);
  std::uniform_real_distribution<double> tall(spec.height_min, spec.height_max);
  struct Disc {
    Eigen::Vector2d centre;
    double radius, height;
  };
  std::vector<Disc> discs;
  for (int attempt = 0; static_cast<int>(discs.size()) < spec.objects; ++attempt) {
    if (attempt > 100000) {
      char size_text[64];
      std::snprintf(size_text, sizeof size_text, "%.2f x %.2f m", width, depth);
      throw std::runtime_error("cannot place " + std::to_string(spec.objects) + " cylinders " +
                               std::to_string(static_cast<int>(spec.min_gap * 1000)) + " mm apart in a " + size_text +
                               " cabinet (" + std::to_string(discs.size()) + " fitted in 100000 tries)");
    }
    const double r = radius(rng);
    const double margin = r + spec.min_gap;
    if (depth < 2 * margin || width < 2 * margin) throw std::runtime_error("the cabinet is too small for one object");
    const Eigen::Vector2d c(std::uniform_real_distribution<double>(x0 + margin, x1 - margin)(rng),
                            std::uniform_real_distribution<double>(-width / 2 + margin, width / 2 - margin)(rng));
    const bool free = std::all_of(discs.begin(), discs.end(), [&](const Disc& d) {
      return (d.centre - c).norm() >= d.radius + r + spec.min_gap;
    });
    if (free) discs.push_back({c, r, tall(rng)});
  }
  // The target: nearest the middle of the back wall.
  const Eigen::Vector2d back(x1, 0.0);
  const auto target = std::min_element(discs.begin(), discs.end(), [&](const Disc& a, const Disc& b) {
    return (a.centre - back).norm() < (b.centre - back).norm();
  });
  int next = 1;
  for (auto it = discs.begin(); it != discs.end(); ++it) {
    SceneObject o;
    o.id = it == target ? "target" : "o" + std::to_string(next++);
    o.shape = Cylinder{it->radius, it->height};
    o.world_T_object = at(it->centre.x(), it->centre.y(), z0 + it->height / 2);
    o.mass = 0.3;
    o.friction = 0.5;
    if (it == target) scene.target = static_cast<ObjectIndex>(scene.objects.size());
    scene.objects.push_back(o);
  }
  scene.world_T_exit = at(spec.front - 0.2, 0.0, z0 + (spec.height_min + spec.height_max) / 4);
  scene.world_T_robot_base = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d camera = at(0.1, 0.0, z0 + height + 0.2);
  camera.linear() = (Eigen::AngleAxisd(-M_PI / 2, Eigen::Vector3d::UnitZ()) *
                     Eigen::AngleAxisd(-2.0 * M_PI / 3, Eigen::Vector3d::UnitX()))
                        .toRotationMatrix();
  scene.world_T_camera = camera;
  scene.workspace = Eigen::AlignedBox3d(Eigen::Vector3d(-0.5, -width / 2 - 0.6, 0.0),
                                        Eigen::Vector3d(x1 + 0.2, width / 2 + 0.6, z0 + height + 0.5));
  return scene;
}

}  // namespace cluttertamp::scenes
