#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "cluttertamp/io/scene_io.hpp"
#include "cluttertamp/io/text_file.hpp"

namespace cluttertamp::io {

namespace {

std::string num(double v) {
  if (std::abs(v) < 1e-12) v = 0.0;  // no "-0" or 1e-17 noise in files people read
  char text[32];
  std::snprintf(text, sizeof text, "%.10g", v);
  return text;
}

std::string vec(const Eigen::Vector3d& v) {
  std::string text = "[";  // appended: g++ 12 warns falsely (-Wrestrict) on "[" + std::string
  text += num(v.x());
  text += ", ";
  text += num(v.y());
  text += ", ";
  text += num(v.z());
  return text + "]";
}

std::string pose(const Eigen::Isometry3d& p) {
  const Eigen::Matrix3d& R = p.linear();
  // R = Rz(yaw) Ry(pitch) Rx(roll), the convention the reader uses.
  const double pitch = std::asin(std::clamp(-R(2, 0), -1.0, 1.0));
  const double roll = std::atan2(R(2, 1), R(2, 2));
  const double yaw = std::atan2(R(1, 0), R(0, 0));
  std::string out = "{xyz: " + vec(p.translation());
  if (std::abs(roll) > 1e-12 || std::abs(pitch) > 1e-12 || std::abs(yaw) > 1e-12) {
    out += ", rpy: " + vec({roll, pitch, yaw});
  }
  return out + "}";
}

std::string shape(const Shape& s) {
  if (const auto* box = std::get_if<Box>(&s)) return "box: {size: " + vec(box->size) + "}";
  if (const auto* sphere = std::get_if<Sphere>(&s)) return "sphere: {radius: " + num(sphere->radius) + "}";
  const auto& c = std::get<Cylinder>(s);
  return "cylinder: {radius: " + num(c.radius) + ", height: " + num(c.height) + "}";
}

}  // namespace

std::string scene_to_yaml(const Scene& scene) {
  std::ostringstream out;
  out << "# Format: cluttertamp docs/file-formats.md, \"Scene files\". World frame z up; metres, radians.\n"
      << "version: 1\n"
      << "name: " << scene.name << "\n"
      << "workspace: {min: " << vec(scene.workspace.min()) << ", max: " << vec(scene.workspace.max()) << "}\n"
      << "robot_base: " << pose(scene.world_T_robot_base) << "\n"
      << "exit: " << pose(scene.world_T_exit) << "\n";
  if (scene.world_T_camera) out << "camera: " << pose(*scene.world_T_camera) << "\n";
  if (!scene.fixed.empty()) {
    out << "fixed:\n";
    for (const FixedBody& f : scene.fixed) {
      out << "  - {id: " << f.id << ", " << shape(f.shape) << ", pose: " << pose(f.world_T_body);
      if (f.friction != FixedBody{}.friction) out << ", friction: " << num(f.friction);
      out << "}\n";
    }
  }
  if (!scene.regions.empty()) {
    out << "regions:\n";
    for (const Region& r : scene.regions) {
      out << "  - {id: " << r.id << ", size: " << vec(r.size) << ", pose: " << pose(r.world_T_region) << "}\n";
    }
  }
  out << "objects:\n";
  for (std::size_t i = 0; i < scene.objects.size(); ++i) {
    const SceneObject& o = scene.objects[i];
    out << "  - {id: " << o.id << ", " << shape(o.shape) << ", pose: " << pose(o.world_T_object)
        << ", mass: " << num(o.mass) << ", friction: " << num(o.friction);
    if (!o.movable) out << ", movable: false";
    if (i == scene.target) out << ", target: true";
    if (!o.supports.empty()) {
      out << ", on: [";
      for (std::size_t k = 0; k < o.supports.size(); ++k) out << (k ? ", " : "") << scene.objects[o.supports[k]].id;
      out << "]";
    }
    out << "}\n";
  }
  return out.str();
}

void write_scene(const std::filesystem::path& file, const Scene& scene) {
  write_text_file(file, scene_to_yaml(scene), "scene file");
}

}  // namespace cluttertamp::io
