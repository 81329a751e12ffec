#include "cluttertamp/io/robot_description_io.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>
#include <system_error>

#include "cluttertamp/io/srdf.hpp"
#include "io/joint_limits_text.hpp"
#include "io/yaml_reader.hpp"

namespace cluttertamp::io {

namespace {
using detail::MapReader;
using detail::YamlFile;
using namespace robot;

std::mutex g_package_paths_mutex;
std::vector<std::filesystem::path> g_command_line_package_paths;

std::vector<std::filesystem::path> command_line_package_paths() {
  std::lock_guard<std::mutex> lock(g_package_paths_mutex);
  return g_command_line_package_paths;
}

// package_paths: and mesh_collision: (URDF loading options; defaults when absent).
UrdfOptions urdf_options(const YamlFile& yaml, const MapReader& top) {
  std::vector<std::filesystem::path> directories = command_line_package_paths();
  if (top.has("package_paths")) {
    const YAML::Node list = top.optional("package_paths");
    if (const auto names = yaml.strings(list, "package_paths")) {
      for (std::size_t i = 0; i < names->size(); ++i) {
        // A directory that is not there is a typo or another machine's path: its meshes
        // would be reported missing later, with no word of the path that was meant.
        const std::filesystem::path directory = yaml.resolve((*names)[i]);
        std::error_code ec;
        if (!std::filesystem::is_directory(directory, ec)) {
          yaml.error(list[i], "package_paths: no such directory '" + (*names)[i] + "' (" + directory.string() + ")");
        }
        directories.push_back(directory);
      }
    }
  }
  UrdfOptions options{PackagePaths::with_environment(std::move(directories))};
  if (top.has("mesh_collision")) {
    const YAML::Node node = top.optional("mesh_collision");
    const auto name = yaml.string(node, "mesh_collision");
    bool known = false;
    for (const MeshCollision m : {MeshCollision::convex_hull, MeshCollision::convex_pieces, MeshCollision::triangles}) {
      if (name == std::string(mesh_collision_name(m))) {
        options.mesh_collision = m;
        known = true;
        break;
      }
    }
    if (name && !known) {
      yaml.error(node, "mesh_collision must be 'convex_hull', 'convex_pieces' or 'triangles', not '" + *name + "'");
    }
  }
  return options;
}

// The errors of an SRDF check, reported with the description's own.
void report(const YamlFile& yaml, const InputError& e) {
  for (const Diagnostic& d : e.diagnostics().items()) yaml.error(d.location, d.message);
}

// "the SRDF F has no group 'x' (did you mean ...); its groups: a, b".
void no_such(const YamlFile& yaml, const YAML::Node& node, const Srdf& srdf, const std::string& what, const std::string& plural,
             const std::string& name, const std::vector<std::string>& known) {
  std::string list;
  for (const std::string& n : known) list += (list.empty() ? "" : ", ") + n;
  yaml.error(node, "the SRDF " + srdf.file.string() + " has no " + what + " '" + name + "'" + did_you_mean(name, known) + "; its " +
                       plural + ": " + (list.empty() ? "none" : list));
}

// group: the chain of an SRDF planning group, for base_link and tip_link not given.
void chain_from_group(const YamlFile& yaml, const YAML::Node& node, const std::optional<Srdf>& srdf, bool srdf_given,
                      const RobotModel& model, RobotDescription::Parts& robot) {
  const auto name = yaml.string(node, "group");
  if (!name) return;
  if (!srdf) {
    if (!srdf_given) yaml.error(node, "group '" + *name + "' is a group of an SRDF: give the SRDF with srdf:");
    return;
  }
  const SrdfGroup* g = srdf->find_group(*name);
  if (!g) {
    no_such(yaml, node, *srdf, "group", "groups", *name, srdf->group_names());
    return;
  }
  if (robot.base_link >= 0 && robot.tip_link >= 0) return;  // both named: the group's chain is not used
  try {
    const auto [base, tip] = srdf_chain(*srdf, *g, model);
    if (robot.base_link < 0) robot.base_link = base;
    if (robot.tip_link < 0) robot.tip_link = tip;
  } catch (const InputError& e) {
    report(yaml, e);
  }
}

// home: joint values in configuration order, or the names of SRDF group states applied
// in turn over zeros (MoveIt's "ready" for the arm, "open" for the hand).
void read_home(const YamlFile& yaml, const YAML::Node& home, const std::optional<Srdf>& srdf, bool srdf_given,
               const RobotModel& model, Eigen::VectorXd& q) {
  // A name is what YAML does not read as a number (as yaml.number decides).
  const auto is_name = [](const YAML::Node& n) {
    double unused = 0;
    return n.IsScalar() && !YAML::convert<double>::decode(n, unused);
  };
  std::vector<YAML::Node> entries;
  if (home.IsScalar()) entries.push_back(home);
  for (std::size_t i = 0; home.IsSequence() && i < home.size(); ++i) entries.push_back(home[i]);
  const auto names = static_cast<std::size_t>(std::count_if(entries.begin(), entries.end(), is_name));
  if (names > 0 && names < entries.size()) {
    yaml.error(home, "home mixes joint values and group state names: give " + std::to_string(model.variable_count()) +
                         " joint values, or names of group states of the SRDF");
    return;
  }
  if (names > 0) {
    if (!srdf) {
      if (!srdf_given) {
        yaml.error(home, "home names group states of an SRDF: give the SRDF with srdf:, or list " +
                             std::to_string(model.variable_count()) + " joint values");
      }
      return;
    }
    bool failed = false;
    for (const YAML::Node& entry : entries) {
      const std::string name = entry.Scalar();
      const SrdfGroupState* state = srdf->find_group_state(name);
      if (!state) {
        no_such(yaml, entry, *srdf, "group state", "group states", name, srdf->group_state_names());
        failed = true;
        continue;
      }
      try {
        apply_group_state(*srdf, *state, model, q);
      } catch (const InputError& e) {
        report(yaml, e);
        failed = true;
      }
    }
    if (failed) return;  // its limits would only repeat the error
  } else if (!home.IsSequence() || home.size() != model.variable_count()) {
    std::string joints;
    for (const std::string& n : model.variable_names()) joints += (joints.empty() ? "" : ", ") + n;
    yaml.error(home, "home must list " + std::to_string(model.variable_count()) + " joint values (" + joints +
                         ") or name group states of the SRDF");
    return;
  } else {
    for (std::size_t i = 0; i < home.size(); ++i) {
      if (auto v = yaml.number(home[i], "home[" + std::to_string(i) + "]")) q[static_cast<Eigen::Index>(i)] = *v;
    }
  }
  if (!model.within_limits(q)) yaml.error(home, "home lies outside the joint limits: " + outside_limits(model, q));
}

// The tool frame's convention, checked on the hand at home: the fingers close along its
// y axis, and its z axis (the approach) points away from the hand's base, the link the
// finger joint hangs from. A frame turned from that makes every grasp turned, unseen
// until a plan fails or grasps beside the object. Within 45 degrees passes.
void check_tool_frame(const YamlFile& yaml, const YAML::Node& tip, const RobotDescription& robot, const Joint& finger) {
  const RobotModel& model = *robot.model();
  std::vector<Eigen::Isometry3d> root_T_links;
  model.link_poses(robot.home(), root_T_links);
  const Eigen::Isometry3d& root_T_tool = root_T_links[static_cast<std::size_t>(robot.tip_link())];
  const Eigen::Isometry3d& root_T_hand = root_T_links[static_cast<std::size_t>(finger.parent)];
  const Eigen::Vector3d tool_closing = root_T_tool.linear().transpose() * root_T_hand.linear() * finger.parent_T_joint.linear() * finger.axis;
  const Eigen::Vector3d tool_p_hand = root_T_tool.inverse() * root_T_hand.translation();
  const std::string& tool = model.links()[static_cast<std::size_t>(robot.tip_link())].name;
  const std::string convention = "cluttertamp's tool frame has z the approach, from the hand towards between the fingertips, and "
                                 "the fingers closing along y (docs/file-formats.md); give a tip_link with that frame, e.g. a link "
                                 "on a fixed joint, turned so, in a copy of the URDF";
  auto axis_name = [](const Eigen::Vector3d& v) {
    Eigen::Index i = 0;
    v.cwiseAbs().maxCoeff(&i);
    return std::string(v[i] < 0 ? "-" : "") + "xyz"[i];
  };
  const double cos45 = std::sqrt(0.5);
  if (std::abs(tool_closing.y()) < cos45) {
    yaml.error(tip, "the fingers ('" + finger.name + "') close along the " + axis_name(tool_closing) + " axis of the tool frame '" +
                        tool + "', not its y axis: " + convention);
  } else if (tool_p_hand.norm() > 0.01 && -tool_p_hand.z() < cos45 * tool_p_hand.norm()) {
    yaml.error(tip, "the hand's base '" + model.links()[static_cast<std::size_t>(finger.parent)].name + "' lies along the " +
                        axis_name(tool_p_hand) + " axis of the tool frame '" + tool + "', where -z is expected: " + convention);
  }
}

// The fingers open by a distance, each half the stroke, along one prismatic joint: a
// revolute jaw or a joint too short for the stroke would put every plan's finger
// values outside the URDF's limits. The tool frame is checked against the hand's joint as well.
void check_fingers(const YamlFile& yaml, const YAML::Node& stroke, const YAML::Node& tip, const RobotDescription& robot) {
  const auto finger = robot.finger_variable();
  if (!finger) return;
  const RobotModel& model = *robot.model();
  const Joint& joint = model.joints()[static_cast<std::size_t>(model.variables()[static_cast<std::size_t>(*finger)])];
  if (joint.type != JointType::prismatic) {
    yaml.error(stroke, "the finger joint '" + joint.name +
                           "' (the first movable joint below the tool that IK does not move) is revolute: cluttertamp opens the "
                           "fingers by a distance along a prismatic joint; make the hand's joints fixed in a copy of the URDF to "
                           "plan with the hand as modelled");
    return;
  }
  const double half = robot.gripper().stroke / 2;
  if (half > joint.upper + 1e-9) {
    char text[256];
    std::snprintf(text, sizeof text, "a stroke of %.6g m opens the finger joint '%s' %.6g m, beyond its upper limit %.6g m: the stroke is at most %.6g m",
                  robot.gripper().stroke, joint.name.c_str(), half, joint.upper, 2 * joint.upper);
    yaml.error(stroke, text);
  }
  check_tool_frame(yaml, tip, robot, joint);
}
}  // namespace

void set_command_line_package_paths(std::vector<std::filesystem::path> directories) {
  std::lock_guard<std::mutex> lock(g_package_paths_mutex);
  g_command_line_package_paths = std::move(directories);
}

RobotDescription load_robot_description(const std::filesystem::path& file) {
  Diagnostics diagnostics;
  YamlFile yaml(file, diagnostics);
  diagnostics.throw_if_any();
  RobotDescription::Parts robot;
  robot.name = file.stem().string();
  MapReader top(yaml, yaml.root(), "the robot description",
                {"version", "name", "urdf", "base_link", "tip_link", "ik", "gripper", "home", "disabled_collisions",
                  "package_paths", "mesh_collision", "srdf", "group"});
  if (!top.valid()) diagnostics.throw_if_any();

  yaml.check_version(top.required("version"), "robot description", 1);
  if (top.has("name")) robot.name = yaml.string(top.optional("name"), "name").value_or(robot.name);
  const YAML::Node urdf = top.required("urdf");
  // An SRDF group may give the chain; base_link and tip_link then only override it.
  const YAML::Node group = top.optional("group");
  const YAML::Node base = group.IsDefined() ? top.optional("base_link") : top.required("base_link");
  const YAML::Node tip = group.IsDefined() ? top.optional("tip_link") : top.required("tip_link");
  const YAML::Node ik = top.required("ik");
  const auto urdf_name = urdf.IsDefined() ? yaml.string(urdf, "urdf") : std::nullopt;
  const auto base_name = base.IsDefined() ? yaml.string(base, "base_link") : std::nullopt;
  const auto tip_name = tip.IsDefined() ? yaml.string(tip, "tip_link") : std::nullopt;
  const auto ik_name = ik.IsDefined() ? yaml.string(ik, "ik") : std::nullopt;
  if (ik_name && *ik_name != "ur_analytic" && *ik_name != "numeric") {
    yaml.error(ik, "ik must be 'ur_analytic' or 'numeric', not '" + *ik_name + "'");
  }

  YAML::Node stroke = top.optional("gripper");  // where a finger joint that cannot open the stroke is reported
  if (top.has("gripper")) {
    MapReader g(yaml, top.optional("gripper"), "gripper", {"finger_thickness", "base_half_length", "stroke", "large_base"});
    if (g.has("stroke")) stroke.reset(g.optional("stroke"));  // reset: = would overwrite the gripper node
    if (g.valid()) {
      auto read = [&](const char* key, double& out) {
        const YAML::Node n = g.required(key);
        if (n.IsDefined()) {
          auto value = yaml.number(n, std::string("gripper ") + key);
          if (value && *value < 0) yaml.error(n, std::string("gripper ") + key + " must not be negative");
          out = value.value_or(0.0);
        }
      };
      read("finger_thickness", robot.gripper.finger_thickness);
      read("base_half_length", robot.gripper.base_half_length);
      read("stroke", robot.gripper.stroke);
      if (g.has("large_base")) robot.gripper.large_base = yaml.boolean(g.optional("large_base"), "gripper large_base").value_or(false);
    }
  } else {
    top.required("gripper");
  }
  const UrdfOptions urdf_loading = urdf_options(yaml, top);
  top.report_unknown_keys();
  diagnostics.throw_if_any();

  robot.urdf = yaml.resolve(*urdf_name);
  if (std::error_code ec; !std::filesystem::exists(robot.urdf, ec)) {
    yaml.error(urdf, "urdf: no such file '" + *urdf_name + "' (" + robot.urdf.string() + ")");
    diagnostics.throw_if_any();
  }
  robot.model = std::make_shared<const RobotModel>(RobotModel::load_urdf(robot.urdf, urdf_loading));
  const RobotModel& model = *robot.model;
  auto link = [&](const YAML::Node& node, const std::string& name) -> LinkIndex {
    if (auto index = model.find_link(name)) return *index;
    yaml.error(node, "the URDF " + robot.urdf.string() + " has no link '" + name + "'");
    return -1;
  };
  std::optional<Srdf> srdf;  // a MoveIt SRDF: its disable_collisions join ours
  if (top.has("srdf")) {
    if (const auto name = yaml.string(top.optional("srdf"), "srdf")) srdf = load_srdf(yaml.resolve(*name), model);
  }
  if (base_name) robot.base_link = link(base, *base_name);
  if (tip_name) robot.tip_link = link(tip, *tip_name);
  if (group.IsDefined()) chain_from_group(yaml, group, srdf, top.has("srdf"), model, robot);

  if (top.has("disabled_collisions")) {
    const YAML::Node pairs = top.optional("disabled_collisions");
    if (!pairs.IsSequence()) yaml.error(pairs, "disabled_collisions must be a list of [link, link] pairs");
    for (std::size_t i = 0; pairs.IsSequence() && i < pairs.size(); ++i) {
      const auto names = yaml.strings(pairs[i], "disabled_collisions entry");
      if (!names) continue;
      if (names->size() != 2) {
        yaml.error(pairs[i], "each disabled_collisions entry names two links");
        continue;
      }
      const LinkIndex a = link(pairs[i][0], (*names)[0]), b = link(pairs[i][1], (*names)[1]);
      if (a >= 0 && b >= 0) robot.disabled_collisions.emplace_back(a, b);
    }
  }
  if (srdf) {
    for (const DisabledPair& p : srdf->disabled_collisions) robot.disabled_collisions.emplace_back(p.first, p.second);
  }
  robot.home = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(model.variable_count()));
  if (top.has("home")) read_home(yaml, top.optional("home"), srdf, top.has("srdf"), model, robot.home);
  diagnostics.throw_if_any();

  try {
    if (*ik_name == "ur_analytic") {
      robot.ik = std::make_shared<UrAnalyticIk>(robot.model, robot.base_link, robot.tip_link);
    } else {
      robot.ik = std::make_shared<NumericIk>(robot.model, robot.base_link, robot.tip_link);
    }
  } catch (const std::invalid_argument& e) {
    yaml.error(ik, e.what());
  }
  diagnostics.throw_if_any();
  RobotDescription description(std::move(robot));
  check_fingers(yaml, stroke, tip.IsDefined() ? tip : group, description);
  diagnostics.throw_if_any();
  return description;
}

}  // namespace cluttertamp::io
