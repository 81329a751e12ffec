#include "cluttertamp/robot/robot_model.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <mutex>
#include <set>
#include <stdexcept>
#include <tuple>

#include <console_bridge/console.h>
#include <urdf_model/model.h>
#include <urdf_parser/urdf_parser.h>

#include "cluttertamp/core/diagnostics.hpp"
#include "robot/urdf_check.hpp"

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

Shape to_shape(const fs::path& file, const std::string& link, std::size_t index, const urdf::Geometry& geometry,
               const char* element = "collision") {
  const std::string where = "link '" + link + "' <" + element + "> #" + std::to_string(index + 1);
  switch (geometry.type) {
    case urdf::Geometry::BOX: {
      const auto& box = static_cast<const urdf::Box&>(geometry);
      Eigen::Vector3d size(box.dim.x, box.dim.y, box.dim.z);
      if (!(size.array() > 0).all() || !size.allFinite()) throw InputError({file.string(), 0, 0}, where + ": box size must be positive");
      return Box{size};
    }
    case urdf::Geometry::CYLINDER: {
      const auto& c = static_cast<const urdf::Cylinder&>(geometry);
      if (!(c.radius > 0 && c.length > 0) || !std::isfinite(c.radius) || !std::isfinite(c.length)) {
        throw InputError({file.string(), 0, 0}, where + ": cylinder radius and length must be positive");
      }
      return Cylinder{c.radius, c.length};
    }
    case urdf::Geometry::SPHERE: {
      const auto& s = static_cast<const urdf::Sphere&>(geometry);
      if (!(s.radius > 0) || !std::isfinite(s.radius)) throw InputError({file.string(), 0, 0}, where + ": sphere radius must be positive");
      return Sphere{s.radius};
    }
    case urdf::Geometry::MESH: break;  // MeshReader
  }
  throw InputError({file.string(), 0, 0}, where + " has an unknown geometry type");
}

// Where `filename="uri"` first stands in the URDF text (urdfdom keeps no positions).
SourceLocation locate(const fs::path& file, const std::string& text, const std::string& uri) {
  for (const char quote : {'"', '\''}) {
    const auto at = text.find(std::string("filename=") + quote + uri + quote);
    if (at == std::string::npos) continue;
    const auto line_start = text.rfind('\n', at);
    const std::size_t line = 1 + static_cast<std::size_t>(std::count(text.begin(), text.begin() + static_cast<long>(at), '\n'));
    return {file.string(), line, at - (line_start == std::string::npos ? 0 : line_start + 1) + 1};
  }
  return {file.string(), 0, 0};
}

// Reads the meshes of one URDF, each file once per scale.
class MeshReader {
 public:
  MeshReader(const fs::path& file, const std::string& text, const UrdfOptions& options)
      : file_(file), text_(text), options_(options) {}

  // What the mesh collides as: one shape (its hull, or its triangles), or its convex pieces.
  std::vector<CollisionShape> shapes(const std::string& link, std::size_t index, const urdf::Mesh& m,
                                     const Eigen::Isometry3d& link_T_mesh) {
    const SourceLocation at = locate(file_, text_, m.filename);
    const Eigen::Vector3d scale = checked_scale(m, at, "link '" + link + "' <collision> #" + std::to_string(index + 1));
    const fs::path found = resolve_mesh_uri(m.filename, file_.parent_path(), options_.packages, at);
    const MeshCollision how = options_.mesh_collision;
    auto& cached = cache_[{found.string(), scale.x(), scale.y(), scale.z()}];
    if (cached.empty()) {
      TriangleMesh mesh = load_mesh(found, scale, at);
      if (how == MeshCollision::convex_pieces) {
        for (TriangleMesh& piece : convex_pieces(mesh, at)) cached.push_back(std::make_shared<const TriangleMesh>(std::move(piece)));
      } else {
        cached.push_back(std::make_shared<const TriangleMesh>(how == MeshCollision::convex_hull ? convex_hull(mesh, at) : std::move(mesh)));
      }
    }
    std::vector<CollisionShape> out;
    for (const auto& mesh : cached) {
      CollisionShape c;
      c.mesh = mesh;
      c.convex = how != MeshCollision::triangles;
      c.link_T_mesh = link_T_mesh;
      Eigen::Vector3d min, max;
      mesh->bounds(min, max);
      c.shape = Box{(max - min).cwiseMax(1e-6)};
      c.link_T_shape = link_T_mesh * Eigen::Translation3d((min + max) / 2);
      out.push_back(std::move(c));
    }
    return out;
  }

  // A visual mesh is found now (a missing file is an error here, not when drawing) and
  // read only by what draws it.
  VisualShape visual(const std::string& link, std::size_t index, const urdf::Mesh& m, const Eigen::Isometry3d& link_T_mesh) {
    const SourceLocation at = locate(file_, text_, m.filename);
    VisualShape v;
    v.mesh_scale = checked_scale(m, at, "link '" + link + "' <visual> #" + std::to_string(index + 1));
    v.mesh_file = resolve_mesh_uri(m.filename, file_.parent_path(), options_.packages, at).string();
    v.link_T_visual = link_T_mesh;
    return v;
  }

 private:
  static Eigen::Vector3d checked_scale(const urdf::Mesh& m, const SourceLocation& at, const std::string& where) {
    const Eigen::Vector3d scale(m.scale.x, m.scale.y, m.scale.z);
    if (!scale.allFinite() || (scale.array() == 0).any()) throw InputError(at, where + ": mesh scale must be finite and not zero");
    return scale;
  }

  const fs::path& file_;
  const std::string& text_;
  const UrdfOptions& options_;
  // One reader makes one kind of collision geometry: the file and scale say which mesh.
  std::map<std::tuple<std::string, double, double, double>, std::vector<std::shared_ptr<const TriangleMesh>>> cache_;
};

}  // namespace

RobotModel RobotModel::load_urdf(const fs::path& file) { return load_urdf(file, UrdfOptions{PackagePaths::with_environment({})}); }

RobotModel RobotModel::load_urdf(const fs::path& file, const UrdfOptions& options) {
  const std::string xml = read_urdf_text(file);
  check_urdf(file, xml);  // with positions: urdfdom keeps none, and lets some mistakes pass
  const auto urdf_model = parse(file, xml);
  MeshReader meshes(file, xml, options);

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
      if (c->geometry->type == urdf::Geometry::MESH) {
        for (CollisionShape& piece : meshes.shapes(name, i, static_cast<const urdf::Mesh&>(*c->geometry), to_isometry(c->origin))) {
          l.collision.push_back(std::move(piece));
        }
      } else {
        CollisionShape primitive;
        primitive.shape = to_shape(file, name, i, *c->geometry);
        primitive.link_T_shape = to_isometry(c->origin);
        l.collision.push_back(std::move(primitive));
      }
    }
    for (std::size_t i = 0; i < link->visual_array.size(); ++i) {
      const auto& v = link->visual_array[i];
      if (!v || !v->geometry) continue;
      if (v->geometry->type == urdf::Geometry::MESH) {
        l.visual.push_back(meshes.visual(name, i, static_cast<const urdf::Mesh&>(*v->geometry), to_isometry(v->origin)));
      } else {
        VisualShape primitive;
        primitive.primitive = to_shape(file, name, i, *v->geometry, "visual");
        primitive.link_T_visual = to_isometry(v->origin);
        l.visual.push_back(std::move(primitive));
      }
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
  // Depth first, children in joint order, without recursion: a chain may be long.
  // Each entry: a link, and the next of its child joints to visit (-1: the link itself).
  std::vector<std::pair<LinkIndex, std::ptrdiff_t>> stack{{root, -1}};
  while (!stack.empty()) {
    auto& [link, next] = stack.back();
    if (next < 0) {
      order_.push_back(link);
      next = 0;
    }
    if (static_cast<std::size_t>(next) == children[link].size()) {
      stack.pop_back();
      continue;
    }
    const JointIndex j = children[link][static_cast<std::size_t>(next++)];
    if (joints_[j].type != JointType::fixed && joints_[j].mimicked < 0) {
      joints_[j].variable = static_cast<std::int32_t>(variables_.size());
      variables_.push_back(j);
    }
    stack.emplace_back(joints_[j].child, -1);
  }

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
