#pragma once

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <map>
#include <memory>
#include <string>

#include "cluttertamp/core/problem.hpp"
#include "cluttertamp/core/world_state.hpp"
#include "cluttertamp/export.hpp"

namespace cluttertamp::collision {
class CollisionWorld;
}
namespace cluttertamp::robot {
class RobotDescription;
}

namespace cluttertamp::plugin {

class GraspSampler;
class PlacementSampler;
class MotionSampler;
class PushSampler;
class ObjectPruner;
class StreamSampler;

/// A point in wall-clock time after which a planner must stop and report.
class CLUTTERTAMP_API Deadline {
 public:
  using Clock = std::chrono::steady_clock;

  /// `seconds` from now; a non-finite or negative value means no limit.
  static Deadline after(double seconds);
  static Deadline never();

  bool expired() const;
  /// Seconds left (0 when expired; a very large number without a limit).
  double remaining() const;

 private:
  explicit Deadline(Clock::time_point at) : at_(at) {}
  Clock::time_point at_;
};

/// The sampler plugins a run was configured with; a role is null when the problem
/// file fills none. A planner that needs an empty role fails with a reason.
struct Samplers {
  std::shared_ptr<GraspSampler> grasp;
  std::shared_ptr<PlacementSampler> placement;
  std::shared_ptr<MotionSampler> motion;
  std::shared_ptr<PushSampler> push;
  std::shared_ptr<ObjectPruner> object_pruner;
  std::map<std::string, std::shared_ptr<StreamSampler>> streams;  ///< by stream name
};

/// What every plugin call sees: the problem, the time it has, the run's seed, where
/// to count work, the other plugins it may call and the geometry of the scene and
/// robot. Owned by the caller; valid for the duration of the call.
struct PlanningContext {
  const Problem& problem;
  Deadline deadline;
  std::uint64_t seed;  ///< derive every random generator of the call from it
  std::map<std::string, std::uint64_t>& counters;  ///< see cluttertamp::counter
  const Samplers& samplers;
  /// The scene and robot over FCL, shared by every plugin of the run. A sampler syncs
  /// it to its query's WorldState before checking (CollisionWorld::sync) and may leave
  /// it in any state. Null when the problem has no robot (e.g. pure PDDL tasks).
  collision::CollisionWorld* world = nullptr;

  const Scene& scene() const { return problem.scene; }
  /// The problem's robot; precondition: problem.robot.loaded is set.
  const robot::RobotDescription& robot() const { return *problem.robot.loaded; }
  void count(const std::string& name, std::uint64_t n = 1) { counters[name] += n; }
  /// This context with its deadline at most `seconds` from now (a sub-task's budget).
  PlanningContext within(double seconds) const {
    return {problem, Deadline::after(std::min(seconds, deadline.remaining())), seed, counters, samplers, world};
  }
};

}  // namespace cluttertamp::plugin
