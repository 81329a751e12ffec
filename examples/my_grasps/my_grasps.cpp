// my_grasps: the smallest useful grasp sampler. One side grasp, straight from the robot
// at half the object's height; usable when the grasp configuration is collision-free,
// otherwise the answer names the objects in the way.
#include <cmath>

#include "cluttertamp/plugin/export.hpp"
#include "cluttertamp/plugin/grasp_sampler.hpp"

namespace {

using namespace cluttertamp;

class MyGrasps final : public plugin::GraspSampler {
 public:
  // Parameters come from the problem file: plugins: {grasp_sampler: {plugin: my_grasps, parameters: {...}}}
  void configure(const Parameters& parameters) override {
    // Key, default, help and the values allowed: `cluttertamp plugins -v my_grasps` lists
    // them, and a value outside the range is reported with its place in the problem file.
    height_ = parameters.get_double("height", height_, "grasp height, a fraction of the object's height",
                                    Range::open(0, 1));
  }

  plugin::GraspAnswer sample(plugin::PlanningContext& context, const plugin::GraspQuery& query) override {
    plugin::GraspAnswer answer;
    const SceneObject& object = context.scene().objects.at(query.object);
    const auto* cylinder = std::get_if<Cylinder>(&object.shape);
    // The scene and robot as they stand in the query's state: collision and IK queries.
    const std::unique_ptr<plugin::WorldView> world = context.world_at(query.state);
    if (!world || !cylinder) {
      answer.failure = Failure{"grasp", "my_grasps grasps standing cylinders with a robot", {}};
      return answer;
    }
    // The tool frame: z approaches the object horizontally from the robot, x points down.
    const Eigen::Isometry3d& world_T_object = query.state.world_T_objects.at(query.object);
    const Eigen::Vector3d towards = world_T_object.translation() - context.scene().world_T_robot_base.translation();
    const Eigen::Vector3d z = Eigen::Vector3d(towards.x(), towards.y(), 0).normalized(), x(0, 0, -1);
    plugin::Grasp grasp;
    grasp.world_T_gripper.linear() << x, z.cross(x), z;
    grasp.world_T_gripper.translation() = world_T_object.translation() + Eigen::Vector3d(0, 0, (height_ - 0.5) * cylinder->height);
    grasp.gripper_T_object = grasp.world_T_gripper.inverse() * world_T_object;
    grasp.finger_open = grasp.finger_closed = cylinder->radius;

    grasp.ik_solutions = world->inverse_kinematics(grasp.world_T_gripper, query.state.robot_configuration);
    if (grasp.ik_solutions.empty()) {
      answer.blocked.push_back({grasp, {}, "unreachable", false});
      answer.failure = Failure{"grasp", "the grasp is out of reach", {}};
      return answer;
    }
    // Everything the robot touches at the grasp, apart from the object itself.
    const ObjectIndex self[] = {query.object};
    context.count(counter::collision_checks);
    const plugin::Contacts contacts = world->contacts(grasp.ik_solutions.front(), self);
    if (contacts.valid()) {
      grasp.motions.push_back({grasp.ik_solutions.front(), grasp.ik_solutions.front(), grasp.ik_solutions.front()});
      answer.usable.push_back(grasp);
    } else {
      answer.blocked.push_back({grasp, contacts.objects, "objects in the way", !contacts.fixed && !contacts.self});
      answer.failure = Failure{"grasp", "the grasp is blocked", contacts.objects};
    }
    return answer;
  }

 private:
  double height_ = 0.5;
};

}  // namespace

// name, kind (by the macro), one-line description, version; the ABI version is added.
CLUTTERTAMP_EXPORT_GRASP_SAMPLER(MyGrasps, my_grasps, "Example: one straight-on side grasp", "0.1.0")
