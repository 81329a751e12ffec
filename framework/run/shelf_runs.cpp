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

bool target_comes_out_directly(const Scene& scene, const std::shared_ptr<const robot::RobotDescription>& robot,
                               const plugin::Samplers& samplers, std::uint64_t seed) {
  Problem problem;
  problem.scene = scene;
  problem.robot.loaded = robot;
  collision::SharedWorld world(scene, robot);
  std::map<std::string, std::uint64_t> counters;
  plugin::PlanningContext context{problem, plugin::Deadline::after(10), seed, counters, samplers, &world};
  WorldState state = WorldState::initial(scene);
  state.robot_configuration = robot->home();
  return manipulation::retrieve(context, state).ok;
}

}  // namespace cluttertamp::run
