// placement_region: stable placements of a standing object inside a region (a box
// volume whose bottom face is the support surface): seeded random positions and yaws,
// kept when the object fits inside the region, touches nothing there, and the robot can
// hold it there (IK for the grip, collision-free with the object held).
#include <algorithm>
#include <cmath>
#include <random>

#include "cluttertamp/collision/shared_world.hpp"
#include "cluttertamp/manipulation/base_placement.hpp"
#include "cluttertamp/plugin/export.hpp"
#include "cluttertamp/plugin/placement_sampler.hpp"

namespace {

using namespace cluttertamp;

class RegionPlacements final : public plugin::PlacementSampler {
 public:
  void configure(const Parameters& p) override {
    attempts_ = p.get_int("attempts", attempts_, "candidate poses tried per query", Range::closed(1, 100000));
    margin_ = p.get_double("margin", margin_, "m kept from the region's sides", Range::closed_open(0, 0.1));
  }

  plugin::PlacementAnswer sample(plugin::PlanningContext& context, const plugin::PlacementQuery& query) override {
    plugin::PlacementAnswer answer;
    const Scene& scene = context.scene();
    const Region* region = scene.find_region(query.region);
    const SceneObject& object = scene.objects.at(query.object);
    if (!region) {
      answer.failure = Failure{"placement", "the scene has no region '" + query.region + "'", {}};
      return answer;
    }
    // The world as the query has it, the held object standing where the state has it.
    WorldState empty_handed = query.state;
    empty_handed.held.reset();
    const std::unique_ptr<plugin::WorldView> world = context.world_at(empty_handed);
    if (!world) {
      answer.failure = Failure{"placement", "the problem has no robot", {}};
      return answer;
    }
    const robot::RobotDescription& robot = context.robot();
    // A mobile base stands behind the tool (IK of the whole robot can leave it in a table).
    const auto mobile = manipulation::BasePlacement::of(robot);
    std::mt19937_64 rng(context.seed ^ (0xc2b2ae3d27d4eb4full * (query.object + 1)));
    std::uniform_real_distribution<double> unit(-0.5, 0.5), turn(-M_PI, M_PI);
    const double half_height = std::get_if<Cylinder>(&object.shape) ? std::get<Cylinder>(object.shape).height / 2
                               : std::get_if<Box>(&object.shape) ? std::get<Box>(object.shape).size.z() / 2
                                                                 : std::get<Sphere>(object.shape).radius;
    std::size_t blocked = 0, unreachable = 0, outside = 0;
    const ObjectIndex self[] = {query.object};
    for (std::int64_t attempt = 0; attempt < attempts_ && answer.world_T_object.size() < query.max_placements; ++attempt) {
      if (context.deadline.expired()) break;
      context.count(counter::samples);
      Eigen::Isometry3d local = Eigen::Isometry3d::Identity();
      local.translation() << unit(rng) * region->size.x(), unit(rng) * region->size.y(), -region->size.z() / 2 + half_height;
      if (std::holds_alternative<Box>(object.shape)) local.linear() = Eigen::AngleAxisd(turn(rng), Eigen::Vector3d::UnitZ()).toRotationMatrix();
      const Eigen::Isometry3d pose = region->world_T_region * local;
      // Inside the region, with a margin, in the region's frame.
      const Eigen::AlignedBox3d bounds = world_bounds(object.shape, local);
      const Eigen::Vector3d half = region->size / 2;
      if ((bounds.min().array() < -half.array() + Eigen::Array3d(margin_, margin_, -1e-9)).any() ||
          (bounds.max().array() > half.array() - Eigen::Array3d(margin_, margin_, -1e-9)).any()) {
        ++outside;
        continue;
      }
      // Lifted 1 mm off its support: it must then touch nothing at all.
      Eigen::Isometry3d lifted = pose;
      lifted.translation().z() += 1e-3;
      const plugin::Contacts contacts = world->shape_contacts(object.shape, lifted, self);
      if (!contacts.valid()) {
        ++blocked;
        continue;
      }
      const Eigen::Isometry3d grip = query.gripper_T_object ? *query.gripper_T_object : facing_grip(scene, pose);
      const auto configuration = reachable(context, *world, robot, mobile, pose, grip, query);
      if (!configuration) {
        ++unreachable;
        continue;
      }
      answer.world_T_object.push_back(pose);
      answer.configurations.push_back(*configuration);
    }
    if (answer.world_T_object.empty()) {
      answer.failure = Failure{"placement", "no placement of '" + object.id + "' in '" + region->id + "': " +
                                                std::to_string(blocked) + " candidates touched something, " +
                                                std::to_string(unreachable) + " were out of reach, " +
                                                std::to_string(outside) + " did not fit",
                               {}};
    }
    return answer;
  }

 private:
  // A side grip facing the robot, at the object's centre: the tool frame in the object's frame.
  static Eigen::Isometry3d facing_grip(const Scene& scene, const Eigen::Isometry3d& world_T_object) {
    const Eigen::Vector2d d = (world_T_object.translation() - scene.world_T_robot_base.translation()).head<2>().normalized();
    Eigen::Isometry3d tool = Eigen::Isometry3d::Identity();
    const Eigen::Vector3d approach(d.x(), d.y(), 0.0), x(0, 0, -1);
    tool.linear().col(0) = x;
    tool.linear().col(1) = approach.cross(x);
    tool.linear().col(2) = approach;
    tool.translation() = world_T_object.translation();
    return tool.inverse() * world_T_object;
  }

  std::optional<Eigen::VectorXd> reachable(plugin::PlanningContext& context, const plugin::WorldView& world,
                                           const robot::RobotDescription& robot,
                                           const std::optional<manipulation::BasePlacement>& mobile,
                                           const Eigen::Isometry3d& world_T_object, const Eigen::Isometry3d& gripper_T_object,
                                           const plugin::PlacementQuery& query) const {
    const Eigen::Isometry3d world_T_tool = world_T_object * gripper_T_object.inverse();
    const Eigen::VectorXd seed = query.state.robot_configuration.size() ? query.state.robot_configuration : robot.home();
    // A mobile base is placed against fixed and self contacts: the world behind the view.
    const auto solutions = manipulation::reach(robot, mobile, collision::synced_world(world),
                                               collision::view_checker(world), world_T_tool, seed);
    if (solutions.empty()) return std::nullopt;
    const std::unique_ptr<plugin::WorldView> holding = world.holding(query.object, gripper_T_object);
    std::optional<Eigen::VectorXd> found;
    for (std::size_t i = 0; i < std::min<std::size_t>(solutions.size(), 2) && !found; ++i) {
      context.count(counter::collision_checks);
      if (holding->is_valid(solutions[i])) found = solutions[i];
    }
    return found;
  }

  std::int64_t attempts_ = 200;
  double margin_ = 0.01;
};

}  // namespace

CLUTTERTAMP_EXPORT_PLACEMENT_SAMPLER(RegionPlacements, placement_region,
                                     "Stable, collision-free, reachable placements inside a region", "1.0.0")
