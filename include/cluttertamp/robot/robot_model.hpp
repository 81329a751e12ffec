#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <Eigen/Geometry>

#include "cluttertamp/core/geometry.hpp"
#include "cluttertamp/export.hpp"
#include "cluttertamp/robot/mesh.hpp"

namespace cluttertamp::robot {

using LinkIndex = std::int32_t;
using JointIndex = std::int32_t;

enum class JointType { fixed, revolute, prismatic };

/// A joint of the kinematic tree. The child link's frame is
/// parent_T_child = parent_T_joint * motion(q), where motion is a rotation about
/// (revolute) or translation along (prismatic) `axis`, a unit vector in the joint frame.
struct Joint {
  std::string name;
  JointType type = JointType::fixed;
  LinkIndex parent = -1;
  LinkIndex child = -1;
  Eigen::Isometry3d parent_T_joint = Eigen::Isometry3d::Identity();
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();
  double lower = 0.0;         ///< rad or m
  double upper = 0.0;         ///< rad or m
  double max_velocity = 0.0;  ///< rad/s or m/s
  bool continuous = false;    ///< a URDF continuous joint: revolute, limits [-pi, pi], wraps
  std::int32_t variable = -1;  ///< index in a configuration vector; -1 for fixed and mimic joints
  /// A URDF <mimic> joint follows another: value = multiplier * value(mimicked) + offset.
  JointIndex mimicked = -1;
  double multiplier = 1.0;
  double offset = 0.0;

  /// This joint's value in configuration q.
  double value(const Eigen::VectorXd& q, const std::vector<Joint>& joints) const;
};

/// A collision body of a link: a primitive, or a mesh.
struct CollisionShape {
  /// The primitive, placed in the link frame. For a mesh: the box bounding it (what a
  /// user of primitives only sees, conservative).
  Shape shape;
  Eigen::Isometry3d link_T_shape = Eigen::Isometry3d::Identity();
  /// For a URDF <mesh>: what collides, in the frame link_T_mesh (its convex hull or its
  /// triangles, as `convex` says). Null for a primitive.
  std::shared_ptr<const TriangleMesh> mesh;
  Eigen::Isometry3d link_T_mesh = Eigen::Isometry3d::Identity();
  bool convex = false;
};

/// How URDF meshes are found and made to collide.
struct UrdfOptions {
  /// Where package:// URIs are looked for (PackagePaths::with_environment adds ROS_PACKAGE_PATH).
  PackagePaths packages;
  MeshCollision mesh_collision = MeshCollision::convex_pieces;
};

/// What a link looks like (URDF <visual>): a primitive, or a mesh file that is read
/// only when something draws it.
struct VisualShape {
  std::optional<Shape> primitive;
  std::string mesh_file;  ///< resolved path; empty for a primitive
  Eigen::Vector3d mesh_scale = Eigen::Vector3d::Ones();
  Eigen::Isometry3d link_T_visual = Eigen::Isometry3d::Identity();
};

struct Link {
  std::string name;
  JointIndex parent_joint = -1;  ///< -1 for the root
  std::vector<CollisionShape> collision;
  std::vector<VisualShape> visual;
};

/// A robot's kinematic tree as read from a URDF: links, joints, joint limits and
/// primitive collision geometry. Poses are relative to the root link. A configuration
/// holds one value (rad or m) per movable joint that does not mimic another, in
/// depth-first order from the root, the children of a link in joint-name order
/// (variable_names() lists them).
/// Immutable after loading; every const member is safe to call from several threads.
class CLUTTERTAMP_API RobotModel {
 public:
  /// Reads a URDF file: box, cylinder, sphere and mesh collision geometry (meshes found
  /// as `options` say; STL, DAE, OBJ). Throws InputError naming the file and the element
  /// (with the line of a <mesh>) for a malformed file, a mesh that is missing or
  /// unreadable, a planar or floating joint (not supported; model a base as prismatic
  /// and revolute joints), or a revolute or prismatic joint without a velocity limit.
  static RobotModel load_urdf(const std::filesystem::path& file, const UrdfOptions& options);
  /// The same, with package paths from ROS_PACKAGE_PATH only and convex-hull collision.
  static RobotModel load_urdf(const std::filesystem::path& file);

  const std::string& name() const { return name_; }
  const std::vector<Link>& links() const { return links_; }
  const std::vector<Joint>& joints() const { return joints_; }
  /// Links in an order where every parent precedes its children; links()[order[0]] is the root.
  const std::vector<LinkIndex>& topological_order() const { return order_; }

  std::size_t variable_count() const { return variables_.size(); }
  /// The joint of each configuration variable.
  const std::vector<JointIndex>& variables() const { return variables_; }
  /// The joint name of each configuration variable, in configuration order.
  std::vector<std::string> variable_names() const;
  const Eigen::VectorXd& lower_limits() const { return lower_; }
  const Eigen::VectorXd& upper_limits() const { return upper_; }
  const Eigen::VectorXd& velocity_limits() const { return velocity_; }
  bool within_limits(const Eigen::VectorXd& q, double tolerance = 1e-9) const;

  std::optional<LinkIndex> find_link(std::string_view name) const;
  std::optional<JointIndex> find_joint(std::string_view name) const;

  /// Root-frame poses of every link for configuration q (size variable_count()).
  /// `root_T_links` is resized to links().size(); pass the same vector again to
  /// avoid allocation.
  void link_poses(const Eigen::VectorXd& q, std::vector<Eigen::Isometry3d>& root_T_links) const;

  /// The joints with a configuration variable from `base` down to `tip`, in order
  /// (mimic joints on the way follow their variables). Throws
  /// std::invalid_argument when `tip` does not descend from `base`.
  std::vector<JointIndex> chain(LinkIndex base, LinkIndex tip) const;

  /// Pairs of links (first < second) whose collision is never checked: links of the
  /// same rigid body (joined by fixed joints only) and links of two rigid bodies
  /// joined by one movable joint.
  const std::vector<std::pair<LinkIndex, LinkIndex>>& adjacent_links() const { return adjacent_; }

  /// The link that `link` is rigidly attached to through fixed joints only (itself
  /// when its parent joint moves): links with the same rigid root move as one body.
  LinkIndex rigid_root(LinkIndex link) const { return rigid_root_[static_cast<std::size_t>(link)]; }
  /// True when `link` is `ancestor` or lies below it in the tree.
  bool descends_from(LinkIndex link, LinkIndex ancestor) const;

  /// parent_T_joint * motion(value): the transform a joint contributes.
  static Eigen::Isometry3d joint_transform(const Joint& joint, double value);

 private:
  void finish();  // computes order, variables, limits and adjacency after loading

  std::string name_;
  std::vector<Link> links_;
  std::vector<Joint> joints_;
  std::vector<LinkIndex> order_;
  std::vector<JointIndex> variables_;
  Eigen::VectorXd lower_, upper_, velocity_;
  std::vector<std::pair<LinkIndex, LinkIndex>> adjacent_;
  std::vector<LinkIndex> rigid_root_;
};

}  // namespace cluttertamp::robot
