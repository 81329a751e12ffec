#pragma once

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <limits>
#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "cluttertamp/core/problem.hpp"
#include "cluttertamp/core/result.hpp"
#include "cluttertamp/core/world_state.hpp"
#include "cluttertamp/export.hpp"
#include "cluttertamp/plugin/plugin.hpp"
#include "cluttertamp/plugin/world_view.hpp"

namespace cluttertamp::robot {
class RobotDescription;
}

namespace cluttertamp::plugin {

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

/// The plugins a run was configured with besides its task planner, one per kind (the
/// problem file's `plugins:` block: grasp_sampler, motion_sampler, ..., or any kind a
/// plugin declares), and the stream samplers by stream name. A kind is empty when the
/// problem file fills none; a planner that needs an empty one fails with a reason.
class CLUTTERTAMP_API Samplers {
 public:
  /// The plugin of kind KindOf<Interface>::name; null when none. Throws
  /// std::logic_error when the plugin set for that kind does not implement Interface.
  template <class Interface>
  std::shared_ptr<Interface> get() const {
    const std::shared_ptr<Plugin> plugin = get(KindOf<Interface>::name);
    if (!plugin) return nullptr;
    auto typed = std::dynamic_pointer_cast<Interface>(plugin);
    if (!typed) wrong_type(KindOf<Interface>::name);
    return typed;
  }
  /// The plugin of `kind`; null when none.
  std::shared_ptr<Plugin> get(std::string_view kind) const;
  /// Fills `kind` with `plugin` (null: empties it).
  void set(std::string_view kind, std::shared_ptr<Plugin> plugin);
  template <class Interface>
  void set(std::shared_ptr<Interface> plugin) {
    set(KindOf<Interface>::name, std::shared_ptr<Plugin>(std::move(plugin)));
  }
  /// The kinds filled, in name order.
  std::vector<std::string> kinds() const;

  std::map<std::string, std::shared_ptr<StreamSampler>> streams;  ///< by stream name

 private:
  [[noreturn]] static void wrong_type(const char* kind);
  std::map<std::string, std::shared_ptr<Plugin>, std::less<>> by_kind_;
};

/// What every plugin call sees: the problem, the run's wall-clock limit, the work a
/// sub-task may still do, the run's seed, where to count work, the other plugins it may
/// call and the geometry of the scene and robot. Owned by the caller; valid for the
/// duration of the call.
///
/// Two limits, on purpose of different kinds. `deadline` is the run's outer limit: when
/// it passes, a planner stops and reports "time limit reached", the one outcome that may
/// depend on the machine's speed. Every budget inside a run (one motion query, one try
/// of a shorter removal order, one pass of quick transfers) is work: collision checks,
/// counted on `counters[counter::collision_checks]`, so that the same seed gives the
/// same plan on any machine under any load. `checks_until` is the counter's value at
/// which the current sub-task's work budget ends (with_checks() sets it).
struct PlanningContext {
  const Problem& problem;
  Deadline deadline;
  std::uint64_t seed;  ///< derive every random generator of the call from it
  std::map<std::string, std::uint64_t>& counters;  ///< see cluttertamp::counter
  const Samplers& samplers;
  /// Views of the scene and robot at a state (see world_at); null when the problem has
  /// no robot (e.g. pure PDDL tasks).
  WorldSource* worlds = nullptr;
  /// The value of counters[counter::collision_checks] at which this sub-task's work
  /// budget ends; no budget by default.
  std::uint64_t checks_until = std::numeric_limits<std::uint64_t>::max();
  /// Where Phase adds what each phase of the run cost; null: not recorded.
  std::map<std::string, PhaseTotals>* phases = nullptr;

  const Scene& scene() const { return problem.scene; }
  /// The scene and robot at `state`, for collision and kinematics queries; null when
  /// the problem has no robot.
  std::unique_ptr<WorldView> world_at(const WorldState& state) const {
    return worlds ? worlds->at(state) : nullptr;
  }
  /// The problem's robot; precondition: problem.robot.loaded is set.
  const robot::RobotDescription& robot() const { return *problem.robot.loaded; }
  void count(const std::string& name, std::uint64_t n = 1) { counters[name] += n; }

  /// Collision checks counted so far in this run.
  std::uint64_t checks_done() const {
    const auto it = counters.find(counter::collision_checks);
    return it == counters.end() ? 0 : it->second;
  }
  /// Collision checks this sub-task may still make (a very large number without a budget).
  std::uint64_t checks_left() const {
    const std::uint64_t done = checks_done();
    return done >= checks_until ? 0 : checks_until - done;
  }
  /// The work budget is spent, or the run's time is up: stop and report.
  bool stopped() const { return deadline.expired() || checks_left() == 0; }
  /// This context with at most `checks` more collision checks (a sub-task's budget,
  /// never more than this context's own).
  PlanningContext with_checks(std::uint64_t checks) const {
    PlanningContext c = *this;
    c.checks_until = checks_done() + std::min(checks, checks_left());
    return c;
  }
  /// This context with another seed (the same limits and budget).
  PlanningContext with_seed(std::uint64_t other) const {
    PlanningContext c = *this;
    c.seed = other;
    return c;
  }
};

/// Adds one call of phase `name` with `checks` collision checks and `seconds` to
/// `context.phases` (nothing when the context records no phases).
CLUTTERTAMP_API void add_phase(const PlanningContext& context, const std::string& name, std::uint64_t checks,
                               double seconds);

/// Adds the collision checks and wall-clock time between its construction and its
/// destruction to `context.phases[name]` (nothing when the context records no phases).
/// The checks are work and reproducible; the seconds are for profiles only.
class CLUTTERTAMP_API Phase {
 public:
  Phase(const PlanningContext& context, std::string name);
  ~Phase();
  Phase(const Phase&) = delete;
  Phase& operator=(const Phase&) = delete;

 private:
  const PlanningContext& context_;
  std::string name_;
  std::uint64_t checks_at_start_;
  Deadline::Clock::time_point started_;
};

}  // namespace cluttertamp::plugin
