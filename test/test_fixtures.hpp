#pragma once
// Scene-building helpers for the tests that plan with the UR10 and the shipped samplers.

#include <filesystem>
#include <memory>
#include <string>

#include "cluttertamp/io/robot_description_io.hpp"
#include "cluttertamp/core/scene.hpp"
#include "cluttertamp/plugin/grasp_sampler.hpp"
#include "cluttertamp/plugin/motion_sampler.hpp"
#include "cluttertamp/plugin/placement_sampler.hpp"
#include "cluttertamp/plugin/registry.hpp"
#include "cluttertamp/robot/robot_description.hpp"
#include "test_support.hpp"

namespace cluttertamp::test {

/// The bundled UR10 with its AG-95 gripper, loaded once.
inline std::shared_ptr<const robot::RobotDescription> ur10() {
  static const auto robot = std::make_shared<const robot::RobotDescription>(
      io::load_robot_description(std::filesystem::path(CLUTTERTAMP_SOURCE_DIR) / "domains/robots/ur10_ag95.yaml"));
  return robot;
}

/// Adds a standing cylinder (0.3 kg, 26 cm tall) centred at (x, y, 0.53): on a surface
/// at z = 0.40. Returns its index.
inline ObjectIndex add_cylinder(Scene& scene, const std::string& id, double x, double y, double radius) {
  SceneObject o;
  o.id = id;
  o.shape = Cylinder{radius, 0.26};
  o.world_T_object = at(x, y, 0.53);
  o.mass = 0.3;
  scene.objects.push_back(o);
  return static_cast<ObjectIndex>(scene.objects.size() - 1);
}

/// Adds a fixed box of `size` centred at `centre` (a table, a shelf board).
inline void add_box(Scene& scene, const std::string& id, const Eigen::Vector3d& size, const Eigen::Vector3d& centre) {
  FixedBody body;
  body.id = id;
  body.shape = Box{size};
  body.world_T_body = at(centre.x(), centre.y(), centre.z());
  scene.fixed.push_back(body);
}

/// grasp_side, motion_ompl and placement_region from `registry`.
inline plugin::Samplers shipped_samplers(const plugin::Registry& registry) {
  plugin::Samplers samplers;
  samplers.set(registry.create<plugin::GraspSampler>("grasp_side"));
  samplers.set(registry.create<plugin::MotionSampler>("motion_ompl"));
  samplers.set(registry.create<plugin::PlacementSampler>("placement_region"));
  return samplers;
}

}  // namespace cluttertamp::test
