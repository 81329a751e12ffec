#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include <Eigen/Core>

#include "cluttertamp/core/diagnostics.hpp"
#include "cluttertamp/core/parameters.hpp"
#include "cluttertamp/core/scene.hpp"

namespace cluttertamp {

namespace robot {
class RobotDescription;
}
namespace stream {
struct ParsedTask;
}

/// Carry the scene's target out to its exit pose x_s, removing what is in the way.
struct RetrievalTask {
  std::string target;  ///< id of the scene object to retrieve
};

/// Plan in a PDDL domain whose continuous parameters come from streams.
struct PddlTask {
  std::filesystem::path domain;
  /// Absent: the facts are derived from the scene (stream::scene_problem).
  std::optional<std::filesystem::path> problem;
  std::optional<std::filesystem::path> streams;  ///< PDDLStream-style stream file
  /// Values of the PDDL problem's objects (`values:`), by object name as written; the
  /// stream search hands them to streams (numbers, lists of numbers and strings as
  /// such, anything else as a plugin::ValuePayload).
  std::map<std::string, Value> values;
  /// The files parsed (io::load_problem parses them once, with every error located);
  /// null for a task built in code (stream::parsed_task parses it then).
  std::shared_ptr<const stream::ParsedTask> parsed;
};

/// Reach the scene's target with the gripper moving in the shelf plane, pushing what is
/// in the way (Papallas & Dogar's reaching through clutter, RTC).
struct ReachTask {
  std::string target;  ///< id of the scene object to reach
};

using Task = std::variant<RetrievalTask, PddlTask, ReachTask>;

/// A plugin chosen by name in a problem file, with its parameters.
struct PluginChoice {
  std::string name;
  Parameters parameters;
  SourceLocation where;  ///< where the problem file names it
};

/// The robot of a problem: its description file (URDF plus semantics) and where its
/// joints start.
struct RobotSpec {
  std::filesystem::path description;  ///< absolute path of the robot description file
  /// Initial joint values (rad, m; URDF order); absent: the description's home.
  std::optional<Eigen::VectorXd> configuration;
  SourceLocation where;
  /// The loaded description (set by io::load_problem).
  std::shared_ptr<const robot::RobotDescription> loaded;
};

/// Everything `cluttertamp plan` needs: the scene, the robot, the task, the planner
/// and its limits, and the plugins that answer its questions. Paths are absolute.
struct Problem {
  std::string name;
  std::filesystem::path source_file;
  std::filesystem::path scene_file;
  Scene scene;
  RobotSpec robot;
  Task task;
  PluginChoice planner;    ///< the task planner plugin
  double time_limit = 0;   ///< seconds of wall-clock time for the whole run
  std::uint64_t seed = 0;  ///< the root of every random choice in the run
  std::vector<std::filesystem::path> plugin_paths;  ///< searched before the defaults
  /// The `plugins:` block's plugins by kind ("grasp_sampler", "motion_sampler", ...,
  /// or any kind a plugin declares); the task planner and stream samplers are not here.
  std::map<std::string, PluginChoice> samplers;
  std::map<std::string, PluginChoice> streams;  ///< stream name -> stream sampler plugin
  /// The `physics:` block: what pushes and how bodies slide in pushing problems (read
  /// by physics::push_settings; docs/file-formats.md, "Problem files"). Empty: defaults.
  Parameters physics;
};

}  // namespace cluttertamp
