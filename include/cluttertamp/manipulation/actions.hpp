#pragma once

#include <optional>
#include <span>
#include <string>
#include <vector>

#include "cluttertamp/core/result.hpp"
#include "cluttertamp/core/world_state.hpp"
#include "cluttertamp/export.hpp"
#include "cluttertamp/plugin/context.hpp"
#include "cluttertamp/plugin/grasp_sampler.hpp"

namespace cluttertamp::manipulation {

/// One robot motion of an action: "transfer", "approach", "grasp", "lift", "retreat",
/// "place", "release", "carry".
struct Segment {
  std::string name;
  Trajectory trajectory;
};

/// What a composite action did: its motions and the state after them, or why it failed
/// (with the movable objects in the way, the retrieval graph's feedback).
struct ActionOutcome {
  bool ok = false;
  std::vector<Segment> segments;
  std::optional<Failure> failure;
  WorldState after;  ///< when ok
  std::optional<plugin::Grasp> grasp;  ///< pick and retrieve: the grasp used
};

/// Pick `object`: transfer to a pre-grasp, approach, close the fingers, lift, retreat.
/// Uses the context's grasp and motion samplers; fails with a reason and the blocking
/// objects of the least blocked grasp, or of the motion, when no grasp works.
/// Precondition: the hand is empty in `state`.
CLUTTERTAMP_API ActionOutcome pick(plugin::PlanningContext& context, const WorldState& state, ObjectIndex object);

/// Place the held object in `region`: transfer above a placement, lower, open the
/// fingers, retreat. Uses the placement and motion samplers. Precondition: the hand
/// holds an object in `state`.
CLUTTERTAMP_API ActionOutcome place(plugin::PlanningContext& context, const WorldState& state, const std::string& region);

/// Retrieve the scene's target: pick it and carry it to the exit pose x_s (its centre
/// there, upright). The target stays in the hand.
///
/// `way`: where the target may travel in the plane (world frame, m), from where it
/// stands to x_s, e.g. a retrieval planner's free path of its footprint. When given,
/// the carry first follows it: the target at its lifted height and orientation, the
/// tool on that straight line every 2 cm by IK from the previous configuration, each
/// segment checked densely; then straight to x_s. Where that is blocked or leaves
/// reach, the carry is planned as without a way (move_out). Fixed-base robots only; a
/// mobile base plans as without.
CLUTTERTAMP_API ActionOutcome retrieve(plugin::PlanningContext& context, const WorldState& state,
                                       std::span<const Eigen::Vector2d> way = {});

/// A motion from `state` (its held object included) to the configuration `goal` that
/// first backs the tool out of where it is: along the tool's approach axis (its z axis,
/// made horizontal), in a straight line of up to 0.25 m while that is free, then planned
/// by the motion sampler from the line's end — the planner's trees find their way out
/// of clutter slowly. When the line is shorter than 8 cm or the plan from its end
/// fails, a motion planned from the start. Empty with `failure` set when no motion
/// is found.
CLUTTERTAMP_API std::optional<Trajectory> move_out(plugin::PlanningContext& context, const WorldState& state,
                                                   const Eigen::VectorXd& goal, std::optional<Failure>& failure);

/// A trajectory through `waypoints`, each segment at the fastest pace the robot's
/// velocity limits (times `scale`) allow.
CLUTTERTAMP_API Trajectory timed(const robot::RobotDescription& robot, const std::vector<Eigen::VectorXd>& waypoints,
                                 double scale = 0.5);

}  // namespace cluttertamp::manipulation
