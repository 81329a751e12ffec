#include "cluttertamp/scenes/shelf_generator.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <random>
#include <stdexcept>

#include "cluttertamp/perception/visibility.hpp"

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

namespace {

// A 0.5 x 0.4 m table centred at `xy`, its top at `top`, with the placement region
// "buffer" over it (2 cm in from its edges, 32 cm high).
void add_buffer_table(Scene& scene, const Eigen::Vector2d& xy, double top) {
  const Eigen::Vector3d table(0.5, 0.4, top);
  scene.fixed.push_back(board("buffer_table", table, {xy.x(), xy.y(), top / 2}));
  Region buffer;
  buffer.id = "buffer";
  buffer.size = {table.x() - 0.04, table.y() - 0.04, 0.32};
  buffer.world_T_region = at(xy.x(), xy.y(), top + 0.16);
  scene.regions.push_back(buffer);
}

// The cabinet (interior depth x width x height, open side at x0, floor top at z0), a
// buffer table with its region, the robot base, the exit x_s, a camera above the robot
// and the workspace; no objects.
Scene cabinet(double x0, double depth, double width, double height, double z0, double object_height,
              double exit_distance = 0.2, bool buffer_table = true) {
  const double x1 = x0 + depth;
  constexpr double wall = 0.02;
  Scene scene;
  const double cx = (x0 + x1) / 2;
  scene.fixed.push_back(board("cabinet_floor", {depth, width + 2 * wall, wall}, {cx, 0, z0 - wall / 2}));
  scene.fixed.push_back(board("cabinet_top", {depth, width + 2 * wall, wall}, {cx, 0, z0 + height + wall / 2}));
  scene.fixed.push_back(board("cabinet_back", {wall, width + 2 * wall, height + 2 * wall}, {x1 + wall / 2, 0, z0 + height / 2}));
  scene.fixed.push_back(board("cabinet_left", {depth, wall, height}, {cx, width / 2 + wall / 2, z0 + height / 2}));
  scene.fixed.push_back(board("cabinet_right", {depth, wall, height}, {cx, -width / 2 - wall / 2, z0 + height / 2}));
  // A buffer table to the robot's right, its top level with the cabinet floor.
  if (buffer_table) add_buffer_table(scene, {0.2, -width / 2 - 0.25}, z0);
  scene.world_T_exit = at(x0 - exit_distance, 0.0, z0 + object_height / 2);
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

// The n-th obstacle's id, "o<n>" (appended: g++ 12 warns falsely, -Wrestrict, on
// "o" + std::string).
std::string obstacle_id(std::size_t n) {
  std::string id = "o";
  id += std::to_string(n);
  return id;
}

SceneObject standing_cylinder(const std::string& id, const Eigen::Vector2d& xy, double radius, double height, double z0) {
  SceneObject o;
  o.id = id;
  o.shape = Cylinder{radius, height};
  o.world_T_object = at(xy.x(), xy.y(), z0 + height / 2);
  o.mass = 0.3;
  o.friction = 0.5;
  return o;
}

}  // namespace

Scene generate_shelf_scene(const ShelfSpec& spec, std::uint64_t seed) {
  const Eigen::Vector3d size = cabinet_size(spec);
  const double depth = size.x(), width = size.y(), height = size.z();
  const double x0 = spec.front, x1 = spec.front + depth, z0 = spec.floor_height;
  Scene scene = cabinet(x0, depth, width, height, z0, (spec.height_min + spec.height_max) / 2, spec.exit_distance);
  scene.name = "shelf" + std::to_string(spec.objects) + "-seed" + std::to_string(seed);

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
  std::size_t next = 1;
  for (auto it = discs.begin(); it != discs.end(); ++it) {
    if (it == target) scene.target = static_cast<ObjectIndex>(scene.objects.size());
    scene.objects.push_back(standing_cylinder(it == target ? std::string("target") : obstacle_id(next++), it->centre, it->radius,
                                              it->height, z0));
  }
  return scene;
}

Scene generate_push_shelf(const PushShelfSpec& spec, std::uint64_t seed) {
  const double x0 = spec.front, x1 = spec.front + spec.depth, z0 = spec.floor_height, r = spec.radius;
  Scene scene = cabinet(x0, spec.depth, spec.width, spec.height, z0, spec.object_height, spec.exit_distance, false);
  scene.name = "push-shelf" + std::to_string(spec.obstacles) + "-seed" + std::to_string(seed);
  for (FixedBody& f : scene.fixed) f.friction = spec.shelf_friction;
  const double margin = r + spec.min_gap;
  if (spec.depth < 2 * margin || spec.width < 2 * margin || spec.back_band < 0) throw std::runtime_error("the shelf is too small for one object");
  if (spec.clutter_from < 0 || spec.clutter_from > spec.depth - 2 * margin) throw std::runtime_error("the clutter starts beyond the shelf's back");
  std::mt19937_64 rng(seed);
  const auto uniform = [&](double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng); };
  std::vector<Eigen::Vector2d> centres{{uniform(std::max(x0 + margin, x1 - margin - spec.back_band), x1 - margin),
                                        uniform(-spec.width / 2 + margin, spec.width / 2 - margin)}};
  for (int attempt = 0; static_cast<int>(centres.size()) < spec.obstacles + 1; ++attempt) {
    if (attempt > 100000) {
      throw std::runtime_error("cannot place " + std::to_string(spec.obstacles) + " obstacles in the shelf (" +
                               std::to_string(centres.size() - 1) + " fitted in 100000 tries)");
    }
    const Eigen::Vector2d c(uniform(std::max(x0 + margin, x0 + spec.clutter_from), x1 - margin),
                            uniform(-spec.width / 2 + margin, spec.width / 2 - margin));
    if (std::all_of(centres.begin(), centres.end(), [&](const Eigen::Vector2d& d) { return (d - c).norm() >= 2 * r + spec.min_gap; })) {
      centres.push_back(c);
    }
  }
  for (std::size_t i = 0; i < centres.size(); ++i) {
    SceneObject o = standing_cylinder(i == 0 ? std::string("target") : obstacle_id(i), centres[i], r, spec.object_height, z0);
    o.mass = spec.mass;
    o.friction = spec.friction;
    scene.objects.push_back(o);
  }
  scene.target = 0;
  return scene;
}

Scene generate_table_scene(const TableSpec& spec, std::uint64_t seed) {
  const double z0 = spec.top_height, half = spec.size / 2;
  const Eigen::Vector2d centre(spec.distance + half, 0.0);
  Scene scene;
  scene.name = "table" + std::to_string(spec.objects) + "-seed" + std::to_string(seed);
  scene.fixed.push_back(board("table", {spec.size, spec.size, z0}, {centre.x(), 0.0, z0 / 2}));
  add_buffer_table(scene, {0.1, -0.75}, z0);
  scene.world_T_exit = at(spec.distance - 0.2, 0.0, z0 + 0.135);
  scene.world_T_robot_base = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d camera = at(-0.3, 0.0, z0 + 0.9);
  camera.linear() = (Eigen::AngleAxisd(-M_PI / 2, Eigen::Vector3d::UnitZ()) *
                     Eigen::AngleAxisd(-2.0 * M_PI / 3, Eigen::Vector3d::UnitX()))
                        .toRotationMatrix();
  scene.world_T_camera = camera;
  const double side = std::max(1.5, half + 1.0);
  scene.workspace = Eigen::AlignedBox3d(Eigen::Vector3d(-1.0, -side, 0.0), Eigen::Vector3d(centre.x() + half + 1.0, side, 2.0));

  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> radius(0.035, 0.040), tall(0.24, 0.29);
  struct Disc {
    Eigen::Vector2d centre;
    double radius, height;
  };
  std::vector<Disc> discs{{centre, radius(rng), tall(rng)}};  // the target, in the middle
  if (half < discs.front().radius + spec.min_gap) throw std::runtime_error("the table is too small for the target");
  for (int attempt = 0; static_cast<int>(discs.size()) < spec.objects; ++attempt) {
    if (attempt > 100000) throw std::runtime_error("cannot place " + std::to_string(spec.objects) + " cylinders on the table");
    const double r = radius(rng);
    const double margin = r + spec.min_gap;
    if (half < margin) throw std::runtime_error("the table is too small for one object");
    const Eigen::Vector2d c(std::uniform_real_distribution<double>(centre.x() - half + margin, centre.x() + half - margin)(rng),
                            std::uniform_real_distribution<double>(-half + margin, half - margin)(rng));
    const bool free = std::all_of(discs.begin(), discs.end(), [&](const Disc& d) {
      return (d.centre - c).norm() >= d.radius + r + spec.min_gap;
    });
    if (free) discs.push_back({c, r, tall(rng)});
  }
  for (std::size_t i = 0; i < discs.size(); ++i) {
    scene.objects.push_back(standing_cylinder(i == 0 ? std::string("target") : obstacle_id(i), discs[i].centre, discs[i].radius,
                                              discs[i].height, z0));
  }
  scene.target = 0;
  return scene;
}

namespace {

// The camera of an occlusion shelf: 0.5 m behind the robot, `eye_height` above the
// floor at z0, looking along +x.
Eigen::Isometry3d occlusion_camera(double z0, double eye_height) {
  Eigen::Isometry3d camera = at(-0.5, 0.0, z0 + eye_height);
  camera.linear() << 0, 0, 1,  // optical z looks along +x, x to the right (-y), y down (-z)
      -1, 0, 0,                //
      0, -1, 0;
  return camera;
}

Scene random_occlusion_scene(const OcclusionSpec& spec, std::uint64_t seed) {
  ShelfSpec shelf;
  shelf.objects = spec.objects;
  shelf.front = spec.front;
  shelf.floor_height = spec.floor_height;
  Scene scene = generate_shelf_scene(shelf, seed);
  scene.name = "occlusion-random" + std::to_string(spec.objects) + "-seed" + std::to_string(seed);
  scene.world_T_camera = occlusion_camera(spec.floor_height, 0.15);
  const std::vector<ObjectIndex> seen = perception::VisibilityModel(scene).observed(WorldState::initial(scene));
  const Eigen::Vector2d back(spec.front + cabinet_size(shelf).x(), 0.0);
  std::optional<ObjectIndex> hidden;
  for (ObjectIndex o = 0; o < scene.objects.size(); ++o) {
    if (std::find(seen.begin(), seen.end(), o) != seen.end()) continue;
    auto distance = [&](ObjectIndex i) { return (scene.objects[i].world_T_object.translation().head<2>() - back).norm(); };
    if (!hidden || distance(o) < distance(*hidden)) hidden = o;
  }
  if (!hidden) throw std::runtime_error("occlusion shelf: the camera sees all " + std::to_string(spec.objects) + " objects, none hides a target");
  std::swap(scene.objects[*hidden].id, scene.objects[scene.target].id);
  scene.target = *hidden;
  return scene;
}

}  // namespace

Scene generate_occlusion_scene(const OcclusionSpec& spec, std::uint64_t seed) {
  if (spec.layout == OcclusionLayout::random) return random_occlusion_scene(spec, seed);
  if (spec.columns < 1 || spec.rows < 2) throw std::runtime_error("an occlusion shelf needs at least 1 column and 2 rows");
  const double z0 = spec.floor_height;
  const double front_radius = 0.045, front_height = 0.33, eye_height = 0.15;
  const Eigen::Vector2d eye(-0.5, 0.0);
  const double x_front = spec.front + 0.02 + front_radius;
  // Each column lies on a ray from the camera, so that its objects line up behind one another.
  const double x_back = x_front + (spec.rows - 1) * spec.row_spacing;
  const double spread = (x_back - eye.x()) / (x_front - eye.x());
  const double half = (spec.columns - 1) / 2.0 * spec.column_spacing * spread + front_radius + 0.03;
  const double depth = x_back + 0.04 + 0.02 - spec.front;
  Scene scene = cabinet(spec.front, depth, 2 * half, 0.5, z0, 0.27);
  scene.name = "occlusion" + std::to_string(spec.columns * spec.rows) + "-seed" + std::to_string(seed);
  scene.world_T_camera = occlusion_camera(z0, eye_height);

  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> radius(0.033, 0.037), tall(0.24, 0.29), jitter(-0.01, 0.01);
  const int target_column = std::uniform_int_distribution<int>(0, spec.columns - 1)(rng);
  std::size_t next = 1;
  for (int c = 0; c < spec.columns; ++c) {
    const double y_front = (c - (spec.columns - 1) / 2.0) * spec.column_spacing;
    for (int r = 0; r < spec.rows; ++r) {
      const double x = x_front + r * spec.row_spacing + (r > 0 ? jitter(rng) : 0.0);
      const Eigen::Vector2d xy(x, y_front * (x - eye.x()) / (x_front - eye.x()));
      const bool is_target = c == target_column && r == spec.rows - 1;
      if (is_target) scene.target = static_cast<ObjectIndex>(scene.objects.size());
      scene.objects.push_back(standing_cylinder(is_target ? std::string("target") : obstacle_id(next++), xy,
                                                r == 0 ? front_radius : radius(rng), r == 0 ? front_height : tall(rng), z0));
    }
  }
  // The layout's promise: the camera sees the front row and nothing else.
  const std::vector<ObjectIndex> seen = perception::VisibilityModel(scene).observed(WorldState::initial(scene));
  std::vector<ObjectIndex> front_row;
  for (int c = 0; c < spec.columns; ++c) front_row.push_back(static_cast<ObjectIndex>(c * spec.rows));
  if (seen != front_row) {
    throw std::runtime_error("occlusion shelf: the camera sees " + std::to_string(seen.size()) + " objects, not just the " +
                             std::to_string(spec.columns) + " in front (spacing too wide for the view?)");
  }
  return scene;
}

}  // namespace cluttertamp::scenes
