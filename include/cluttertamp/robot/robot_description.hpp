#pragma once

#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "cluttertamp/core/problem.hpp"
#include "cluttertamp/export.hpp"
#include "cluttertamp/robot/ik.hpp"
#include "cluttertamp/robot/robot_model.hpp"

namespace cluttertamp::robot {

/// The gripper measures the retrieval planner needs (Tian et al., Appendix B).
struct GripperParameters {
  double finger_thickness = 0.0;  ///< r_f, m
  double base_half_length = 0.0;  ///< r_base, m
  double stroke = 0.0;            ///< largest opening, m
  bool large_base = false;        ///< true when the base, not the fingers, bounds the footprint

  /// r_b: the radius of the target's footprint while held, for a target of radius r_g.
  double footprint_radius(double target_radius) const {
    return large_base ? base_half_length : target_radius + finger_thickness;
  }
};

/// A robot as the planners use it: the URDF model plus what a URDF does not say —
/// which chain is the arm, which link is the tool centre point, the IK solver, the
/// gripper's measures and a home configuration. Read from a robot description file
/// (docs/file-formats.md, "Robot description files") by io::load_robot_description.
class CLUTTERTAMP_API RobotDescription {
 public:
  /// What a description says, with the model it names loaded and its IK solver made.
  struct Parts {
    std::string name;
    std::filesystem::path urdf;
    std::shared_ptr<const RobotModel> model;  ///< not null
    LinkIndex base_link = -1;                 ///< a link of `model`
    LinkIndex tip_link = -1;                  ///< a link of `model`
    GripperParameters gripper;
    Eigen::VectorXd home;                     ///< one value per model variable
    std::shared_ptr<const IkSolver> ik;       ///< not null: the chain base_link to tip_link
    /// Link pairs never checked beyond the model's adjacent links, in any order.
    std::vector<std::pair<LinkIndex, LinkIndex>> disabled_collisions;
  };

  RobotDescription() = default;
  /// Finds the finger variable and merges the disabled pairs with the adjacent links.
  /// Throws std::invalid_argument when `model` or `ik` is null, a link is no link of
  /// the model or `home` has the wrong size.
  explicit RobotDescription(Parts parts);

  const std::string& name() const { return name_; }
  const std::shared_ptr<const RobotModel>& model() const { return model_; }
  const std::filesystem::path& urdf() const { return urdf_; }
  LinkIndex base_link() const { return base_link_; }
  LinkIndex tip_link() const { return tip_link_; }  ///< the TCP: grasp poses are its poses
  const GripperParameters& gripper() const { return gripper_; }
  const Eigen::VectorXd& home() const { return home_; }
  /// This description with another home configuration (one value per model variable;
  /// throws std::invalid_argument otherwise): how a problem's start stands in for it.
  RobotDescription with_home(Eigen::VectorXd home) const;
  /// The IK solver of the arm chain (base_link to tip_link). Its poses are in the
  /// base link's frame; a scene places the URDF's root (Scene::world_T_robot_base), so
  /// convert with world_T_ik_base().
  const IkSolver& ik() const { return *ik_; }
  /// The pose of the IK chain's base link in the URDF root's frame, the joints between
  /// them held at home (identity when base_link is the root).
  const Eigen::Isometry3d& root_T_ik_base() const { return root_T_ik_base_; }
  /// The IK chain's base link in the world for a root standing at `world_T_root`:
  /// IK targets are world_T_ik_base(world_T_root).inverse() * world_T_tool.
  Eigen::Isometry3d world_T_ik_base(const Eigen::Isometry3d& world_T_root) const { return world_T_root * root_T_ik_base_; }
  /// The configuration variable that opens and closes the fingers (a movable joint
  /// below the tool that is not on the IK chain), if the gripper has one.
  std::optional<int> finger_variable() const { return finger_variable_; }
  /// Link pairs (first < second) never checked against each other: the model's
  /// adjacent links plus the description's `disabled_collisions`, sorted.
  const std::vector<std::pair<LinkIndex, LinkIndex>>& disabled_collisions() const { return disabled_; }

 private:
  std::string name_;
  std::filesystem::path urdf_;
  std::shared_ptr<const RobotModel> model_;
  LinkIndex base_link_ = -1;
  LinkIndex tip_link_ = -1;
  GripperParameters gripper_;
  Eigen::VectorXd home_;
  std::shared_ptr<const IkSolver> ik_;
  Eigen::Isometry3d root_T_ik_base_ = Eigen::Isometry3d::Identity();
  std::vector<std::pair<LinkIndex, LinkIndex>> disabled_;
  std::optional<int> finger_variable_;
};

/// A problem's initial joint values (rad, m; URDF order): its `configuration`, or else
/// the home of its loaded description; empty when it has neither.
CLUTTERTAMP_API Eigen::VectorXd initial_configuration(const RobotSpec& spec);

}  // namespace cluttertamp::robot
