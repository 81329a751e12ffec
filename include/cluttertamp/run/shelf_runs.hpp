#pragma once
// What `generate` and the benchmarks share: the shipped samplers,
// a planner's run on a shelf and the test that makes a generated shelf worth planning on.
#include <cstdint>
#include <memory>

#include "cluttertamp/core/result.hpp"
#include "cluttertamp/core/scene.hpp"
#include "cluttertamp/export.hpp"
#include "cluttertamp/plugin/context.hpp"
#include "cluttertamp/plugin/registry.hpp"
#include "cluttertamp/plugin/task_planner.hpp"
#include "cluttertamp/robot/robot_description.hpp"

namespace cluttertamp::run {

/// grasp_side, motion_ompl and placement_region from `registry`; throws InputError
/// (listing what was searched) when one is missing.
CLUTTERTAMP_API plugin::Samplers shipped_samplers(const plugin::Registry& registry);

/// `planner`'s run on `scene`'s retrieval task, the robot starting from its home
/// configuration, with `seed` and a time limit of `seconds`.
CLUTTERTAMP_API Result plan_scene(const Scene& scene, const std::shared_ptr<const robot::RobotDescription>& robot,
                  plugin::TaskPlanner& planner, const plugin::Samplers& samplers, std::uint64_t seed, double seconds);

/// True when `robot`, from its home configuration, retrieves the scene's target to the
/// exit pose without moving anything (the paper keeps only scenes where it cannot).
/// Decided by the samplers' work budgets, so the same on any machine; 300 s of wall-clock
/// time bound it.
CLUTTERTAMP_API bool target_comes_out_directly(const Scene& scene, const std::shared_ptr<const robot::RobotDescription>& robot,
                               const plugin::Samplers& samplers, std::uint64_t seed);

/// How `robot`, from its home configuration, gets the scene's target out.
enum class TargetAccess {
  directly,        ///< as the scene stands (target_comes_out_directly)
  after_removals,  ///< not as it stands, but from the scene emptied of every other movable object
  never,           ///< not even from the emptied scene: no removal order helps, the scene is for another robot
};

/// The scene's TargetAccess: target_comes_out_directly on the scene and, when that
/// fails, on the scene holding only the target and the objects that cannot move.
CLUTTERTAMP_API TargetAccess target_access(const Scene& scene, const std::shared_ptr<const robot::RobotDescription>& robot,
                                           const plugin::Samplers& samplers, std::uint64_t seed);

}  // namespace cluttertamp::run
