#include "cluttertamp/robot/robot_model.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <mutex>
#include <set>
#include <stdexcept>

#include <console_bridge/console.h>
#include <urdf_model/model.h>
#include <urdf_parser/urdf_parser.h>

#include <fstream>
#include <sstream>

#include "cluttertamp/core/diagnostics.hpp"

namespace cluttertamp::robot {

namespace fs = std::filesystem;

namespace {

// urdfdom reports why a file is malformed only through console_bridge; this handler
// keeps the messages of one parse so they can go into our own error.
class CapturingHandler : public console_bridge::OutputHandler {
 public:
  void log(const std::string& text, console_bridge::LogLevel level, const char*, int) override {
    if (level >= console_bridge::CONSOLE_BRIDGE_LOG_WARN) messages.push_back(text);
  }
  std::vector<std::string> messages;
};

std::mutex g_console_mutex;  // console_bridge's handler is process-global

std::shared_ptr<urdf::ModelInterface> parse(const fs::path& file, const std::string& xml) {
  std::lock_guard<std::mutex> lock(g_console_mutex);
  CapturingHandler handler;
  console_bridge::useOutputHandler(&handler);
  std::shared_ptr<urdf::ModelInterface> model = urdf::parseURDF(xml);
  console_bridge::restorePreviousOutputHandler();
  if (!model) {
    std::string why;
    for (const std::string& m : handler.messages) why += (why.empty() ? "" : "; ") + m;
    throw InputError({file.string(), 0, 0}, "malformed URDF: " + (why.empty() ? std::string("the parser gave no reason") : why));
  }
  return model;
}

Eigen::Isometry3d to_isometry(const urdf::Pose& pose) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.translation() = Eigen::Vector3d(pose.position.x, pose.position.y, pose.position.z);
  t.linear() = Eigen::Quaterniond(pose.rotation.w, pose.rotation.x, pose.rotation.y, pose.rotation.z)
                   .normalized()
                   .toRotationMatrix();
  return t;
}

Shape to_shape(const fs::path& file, const std::string& link, std::size_t index, const urdf::Geometry& geometry) {
  const std::string where = "link '" + link + "' <collision> #" + std::to_string(index + 1);
  switch (geometry.type) {
    case urdf::Geometry::BOX: {
      const auto& box = static_cast<const urdf::Box&>(geometry);
      Eigen::Vector3d size(box.dim.x, box.dim.y, box.dim.z);
      if ((size.array() <= 0).any()) throw InputError({file.string(), 0, 0}, where + ": box size must be positive");
      return Box{size};
    }
    case urdf::Geometry::CYLINDER: {
      const auto& c = static_cast<const urdf::Cylinder&>(geometry);
      if (c.radius <= 0 || c.length <= 0) {
        throw InputError({file.string(), 0, 0}, where + ": cylinder radius and length must be positive");
      }
      return Cylinder{c.radius, c.length};
    }
    case urdf::Geometry::SPHERE: {
      const auto& s = static_cast<const urdf::Sphere&>(geometry);
      if (s.radius <= 0) throw InputError({file.string(), 0, 0}, where + ": sphere radius must be positive");
      return Sphere{s.radius};
    }
    case urdf::Geometry::MESH:
      throw InputError({file.string(), 0, 0},
                       where + " is a <mesh>; cluttertamp needs primitive collision geometry (box, cylinder, sphere)");
  }
  throw InputError({file.string(), 0, 0}, where + " has an unknown geometry type");
}

}  // namespace

RobotModel RobotModel::load_urdf(const fs::path& file) {
  std::ifstream in(file);
  if (!in) throw InputError({file.string(), 0, 0}, fs::exists(file) ? "cannot read the URDF file" : "no such URDF file");
  std::stringstream text;
  text << in.rdbuf();
  const auto urdf_model = parse(file, text.str());

  RobotModel model;
  model.name_ = urdf_model->getName();
  // Links in name order for determinism; the tree fixes the topological order later.
  std::map<std::string, LinkIndex> link_index;
  for (const auto& [name, link] : urdf_model->links_) {
    link_index[name] = static_cast<LinkIndex>(model.links_.size());
    Link l;
    l.name = name;
    for (std::size_t i = 0; i < link->collision_array.size(); ++i) {
      const auto& c = link->collision_array[i];
      if (!c || !c->geometry) continue;
      l.collision.push_back({to_shape(file, name, i, *c->geometry), to_isometry(c->origin)});
    }
    model.links_.push_back(std::move(l));
  }
  for (const auto& [name, urdf_joint] : urdf_model->joints_) {
    const std::string where = "joint '" + name + "'";
    Joint j;
    j.name = name;
    j.parent = link_index.at(urdf_joint->parent_link_name);
    j.child = link_index.at(urdf_joint->child_link_name);
    j.parent_T_joint = to_isometry(urdf_joint->parent_to_joint_origin_transform);
    const Eigen::Vector3d axis(urdf_joint->axis.x, urdf_joint->axis.y, urdf_joint->axis.z);
    switch (urdf_joint->type) {
      case urdf::Joint::FIXED: j.type = JointType::fixed; break;
      case urdf::Joint::REVOLUTE:
      case urdf::Joint::CONTINUOUS: j.type = JointType::revolute; break;
      case urdf::Joint::PRISMATIC: j.type = JointType::prismatic; break;
      default:
        throw InputError({file.string(), 0, 0},
                         where + " is planar or floating; model a mobile base as prismatic x, y and revolute yaw joints");
    }
    if (j.type != JointType::fixed) {
      if (axis.norm() < 1e-9) throw InputError({file.string(), 0, 0}, where + " has a zero <axis>");
      j.axis = axis.normalized();
      if (!urdf_joint->limits || urdf_joint->limits->velocity <= 0) {
        throw InputError({file.string(), 0, 0}, where + " needs <limit velocity=...> greater than zero");
      }
      j.max_velocity = urdf_joint->limits->velocity;
      if (urdf_joint->type == urdf::Joint::CONTINUOUS) {
        j.continuous = true;
        j.lower = -M_PI;
        j.upper = M_PI;
      } else {
        j.lower = urdf_joint->limits->lower;
        j.upper = urdf_joint->limits->upper;
        if (!(j.lower <= j.upper)) throw InputError({file.string(), 0, 0}, where + " has <limit lower> above upper");
      }
    }
    model.links_[j.child].parent_joint = static_cast<JointIndex>(model.joints_.size());
    model.joints_.push_back(j);
  }
  // Mimic joints, once every joint has its index.
  for (const auto& [name, urdf_joint] : urdf_model->joints_) {
    if (!urdf_joint->mimic) continue;
    Joint& j = model.joints_[*model.find_joint(name)];
    const auto mimicked = model.find_joint(urdf_joint->mimic->joint_name);
    if (!mimicked || model.joints_[*mimicked].type == JointType::fixed || j.type == JointType::fixed) {
      throw InputError({file.string(), 0, 0}, "joint '" + name + "' mimics '" + urdf_joint->mimic->joint_name +
                                                  "', which is not a movable joint of this robot");
    }
    j.mimicked = *mimicked;
    j.multiplier = urdf_joint->mimic->multiplier;
    j.offset = urdf_joint->mimic->offset;
  }
  for (const Joint& j : model.joints_) {
    if (j.mimicked >= 0 && model.joints_[j.mimicked].mimicked >= 0) {
      throw InputError({file.string(), 0, 0}, "joint '" + j.name + "' mimics a joint that mimics another; not supported");
    }
  }
  model.finish();
  return model;
}

void RobotModel::finish() {
  // Topological order from the root (the one link without a parent joint).
  std::vector<std::vector<JointIndex>> children(links_.size());
  LinkIndex root = -1;
  for (std::size_t j = 0; j < joints_.size(); ++j) children[joints_[j].parent].push_back(static_cast<JointIndex>(j));
  for (std::size_t l = 0; l < links_.size(); ++l) {
    if (links_[l].parent_joint < 0) root = static_cast<LinkIndex>(l);
  }
  order_.clear();
  variables_.clear();
  std::function<void(LinkIndex)> visit = [&](LinkIndex link) {
    order_.push_back(link);
    for (JointIndex j : children[link]) {
      if (joints_[j].type != JointType::fixed && joints_[j].mimicked < 0) {
        joints_[j].variable = static_cast<std::int32_t>(variables_.size());
        variables_.push_back(j);
      }
      visit(joints_[j].child);
    }
  };
  visit(root);

  const auto n = static_cast<Eigen::Index>(variables_.size());
  lower_.resize(n);
  upper_.resize(n);
  velocity_.resize(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const Joint& j = joints_[variables_[i]];
    lower_[i] = j.lower;
    upper_[i] = j.upper;
    velocity_[i] = j.max_velocity;
  }

  // Pairs never checked for collision: links of one rigid body (joined by fixed joints
  // only), and links of two rigid bodies joined by one movable joint.
  adjacent_.clear();
  rigid_root_.assign(links_.size(), -1);
  for (LinkIndex l : order_) {
    const JointIndex j = links_[l].parent_joint;
    rigid_root_[l] = (j >= 0 && joints_[j].type == JointType::fixed) ? rigid_root_[joints_[j].parent] : l;
  }
  auto parent_body = [&](LinkIndex body) -> LinkIndex {
    const JointIndex j = links_[body].parent_joint;
    return j < 0 ? -1 : rigid_root_[joints_[j].parent];
  };
  for (std::size_t a = 0; a < links_.size(); ++a) {
    if (links_[a].collision.empty()) continue;
    for (std::size_t b = a + 1; b < links_.size(); ++b) {
      if (links_[b].collision.empty()) continue;
      const LinkIndex ra = rigid_root_[a], rb = rigid_root_[b];
      if (ra == rb || parent_body(ra) == rb || parent_body(rb) == ra) {
        adjacent_.emplace_back(static_cast<LinkIndex>(a), static_cast<LinkIndex>(b));
      }
    }
  }
  std::sort(adjacent_.begin(), adjacent_.end());
  adjacent_.erase(std::unique(adjacent_.begin(), adjacent_.end()), adjacent_.end());
}

bool RobotModel::within_limits(const Eigen::VectorXd& q, double tolerance) const {
  return q.size() == lower_.size() && (q.array() >= lower_.array() - tolerance).all() &&
         (q.array() <= upper_.array() + tolerance).all();
}

double Joint::value(const Eigen::VectorXd& q, const std::vector<Joint>& joints) const {
  if (variable >= 0) return q[variable];
  if (mimicked >= 0) return multiplier * q[joints[mimicked].variable] + offset;
  return 0.0;
}

std::vector<std::string> RobotModel::variable_names() const {
  std::vector<std::string> names;
  for (JointIndex j : variables_) names.push_back(joints_[j].name);
  return names;
}

bool RobotModel::descends_from(LinkIndex link, LinkIndex ancestor) const {
  while (link != ancestor) {
    const JointIndex j = links_[link].parent_joint;
    if (j < 0) return false;
    link = joints_[j].parent;
  }
  return true;
}

std::optional<LinkIndex> RobotModel::find_link(std::string_view name) const {
  for (std::size_t i = 0; i < links_.size(); ++i) {
    if (links_[i].name == name) return static_cast<LinkIndex>(i);
  }
  return std::nullopt;
}

std::optional<JointIndex> RobotModel::find_joint(std::string_view name) const {
  for (std::size_t i = 0; i < joints_.size(); ++i) {
    if (joints_[i].name == name) return static_cast<JointIndex>(i);
  }
  return std::nullopt;
}

Eigen::Isometry3d RobotModel::joint_transform(const Joint& joint, double value) {
  switch (joint.type) {
    case JointType::fixed: return joint.parent_T_joint;
    case JointType::revolute: {
      Eigen::Isometry3d t = joint.parent_T_joint;
      if (joint.axis.z() == 1.0) {  // the common case: a rotation about z, without AngleAxis
        const double c = std::cos(value), s = std::sin(value);
        Eigen::Matrix3d rz;
        rz << c, -s, 0, s, c, 0, 0, 0, 1;
        t.linear() = t.linear() * rz;
      } else {
        t.linear() = t.linear() * Eigen::AngleAxisd(value, joint.axis).toRotationMatrix();
      }
      return t;
    }
    case JointType::prismatic: {
      Eigen::Isometry3d t = joint.parent_T_joint;
      t.translation() += t.linear() * (joint.axis * value);
      return t;
    }
  }
  return joint.parent_T_joint;
}

void RobotModel::link_poses(const Eigen::VectorXd& q, std::vector<Eigen::Isometry3d>& root_T_links) const {
  root_T_links.resize(links_.size());
  for (LinkIndex link : order_) {
    const JointIndex j = links_[link].parent_joint;
    if (j < 0) {
      root_T_links[link].setIdentity();
      continue;
    }
    const Joint& joint = joints_[j];
    root_T_links[link] = root_T_links[joint.parent] * joint_transform(joint, joint.value(q, joints_));
  }
}

std::vector<JointIndex> RobotModel::chain(LinkIndex base, LinkIndex tip) const {
  std::vector<JointIndex> joints;
  LinkIndex current = tip;
  while (current != base) {
    const JointIndex j = links_.at(current).parent_joint;
    if (j < 0) {
      throw std::invalid_argument("link '" + links_.at(tip).name + "' does not descend from '" + links_.at(base).name + "'");
    }
    if (joints_[j].variable >= 0) joints.push_back(j);
    current = joints_[j].parent;
  }
  std::reverse(joints.begin(), joints.end());
  return joints;
}

}  // namespace cluttertamp::robot
