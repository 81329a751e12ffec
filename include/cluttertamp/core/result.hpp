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

/// Names of the counters every planner is expected to fill (others may be added).
namespace counter {
inline constexpr const char* samples = "samples";
inline constexpr const char* collision_checks = "collision_checks";
inline constexpr const char* motion_planning_calls = "motion_planning_calls";
}  // namespace counter

/// The outcome of a planning run. A failed run is a Result with solved = false and a
/// reason, never an exception.
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
};

}  // namespace cluttertamp
