#pragma once

#include <map>
#include <string>
#include <vector>

#include "cluttertamp/core/scene.hpp"
#include "cluttertamp/export.hpp"
#include "cluttertamp/pddl/ast.hpp"
#include "cluttertamp/plugin/stream_sampler.hpp"

namespace cluttertamp::stream {

/// A scene as a PDDL problem for domains/pddl/clutter-streams, and the values of its
/// objects for the streams.
struct SceneProblem {
  pddl::Problem problem;
  /// "p0-<object>" -> the object's pose in the scene file (Eigen::Isometry3d).
  std::map<std::string, plugin::StreamValue> values;
  /// PDDL name -> scene object (names are the objects' ids, lower-cased).
  std::map<std::string, ObjectIndex> objects;
};

/// The facts of a scene: (Object o), (Pose o p0-o) and (AtPose o p0-o) for every movable
/// object (`movable[o]`, all when `movable` is empty; the target always), (On o s) for
/// each support s of o, (Region r) for every region, (HandEmpty); the goal (Holding
/// target). Objects that are not movable stay where they are, as obstacles, and have no
/// pose fact: no action moves them and no test is asked about them, so the streams must
/// treat them as fixed geometry (give them `movable: false` in the scene the streams
/// see, as stream_planner does). Throws InputError when two ids differ only in case.
CLUTTERTAMP_API SceneProblem scene_problem(const Scene& scene, const std::vector<bool>& movable,
                                           const std::string& domain_name);

}  // namespace cluttertamp::stream
