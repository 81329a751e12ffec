// The pusher an arm makes, and a problem's `physics:` block read into PushSettings.
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "cluttertamp/core/problem.hpp"
#include "cluttertamp/physics/push_world.hpp"
#include "cluttertamp/robot/robot_description.hpp"

namespace cluttertamp::physics {

namespace {

using robot::CollisionShape;
using robot::LinkIndex;
using robot::JointIndex;
using robot::RobotModel;

// A mesh part: its bounding box as the shape (centred where link_T_shape puts it) and
// its vertices in that box's frame.
PusherPart mesh_part(const CollisionShape& c, const Eigen::Isometry3d& arm_T_link) {
  PusherPart part{c.shape, arm_T_link * c.link_T_shape, {}};
  const Eigen::Isometry3d shape_T_mesh = c.link_T_shape.inverse() * c.link_T_mesh;
  part.hull.reserve(c.mesh->vertices.size());
  for (const Eigen::Vector3d& v : c.mesh->vertices) part.hull.push_back(shape_T_mesh * v);
  return part;
}

// The hand: the tip link and every link below the child of the chain's last moving joint.
LinkIndex hand_root(const robot::RobotDescription& robot) {
  const RobotModel& model = *robot.model();
  const std::vector<JointIndex> chain = model.chain(robot.base_link(), robot.tip_link());
  return chain.empty() ? robot.tip_link() : model.joints()[static_cast<std::size_t>(chain.back())].child;
}

std::vector<double> as_vector(const Eigen::VectorXd& v) { return {v.data(), v.data() + v.size()}; }

}  // namespace

ArmPusher arm_pusher(const robot::RobotDescription& robot, const Eigen::VectorXd& posture) {
  const RobotModel& model = *robot.model();
  if (static_cast<std::size_t>(posture.size()) != model.variable_count()) {
    throw std::invalid_argument("arm_pusher: the posture needs " + std::to_string(model.variable_count()) + " values, one per joint variable");
  }
  std::vector<Eigen::Isometry3d> root_T_links;
  model.link_poses(posture, root_T_links);
  const Eigen::Isometry3d arm_T_root = root_T_links[static_cast<std::size_t>(robot.base_link())].inverse();
  const LinkIndex hand = hand_root(robot);
  ArmPusher arm;
  arm.robot = robot.name();
  arm.arm_T_tcp = arm_T_root * root_T_links[static_cast<std::size_t>(robot.tip_link())];
  for (std::size_t l = 0; l < model.links().size(); ++l) {
    const Eigen::Isometry3d arm_T_link = arm_T_root * root_T_links[l];
    for (const CollisionShape& c : model.links()[l].collision) {
      arm.parts.push_back(c.mesh ? mesh_part(c, arm_T_link) : PusherPart{c.shape, arm_T_link * c.link_T_shape, {}});
      arm.hand.push_back(model.descends_from(static_cast<LinkIndex>(l), hand));
    }
  }
  return arm;
}

double base_offset_for_lever(const ArmPusher& arm, double lever) {
  const Eigen::Vector2d tcp = arm.arm_T_tcp.translation().head<2>();
  return std::max(0.0, std::sqrt(std::max(0.0, lever * lever - tcp.y() * tcp.y())) - tcp.x());
}

PushSettings push_settings(const Problem& problem) {
  const Parameters p = problem.physics.fresh(/*collect=*/true);
  PushSettings s;
  const std::string pusher = p.get_string("pusher", "gripper",
                                          "what pushes: gripper (a floating gripper) or arm (the problem's robot, held in "
                                          "its posture on a holonomic planar base)");
  p.require(pusher == "gripper" || pusher == "arm", "pusher", "must be gripper or arm");
  s.time_step = p.get_double("time_step", s.time_step, "s per physics step", Range::open_closed(0, 0.1));
  const std::string combine = p.get_string("friction_combine", "product",
                                           "how two bodies' friction coefficients make a contact's: product (Bullet) or max (MuJoCo)");
  p.require(combine == "product" || combine == "max", "friction_combine", "must be product or max");
  if (combine == "max") s.friction_combine = PushSettings::FrictionCombine::max;
  const auto optional_double = [&](const char* key, std::string_view help, const Range& range) -> std::optional<double> {
    if (!p.contains(key)) {
      p.get_double(key, 0.0, help, range);  // declared for the help, absent
      return std::nullopt;
    }
    return p.get_double(key, 0.0, help, range);
  };
  s.fixed_friction = optional_double("fixed_friction", "every fixed body's friction coefficient (default: each its own)", Range::closed(0, 10));
  s.object_friction = optional_double("object_friction", "every movable object's friction coefficient (default: each its own)", Range::closed(0, 10));
  s.object_mass = optional_double("object_mass", "kg of every movable object (default: each its own)", Range::open_closed(0, 1e4));
  s.tip_limit = optional_double("tip_limit", "rad an object may tilt by the end of a control; set, objects tip (default: they never do)",
                                Range::open_closed(0, M_PI / 2));
  s.wall_force_limit = optional_double("wall_force_limit", "N on one contact point of a wall in any step (default: no limit)",
                                       Range::open_closed(0, 1e6));
  s.pusher_friction = p.get_double("pusher_friction", s.pusher_friction, "the pusher's friction coefficient", Range::closed(0, 10));
  s.gripper_clearance = p.get_double("clearance", s.gripper_clearance, "m between the support and the hand's lowest point",
                                     Range::closed(0, 1));
  if (p.contains("start")) {
    const std::vector<double> start = p.get_vector("start", {}, "the hand's start x, y (m), yaw (rad), world frame (default: at the exit facing +x)");
    p.require(start.size() == 3 && std::isfinite(start[0]) && std::isfinite(start[1]) && std::isfinite(start[2]), "start",
              "must be [x, y, yaw]");
    if (start.size() == 3) s.start_hand = Eigen::Vector3d(start[0], start[1], start[2]);
  }
  const bool arm = pusher == "arm";
  const double quarter = M_PI / 4;
  const std::vector<double> limits = p.get_vector("yaw_limits", arm ? std::vector<double>{-quarter, quarter} : std::vector<double>{},
                                                  "[min, max] rad of the pusher's heading, world frame (arm default +-pi/4; gripper: free)");
  p.require(limits.empty() || (limits.size() == 2 && limits[0] <= limits[1] && limits[1] - limits[0] < 2 * M_PI), "yaw_limits",
            "must be [min, max] with min <= max, less than a turn apart");
  if (limits.size() == 2 && limits[0] <= limits[1]) s.yaw_limits = {limits[0], limits[1]};
  const Eigen::VectorXd start_configuration = robot::initial_configuration(problem.robot);
  const std::vector<double> posture = p.get_vector("posture", as_vector(start_configuration),
                                                   "arm: joint values it pushes in (default: the problem's start, else the robot's home)");
  p.require(std::all_of(posture.begin(), posture.end(), [](double v) { return std::isfinite(v); }), "posture",
            "must be finite joint values");
  const std::vector<double> offset = p.get_vector("base_offset", {0.0, 0.0},
                                                  "arm: [x, y] m of the arm's base ahead of and left of the mobile base's centre",
                                                  Range::closed(-10, 10));
  p.require(offset.size() == 2, "base_offset", "must be [x, y]");
  const std::optional<double> hand_height =
      optional_double("hand_height", "arm: m of the tool centre point above the support (default: its lowest point at clearance)",
                      Range::open_closed(0, 2));
  for (const char* key : {"posture", "base_offset", "hand_height"}) {
    p.require(arm || !p.contains(key), key, "applies to pusher: arm only");
  }
  if (arm) {
    const auto* robot = problem.robot.loaded.get();
    p.require(robot != nullptr, "pusher", "arm needs the problem's robot (robot: {description: ...})");
    const bool fits = robot && posture.size() == robot->model()->variable_count();
    p.require(!robot || fits, "posture", "needs one value per joint variable of the robot");
    const Eigen::Map<const Eigen::VectorXd> q(posture.data(), Eigen::Index(posture.size()));
    p.require(!fits || robot->model()->within_limits(q, 1e-6), "posture", "is outside the robot's joint limits");
    if (fits) {
      auto made = std::make_shared<ArmPusher>(arm_pusher(*robot, q));
      if (offset.size() == 2) made->base_offset = {offset[0], offset[1]};
      // What PushWorld would refuse, said here at the key.
      p.require(!made->parts.empty(), "pusher", "arm needs a robot with collision geometry; '" + robot->name() + "' has none");
      p.require(made->arm_T_tcp.linear().col(2).head<2>().norm() >= 0.1, "posture",
                "points the tool up or down: it cannot push in the plane (the tool's z axis must lean at least 6 degrees from vertical)");
      s.arm = std::move(made);
      s.hand_height = hand_height;
    }
  }
  Diagnostics all = p.errors();
  std::vector<std::string> read;
  for (const ParameterDeclaration& d : p.declarations()) read.push_back(d.key);
  for (const std::string& key : p.unused()) {
    all.error(p.location(key), "unknown physics key '" + key + "'" + did_you_mean(key, read));
  }
  all.throw_if_any();
  return s;
}

}  // namespace cluttertamp::physics
