#pragma once

#include <memory>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "cluttertamp/core/scene.hpp"
#include "cluttertamp/core/world_state.hpp"
#include "cluttertamp/export.hpp"

namespace cluttertamp::plugin {

/// What a robot configuration (or a shape) touches.
struct Contacts {
  bool self = false;                ///< two robot links (not adjacent, not disabled) overlap
  bool fixed = false;               ///< the robot or the held object touches fixed geometry
  std::vector<ObjectIndex> objects;  ///< every movable object touched, sorted, without repeats
  bool valid() const { return !self && !fixed && objects.empty(); }
};

/// The scene and the robot at one WorldState: the geometry a sampler checks against.
/// Made by PlanningContext::world_at(state); every query answers for that state, whatever
/// other views of the same run were asked in between, so a sampler never finds, nor
/// leaves, a world in some other state.
///
/// Robot configurations are full joint vectors in the robot's joint order (rad, m);
/// poses are in the world frame (z up, metres). Objects in `ignored` are not looked at.
/// When a view that answered a geometry query is destroyed, the run's shared geometry is
/// left at its state: a caller that asked a sampler about state S finds it at S afterwards.
///
/// Not thread-safe: the views of a run share one collision engine.
class CLUTTERTAMP_API WorldView {
 public:
  virtual ~WorldView();

  /// The state every query of this view answers for.
  virtual const WorldState& state() const = 0;

  /// The world pose of the robot's tool (TCP) at q.
  virtual Eigen::Isometry3d tool_pose(const Eigen::VectorXd& q) const = 0;
  /// Robot configurations with the tool at `world_T_tool`, nearest to `seed` first
  /// (the robot's own IK; at most a few branches); empty when out of reach. Collisions
  /// are not checked.
  virtual std::vector<Eigen::VectorXd> inverse_kinematics(const Eigen::Isometry3d& world_T_tool,
                                                          const Eigen::VectorXd& seed) const = 0;

  /// True when q touches nothing: no self collision, fixed body or movable object.
  /// Stops at the first contact.
  virtual bool is_valid(const Eigen::VectorXd& q, std::span<const ObjectIndex> ignored = {}) const = 0;
  /// Everything q touches: the full set of movable objects, not the first one met.
  virtual Contacts contacts(const Eigen::VectorXd& q, std::span<const ObjectIndex> ignored = {}) const = 0;
  /// True when the robot or the held object at q touches a movable object; self and
  /// fixed contacts are not looked at. Stops at the first contact.
  virtual bool touches_object(const Eigen::VectorXd& q, std::span<const ObjectIndex> ignored = {}) const = 0;
  /// Smallest distance (m) from the robot and the held object to anything; 0 when touching.
  virtual double min_distance(const Eigen::VectorXd& q, std::span<const ObjectIndex> ignored = {}) const = 0;
  /// Which robot links touch which fixed bodies at q, in words ("" when none): for
  /// a failure's reason.
  virtual std::string describe_fixed_contacts(const Eigen::VectorXd& q) const = 0;
  /// What `shape` at `world_T_shape` would touch (the robot is not looked at): a
  /// placement check.
  virtual Contacts shape_contacts(const Shape& shape, const Eigen::Isometry3d& world_T_shape,
                                  std::span<const ObjectIndex> ignored = {}) const = 0;

  /// The same state with `object` in the gripper at `gripper_T_object` (tool frame),
  /// whatever the state holds: for checking a motion that carries it.
  virtual std::unique_ptr<WorldView> holding(ObjectIndex object, const Eigen::Isometry3d& gripper_T_object) const = 0;
};

/// Makes the views of a run; the runner owns one and hands it to every plugin call
/// through PlanningContext::worlds.
class CLUTTERTAMP_API WorldSource {
 public:
  virtual ~WorldSource();
  /// A view of the scene and robot at `state` (copied). Precondition: `state` has one
  /// pose and one removed flag per scene object.
  virtual std::unique_ptr<WorldView> at(const WorldState& state) = 0;
};

}  // namespace cluttertamp::plugin
