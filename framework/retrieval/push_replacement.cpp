// Tian et al., Section VI-G: pushes in place of pick-and-place in a retrieval plan.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>

#include "cluttertamp/core/geometry.hpp"
#include "cluttertamp/physics/push_world.hpp"
#include "cluttertamp/plugin/push_sampler.hpp"
#include "cluttertamp/retrieval/removal_checker.hpp"

namespace cluttertamp::retrieval {

namespace {

constexpr int kSpots = 3;          // pushes tried per object
constexpr double kGap = 0.01;      // m between a spot's object and the others, or the way out
constexpr double kRadius = 0.03;   // m: a push ends with the object's centre this near its spot
// At most, per push query, physics propagations (about 2 s on our machine): a push is an
// improvement, not worth a long search.
constexpr std::uint64_t kPushPropagations = 2500;

// Spots 8-16 cm from `object` (every 30 degrees), nearest first: on its support, clear
// of every other present object and of the target's way out to x_s.
std::vector<Eigen::Vector2d> push_spots(const plugin::PlanningContext& context, const WorldState& state,
                                        ObjectIndex object) {
  const Scene& scene = context.scene();
  const auto radius = [&](ObjectIndex i) { return footprint_radius(scene.objects[i].shape, state.world_T_objects[i]); };
  const double r = radius(object);
  const Eigen::Vector2d here = state.world_T_objects[object].translation().head<2>();
  const Eigen::Vector2d target = state.world_T_objects[scene.target].translation().head<2>();
  const Eigen::Vector2d exit = scene.world_T_exit.translation().head<2>();
  const double way = held_footprint(context, state, scene.target).radius;
  Eigen::AlignedBox2d support = physics::support_region(scene, state);
  support.min().array() += r;
  support.max().array() -= r;
  std::vector<Eigen::Vector2d> spots;
  for (const double distance : {0.08, 0.12, 0.16}) {
    for (int k = 0; k < 12; ++k) {
      const double angle = k * M_PI / 6;
      const Eigen::Vector2d spot = here + distance * Eigen::Vector2d(std::cos(angle), std::sin(angle));
      if (!support.contains(spot) || distance_to_segment(spot, target, exit) < way + r + kGap) continue;
      bool clear = true;
      for (ObjectIndex j = 0; j < scene.objects.size() && clear; ++j) {
        if (j == object || state.removed[j]) continue;
        const double rj = radius(j);
        clear = (state.world_T_objects[j].translation().head<2>() - spot).norm() > r + rj + kGap;
      }
      if (clear) spots.push_back(spot);
    }
  }
  return spots;
}

}  // namespace

PushReplacement write_plan_with_pushes(plugin::PlanningContext& context, RemovalChecker& checker,
                                       std::span<const ObjectIndex> order,
                                       const std::string& placement_region, std::uint64_t salt, Result& result) {
  PushReplacement done;
  const auto start = std::chrono::steady_clock::now();  // for done.seconds only
  const Scene& scene = context.scene();
  const Eigen::Vector3d from_exit =
      physics::PushWorld(scene, WorldState::initial(scene), physics::push_settings(context.problem)).start_pose();
  std::vector<std::unique_ptr<RemovalChecker>> owned;
  RemovalChecker* current = &checker;   // rooted where the last push left the world (or at checker's)
  std::vector<ObjectIndex> picked;      // objects picked and placed since `current`'s root
  for (std::size_t i = 0; i < order.size(); ++i) {
    const ObjectIndex object = order[i];
    const std::vector<ObjectIndex> rest(order.begin() + static_cast<std::ptrdiff_t>(i) + 1, order.end());
    bool pushed = false;
    if (context.samplers.get<plugin::PushSampler>() && !context.deadline.expired()) {
      const WorldState before = current->remove(picked, salt).state;  // planned already: cached
      int tries = 0;
      for (const Eigen::Vector2d& spot : push_spots(context, before, object)) {
        if (tries++ == kSpots || context.deadline.expired()) break;
        ++done.pushes_tried;
        const plugin::PushAnswer answer =
            context.samplers.get<plugin::PushSampler>()->push(context, {object, spot, kRadius, before, from_exit, kPushPropagations});
        if (!answer.step || answer.step->objects != std::vector<ObjectIndex>{object}) continue;
        auto next = std::make_unique<RemovalChecker>(context, *answer.resulting_state, placement_region);
        if (!next->retrieve(rest, salt).ok) continue;
        current->write_steps(picked, salt, result);
        result.plan.push_back(*answer.step);
        result.moved_objects.push_back(object);
        current = next.get();
        owned.push_back(std::move(next));
        picked.clear();
        pushed = true;
        ++done.pushes;
        break;
      }
    }
    if (!pushed) picked.push_back(object);
  }
  current->write_plan(picked, salt, result);
  done.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return done;
}

}  // namespace cluttertamp::retrieval
