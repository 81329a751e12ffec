// Runs of the shipped planners on generated shelves, for `generate` and the benchmarks.
#include "cluttertamp/run/shelf_runs.hpp"

#include <map>

#include "cluttertamp/collision/shared_world.hpp"
#include "cluttertamp/manipulation/actions.hpp"
#include "cluttertamp/plugin/grasp_sampler.hpp"
#include "cluttertamp/plugin/motion_sampler.hpp"
#include "cluttertamp/plugin/placement_sampler.hpp"

namespace cluttertamp::run {

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

namespace {
constexpr double kTargetCheckSeconds = 300;

// Whether `robot` retrieves the scene's target from `state`, the robot at its home.
bool retrieves(const Scene& scene, const std::shared_ptr<const robot::RobotDescription>& robot, const plugin::Samplers& samplers,
               std::uint64_t seed, WorldState state) {
  Problem problem;
  problem.scene = scene;
  problem.robot.loaded = robot;
  collision::SharedWorld world(scene, robot);
  std::map<std::string, std::uint64_t> counters;
  // The samplers' work budgets decide; the clock only bounds a run on a machine so slow
  // that it should not decide which scenes are kept.
  plugin::PlanningContext context{problem, plugin::Deadline::after(kTargetCheckSeconds), seed, counters, samplers, &world};
  state.robot_configuration = robot->home();
  return manipulation::retrieve(context, state).ok;
}
}  // namespace

bool target_comes_out_directly(const Scene& scene, const std::shared_ptr<const robot::RobotDescription>& robot,
                               const plugin::Samplers& samplers, std::uint64_t seed) {
  return retrieves(scene, robot, samplers, seed, WorldState::initial(scene));
}

TargetAccess target_access(const Scene& scene, const std::shared_ptr<const robot::RobotDescription>& robot,
                           const plugin::Samplers& samplers, std::uint64_t seed) {
  if (target_comes_out_directly(scene, robot, samplers, seed)) return TargetAccess::directly;
  WorldState emptied = WorldState::initial(scene);  // every movable object but the target taken out
  for (std::size_t i = 0; i < scene.objects.size(); ++i) {
    emptied.removed[i] = static_cast<ObjectIndex>(i) != scene.target && scene.objects[i].movable;
  }
  return retrieves(scene, robot, samplers, seed, std::move(emptied)) ? TargetAccess::after_removals : TargetAccess::never;
}

}  // namespace cluttertamp::run
