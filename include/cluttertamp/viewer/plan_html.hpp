#pragma once

#include <filesystem>
#include <string>

#include "cluttertamp/core/problem.hpp"
#include "cluttertamp/export.hpp"

namespace cluttertamp::viewer {

/// What a replay page shows, as JSON (for tests and other front ends): the scene
/// (`fixed`, `objects`, `regions`), the robot's links and their shapes, the steps with
/// their start times and durations, and `frames` — the robot's link poses, the moving
/// objects' poses and the pusher's pose every `frame_step` seconds of plan time. Poses
/// are world-frame [x y z qx qy qz qw] in metres.
///
/// How objects move: where a robot step moves its fingers while the arm holds still, an
/// empty hand grasps the step's object nearest the tool (within 0.2 m of its centre, at
/// the end of the finger motion) and a full hand lets go (at its start); fingers set
/// while the arm moves (a transfer opening them) do neither. A robot without a finger
/// joint grasps where the tool comes nearest the object and lets go where the tool is
/// lowest. The held object keeps its pose relative to the tool; one still held when a
/// later step moves the robot for other objects before any step names it again was
/// carried out of the workspace, and a frame gives it the pose null from there. A push step is drawn
/// from what the result recorded (no physics runs here): the pusher's planar poses, its
/// boxes and height (values pusher_boxes, pusher_z) and the paths of the objects it
/// moved, linear between the recorded times.
///
/// `result_json`: the text of a result.json written for `problem` (io::result_to_json);
/// `drawings_json`: the text of its drawings.json (io::drawings_to_json), or empty.
/// `name` names the result in errors. Throws InputError naming `name` when the text is
/// not JSON or does not fit the problem (an unknown object or joint, a drawing index out
/// of range), or describes more than 10^5 frames or push propagations.
struct PlanFiles {
  std::string result_json;
  std::string drawings_json;  ///< may be empty
  std::string name;
};
CLUTTERTAMP_API std::string replay_json(const Problem& problem, const PlanFiles& plan, double frame_step = 0.1);

/// One self-contained HTML page replaying the plan of replay_json in 3-D (three.js is
/// inlined: it opens from disk with no server and no network): play, pause, a time
/// slider and the step list with timing; a planner's drawings (e.g. the roadmap and the
/// retrieval graph) top-down beside the scene. Throws as replay_json does, and
/// InputError when three.js (Debian's libjs-three) is not installed.
CLUTTERTAMP_API std::string plan_html(const Problem& problem, const PlanFiles& plan);

/// plan_html written to `file` (its directory created). Throws InputError when the file
/// cannot be written.
CLUTTERTAMP_API void write_plan_html(const std::filesystem::path& file, const Problem& problem, const PlanFiles& plan);

}  // namespace cluttertamp::viewer
