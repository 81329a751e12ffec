// my_grasps: the smallest useful grasp sampler. One side grasp, straight from the robot
// at half the object's height; usable when the grasp configuration is collision-free,
// otherwise the answer names the objects in the way.
#include <cmath>

#include "cluttertamp/collision/collision_world.hpp"
#include "cluttertamp/plugin/export.hpp"
#include "cluttertamp/plugin/grasp_sampler.hpp"

namespace {

using namespace cluttertamp;

class MyGrasps final : public plugin::GraspSampler {
 public:
  // Parameters come from the problem file: plugins: {grasp_sampler: {plugin: my_grasps, parameters: {...}}}
  void configure(const Parameters& parameters) override {
    height_ = parameters.get_double("height", height_);
    parameters.require(height_ > 0 && height_ < 1, "height", "must be a fraction of the object's height in (0, 1)");
  }

  plugin::GraspAnswer sample(plugin::PlanningContext& context, const plugin::GraspQuery& query) override {
    plugin::GraspAnswer answer;
    const SceneObject& object = context.scene().objects.at(query.object);
    const auto* cylinder = std::get_if<Cylinder>(&object.shape);
    if (!context.world || !cylinder) {
      answer.failure = Failure{"grasp", "my_grasps grasps standing cylinders with a robot", {}};
      return answer;
    }
    // The tool frame: z approaches the object horizontally from the robot, x points down.
    const Eigen::Isometry3d& world_T_object = query.state->world_T_objects.at(query.object);
    const Eigen::Vector3d towards = world_T_object.translation() - context.scene().world_T_robot_base.translation();
    const Eigen::Vector3d z = Eigen::Vector3d(towards.x(), towards.y(), 0).normalized(), x(0, 0, -1);
    plugin::Grasp grasp;
    grasp.world_T_gripper.linear() << x, z.cross(x), z;
    grasp.world_T_gripper.translation() = world_T_object.translation() + Eigen::Vector3d(0, 0, (height_ - 0.5) * cylinder->height);
    grasp.gripper_T_object = grasp.world_T_gripper.inverse() * world_T_object;
    grasp.finger_open = grasp.finger_closed = cylinder->radius;

    const robot::RobotDescription& robot = context.robot();
    grasp.ik_solutions = robot.ik().solve(context.scene().world_T_robot_base.inverse() * grasp.world_T_gripper,
                                          query.state->robot_configuration);
    if (grasp.ik_solutions.empty()) {
      answer.blocked.push_back({grasp, {}, "unreachable", false});
      answer.failure = Failure{"grasp", "the grasp is out of reach", {}};
      return answer;
    }
    // Everything the robot touches at the grasp, apart from the object itself.
    context.world->sync(*query.state);
    auto checker = context.world->make_context();
    const ObjectIndex self[] = {query.object};
    const collision::CollisionReport report = context.world->check(grasp.ik_solutions.front(), *checker, self);
    if (report.valid()) {
      grasp.motions.push_back({grasp.ik_solutions.front(), grasp.ik_solutions.front(), grasp.ik_solutions.front()});
      answer.usable.push_back(grasp);
    } else {
      answer.blocked.push_back({grasp, report.objects, "objects in the way", !report.fixed && !report.self});
      answer.failure = Failure{"grasp", "the grasp is blocked", report.objects};
    }
    return answer;
  }

 private:
  double height_ = 0.5;
};

}  // namespace

// name, kind (by the macro), one-line description, version; the ABI version is added.
CLUTTERTAMP_EXPORT_GRASP_SAMPLER(MyGrasps, my_grasps, "Example: one straight-on side grasp", "0.1.0")
