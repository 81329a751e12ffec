#pragma once
// Kinodynamic planning over the pushing physics (Papallas & Dogar, ICRA 2020,
// Section IV): OMPL's control-based RRT or KPIECE1 grows a tree of gripper controls
// propagated through PushWorld until a goal holds. OMPL stays in the .cpp file.
//
// A state is valid while no pushable object has fallen, tipped (PushSettings::tip_limit)
// or left the support region, no wall has taken more than PushSettings::wall_force_limit,
// and the pusher's hand is inside its region, its heading within the yaw limits, and no
// part of it has entered fixed geometry.

#include <cstdint>
#include <limits>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "cluttertamp/core/parameters.hpp"
#include "cluttertamp/core/result.hpp"
#include "cluttertamp/physics/push_world.hpp"

namespace cluttertamp::physics {

/// How the kinodynamic search samples and propagates controls. The defaults are ours:
/// the seed paper gives its time limit (300 s) but not these values.
struct KinodynamicSettings {
  std::string planner = "rrt";  ///< "rrt" or "kpiece"
  double step = 0.1;            ///< s: one propagation (each a fresh simulation)
  int max_steps = 10;           ///< a control lasts 1..max_steps steps
  double max_speed = 0.15;      ///< m/s along world +x (into the shelf)
  double max_side_speed = 0.1;  ///< m/s along world y either way, and along -x
  double max_turn = 0.5;        ///< rad/s, either way
  double goal_bias = 0.05;      ///< RRT: fraction of samples drawn from the goal
  /// Fraction of sampled controls steered towards the goal's gripper target from the
  /// state they extend (the seed's Section V-A steers its approaches); 0 for the plain
  /// planners of Section IV.
  double steer = 0.0;
  /// Physics propagations one search may make (0: no budget, only the run's time
  /// limit). Work, not time: a search stopped by it ends the same on any machine.
  std::uint64_t max_propagations = 0;
  /// Where states are sampled: empty, hand poses over the hand's region (ours, focused
  /// on the shelf); [x_min, y_min, x_max, y_max] (m, world), the pusher's pose anywhere
  /// in that box, as a plain planner samples its state space (the paper's code: a 4 m
  /// square). Headings within the yaw limits either way.
  std::vector<double> sample_bounds;

  /// Reads the keys named like the members (`planner`, `step`, ...); throws InputError
  /// naming the value for a bad one.
  void read(const Parameters& parameters);
};

/// What a kinodynamic search is after. Satisfied when distance(state) <= tolerance().
class CLUTTERTAMP_API PushGoal {
 public:
  explicit PushGoal(double tolerance) : tolerance_(tolerance) {}
  virtual ~PushGoal();

  virtual double distance(const PushState& state) const = 0;
  /// A pose of the pusher (x, y m, yaw rad; PushState::gripper) to head for from
  /// `state` to get nearer the goal: steered controls head for it.
  virtual Eigen::Vector3d gripper_target(const PushState& state) const = 0;
  /// Where the gripper may be once the goal holds, as foreseen from `start`: goal
  /// samples are drawn about one of them at random. Defaults to gripper_target(start).
  virtual std::vector<Eigen::Vector3d> goal_grippers(const PushState& start) const { return {gripper_target(start)}; }
  /// How far goal samples scatter about goal_grippers (x, y in m, yaw in rad).
  virtual Eigen::Vector3d sample_spread() const { return {0.01, 0.01, 0.1}; }

  double tolerance() const { return tolerance_; }

 private:
  double tolerance_;
};

/// When the target counts as reached; the hand is the floating gripper or the arm's
/// tool (PushWorld::hand).
///
/// `pocket` (the default): with fingers, the target's centre within `distance` m of the
/// pocket between them (from the palm's face to the fingertips, as wide as the gap less
/// the target's radius): "the target within the end-effector" of Papallas & Dogar,
/// Section II-A. A plain box, a target too wide for the gap, or an arm's hand: the
/// hand's face within `distance` of the target's surface. And the target within
/// `heading` rad of the hand's heading, seen from the hand's point.
///
/// `point`: the hand's reach point (the arm's tool centre point; the middle of the
/// floating gripper's pocket) within `distance` of the target's centre (the paper's
/// public code: 0.07 m); the heading checked only when `heading` is set.
struct ReachTolerances {
  enum class Kind { pocket, point };
  Kind kind = Kind::pocket;
  double distance = 0.005;
  std::optional<double> heading = 0.5;

  /// Reads `goal` (pocket or point), `goal_distance` (default 0.005 m, point 0.07 m) and
  /// `goal_heading` (default 0.5 rad, point: none); throws InputError for a bad one.
  void read(const Parameters& parameters);
};

/// Reaching through clutter (Section II-A): the target within the tolerances, wherever
/// pushes have moved it (distance: metres off plus radians beyond `heading`, a sum).
class CLUTTERTAMP_API ReachGoal final : public PushGoal {
 public:
  ReachGoal(const PushWorld& world, ObjectIndex target, const ReachTolerances& tolerances);
  double distance(const PushState& state) const override;
  /// The pusher's pose that faces the target with its centre at the hand's face plus
  /// its radius (at most the fingers' length) or, for `point`, just short of the
  /// hand's face.
  Eigen::Vector3d gripper_target(const PushState& state) const override;
  Eigen::Vector3d sample_spread() const override;

 private:
  const PushWorld* world_;
  ObjectIndex target_;
  ReachTolerances::Kind kind_;
  std::optional<double> heading_;  // rad
  double reach_ = 0;     // hand point to target centre at gripper_target, m
  double ahead_ = 0;     // point: the reach point ahead of the hand's point, m
  // The pocket the target's centre must be in, in the hand's frame (m): x from
  // near to far (equal without fingers), |y| up to half_width.
  double pocket_near_ = 0, pocket_far_ = 0, pocket_half_width_ = 0;
  bool has_pocket() const { return pocket_far_ > pocket_near_; }
  double heading_excess(const Eigen::Vector3d& hand, const Eigen::Vector2d& target) const;
};

/// The hand at one of `poses` (x, y m, yaw rad; PushWorld::hand): an approach state
/// of Section V-A. Distance: metres off the pose plus radians beyond `heading` (a sum,
/// so a heading error may exceed `heading` by what the position leaves of `position`).
class CLUTTERTAMP_API GripperPoseGoal final : public PushGoal {
 public:
  /// Throws std::invalid_argument without a pose.
  GripperPoseGoal(const PushWorld& world, std::vector<Eigen::Vector3d> poses, double position, double heading);
  double distance(const PushState& state) const override;
  Eigen::Vector3d gripper_target(const PushState& state) const override;  ///< the pusher's pose for the nearest
  std::vector<Eigen::Vector3d> goal_grippers(const PushState&) const override;
  Eigen::Vector3d sample_spread() const override { return {position_ / 2, position_ / 2, heading_ / 2}; }

 private:
  const PushWorld* world_;
  std::vector<Eigen::Vector3d> poses_;  // of the hand
  double position_, heading_;
};

/// An object's centre within `radius` of `centre` (world x, y, m): a guide satisfied.
/// The hand's target: lined up behind the object on the line through the centre (the
/// fingertips short of it), then where the hand's face leaves it at the centre.
class CLUTTERTAMP_API ObjectInRegionGoal final : public PushGoal {
 public:
  ObjectInRegionGoal(const PushWorld& world, ObjectIndex object, const Eigen::Vector2d& centre, double radius);
  double distance(const PushState& state) const override;
  Eigen::Vector3d gripper_target(const PushState& state) const override;
  std::vector<Eigen::Vector3d> goal_grippers(const PushState& start) const override;

 private:
  const PushWorld* world_;
  ObjectIndex object_;
  Eigen::Vector2d centre_;
  double standoff_;  // gripper centre behind the object's centre when the palm pushes it, m
  double approach_;  // ... when lining up, the fingertips 1 cm short of it, m
};

/// A pushing plan: `states[k + 1]` is `controls[k]` applied to `states[k]` in
/// propagations of `step` seconds (each control lasts a whole number of them).
struct PushPath {
  std::vector<PushState> states;
  std::vector<PushControl> controls;
  double step = 0.0;

  double duration() const;
};

struct KinodynamicOutcome {
  std::optional<PushPath> path;      ///< set when the goal was reached
  std::string reason;                ///< why not, otherwise
  std::uint64_t propagations = 0;    ///< physics propagations of `step` seconds
  bool time_limit_reached = false;   ///< stopped by `PushBudget::seconds`
  bool budget_reached = false;       ///< stopped by `PushBudget::propagations`
};

/// How long one kinodynamic search may go on, whichever ends first: `propagations`
/// physics propagations (work: the same seed and budget end the same way on any
/// machine) and `seconds` of wall-clock time (the run's outer limit, the one stop
/// whose outcome depends on the machine's speed).
struct PushBudget {
  static constexpr std::uint64_t kNone = std::numeric_limits<std::uint64_t>::max();  ///< no propagation budget
  double seconds = 1e7;
  std::uint64_t propagations = kNone;

  /// The run's `seconds` left and the settings' max_propagations (0: none), at most `cap`.
  static PushBudget of(const KinodynamicSettings& settings, double seconds, std::uint64_t cap = kNone) {
    const std::uint64_t own = settings.max_propagations == 0 ? cap : std::min(settings.max_propagations, cap);
    return {seconds, own};
  }
  /// `fraction` of the propagations (none stays none).
  PushBudget share(double fraction) const {
    return {seconds, propagations == kNone ? kNone : static_cast<std::uint64_t>(fraction * static_cast<double>(propagations))};
  }
  /// What is left after `used` propagations, with `seconds_left` of the run's time.
  PushBudget after(std::uint64_t used, double seconds_left) const {
    return {seconds_left, propagations == kNone ? kNone : propagations - std::min(propagations, used)};
  }
};

/// Plans from `start` until `goal` holds or the budget ends (a start that is not valid
/// is refused with a reason). The same seed and settings give the same tree: a search
/// stopped by its propagation budget ends the same way everywhere, one stopped by its
/// time is repeatable only as far as it got. Throws std::invalid_argument when `start`
/// does not fit the world.
CLUTTERTAMP_API KinodynamicOutcome plan_pushes(const PushWorld& world, const PushState& start, const PushGoal& goal,
                                               const KinodynamicSettings& settings, const PushBudget& budget,
                                               std::uint64_t seed);

/// Controls that move the gripper from `from` to `to` (x, y m, yaw rad) along a straight
/// line, turning evenly, as fast as the settings' speed bounds allow, in whole
/// propagation steps and at most max_steps per control. Empty when `to` is `from`.
CLUTTERTAMP_API std::vector<PushControl> straight_controls(const Eigen::Vector3d& from, const Eigen::Vector3d& to,
                                                           const KinodynamicSettings& settings);

/// Applies `controls` to the end of `path` in propagations of path.step seconds,
/// appending the state after each control. Stops and returns false at the first
/// propagation that is not valid (see the top of this file), appending nothing of it.
CLUTTERTAMP_API bool simulate(const PushWorld& world, PushPath& path, const std::vector<PushControl>& controls);

/// The outcome of applying a plan's controls to `start` in propagations of `step`
/// seconds, with whether every intermediate state stayed valid (see the top of this
/// file): an independent check of a plan.
struct Replay {
  PushState end;
  bool valid = true;
  std::vector<ObjectIndex> touched;  ///< objects the gripper touched (sorted)
};
CLUTTERTAMP_API Replay replay(const PushWorld& world, const PushState& start, const std::vector<PushControl>& controls,
                              double step);

/// A pushing path as a plan step: action "push"; its trajectory the gripper's planar
/// pose (joints gripper_x, gripper_y m, gripper_yaw rad) at the start and the end of
/// every control; values "controls" ([vx vy yaw-rate duration] per control), "step"
/// (the propagation step, s) and, under each object's id, the end pose [x y yaw] of
/// every object that moved more than 1 cm from `before` (also listed in `objects`).
CLUTTERTAMP_API PlanStep push_step(const PushWorld& world, const PushPath& path, const WorldState& before);

/// The controls of a push step (its "controls" values; none without them).
CLUTTERTAMP_API std::vector<PushControl> controls_of(const PlanStep& step);

/// `before` with each object where `state` has it: x, y and a turn about z; its height
/// and tilt kept.
CLUTTERTAMP_API WorldState world_state_of(const WorldState& before, const PushState& state);

/// Whether a propagation outcome keeps the plan valid (see the top of this file).
CLUTTERTAMP_API bool valid_outcome(const PushWorld& world, const PushOutcome& outcome);

}  // namespace cluttertamp::physics
