#pragma once
// Planar pushing physics (Papallas & Dogar, ICRA 2020, Section III): a gripper moving
// in the shelf plane pushes the movable objects, which slide on their support under
// friction. Bullet does the dynamics; it stays in the .cpp file.

#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "cluttertamp/core/scene.hpp"
#include "cluttertamp/core/world_state.hpp"
#include "cluttertamp/export.hpp"

namespace cluttertamp {
struct Problem;
namespace robot {
class RobotDescription;
}
}  // namespace cluttertamp

namespace cluttertamp::physics {

/// A body in the plane: pose (x, y in m, yaw in rad, world frame) and its rate of
/// change (m/s, m/s, rad/s).
struct PlanarBody {
  Eigen::Vector3d pose = Eigen::Vector3d::Zero();
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();
};

/// The state of a pushing problem: the pusher's planar pose (the pose the controls move:
/// the floating gripper's, or the mobile base's under an arm, see PushSettings) and every
/// scene object's planar body, indexed like Scene::objects (objects removed in the
/// initial world state and fixed objects keep their entry and never move).
struct PushState {
  Eigen::Vector3d gripper = Eigen::Vector3d::Zero();  ///< the pusher's x, y (m), yaw (rad), world frame
  std::vector<PlanarBody> objects;
};

/// A control: the pusher's planar velocity (vx, vy in m/s, yaw rate in rad/s, world
/// frame) held for `duration` seconds.
struct PushControl {
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();
  double duration = 0.0;
};

/// A rigid part of a pusher, fixed in the pusher's frame: a primitive, or the convex
/// hull of `hull` points.
struct PusherPart {
  /// The primitive; for a hull, the box bounding its points in the part's frame (what a
  /// viewer draws).
  Shape shape;
  /// The part in the pusher's frame (m): origin at the pose the controls move, x ahead
  /// at yaw 0, z up from the frame's height (PushWorld::pusher_z).
  Eigen::Isometry3d frame_T_part = Eigen::Isometry3d::Identity();
  std::vector<Eigen::Vector3d> hull;  ///< points in the part's frame whose hull collides; empty: `shape` does
};

/// A robot arm held in one posture on a holonomic planar base: what pushes in Papallas &
/// Dogar's experiments (a UR5 on an omnidirectional base that turns within +-pi/4). Its
/// links sweep objects and walls at their own heights, and turning the base swings the
/// hand on the lever from the base's centre to the tool. Made by arm_pusher().
struct ArmPusher {
  std::string robot;                  ///< the robot's name
  std::vector<PusherPart> parts;      ///< the links' collision geometry in the arm's base frame
  /// Which of `parts` are the hand's (the tip link and the links below the last moving
  /// joint of the arm chain): what the hand's face and its lowest point are taken from.
  std::vector<bool> hand;
  Eigen::Isometry3d arm_T_tcp = Eigen::Isometry3d::Identity();  ///< the tool centre point, arm's base frame
  /// The arm's base in the mobile base's frame (x ahead, y left; m): the mobile base
  /// turns about its own centre, this far behind the arm.
  Eigen::Vector2d base_offset = Eigen::Vector2d::Zero();
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
  double gripper_clearance = 0.01;  ///< m between the support plane and the gripper's (the hand's) bottom
  double fall_drop = 0.02;          ///< m an object's centre must sink to count as fallen

  /// What pushes: null, the floating gripper above (a palm and fingers moving freely in
  /// the plane); set, a robot arm on a planar base (ArmPusher).
  std::shared_ptr<const ArmPusher> arm;
  /// The hand's height (m): its tool centre point this far above the support's top.
  /// Unset: as low as gripper_clearance lets the hand's lowest point be. Arm only.
  std::optional<double> hand_height;
  /// The pusher's heading stays within [min, max] (rad, world frame). The floating
  /// gripper turns freely by default, the arm's base within +-pi/4.
  Eigen::Vector2d yaw_limits{-std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()};
  /// Where the hand starts (x, y m, yaw rad; world frame). Unset: at the scene's exit
  /// x_s, facing into the shelf (+x).
  std::optional<Eigen::Vector3d> start_hand;

  /// How two bodies' friction coefficients make a contact's: Bullet's product (with the
  /// default fixed friction 1, an object's own coefficient is the one against the
  /// shelf) or MuJoCo's larger of the two (what Papallas & Dogar simulated with).
  enum class FrictionCombine { product, max };
  FrictionCombine friction_combine = FrictionCombine::product;
  std::optional<double> fixed_friction;   ///< every fixed body's coefficient; unset: each its scene's `friction`
  std::optional<double> object_friction;  ///< every movable object's coefficient; unset: each its own
  std::optional<double> object_mass;      ///< kg of every movable object; unset: each its own
  double pusher_friction = 0.5;           ///< the pusher's coefficient

  /// Set: objects (but spheres, which slide as before) turn freely about every axis, and
  /// one tilted more than this (rad: the angle between its z axis and the world's) at
  /// the end of a control has tipped (PushOutcome::tipped, an invalid outcome). A
  /// smaller tilt is not carried on: states hold x, y and yaw, so every propagation
  /// starts the objects upright. Unset: objects turn about z only and never tip.
  /// Papallas & Dogar's code: 0.1 rad in roll or pitch.
  /// Set, bodies collide as polyhedra (a cylinder as a 24-sided prism) so that an object
  /// stands on its whole base; an object that starts a propagation at rest sleeps until
  /// something comes within contact distance, and one slower than 1 cm/s and 0.1 rad/s
  /// at the end is at rest. Known limit: a woken, light, slender object (0.3 kg, 26 cm
  /// tall on a 2-3 cm radius) can rock and wander in Bullet while nothing pushes it.
  std::optional<double> tip_limit;
  /// Set: a contact force above this (N, one contact point's, normal and friction
  /// together) on a wall in any physics step is an invalid outcome
  /// (PushOutcome::wall_force), and the simulation stops at that step (the state is where
  /// it stopped). Walls: the scene's fixed bodies other than the boards the objects stand
  /// on. Unset: no limit. Papallas & Dogar's code: 9 on the shelf.
  std::optional<double> wall_force_limit;
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
  bool gripper_hit_fixed = false;       ///< the pusher (any part) entered fixed geometry (walls, boards)
  std::vector<ObjectIndex> fallen;      ///< objects that left their support (sorted)
  std::vector<ObjectIndex> touched;     ///< objects the pusher touched (sorted)
  /// Objects tilted beyond PushSettings::tip_limit at the end (sorted; empty without a limit).
  std::vector<ObjectIndex> tipped;
  /// The largest force (N) on one contact point of a wall in any step: from the pusher or
  /// an object, normal and friction together (see PushSettings::wall_force_limit).
  double wall_force = 0.0;
};

/// The physics of one scene. Every propagation starts from a fresh simulation of the
/// given state, so the same state and control give the same outcome, bit for bit.
/// Objects slide and turn about z only (they do not tip) unless PushSettings::tip_limit
/// is set; gravity holds them on their support, whose friction is each object's
/// `friction`; fixed bodies are static.
///
/// The pusher moves rigidly in the plane: its pose (PushState::gripper) is the floating
/// gripper's centre, or the mobile base's under an arm. Goals and regions are about the
/// hand: the floating gripper itself, or the arm's tool centre point (hand()).
class CLUTTERTAMP_API PushWorld {
 public:
  /// `initial` says which objects are present (removed ones take no part) and at what
  /// height each stands (kept upright: states hold only x, y and yaw). The plane the
  /// gripper moves in: the bottom of the target, raised by gripper_clearance; an arm's
  /// hand stands as settings.hand_height says.
  /// Throws std::invalid_argument for a movable object without a positive mass, bad
  /// gripper measures, empty yaw limits or an arm without parts.
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
  double plane_z() const;  ///< height of the gripper's bottom (of the arm's hand: its lowest point at hand_height), m

  /// The parts that push, in the pusher's frame (see PusherPart); that frame stands at
  /// pusher_z (m) in the world.
  const std::vector<PusherPart>& pusher_parts() const;
  double pusher_z() const;
  /// The hand's planar pose (x, y m, yaw rad; world) when the pusher is at `pose`: the
  /// floating gripper's own pose, or the arm's tool centre point heading along its
  /// approach axis.
  Eigen::Vector3d hand(const Eigen::Vector3d& pose) const;
  /// The pusher's pose that puts the hand at `hand` (the inverse of hand()), its heading
  /// turned into the yaw limits about the hand's point when it falls outside them.
  Eigen::Vector3d pose_for_hand(const Eigen::Vector3d& hand) const;
  /// m from the hand's point to the front of the hand along its heading: the palm's
  /// face, or the arm hand's foremost point.
  double hand_face() const;
  /// m from the hand's point to the farther of the hand's sides, across its heading.
  double hand_half_width() const;
  /// Whether the pusher may head at `yaw` (rad): within settings().yaw_limits (1e-9
  /// rad of rounding allowed).
  bool yaw_allowed(double yaw) const;
  /// Whether the hand may head at `hand_yaw` (rad): the pusher's heading then allowed.
  bool hand_heading_allowed(double hand_yaw) const;
  /// `yaw` moved into the yaw limits (unchanged when allowed).
  double clamp_yaw(double yaw) const;
  /// Where the pusher starts: the hand at settings().start_hand, else at the exit
  /// facing +x (the pose_for_hand of it).
  Eigen::Vector3d start_pose() const;

  /// The objects a push can move: present in the initial state and movable (sorted).
  const std::vector<ObjectIndex>& pushable() const;
  /// Where pushed objects must stay (world x, y, m): the fixed boards whose top is the
  /// target's support plane and that hold the target, merged (the workspace without
  /// any), less the footprints of walls standing on them, cut off on the side away
  /// from the target.
  const Eigen::AlignedBox2d& support_region() const;
  /// Where the hand's point may be (world x, y, m): over the support region and in
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
/// the floating gripper starts by default (x, y in m, yaw 0). PushWorld::start_pose is
/// the pusher's start under any settings.
CLUTTERTAMP_API Eigen::Vector3d gripper_at_exit(const Scene& scene);

/// The arm of `robot` held at `posture` (one value per model variable, rad or m): every
/// link's collision geometry placed by forward kinematics in the arm's base frame
/// (meshes as the hulls of their vertices), and the tool centre point. Throws
/// std::invalid_argument for a posture of the wrong size.
CLUTTERTAMP_API ArmPusher arm_pusher(const robot::RobotDescription& robot, const Eigen::VectorXd& posture);

/// m from the centre Papallas & Dogar's base turns about to the hand (a UR5 on an
/// omnidirectional base; their Section VI-C robot).
inline constexpr double kPaperLever = 1.27;

/// How far ahead of the mobile base's centre to put the arm's base (m, along x) so that
/// the tool centre point stands `lever` m from that centre; 0 when the arm alone reaches
/// farther.
CLUTTERTAMP_API double base_offset_for_lever(const ArmPusher& arm, double lever);

/// The pushing physics a problem asks for: its `physics:` block (docs/file-formats.md,
/// "Problem files") over the defaults, an arm made from its robot at the block's
/// `posture` (else the problem's start configuration, else the robot's home). Throws
/// InputError listing every bad or unknown key with its location.
CLUTTERTAMP_API PushSettings push_settings(const Problem& problem);

}  // namespace cluttertamp::physics
