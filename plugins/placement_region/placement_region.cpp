// placement_region: stable placements of a standing object inside a region (a box
// volume whose bottom face is the support surface): seeded random positions and yaws,
// kept when the object fits inside the region, touches nothing there, and the robot can
// hold it there (IK for the grip, collision-free with the object held).
#include <algorithm>
#include <cmath>
#include <random>

#include "cluttertamp/manipulation/placement_check.hpp"
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
    const Eigen::VectorXd seed = query.state.robot_configuration.size() ? query.state.robot_configuration : robot.home();
    const manipulation::PlacementChecker checker(context, *world, query.object, seed);
    std::mt19937_64 rng(context.seed ^ (0xc2b2ae3d27d4eb4full * (query.object + 1)));
    std::uniform_real_distribution<double> unit(-0.5, 0.5), turn(-M_PI, M_PI);
    const double half_height = std::get_if<Cylinder>(&object.shape) ? std::get<Cylinder>(object.shape).height / 2
                               : std::get_if<Box>(&object.shape) ? std::get<Box>(object.shape).size.z() / 2
                                                                 : std::get<Sphere>(object.shape).radius;
    std::size_t blocked = 0, unreachable = 0, outside = 0;
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
      const Eigen::Isometry3d grip =
          query.gripper_T_object ? *query.gripper_T_object : manipulation::PlacementChecker::facing_grip(scene, pose);
      const manipulation::PlacementCheck checked = checker.check(pose, grip);
      if (checked.verdict != manipulation::PlacementCheck::Verdict::ok) {
        ++(checked.verdict == manipulation::PlacementCheck::Verdict::touches ? blocked : unreachable);
        continue;
      }
      answer.world_T_object.push_back(pose);
      answer.configurations.push_back(checked.configuration);
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
  std::int64_t attempts_ = 200;
  double margin_ = 0.01;
};

}  // namespace

CLUTTERTAMP_EXPORT_PLACEMENT_SAMPLER(RegionPlacements, placement_region,
                                     "Stable, collision-free, reachable placements inside a region", "1.0.0")
