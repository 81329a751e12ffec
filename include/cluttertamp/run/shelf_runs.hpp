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
/// Uses at most 10 s.
CLUTTERTAMP_API bool target_comes_out_directly(const Scene& scene, const std::shared_ptr<const robot::RobotDescription>& robot,
                               const plugin::Samplers& samplers, std::uint64_t seed);

}  // namespace cluttertamp::run
