#include "cluttertamp/manipulation/placement_check.hpp"

#include <algorithm>

#include "cluttertamp/collision/shared_world.hpp"
#include "cluttertamp/robot/robot_description.hpp"

namespace cluttertamp::manipulation {

PlacementChecker::PlacementChecker(plugin::PlanningContext& context, const plugin::WorldView& world,
                                   ObjectIndex object, Eigen::VectorXd seed)
    : context_(context),
      world_(world),
      object_(object),
      seed_(std::move(seed)),
      // A mobile base stands behind the tool (IK of the whole robot can leave it in a table).
      mobile_(BasePlacement::of(context.robot())) {}

PlacementCheck PlacementChecker::check(const Eigen::Isometry3d& world_T_object,
                                       const Eigen::Isometry3d& gripper_T_object) const {
  PlacementCheck out;
  const SceneObject& object = context_.scene().objects.at(object_);
  // Lifted 1 mm off its support: it must then touch nothing at all.
  Eigen::Isometry3d lifted = world_T_object;
  lifted.translation().z() += 1e-3;
  const ObjectIndex self[] = {object_};
  out.contacts = world_.shape_contacts(object.shape, lifted, self);
  if (!out.contacts.valid()) {
    out.verdict = PlacementCheck::Verdict::touches;
    return out;
  }
  const Eigen::Isometry3d world_T_tool = world_T_object * gripper_T_object.inverse();
  // A mobile base is placed against fixed and self contacts: the world behind the view.
  const auto solutions = reach(context_.robot(), mobile_, collision::synced_world(world_),
                               collision::view_checker(world_), world_T_tool, seed_);
  if (solutions.empty()) return out;
  const std::unique_ptr<plugin::WorldView> holding = world_.holding(object_, gripper_T_object);
  for (std::size_t i = 0; i < std::min<std::size_t>(solutions.size(), 2); ++i) {
    context_.count(counter::collision_checks);
    if (holding->is_valid(solutions[i])) {
      out.verdict = PlacementCheck::Verdict::ok;
      out.configuration = solutions[i];
      return out;
    }
  }
  return out;
}

Eigen::Isometry3d PlacementChecker::facing_grip(const Scene& scene, const Eigen::Isometry3d& world_T_object) {
  const Eigen::Vector2d d = (world_T_object.translation() - scene.world_T_robot_base.translation()).head<2>().normalized();
  Eigen::Isometry3d tool = Eigen::Isometry3d::Identity();
  const Eigen::Vector3d approach(d.x(), d.y(), 0.0), x(0, 0, -1);
  tool.linear().col(0) = x;
  tool.linear().col(1) = approach.cross(x);
  tool.linear().col(2) = approach;
  tool.translation() = world_T_object.translation();
  return tool.inverse() * world_T_object;
}

}  // namespace cluttertamp::manipulation
