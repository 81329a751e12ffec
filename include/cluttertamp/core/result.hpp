#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "cluttertamp/core/scene.hpp"
#include "cluttertamp/export.hpp"

namespace cluttertamp {

/// A joint-space path with a time for each waypoint (seconds from the step's start).
struct Trajectory {
  std::vector<std::string> joint_names;
  std::vector<double> times;
  std::vector<Eigen::VectorXd> positions;  ///< one per time, in joint_names order
  /// The objects the step moves without holding them (a push), each with its planar
  /// pose (x, y, yaw; m, m, rad; world frame) at every time: enough to draw the step
  /// without its physics.
  std::map<ObjectIndex, std::vector<Eigen::Vector3d>> object_paths;
};

/// Why something could not be done, and which movable objects were in the way.
/// The blocking objects are the robot-obstacle collision feedback the retrieval
/// graph consumes (Tian et al., Section IV-D).
struct Failure {
  std::string stage;   ///< who failed: "grasp", "motion", "task_planner", ...
  std::string reason;  ///< a sentence a person can act on
  std::vector<ObjectIndex> blocking_objects;
};

/// One step of a plan: an action, the objects it involves and its continuous values
/// (poses as [x y z qx qy qz qw], configurations, grasps).
struct PlanStep {
  std::string action;
  /// The step's symbolic arguments in order, as the task planner names them (a PDDL
  /// action's objects and stream values, e.g. "o1", "#g0"); empty when it has none.
  std::vector<std::string> arguments;
  std::vector<ObjectIndex> objects;
  std::map<std::string, std::vector<double>> values;
  std::optional<Trajectory> trajectory;
};

/// A planner's picture of its search for a person to look at, drawn top-down by the
/// plan viewer: points in the world's x-y plane (m) joined by edges, e.g. a roadmap or
/// a retrieval graph.
struct PlaneDrawing {
  std::string name;
  std::vector<Eigen::Vector2d> nodes;
  std::vector<std::string> labels;        ///< one per node, or none
  std::vector<std::pair<int, int>> edges;  ///< indices into nodes
  std::vector<int> path;                   ///< the nodes of the way the planner chose, in order
};

/// Wall-clock seconds spent in each part of a run.
struct Timing {
  double task_planning = 0.0;
  double motion_planning = 0.0;
  double total = 0.0;
};

/// The work and time of one phase of planning (a kind of motion, the task search, ...),
/// summed over its calls: where a run's effort went, without a profiler.
struct PhaseTotals {
  std::uint64_t calls = 0;
  std::uint64_t collision_checks = 0;  ///< counted inside the phase, nested phases included
  double seconds = 0.0;                ///< wall-clock, nested phases included
};

/// The names of the counters in Result::counters and result.json, one constant each,
/// so that producers and readers cannot disagree on a spelling. Every planner fills
/// the first three; the others belong to the planners that name them. A plugin may add
/// its own.
namespace counter {
inline constexpr const char* samples = "samples";  ///< candidate grasps, placements and other samples drawn
inline constexpr const char* collision_checks = "collision_checks";  ///< collision checks made: the unit of every work budget
inline constexpr const char* motion_planning_calls = "motion_planning_calls";  ///< queries to the motion sampler
inline constexpr const char* iterations = "iterations";  ///< rounds of the task planner's main loop (retrieval_graph: roadmap expansions; occlusion: goals tried)
inline constexpr const char* planning_sequences = "planning_sequences";  ///< removal sequences planned on the retrieval graph
inline constexpr const char* restarts = "restarts";  ///< times the retrieval search started again from a larger roadmap
inline constexpr const char* exploration_limit = "exploration_limit";  ///< the roadmap's exploration limit when the search stopped
inline constexpr const char* roadmap_nodes = "roadmap_nodes";  ///< nodes of the roadmap
inline constexpr const char* feedback_nodes = "feedback_nodes";  ///< nodes added to the roadmap where a motion failed (feedback)
inline constexpr const char* removals_dropped = "removals_dropped";  ///< removals the shortener found unnecessary
inline constexpr const char* grasp_orders_taken = "grasp_orders_taken";  ///< 1 when another grasp order replaced the planned one
inline constexpr const char* pushes = "pushes";  ///< pushes made instead of pick-and-place removals
inline constexpr const char* pushes_tried = "pushes_tried";  ///< pushes attempted
inline constexpr const char* actions_planned = "actions_planned";  ///< pick, place and carry actions planned with robot motions
inline constexpr const char* removal_sets_checked = "removal_sets_checked";  ///< sets of objects to remove that the exhaustive planner checked
inline constexpr const char* checks_without_motion = "checks_without_motion";  ///< removal sets accepted at the task level without motions
inline constexpr const char* traversability_edges = "traversability_edges";  ///< edges of the traversability graph
inline constexpr const char* extra_expansions = "extra_expansions";  ///< roadmap expansions beyond the first to reach a goal (occlusion)
inline constexpr const char* retrievals_without_a_way = "retrievals_without_a_way";  ///< times no way to the target was found (occlusion)
inline constexpr const char* temporary_goals_given_up = "temporary_goals_given_up";  ///< temporary goals abandoned as unreachable (occlusion)
inline constexpr const char* removal_attempts = "removal_attempts";  ///< objects the occlusion planner tried to remove
inline constexpr const char* revealed = "revealed";  ///< objects seen after a removal uncovered them (occlusion)
inline constexpr const char* observed_initially = "observed_initially";  ///< objects seen at the start (occlusion)
inline constexpr const char* observed = "observed";  ///< objects known at the end (occlusion)
inline constexpr const char* found_by_touch = "found_by_touch";  ///< hidden objects found by touching them (occlusion)
inline constexpr const char* final_sequence = "final_sequence";  ///< length of the final removal sequence (occlusion)
inline constexpr const char* propagations = "propagations";  ///< physics propagations of the pushing planners
inline constexpr const char* quick_pushes = "quick_pushes";  ///< pushes found by the push sampler's quick pass
inline constexpr const char* plan_controls = "plan_controls";  ///< controls of the pushing plan
inline constexpr const char* guides = "guides";  ///< guides in the guidance
inline constexpr const char* guides_satisfied = "guides_satisfied";  ///< guides whose push reached its disc
inline constexpr const char* guides_skipped = "guides_skipped";  ///< guides passed over (unsatisfied_guides: skip)
inline constexpr const char* movable_objects = "movable_objects";  ///< objects the stream planner left movable after pruning
inline constexpr const char* stream_calls = "stream_calls";  ///< calls of stream generators
inline constexpr const char* stream_instances = "stream_instances";  ///< stream instances given a generator
inline constexpr const char* searches = "searches";  ///< symbolic searches of the stream planner
inline constexpr const char* skeletons = "skeletons";  ///< plan skeletons whose streams were bound
inline constexpr const char* level = "level";  ///< the highest complexity level the stream search reached
inline constexpr const char* plan_length = "plan_length";  ///< steps of the plan
inline constexpr const char* plans_found = "plans_found";  ///< plans the stream search found (the last is the best)
}  // namespace counter

/// The outcome of a planning run. A failed run is a Result with solved = false and a
/// reason, never an exception.
/// One guide of a guided run as it was followed: push `object` until its centre is in
/// the disc (world x, y and diameter, m).
struct GuideRecord {
  ObjectIndex object = 0;
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
  double diameter = 0.0;
  bool satisfied = false;
  std::string reason;  ///< why not, when not satisfied
};

/// The guidance a guided planner followed (Papallas & Dogar's guides, in order) and
/// where it came from: enough to run the same guidance again.
struct GuidanceRecord {
  std::string source;  ///< the guidance file's path, or "auto" (generated)
  std::vector<GuideRecord> guides;
};

struct Result {
  bool solved = false;
  std::string reason;  ///< why not solved; empty when solved
  std::vector<PlanStep> plan;
  /// The plan's cost, where the planner reckons one (stream_planner: action costs and
  /// function values, or its length without a metric, when it costs plans).
  std::optional<double> cost;
  std::vector<ObjectIndex> moved_objects;  ///< in the order they were moved
  Timing time;
  std::map<std::string, std::uint64_t> counters;
  /// By phase name ("pick.transfer", "retrieve.carry", ...): what each phase of the run
  /// cost (plugin::Phase fills it). Phases may nest; the names say which.
  std::map<std::string, PhaseTotals> phases;
  std::vector<Failure> failures;  ///< what went wrong along the way, solved or not
  std::vector<PlaneDrawing> drawings;  ///< optional: what the planner built, for the viewer
  std::optional<GuidanceRecord> guidance;  ///< a guided planner's guidance, as followed
};

}  // namespace cluttertamp
