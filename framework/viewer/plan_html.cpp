#include "cluttertamp/viewer/plan_html.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>

#include <nlohmann/json.hpp>

#include "cluttertamp/core/world_state.hpp"
#include "cluttertamp/robot/mesh.hpp"
#include "cluttertamp/robot/robot_description.hpp"
#include "cluttertamp/io/shape_json.hpp"
#include "cluttertamp/io/text_file.hpp"

namespace cluttertamp::assets {
extern const char* const viewer_html;  // framework/viewer/viewer.html, embedded at build time
}

namespace cluttertamp::viewer {

namespace {

using Json = nlohmann::ordered_json;

// Enough for a millimetre-true picture, and a third of the file of full precision.
double rounded(double v) { return std::round(v * 1e5) / 1e5; }

Json pose_json(const Eigen::Isometry3d& pose) {
  const Eigen::Quaterniond q(pose.rotation());
  const Eigen::Vector3d& t = pose.translation();
  return Json::array({rounded(t.x()), rounded(t.y()), rounded(t.z()), rounded(q.x()), rounded(q.y()), rounded(q.z()),
                      rounded(q.w())});
}

using io::shape_json;

// Triangles a mesh keeps on the page: the page stays one self-contained file of a few
// megabytes for a robot of a dozen meshed links.
constexpr std::size_t kMaxDrawnTriangles = 20000;

// {"mesh": {"vertices": [x y z ...], "triangles": [i j k ...]}}, simplified if large.
Json mesh_json(const robot::TriangleMesh& full) {
  const robot::TriangleMesh mesh = robot::simplified(full, kMaxDrawnTriangles);
  Json vertices = Json::array(), triangles = Json::array();
  for (const Eigen::Vector3d& v : mesh.vertices) {
    for (int k = 0; k < 3; ++k) vertices.push_back(rounded(v[k]));
  }
  for (const auto& t : mesh.triangles) triangles.insert(triangles.end(), {t[0], t[1], t[2]});
  return {{"mesh", {{"vertices", std::move(vertices)}, {"triangles", std::move(triangles)}}}};
}

// Beyond these a result.json is not a plan but a way to exhaust memory.
constexpr double kMaxFrames = 1e5;

Eigen::Isometry3d planar_pose(const Eigen::Vector3d& xy_yaw, double z) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = Eigen::Vector3d(xy_yaw.x(), xy_yaw.y(), z);
  pose.linear() = Eigen::AngleAxisd(xy_yaw.z(), Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return pose;
}

// Code inlined into a <script> element must not close it early.
std::string script_safe(std::string code) {
  for (std::size_t at = code.find("</"); at != std::string::npos; at = code.find("</", at + 3)) code.replace(at, 2, "<\\/");
  return code;
}

// JSON inlined into a <script> element: every '<' (only ever inside a string) escaped,
// so no id or name can end the element or start an HTML comment in it.
std::string json_safe(const std::string& json) {
  std::string out;
  out.reserve(json.size());
  for (char c : json) {
    if (c == '<') out += "\\u003c";
    else out += c;
  }
  return out;
}

void replace_once(std::string& text, const std::string& marker, const std::string& with) {
  const std::size_t at = text.find(marker);
  if (at != std::string::npos) text.replace(at, marker.size(), with);
}

// Walks a plan step by step, keeping the world state, and writes the frames.
class Replayer {
 public:
  Replayer(const Problem& problem, std::string name, double frame_step)
      : scene_(problem.scene), name_(std::move(name)), frame_step_(frame_step),
        state_(WorldState::initial(problem.scene)) {
    if (problem.robot.loaded) {
      robot_ = problem.robot.loaded.get();
      state_.robot_configuration = robot::initial_configuration(problem.robot);
      const auto& links = robot_->model()->links();
      for (std::size_t i = 0; i < links.size(); ++i) {
        if (!links[i].collision.empty() || !links[i].visual.empty()) drawn_links_.push_back(static_cast<robot::LinkIndex>(i));
      }
    }
  }

  Json robot_json() const {
    if (!robot_) return nullptr;
    Json links = Json::array();
    for (robot::LinkIndex l : drawn_links_) {
      const robot::Link& link = robot_->model()->links()[static_cast<std::size_t>(l)];
      Json shapes = Json::array();
      // What the link looks like when the URDF says (<visual>), else what collides.
      for (const robot::VisualShape& v : link.visual) {
        if (v.primitive) {
          shapes.push_back({{"shape", shape_json(*v.primitive)}, {"pose", pose_json(v.link_T_visual)}});
        } else {
          const robot::TriangleMesh mesh = robot::load_mesh(v.mesh_file, v.mesh_scale, {v.mesh_file, 0, 0});
          shapes.push_back({{"shape", mesh_json(mesh)}, {"pose", pose_json(v.link_T_visual)}});
        }
      }
      if (link.visual.empty()) {
        for (const robot::CollisionShape& s : link.collision) {
          if (s.mesh) shapes.push_back({{"shape", mesh_json(*s.mesh)}, {"pose", pose_json(s.link_T_mesh)}});
          else shapes.push_back({{"shape", shape_json(s.shape)}, {"pose", pose_json(s.link_T_shape)}});
        }
      }
      links.push_back({{"name", link.name}, {"shapes", shapes}});
    }
    return {{"name", robot_->name()}, {"links", links}};
  }

  // Adds the step's frames from plan time `start`; returns its duration (s).
  double step(const Json& step, double start) {
    objects_of(step);  // every object named must be the scene's
    const Json& trajectory = step.at("trajectory");
    if (trajectory.is_null()) return 0.0;
    const auto names = trajectory.at("joint_names").get<std::vector<std::string>>();
    if (step.at("action").get<std::string>() == "push" || (!names.empty() && names.front() == "gripper_x")) {
      return push(step, start);
    }
    return move_robot(step, names, start);
  }

  // The robot where the problem starts it, at time 0 (pushes do not move its links).
  void initial_frame() {
    if (!robot_) return;
    std::vector<Eigen::Isometry3d> links;
    robot_->model()->link_poses(state_.robot_configuration, links);
    frames_.push_back({{"t", 0.0}, {"links", links_json(links)}});
  }

  // An object still in the hand when a later step moves the robot for other objects
  // before any step names it again was carried out of the workspace (Tian et al.'s
  // assumption 4): it leaves the picture at `t`. Steps naming it, or nothing, keep it
  // in the hand (a PDDL domain may move between pick and place).
  void carry_out_unless_placed(const Json& steps, std::size_t from, double t) {
    if (!state_.held) return;
    const std::string id = scene_.objects[*state_.held].id;
    for (std::size_t k = from; k < steps.size(); ++k) {
      const Json& step = steps[k];
      const Json& objects = step.at("objects");
      if (std::any_of(objects.begin(), objects.end(), [&](const Json& o) { return o == id; })) return;
      if (!objects.empty() && !step.at("trajectory").is_null()) {
        state_.removed[*state_.held] = true;
        state_.held.reset();
        frames_.push_back({{"t", rounded(t)}, {"objects", {{id, nullptr}}}});
        return;
      }
    }
  }

  Json take_frames() { return std::move(frames_); }
  bool pushed() const { return pushed_; }
  /// The pusher's boxes, each {shape, offset in the pusher's frame}; empty without a push
  /// that recorded them.
  const Json& pusher_parts() const { return pusher_parts_; }
  bool robot_moved() const { return robot_moved_; }
  std::vector<std::string> warnings() const { return warnings_; }

 private:
  std::vector<ObjectIndex> objects_of(const Json& step) const {
    std::vector<ObjectIndex> out;
    for (const Json& id : step.at("objects")) {
      const auto o = scene_.find_object(id.get<std::string>());
      if (!o) throw InputError({name_, 0, 0}, "plan step names object '" + id.get<std::string>() + "', which the scene " + scene_.source_file + " does not have");
      out.push_back(*o);
    }
    return out;
  }

  // The drawn links' world poses, flattened: 7 numbers per link.
  Json links_json(const std::vector<Eigen::Isometry3d>& root_T_links) const {
    Json flat = Json::array();
    for (robot::LinkIndex l : drawn_links_) {
      for (const Json& v : pose_json(scene_.world_T_robot_base * root_T_links[static_cast<std::size_t>(l)])) flat.push_back(v);
    }
    return flat;
  }

  Eigen::Isometry3d tool_pose(const std::vector<Eigen::Isometry3d>& root_T_links) const {
    return scene_.world_T_robot_base * root_T_links[static_cast<std::size_t>(robot_->tip_link())];
  }

  double move_robot(const Json& step, const std::vector<std::string>& names, double start) {
    if (!robot_) throw InputError({name_, 0, 0}, "plan step '" + step.at("action").get<std::string>() + "' moves joints, but the problem has no robot");
    const robot::RobotModel& model = *robot_->model();
    const std::vector<std::string> variables = model.variable_names();
    std::vector<int> column;
    for (const std::string& n : names) {
      const auto it = std::find(variables.begin(), variables.end(), n);
      if (it == variables.end()) throw InputError({name_, 0, 0}, "trajectory joint '" + n + "' is not a joint of robot '" + robot_->name() + "'");
      column.push_back(static_cast<int>(it - variables.begin()));
    }
    const auto times = step.at("trajectory").at("times").get<std::vector<double>>();
    const auto positions = step.at("trajectory").at("positions").get<std::vector<std::vector<double>>>();
    if (times.empty() || times.size() != positions.size()) throw InputError({name_, 0, 0}, "a trajectory needs one position per time");
    for (std::size_t k = 0; k < times.size(); ++k) {
      if (!std::isfinite(times[k]) || times[k] < 0 || (k > 0 && times[k] < times[k - 1])) {
        throw InputError({name_, 0, 0}, "trajectory times must be finite, from 0 and never decreasing");
      }
    }
    const double duration = times.back();
    if (duration / frame_step_ > kMaxFrames) throw InputError({name_, 0, 0}, "a trajectory of " + std::to_string(duration) + " s is too long to replay");

    // The configurations at every waypoint and every frame_step between (joint-space
    // linear): a grasp is told by what moves between two waypoints.
    std::vector<double> at = times;
    for (double t = 0.0; t < duration; t += frame_step_) at.push_back(t);
    std::sort(at.begin(), at.end());
    at.erase(std::unique(at.begin(), at.end(), [](double a, double b) { return b - a < 1e-6; }), at.end());
    std::vector<Eigen::VectorXd> qs;
    std::size_t k = 0;
    for (double t : at) {
      while (k + 1 < times.size() && times[k + 1] < t) ++k;
      const std::size_t k1 = std::min(k + 1, times.size() - 1);
      const double span = times[k1] - times[k];
      const double s = span > 0 ? std::clamp((t - times[k]) / span, 0.0, 1.0) : 1.0;
      Eigen::VectorXd q = state_.robot_configuration;
      for (std::size_t j = 0; j < column.size(); ++j) {
        if (positions[k].size() != column.size() || positions[k1].size() != column.size()) {
          throw InputError({name_, 0, 0}, "a trajectory position has the wrong number of joints");
        }
        q[column[j]] = (1 - s) * positions[k][j] + s * positions[k1][j];
      }
      qs.push_back(std::move(q));
    }

    std::vector<std::vector<Eigen::Isometry3d>> links(qs.size());
    for (std::size_t i = 0; i < qs.size(); ++i) model.link_poses(qs[i], links[i]);
    const auto events = grasp_events(step, qs, links);
    auto next = events.begin();
    for (std::size_t i = 0; i < qs.size(); ++i) {
      for (; next != events.end() && next->first == i; ++next) {
        if (next->second) grasp(step, links[i]);
        else state_.held.reset();
      }
      Json frame{{"t", rounded(start + at[i])}};
      frame["links"] = links_json(links[i]);
      if (state_.held) {
        state_.world_T_objects[*state_.held] = tool_pose(links[i]) * tool_T_held_;
        frame["objects"] = {{scene_.objects[*state_.held].id, pose_json(state_.world_T_objects[*state_.held])}};
      }
      frames_.push_back(std::move(frame));
    }
    state_.robot_configuration = qs.back();
    robot_moved_ = true;
    return duration;
  }

  // Where the hand grasps (true) or lets go (false), by frame. With fingers: the
  // fingers moving while the arm holds still grasp the step object within reach of the
  // tool, or let go of the held one (fingers set while the arm moves, as a transfer
  // opens them, are neither). Without fingers: the grasp is where the tool comes
  // nearest the object, the release where the tool is lowest.
  std::vector<std::pair<std::size_t, bool>> grasp_events(const Json& step, const std::vector<Eigen::VectorXd>& qs,
                                                         const std::vector<std::vector<Eigen::Isometry3d>>& links) {
    std::vector<std::pair<std::size_t, bool>> events;
    bool holding = state_.held.has_value();
    if (const auto finger = robot_->finger_variable()) {
      auto arm_still = [&](std::size_t a, std::size_t b) {
        Eigen::VectorXd d = qs[b] - qs[a];
        d[*finger] = 0;
        return d.cwiseAbs().maxCoeff() <= 1e-6;
      };
      for (std::size_t i = 1; i < qs.size(); ++i) {
        if (std::abs(qs[i][*finger] - qs[i - 1][*finger]) <= 1e-6) continue;
        const std::size_t begin = i - 1;
        while (i + 1 < qs.size() && std::abs(qs[i + 1][*finger] - qs[i][*finger]) > 1e-6) ++i;
        bool still = true;
        for (std::size_t k = begin; k < i && still; ++k) still = arm_still(k, k + 1);
        if (!still) continue;  // fingers set on the way (a transfer opens them), not a grasp
        if (!holding && graspable(step, links[i])) {
          events.emplace_back(i, true);
          holding = true;
        } else if (holding) {
          events.emplace_back(begin, false);
          holding = false;
        }
      }
      return events;
    }
    const std::vector<ObjectIndex> objects = objects_of(step);
    if (!holding && objects.empty()) return events;
    std::size_t best = 0;
    double best_value = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < qs.size(); ++i) {
      const Eigen::Vector3d tool = tool_pose(links[i]).translation();
      const double value = holding ? tool.z() : (tool - state_.world_T_objects[objects.front()].translation()).norm();
      if (value < best_value) best_value = value, best = i;
    }
    events.emplace_back(best, !holding);
    return events;
  }

  // The step's object (any movable one when it names none) nearest the tool, within
  // grasping distance.
  std::optional<ObjectIndex> graspable(const Json& step, const std::vector<Eigen::Isometry3d>& links) const {
    std::vector<ObjectIndex> candidates = objects_of(step);
    if (candidates.empty()) {
      for (ObjectIndex o = 0; o < scene_.objects.size(); ++o) if (scene_.objects[o].movable) candidates.push_back(o);
    }
    const Eigen::Vector3d tool = tool_pose(links).translation();
    std::optional<ObjectIndex> nearest;
    double distance = 0.2;  // m: farther than this, the fingers close on nothing drawn
    for (ObjectIndex o : candidates) {
      if (state_.removed[o]) continue;  // carried out of the workspace
      const double d = (state_.world_T_objects[o].translation() - tool).norm();
      if (d < distance) distance = d, nearest = o;
    }
    return nearest;
  }

  void grasp(const Json& step, const std::vector<Eigen::Isometry3d>& links) {
    state_.held = graspable(step, links);
    if (!state_.held) {  // no fingers: the nearest approach grasps whatever it is
      const std::vector<ObjectIndex> objects = objects_of(step);
      if (!objects.empty()) state_.held = objects.front();
    }
    if (state_.held) tool_T_held_ = tool_pose(links).inverse() * state_.world_T_objects[*state_.held];
  }

  // The pusher's parts and height as the push step recorded them (values pusher_parts,
  // or an older result's pusher_boxes, and pusher_z); the first push that records them
  // gives the page its pusher. A step without them (an older result) is replayed
  // without drawing the pusher.
  std::optional<double> pusher_of(const Json& step) {
    const Json& values = step.at("values");
    const auto parts = values.find("pusher_parts");
    const auto boxes = values.find("pusher_boxes");
    const auto z = values.find("pusher_z");
    if ((parts == values.end() && boxes == values.end()) || z == values.end()) {
      warnings_.push_back("step " + std::to_string(step.value("index", 0)) +
                          ": the result does not record the pusher (written by an older cluttertamp); it is not drawn");
      return std::nullopt;
    }
    const auto finite = [](const std::vector<double>& v) { return std::all_of(v.begin(), v.end(), [](double x) { return std::isfinite(x); }); };
    const auto height = z->get<std::vector<double>>();
    if (height.size() != 1 || !std::isfinite(height[0])) throw InputError({name_, 0, 0}, "a push step's pusher_z must be one finite height");
    if (parts != values.end()) {
      const auto numbers = parts->get<std::vector<double>>();
      if (numbers.empty() || numbers.size() % 11 != 0 || !finite(numbers)) {
        throw InputError({name_, 0, 0}, "a push step's pusher_parts must be finite [kind, 3 sizes, position x y z, quaternion x y z w] per part");
      }
      if (pusher_parts_.empty()) {
        for (std::size_t i = 0; i < numbers.size(); i += 11) pusher_parts_.push_back(part_json(&numbers[i]));
      }
      return height[0];
    }
    const auto numbers = boxes->get<std::vector<double>>();
    if (numbers.empty() || numbers.size() % 5 != 0 || !finite(numbers)) {
      throw InputError({name_, 0, 0}, "a push step's pusher_boxes must be finite [size x y z, centre x y] per box and its pusher_z one height");
    }
    if (pusher_parts_.empty()) {
      for (std::size_t i = 0; i < numbers.size(); i += 5) {
        pusher_parts_.push_back({{"shape", shape_json(Box{Eigen::Vector3d(numbers[i], numbers[i + 1], numbers[i + 2])})},
                                 {"offset", {numbers[i + 3], numbers[i + 4], 0.0}},
                                 {"rotation", {0.0, 0.0, 0.0, 1.0}}});
      }
    }
    return height[0];
  }

  // One of pusher_parts' records: kind (0 box, 1 cylinder, 2 sphere; any other a box),
  // its sizes, its position and quaternion in the pusher's frame.
  Json part_json(const double* v) const {
    const Shape shape = v[0] == 1.0   ? Shape{Cylinder{std::abs(v[1]), std::abs(v[2])}}
                        : v[0] == 2.0 ? Shape{Sphere{std::abs(v[1])}}
                                      : Shape{Box{Eigen::Vector3d(v[1], v[2], v[3]).cwiseAbs()}};
    return {{"shape", shape_json(shape)}, {"offset", {v[4], v[5], v[6]}}, {"rotation", {v[7], v[8], v[9], v[10]}}};
  }

  // A push drawn from what the result recorded: the pusher's planar poses and, for each
  // object it moved, that object's at the same times, both linear between them. A
  // result without object paths (written before they were recorded) moves each pushed
  // object to its end pose at the end of the step, and says so.
  double push(const Json& step, double start) {
    const Json& trajectory = step.at("trajectory");
    const auto times = trajectory.at("times").get<std::vector<double>>();
    const auto positions = trajectory.at("positions").get<std::vector<std::vector<double>>>();
    if (positions.empty() || times.size() != positions.size()) throw InputError({name_, 0, 0}, "a push step needs one gripper pose per time");
    for (std::size_t k = 0; k < times.size(); ++k) {
      if (positions[k].size() != 3 || !std::isfinite(times[k]) || times[k] < 0 || (k > 0 && times[k] < times[k - 1])) {
        throw InputError({name_, 0, 0}, "a push step needs gripper poses [x y yaw] at finite times from 0, never decreasing");
      }
    }
    if (times.back() / frame_step_ > kMaxFrames) throw InputError({name_, 0, 0}, "a push of " + std::to_string(times.back()) + " s is too long to replay");
    std::map<ObjectIndex, std::vector<Eigen::Vector3d>> paths;
    if (const auto objects = trajectory.find("objects"); objects != trajectory.end()) {
      for (const auto& [id, poses] : objects->items()) {
        const ObjectIndex object = object_index(id);
        for (const Json& pose : poses) paths[object].push_back(planar(pose.get<std::vector<double>>()));
        if (paths[object].size() != times.size()) throw InputError({name_, 0, 0}, "object '" + id + "' needs one pose per time of its push");
      }
    } else if (!step.at("objects").empty()) {
      warnings_.push_back("step " + std::to_string(step.value("index", 0)) +
                          ": the result has no object paths (written by an older cluttertamp); pushed objects jump to their end poses");
    }

    const std::optional<double> pusher_z = pusher_of(step);
    std::vector<double> at = times;  // every recorded time and every frame_step between
    for (double t = 0.0; t < times.back(); t += frame_step_) at.push_back(t);
    std::sort(at.begin(), at.end());
    at.erase(std::unique(at.begin(), at.end(), [](double a, double b) { return b - a < 1e-6; }), at.end());
    pushed_ = true;
    std::size_t k = 0;
    for (const double t : at) {
      while (k + 1 < times.size() && times[k + 1] < t) ++k;
      const std::size_t k1 = std::min(k + 1, times.size() - 1);
      const double span = times[k1] - times[k];
      const double s = span > 0 ? std::clamp((t - times[k]) / span, 0.0, 1.0) : 1.0;
      const Eigen::Vector3d pusher_pose = between(planar(positions[k]), planar(positions[k1]), s);
      Json frame{{"t", rounded(start + t)}};
      if (pusher_z) frame["pusher"] = pose_json(planar_pose(pusher_pose, *pusher_z));
      Json objects = Json::object();
      for (const auto& [object, poses] : paths) {
        const Eigen::Vector3d pose = between(poses[k], poses[k1], s);
        if ((pose - poses.front()).norm() > 1e-5) objects[scene_.objects[object].id] = pose_json(with_planar_pose(state_.world_T_objects[object], pose));
      }
      if (!objects.empty()) frame["objects"] = std::move(objects);
      frames_.push_back(std::move(frame));
    }
    for (const auto& [object, poses] : paths) state_.world_T_objects[object] = with_planar_pose(state_.world_T_objects[object], poses.back());
    if (paths.empty()) {  // the end poses the step's values hold, drawn at its end
      Json objects = Json::object();
      for (const ObjectIndex object : objects_of(step)) {
        const auto end = step.at("values").find(scene_.objects[object].id);
        if (end == step.at("values").end()) continue;
        state_.world_T_objects[object] = with_planar_pose(state_.world_T_objects[object], planar(end->get<std::vector<double>>()));
        objects[scene_.objects[object].id] = pose_json(state_.world_T_objects[object]);
      }
      if (!objects.empty()) frames_.back()["objects"] = std::move(objects);
    }
    return times.back();
  }

  ObjectIndex object_index(const std::string& id) const {
    for (ObjectIndex i = 0; i < scene_.objects.size(); ++i) {
      if (scene_.objects[i].id == id) return i;
    }
    throw InputError({name_, 0, 0}, "the result names an object '" + id + "' that the scene does not have");
  }

  Eigen::Vector3d planar(const std::vector<double>& v) const {
    if (v.size() != 3 || !std::isfinite(v[0]) || !std::isfinite(v[1]) || !std::isfinite(v[2])) {
      throw InputError({name_, 0, 0}, "a planar pose needs three finite numbers [x y yaw]");
    }
    return {v[0], v[1], v[2]};
  }

  // Linear in x and y, the shorter way round in yaw.
  static Eigen::Vector3d between(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double s) {
    const double turn = std::remainder(b.z() - a.z(), 2 * M_PI);
    return {a.x() + s * (b.x() - a.x()), a.y() + s * (b.y() - a.y()), a.z() + s * turn};
  }

  const Scene& scene_;
  std::string name_;
  double frame_step_;
  WorldState state_;
  const robot::RobotDescription* robot_ = nullptr;
  std::vector<robot::LinkIndex> drawn_links_;
  Eigen::Isometry3d tool_T_held_ = Eigen::Isometry3d::Identity();
  Json frames_ = Json::array();
  bool pushed_ = false;
  Json pusher_parts_ = Json::array();
  bool robot_moved_ = false;
  std::vector<std::string> warnings_;
};

Json scene_json(const Scene& scene, const std::vector<std::string>& moved) {
  Json fixed = Json::array();
  for (const FixedBody& f : scene.fixed) fixed.push_back({{"id", f.id}, {"shape", shape_json(f.shape)}, {"pose", pose_json(f.world_T_body)}});
  Json objects = Json::array();
  for (ObjectIndex i = 0; i < scene.objects.size(); ++i) {
    const SceneObject& o = scene.objects[i];
    const std::string role = i == scene.target ? "target"
                             : !o.movable     ? "fixed"
                             : std::find(moved.begin(), moved.end(), o.id) != moved.end() ? "moved"
                                                                                         : "movable";
    objects.push_back({{"id", o.id}, {"shape", shape_json(o.shape)}, {"pose", pose_json(o.world_T_object)}, {"role", role}});
  }
  Json regions = Json::array();
  for (const Region& r : scene.regions) regions.push_back({{"id", r.id}, {"shape", shape_json(Box{r.size})}, {"pose", pose_json(r.world_T_region)}});
  const Eigen::Vector3d exit = scene.world_T_exit.translation();
  return {{"name", scene.name}, {"fixed", fixed}, {"objects", objects}, {"regions", regions},
          {"exit", {exit.x(), exit.y(), exit.z()}},
          {"workspace", {{"min", {scene.workspace.min().x(), scene.workspace.min().y(), scene.workspace.min().z()}},
                         {"max", {scene.workspace.max().x(), scene.workspace.max().y(), scene.workspace.max().z()}}}}};
}

// The drawings as the page draws them, every index checked (nlohmann throws on a wrong type).
Json checked_drawings(const Json& drawings, const std::string& name) {
  Json out = Json::array();
  for (const Json& d : drawings) {
    const auto nodes = d.at("nodes").get<std::vector<std::array<double, 2>>>();
    const auto labels = d.value("labels", std::vector<std::string>{});
    const auto edges = d.at("edges").get<std::vector<std::array<long, 2>>>();
    const auto path = d.value("path", std::vector<long>{});
    const long n = static_cast<long>(nodes.size());
    auto in_range = [n](long i) { return i >= 0 && i < n; };
    bool ok = labels.empty() || labels.size() == nodes.size();
    for (const auto& x : nodes) ok = ok && std::isfinite(x[0]) && std::isfinite(x[1]);
    for (const auto& [a, b] : edges) ok = ok && in_range(a) && in_range(b);
    for (long i : path) ok = ok && in_range(i);
    if (!ok) throw InputError({name, 0, 0}, "drawing '" + d.value("name", "") + "' has a node index out of range, a label count that is not its node count, or a coordinate that is not finite");
    out.push_back({{"name", d.value("name", "drawing")}, {"nodes", nodes}, {"labels", labels}, {"edges", edges}, {"path", path}});
  }
  return out;
}

Json checked_failures(const Json& failures) {
  Json out = Json::array();
  for (const Json& f : failures) {
    out.push_back({{"stage", f.value("stage", "")}, {"reason", f.value("reason", "")},
                   {"blocking_objects", f.value("blocking_objects", std::vector<std::string>{})}});
  }
  return out;
}

}  // namespace

std::string replay_json(const Problem& problem, const PlanFiles& plan, double frame_step) {
  const std::string& name = plan.name;
  Json result, drawings = Json::array();
  try {
    result = Json::parse(plan.result_json);
  } catch (const Json::exception& e) {  // a syntax error, or a number out of range ("1e400")
    throw InputError({name, 0, 0}, std::string("not a result.json: ") + e.what());
  }
  if (!plan.drawings_json.empty()) {
    try {
      drawings = Json::parse(plan.drawings_json).at("drawings");
    } catch (const Json::exception& e) {
      throw InputError({name, 0, 0}, std::string("its drawings.json is not one: ") + e.what());
    }
  }
  try {
    Replayer replayer(problem, name, frame_step);
    replayer.initial_frame();
    Json steps = Json::array();
    double clock = 0.0;
    const Json& plan_steps = result.at("plan");
    for (std::size_t k = 0; k < plan_steps.size(); ++k) {
      const Json& s = plan_steps[k];
      const double duration = replayer.step(s, clock);
      replayer.carry_out_unless_placed(plan_steps, k + 1, clock + duration);
      Json step{{"index", s.value("index", steps.size())}, {"action", s.at("action")}, {"objects", s.at("objects")},
                {"start", rounded(clock)}, {"duration", rounded(duration)}};
      const Json& values = s.at("values");
      if (values.contains("region")) step["region"] = values.at("region");  // a guide's disc: centre x, y and diameter
      if (values.contains("guide")) step["guide"] = values.at("guide").at(0);
      steps.push_back(std::move(step));
      clock += duration;
    }
    const auto moved = result.value("moved_objects", std::vector<std::string>{});
    Json out{{"problem", problem.name},
             {"problem_file", problem.source_file.string()},
             {"source", name},
             {"planner", result.value("planner", "")},
             {"solved", result.value("solved", false)},
             {"reason", result.value("reason", Json(nullptr))},
             {"time", result.value("time", Json::object())},
             {"moved_objects", moved},
             {"failures", checked_failures(result.value("failures", Json::array()))},
             {"drawings", checked_drawings(drawings, name)},
             {"scene", scene_json(problem.scene, moved)},
             {"robot", replayer.robot_json()},
             {"steps", steps},
             {"duration", rounded(clock)},
             {"frames", replayer.take_frames()},
             {"warnings", replayer.warnings()}};
    if (replayer.pushed() && !replayer.robot_moved()) {
      // A pushing plan moves the planar pusher only: the arm at home would only be in the way.
      out["robot"] = nullptr;
      for (Json& frame : out["frames"]) frame.erase("links");
    }
    if (!replayer.pusher_parts().empty()) out["pusher"] = {{"parts", replayer.pusher_parts()}};
    if (result.contains("human_guidance")) out["human_guidance"] = result.at("human_guidance");
    return out.dump(-1, ' ', false, Json::error_handler_t::replace);
  } catch (const Json::exception& e) {
    throw InputError({name, 0, 0}, std::string("does not look like a result.json: ") + e.what());
  }
}

std::string plan_html(const Problem& problem, const PlanFiles& plan) {
  const std::string data = replay_json(problem, plan);
  const std::filesystem::path three(CLUTTERTAMP_THREE_JS_DIR);
  std::string page = assets::viewer_html;
  const std::string what = "three.js file (is Debian's libjs-three installed?)";
  replace_once(page, "/*@THREE_JS@*/", script_safe(io::read_text_file(three / "build" / "three.min.js", what)));
  replace_once(page, "/*@ORBIT_CONTROLS@*/",
               script_safe(io::read_text_file(three / "examples" / "js" / "controls" / "OrbitControls.js", what)));
  replace_once(page, "/*@REPLAY_DATA@*/", json_safe(data));
  return page;
}

void write_plan_html(const std::filesystem::path& file, const Problem& problem, const PlanFiles& plan) {
  io::write_text_file(file, plan_html(problem, plan), "page");
}

}  // namespace cluttertamp::viewer
