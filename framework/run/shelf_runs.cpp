// Runs of the shipped planners on generated shelves, for `generate` and the benchmarks.
#include "cluttertamp/run/shelf_runs.hpp"

#include <map>
#include <optional>
#include <vector>

#include "cluttertamp/collision/shared_world.hpp"
#include "cluttertamp/manipulation/actions.hpp"
#include "cluttertamp/plugin/grasp_sampler.hpp"
#include "cluttertamp/plugin/motion_sampler.hpp"
#include "cluttertamp/plugin/placement_sampler.hpp"

namespace cluttertamp::run {

namespace {
constexpr double kTargetCheckSeconds = 300;
}  // namespace

plugin::Samplers shipped_samplers(const plugin::Registry& registry) {
  plugin::Samplers samplers;
  samplers.set(registry.create<plugin::GraspSampler>("grasp_side"));
  samplers.set(registry.create<plugin::MotionSampler>("motion_ompl"));
  samplers.set(registry.create<plugin::PlacementSampler>("placement_region"));
  return samplers;
}

Result plan_scene(const Scene& scene, const std::shared_ptr<const robot::RobotDescription>& robot,
                  plugin::TaskPlanner& planner, const plugin::Samplers& samplers, std::uint64_t seed, double seconds) {
  Problem problem;
  problem.scene = scene;
  problem.robot.loaded = robot;
  problem.task = RetrievalTask{scene.objects[scene.target].id};
  collision::SharedWorld world(scene, robot);
  std::map<std::string, std::uint64_t> counters;
  plugin::PlanningContext context{problem, plugin::Deadline::after(seconds), seed, counters, samplers, &world};
  std::map<std::string, PhaseTotals> phases;
  context.phases = &phases;
  WorldState state = WorldState::initial(scene);
  state.robot_configuration = robot->home();
  Result result = planner.solve(context, state);
  // As the runner does: the work counted on the context is the run's.
  for (const auto& [key, value] : counters) result.counters[key] += value;
  result.phases = std::move(phases);
  return result;
}

bool target_comes_out_directly(const Scene& scene, const std::shared_ptr<const robot::RobotDescription>& robot,
                               const plugin::Samplers& samplers, std::uint64_t seed) {
  Problem problem;
  problem.scene = scene;
  problem.robot.loaded = robot;
  collision::SharedWorld world(scene, robot);
  std::map<std::string, std::uint64_t> counters;
  // The samplers' work budgets decide; the clock only bounds a run on a machine so slow
  // that it should not decide which scenes are kept.
  plugin::PlanningContext context{problem, plugin::Deadline::after(kTargetCheckSeconds), seed, counters, samplers, &world};
  WorldState state = WorldState::initial(scene);
  state.robot_configuration = robot->home();
  return manipulation::retrieve(context, state).ok;
}

namespace {
// `scene` with its target and its immovable objects only, supports renumbered.
Scene without_movable_obstacles(const Scene& scene) {
  Scene alone = scene;
  alone.objects.clear();
  std::vector<std::optional<ObjectIndex>> kept(scene.objects.size());
  for (std::size_t i = 0; i < scene.objects.size(); ++i) {
    if (static_cast<ObjectIndex>(i) != scene.target && scene.objects[i].movable) continue;
    kept[i] = static_cast<ObjectIndex>(alone.objects.size());
    alone.objects.push_back(scene.objects[i]);
  }
  for (SceneObject& object : alone.objects) {
    std::vector<ObjectIndex> supports;
    for (const ObjectIndex s : object.supports) {
      if (const auto index = kept[s]) supports.push_back(*index);
    }
    object.supports = std::move(supports);  // what rested on a removed object now stands where it stood
  }
  alone.target = *kept[scene.target];
  return alone;
}
}  // namespace

TargetAccess target_access(const Scene& scene, const std::shared_ptr<const robot::RobotDescription>& robot,
                           const plugin::Samplers& samplers, std::uint64_t seed) {
  if (target_comes_out_directly(scene, robot, samplers, seed)) return TargetAccess::directly;
  return target_comes_out_directly(without_movable_obstacles(scene), robot, samplers, seed) ? TargetAccess::after_removals
                                                                                           : TargetAccess::never;
}

}  // namespace cluttertamp::run
