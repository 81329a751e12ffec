#pragma once
// Planar pushing physics (Papallas & Dogar, ICRA 2020, Section III): a gripper moving
// in the shelf plane pushes the movable objects, which slide on their support under
// friction. Bullet does the dynamics; it stays in the .cpp file.

#include <memory>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "cluttertamp/core/scene.hpp"
#include "cluttertamp/core/world_state.hpp"
#include "cluttertamp/export.hpp"

namespace cluttertamp::physics {

/// A body in the plane: pose (x, y in m, yaw in rad, world frame) and its rate of
/// change (m/s, m/s, rad/s).
struct PlanarBody {
  Eigen::Vector3d pose = Eigen::Vector3d::Zero();
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();
};

/// The state of a pushing problem: the gripper's planar pose and every scene object's
/// planar body, indexed like Scene::objects (objects removed in the initial world state
/// and fixed objects keep their entry and never move).
struct PushState {
  Eigen::Vector3d gripper = Eigen::Vector3d::Zero();  ///< x, y (m), yaw (rad)
  std::vector<PlanarBody> objects;
};

/// A control: the gripper's planar velocity (vx, vy in m/s, yaw rate in rad/s, world
/// frame) held for `duration` seconds.
struct PushControl {
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();
  double duration = 0.0;
};

struct PushSettings {
  double time_step = 1.0 / 240.0;  ///< s per physics step (a control's duration is split evenly)
  /// The gripper's palm as a box (full edge lengths, m) in the gripper's frame, centred
  /// on it: x along the push direction at yaw 0, y across it, z up.
  Eigen::Vector3d gripper_size{0.04, 0.12, 0.06};
  /// The fingers: two boxes `finger_length` (m) beyond the palm's face (+x) and
  /// `finger_width` (m) across, their outer sides flush with the palm's, as tall as
  /// it; a target between them is reached (ReachGoal). 0: the palm alone, a plain box.
  /// Defaults: an open parallel gripper, 0.09 m between the fingers.
  double finger_length = 0.05;
  double finger_width = 0.015;
  double gripper_clearance = 0.01;  ///< m between the support plane and the gripper's bottom
  double fall_drop = 0.02;          ///< m an object's centre must sink to count as fallen
};

/// One box of the gripper: full edge lengths and where its centre is in the gripper's
/// frame (x, y; m).
struct GripperBox {
  Eigen::Vector3d size = Eigen::Vector3d::Zero();
  Eigen::Vector2d offset = Eigen::Vector2d::Zero();
};

/// The gripper as boxes: the palm, then the fingers (none when finger_length is 0).
CLUTTERTAMP_API std::vector<GripperBox> gripper_boxes(const PushSettings& settings);

/// What a propagation did besides the new state.
struct PushOutcome {
  PushState state;
  bool gripper_hit_fixed = false;       ///< the gripper entered fixed geometry (walls, boards)
  std::vector<ObjectIndex> fallen;      ///< objects that left their support (sorted)
  std::vector<ObjectIndex> touched;     ///< objects the gripper touched (sorted)
};

/// The physics of one scene. Every propagation starts from a fresh simulation of the
/// given state, so the same state and control give the same outcome, bit for bit.
/// Objects slide and turn about z only (they do not tip); gravity holds them on their
/// support, whose friction is each object's `friction`; fixed bodies are static.
class CLUTTERTAMP_API PushWorld {
 public:
  /// `initial` says which objects are present (removed ones take no part) and at what
  /// height each stands (kept upright: states hold only x, y and yaw). The plane the
  /// gripper moves in: the bottom of the target, raised by gripper_clearance.
  /// Throws std::invalid_argument for a movable object without a positive mass.
  PushWorld(const Scene& scene, const WorldState& initial, PushSettings settings = {});
  ~PushWorld();
  PushWorld(const PushWorld&) = delete;
  PushWorld& operator=(const PushWorld&) = delete;

  /// The objects of `initial` at rest and the gripper at `gripper` (x, y, yaw).
  PushState state_of(const WorldState& initial, const Eigen::Vector3d& gripper) const;

  /// Simulates `control` from `from`. Precondition: `from` has one body per scene object.
  PushOutcome propagate(const PushState& from, const PushControl& control) const;

  const PushSettings& settings() const;
  const Scene& scene() const;
  double plane_z() const;  ///< height of the gripper's bottom, m

  /// The objects a push can move: present in the initial state and movable (sorted).
  const std::vector<ObjectIndex>& pushable() const;
  /// Where pushed objects must stay (world x, y, m): the fixed boards whose top is the
  /// target's support plane and that hold the target, merged (the workspace without
  /// any), less the footprints of walls standing on them, cut off on the side away
  /// from the target.
  const Eigen::AlignedBox2d& support_region() const;
  /// Where the gripper's centre may be (world x, y, m): over the support region and in
  /// front of it as far as the exit x_s and 5 cm beyond, within the scene's workspace.
  Eigen::AlignedBox2d gripper_region() const;
  /// Radius of a circle about an object's centre that holds its footprint in the
  /// initial state, m (cluttertamp::footprint_radius: exact for upright cylinders and
  /// boxes; a box's circle reaches its corners, so a push or reach goal measured from
  /// it is a circle's, not the box's faces').
  double footprint_radius(ObjectIndex object) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Where pushed objects must stay in `state` (see PushWorld::support_region), without
/// building a simulation: the board under the target less the walls standing on it.
CLUTTERTAMP_API Eigen::AlignedBox2d support_region(const Scene& scene, const WorldState& state,
                                                   const PushSettings& settings = {});

/// The gripper's planar pose at the scene's exit x_s, facing into the shelf (+x): where
/// reaching and pushing start (x, y in m, yaw 0).
CLUTTERTAMP_API Eigen::Vector3d gripper_at_exit(const Scene& scene);

}  // namespace cluttertamp::physics
