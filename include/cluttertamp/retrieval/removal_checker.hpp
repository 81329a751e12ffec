#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "cluttertamp/collision/collision_world.hpp"
#include "cluttertamp/core/result.hpp"
#include "cluttertamp/core/world_state.hpp"
#include "cluttertamp/export.hpp"
#include "cluttertamp/plugin/context.hpp"

namespace cluttertamp::retrieval {

/// How a removal sequence fared with the robot.
struct RemovalCheck {
  bool ok = false;  ///< every object removed (and the target retrieved, when asked)
  /// The objects of the sequence removed before the failure (all of them when ok).
  std::size_t removed = 0;
  /// The object that could not be removed, or the target when only retrieving failed.
  std::optional<ObjectIndex> failed_object;
  std::optional<Failure> failure;  ///< why, with the objects in the robot's way
  WorldState state;  ///< the world after the removals that worked
};

/// The feasibility check of a retrieval planner (Tian et al., Section IV-D): removes a
/// sequence of objects with the robot — pick, then place in the buffer region or, when
/// nothing there fits, carry it out of the workspace (the paper's assumption 4) — and
/// retrieves the target, always from the initial world: a sequence that fails is
/// planning, not execution, and leaves nothing moved. Actions are remembered by
/// the prefix they follow, so sequences that share a prefix plan it once.
///
/// The time spent in the actions is the planner's motion-planning time. Uses the
/// context's grasp, placement and motion samplers; `context` and `initial` must outlive
/// the checker.
class CLUTTERTAMP_API RemovalChecker {
 public:
  RemovalChecker(plugin::PlanningContext& context, const WorldState& initial, std::string placement_region);

  /// Removes `order` from the initial world, in order. `salt` varies the samplers'
  /// seed (0: the context's seed), for a fresh draw after an attempt that taught nothing.
  RemovalCheck remove(std::span<const ObjectIndex> order, std::uint64_t salt = 0);

  /// remove(order), then the target out to the exit pose.
  RemovalCheck retrieve(std::span<const ObjectIndex> order, std::uint64_t salt = 0);
  /// Where the target may travel, given the world after the removals: its footprint's
  /// free way in the plane from where it stands to x_s (see manipulation::retrieve), or
  /// empty for none known.
  using WayOut = std::function<std::vector<Eigen::Vector2d>(const WorldState& after_removals)>;
  /// The carry of every later retrieval first follows `way_out`'s way (a retrieval
  /// planner's roadmap knows one); without it the carry is planned.
  void set_way_out(WayOut way_out) { way_out_ = std::move(way_out); }

  /// The plan of a successful retrieve(order, salt): pick and place steps with their
  /// trajectories, then the retrieval; moved objects in order, target last; and a
  /// note in `failures` for each object carried out of the workspace.
  /// Precondition: retrieve(order, salt) returned ok.
  void write_plan(std::span<const ObjectIndex> order, std::uint64_t salt, Result& result) const;
  /// The pick and place steps of a successful remove(order, salt), without the target's.
  void write_steps(std::span<const ObjectIndex> order, std::uint64_t salt, Result& result) const;

  /// Of `restored` (objects gone from, or standing elsewhere in, the initial world), those
  /// the robot or the object it holds would touch on the motions of remove(order, salt)
  /// — and of the target's retrieval after it when `with_target` — had each stood at its
  /// pose in `where`: the objects this plan needed moved before it. Configurations are
  /// checked every 0.01 rad; the object being moved is never counted. Sorted.
  /// Precondition: remove(order, salt) (retrieve, when `with_target`) returned ok.
  std::vector<ObjectIndex> met_by_plan(std::span<const ObjectIndex> order, std::uint64_t salt, bool with_target,
                                       std::span<const ObjectIndex> restored, const WorldState& where) const;

  double motion_seconds() const { return motion_seconds_; }  ///< spent planning actions, s

  /// Fills `result.time` — motion planning: motion_seconds(); task planning: the rest
  /// of the time since `start` — and the `actions_planned` counter.
  void record_times(Result& result, std::chrono::steady_clock::time_point start) const;
  std::uint64_t actions_planned() const { return actions_planned_; }  ///< cache misses

 private:
  struct Motion {  // a stretch of a step's motions with one held object (or none)
    WorldState start;  // the held object's grip follows from its pose at start.robot_configuration
    Trajectory trajectory;
  };
  struct Step {  // removing one object after a prefix
    bool ok = false;
    std::optional<Failure> failure;
    WorldState after;
    std::vector<PlanStep> steps;
    std::vector<Motion> motions;  // the steps' trajectories, split where the hand takes or lets go
    std::optional<Failure> note;  // carried out of the workspace
  };
  using Key = std::pair<std::vector<ObjectIndex>, std::uint64_t>;

  const Step& step(std::span<const ObjectIndex> prefix, ObjectIndex object, std::uint64_t salt);
  plugin::PlanningContext attempt(std::uint64_t salt) const;

  plugin::PlanningContext& context_;
  WorldState initial_;
  std::string region_;
  std::map<Key, Step> steps_;  // key: the prefix then the object removed after it
  WayOut way_out_;
  double motion_seconds_ = 0.0;
  std::uint64_t actions_planned_ = 0;
};

/// What write_plan_with_pushes did.
struct PushReplacement {
  std::uint64_t pushes = 0;         ///< pick-and-place actions replaced by a push
  std::uint64_t pushes_tried = 0;   ///< push sampler queries
  double seconds = 0.0;             ///< spent pushing and re-checking, s
};

/// Tian et al., Section VI-G: the plan of a removal order that `checker` retrieved, with each object pushed instead of picked and placed where a
/// push works. In order, each object is tried at up to three spots 8-16 cm away on its
/// support, clear of the other objects and of the target's way out (the disc of
/// held_footprint along the straight line to x_s), with the context's push sampler,
/// the gripper coming from x_s facing into the shelf. A push counts when it moves no
/// other object more than 1 cm and the rest of the order and the target's retrieval
/// still work from the state it leaves (checked, so the later actions are planned
/// around the pushed object). The push step is the planar gripper's (see push_ompl);
/// the arm following it is not checked. Without a push sampler, or once the deadline
/// has passed, the plan is checker.write_plan's. Precondition: checker.retrieve(order,
/// salt) returned ok.
CLUTTERTAMP_API PushReplacement write_plan_with_pushes(plugin::PlanningContext& context, RemovalChecker& checker,
                                                       std::span<const ObjectIndex> order,
                                                       const std::string& placement_region, std::uint64_t salt,
                                                       Result& result);

/// The disc `object` sweeps in the shelf plane while the gripper holds it (radius r_b
/// of Tian et al., Appendix B) and the height band it occupies at its pose in `state`.
CLUTTERTAMP_API collision::Footprint held_footprint(const plugin::PlanningContext& context, const WorldState& state,
                                                    ObjectIndex object);

/// Appends `failure` to `result.failures` unless an equal one (stage, reason, blocking
/// objects) is there: checks repeat as planners retry.
CLUTTERTAMP_API void record_failure_once(Result& result, const Failure& failure);

/// The plugin kinds a retrieval planner cannot plan without: grasp_sampler,
/// motion_sampler and placement_sampler (TaskPlanner::required_kinds).
CLUTTERTAMP_API std::vector<std::string> retrieval_sampler_kinds();

/// Why a retrieval planner named `planner` cannot run in `context` (no robot, not a
/// retrieve task, a sampler missing), or nothing.
CLUTTERTAMP_API std::optional<std::string> retrieval_inputs_missing(const plugin::PlanningContext& context,
                                                                    const std::string& planner);

}  // namespace cluttertamp::retrieval
