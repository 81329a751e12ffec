#include "cluttertamp/robot/robot_description.hpp"

#include <algorithm>
#include <stdexcept>

namespace cluttertamp::robot {

namespace {

Eigen::Isometry3d root_T_link(const RobotModel& model, const Eigen::VectorXd& q, LinkIndex link) {
  std::vector<Eigen::Isometry3d> root_T_links;
  model.link_poses(q, root_T_links);
  return root_T_links[static_cast<std::size_t>(link)];
}

}  // namespace

RobotDescription::RobotDescription(Parts parts)
    : name_(std::move(parts.name)),
      urdf_(std::move(parts.urdf)),
      model_(std::move(parts.model)),
      base_link_(parts.base_link),
      tip_link_(parts.tip_link),
      gripper_(parts.gripper),
      home_(std::move(parts.home)),
      ik_(std::move(parts.ik)) {
  if (!model_ || !ik_) throw std::invalid_argument("a robot description needs a model and an IK solver");
  const RobotModel& model = *model_;
  const auto links = static_cast<LinkIndex>(model.links().size());
  if (base_link_ < 0 || base_link_ >= links || tip_link_ < 0 || tip_link_ >= links) {
    throw std::invalid_argument("a robot description's base and tip must be links of its model");
  }
  if (static_cast<std::size_t>(home_.size()) != model.variable_count()) {
    throw std::invalid_argument("a robot description's home must have one value per joint variable");
  }

  disabled_ = model.adjacent_links();
  for (auto [a, b] : parts.disabled_collisions) {
    if (a < 0 || a >= links || b < 0 || b >= links) throw std::invalid_argument("a disabled collision pair names no link");
    disabled_.emplace_back(std::min(a, b), std::max(a, b));
  }
  std::sort(disabled_.begin(), disabled_.end());
  disabled_.erase(std::unique(disabled_.begin(), disabled_.end()), disabled_.end());
  root_T_ik_base_ = root_T_link(model, home_, base_link_);

  // The fingers: the first movable joint below the hand's rigid body that IK does not move.
  const LinkIndex hand = model.rigid_root(tip_link_);
  const auto& chain = ik_->chain();
  for (std::size_t v = 0; v < model.variable_count(); ++v) {
    const JointIndex j = model.variables()[v];
    if (model.descends_from(model.joints()[j].child, hand) && std::find(chain.begin(), chain.end(), j) == chain.end()) {
      finger_variable_ = static_cast<int>(v);
      break;
    }
  }
}

RobotDescription RobotDescription::with_home(Eigen::VectorXd home) const {
  if (static_cast<std::size_t>(home.size()) != model_->variable_count()) {
    throw std::invalid_argument("a robot description's home must have one value per joint variable");
  }
  RobotDescription copy = *this;
  copy.home_ = std::move(home);
  copy.root_T_ik_base_ = root_T_link(*model_, copy.home_, base_link_);
  return copy;
}

Eigen::VectorXd initial_configuration(const RobotSpec& spec) {
  if (spec.configuration) return *spec.configuration;
  return spec.loaded ? spec.loaded->home() : Eigen::VectorXd();
}

}  // namespace cluttertamp::robot
