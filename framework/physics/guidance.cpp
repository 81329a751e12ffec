#include "cluttertamp/physics/guidance.hpp"

#include <algorithm>

#include "cluttertamp/core/geometry.hpp"
#include <limits>
#include <optional>

namespace cluttertamp::physics {


Guidance generate_guidance(const PushWorld& world, const PushState& state, const Eigen::Vector2d& from, int max_guides,
                           double diameter) {
  const Scene& scene = world.scene();
  const Eigen::Vector2d target = state.objects.at(scene.target).pose.head<2>();
  const double lane = world.settings().gripper_size.y() / 2 + 0.02;  // half the way's width, m
  constexpr double kClear = 0.01;     // m between a pushed object and the way
  constexpr double kCrossing = 0.15;  // m of push length an object in the way costs
  const Eigen::Vector2d along = (target - from).normalized();
  const Eigen::Vector2d normal(-along.y(), along.x());
  // The way ends where the gripper's centre stops, its face at the target.
  const Eigen::Vector2d end = target - (world.settings().gripper_size.x() / 2 + world.footprint_radius(scene.target)) * along;

  std::vector<std::pair<double, ObjectIndex>> blockers;  // distance along the way, object
  for (ObjectIndex i : world.pushable()) {
    const Eigen::Vector2d p = state.objects[i].pose.head<2>();
    if (i == scene.target || distance_to_segment(p, from, end) > lane + world.footprint_radius(i)) continue;
    blockers.emplace_back((p - from).dot(along), i);
  }
  std::sort(blockers.begin(), blockers.end());

  const Eigen::AlignedBox2d& shelf = world.support_region();
  std::vector<Eigen::Vector2d> at(state.objects.size());  // where each object is, once earlier guides hold
  for (std::size_t i = 0; i < at.size(); ++i) at[i] = state.objects[i].pose.head<2>();
  Guidance guidance;
  for (const auto& [distance, object] : blockers) {
    if (static_cast<int>(guidance.size()) >= max_guides) break;
    const double r = world.footprint_radius(object);
    const Eigen::Vector2d here = at[object];
    const double side = (here - from).dot(normal);  // signed distance from the way's centre line
    const double inset = std::max(r, diameter / 2);
    std::optional<Eigen::Vector2d> best;
    double best_cost = std::numeric_limits<double>::infinity();
    for (const double s : {1.0, -1.0}) {
      // Its centre clears the way by kClear; anywhere in its region (a person's guide
      // is as loose) it may still reach into the way by up to diameter / 2: pushing
      // further, to the walls, failed more often than the overlap hindered.
      const Eigen::Vector2d spot = here + (s * (lane + r + kClear) - side) * normal;
      if (spot.x() < shelf.min().x() + inset || spot.x() > shelf.max().x() - inset ||
          spot.y() < shelf.min().y() + inset || spot.y() > shelf.max().y() - inset) {
        continue;
      }
      double cost = (spot - here).norm();
      for (ObjectIndex j : world.pushable()) {
        if (j != object && distance_to_segment(at[j], here, spot) < r + world.footprint_radius(j)) cost += kCrossing;
      }
      if (cost < best_cost) {
        best = spot;
        best_cost = cost;
      }
    }
    if (!best) continue;
    guidance.push_back(Guide{object, *best, diameter, {}});
    at[object] = *best;
  }
  return guidance;
}

}  // namespace cluttertamp::physics
