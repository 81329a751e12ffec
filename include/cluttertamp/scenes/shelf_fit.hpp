#pragma once
// Where a shelf goes for a given robot: its opening and floor moved to where the arm
// reaches the inside with side grasps.

#include <memory>

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
};

/// Keeps `spec` when `robot` reaches every test grasp in it, else moves its opening
/// (`front`, 0.2 to 0.9 m in 5 cm steps) and floor (`floor_height`, 0 to 0.9 m) to the
/// placement that reaches the most, nearest the given one on a tie. A test grasp counts
/// when IK finds a configuration for it that touches neither the cabinet, the buffer
/// table nor the robot itself; a placement where the home configuration touches them
/// counts none. Test grasps: the tool at mid-cylinder height on a 3 x 3 grid of the
/// interior (front, middle, back x left, centre, right), at the exit pose and over the
/// buffer table, approaching horizontally from the robot's base, fingers vertical, both
/// ways up (as the grasp_side sampler makes them). Deterministic.
CLUTTERTAMP_API ShelfFit fit_shelf_to_robot(const ShelfSpec& spec, std::shared_ptr<const robot::RobotDescription> robot);

}  // namespace cluttertamp::scenes
