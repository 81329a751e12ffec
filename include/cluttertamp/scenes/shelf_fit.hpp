#pragma once
// Where a shelf goes for a given robot: its opening and floor moved to where the arm
// reaches the inside with side grasps.

#include <memory>
#include <optional>
#include <string>

#include <Eigen/Core>

#include "cluttertamp/export.hpp"
#include "cluttertamp/robot/robot_description.hpp"
#include "cluttertamp/scenes/shelf_generator.hpp"

namespace cluttertamp::scenes {

/// How well a shelf placement suits a robot.
struct ShelfFit {
  ShelfSpec spec;   ///< `front` and `floor_height` chosen; the rest as given
  int reached = 0;  ///< test grasps the arm reaches without touching the furniture
  int tried = 0;
  int reached_as_given = 0;  ///< the same, at the placement `spec` gave
  /// Where the robot must start instead of its home, which reaches into the cabinet at
  /// this placement: the home's tool pose drawn back towards the base (and raised)
  /// until the arm clears the cabinet. Empty when the home is clear.
  std::optional<Eigen::VectorXd> start;
  double start_drawn_back = 0.0;  ///< m, horizontally, when `start` is set
};

/// Keeps `spec` when `robot` reaches every test grasp in it, else moves its opening
/// (`front`, 0.2 to 0.9 m in 5 cm steps) and floor (`floor_height`, 0 to 0.9 m) to the
/// placement that reaches the most, nearest the given one on a tie; if that still
/// leaves some unreached, the cabinet is made shallower there (`depth`, 5 cm steps down
/// to 0.4 m) while that reaches more. A test grasp counts
/// when IK finds a configuration for it that touches neither the cabinet, the buffer
/// table nor the robot itself. The robot must start clear of the furniture and of the
/// cabinet's interior (where objects may stand): where its home is not, `start` is a
/// configuration that is (see ShelfFit::start), and a placement where neither is found
/// counts none. Test grasps: the tool at mid-cylinder height on a 3 x 3 grid of the
/// interior (front, middle, back x left, centre, right) and over the buffer table,
/// approaching horizontally from the robot's base, fingers vertical, both ways up (as
/// the grasp_side sampler makes them); and the exit pose, either way up, holding the
/// largest cylinder the spec draws (upright, approached along +x as taken out of the
/// cabinet) clear of the arm and the furniture, which moves from `spec.exit_distance`
/// in front of the opening to 0.15 or 0.1 m when the arm cannot hold it farther out
/// (`exit_distance` of the result) and never stands less than 0.05 m in front of the
/// base's axis (over the base, carrying it there is a hard motion for every removal).
/// Deterministic.
/// "opening at x = 0.25 m, floor at z = 0.50 m, 0.55 m deep, exit 0.20 m in front of
/// it: 15 of 22 test grasps reachable": where the fit put the shelf, in words.
CLUTTERTAMP_API std::string describe_placement(const ShelfFit& fit);

CLUTTERTAMP_API ShelfFit fit_shelf_to_robot(const ShelfSpec& spec, std::shared_ptr<const robot::RobotDescription> robot);

}  // namespace cluttertamp::scenes
