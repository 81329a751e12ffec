#pragma once

#include <cstdint>

#include "cluttertamp/core/scene.hpp"
#include "cluttertamp/export.hpp"

namespace cluttertamp::scenes {

/// A cabinet in front of a robot, filled with standing cylinders (Tian et al.,
/// Section VI-B). World frame: robot base at the origin, the cabinet's open side
/// facing it at x = front; lengths in metres.
struct ShelfSpec {
  int objects = 12;
  /// Cabinet interior; zero means "from the object count": 0.9 x 0.6 x 0.5 m for 12
  /// objects up to 1.2 x 0.7 x 0.5 m for 20 (the paper's), interpolated linearly;
  /// beyond 20, 2.25 cm wider per object (3.0 x 0.7 m for 100; the paper gives no size).
  double width = 0.0;   ///< along y
  double depth = 0.0;   ///< along x
  double height = 0.5;  ///< along z
  double front = 0.6;        ///< x of the cabinet's open side
  double floor_height = 0.4; ///< z of the cabinet floor's top
  double radius_min = 0.035, radius_max = 0.040;
  double height_min = 0.24, height_max = 0.29;
  /// m between neighbouring cylinders, and to the walls. 0 is the paper's recipe
  /// ("randomly and uniformly placed without any collisions"): neighbours may touch.
  double min_gap = 0.0;
  /// m in front of the opening where x_s, the exit pose a retrieved target is carried
  /// to, stands (at the cylinders' mid-height, on the cabinet's centre line).
  double exit_distance = 0.2;
};

/// The cabinet size `spec` gives for its object count.
CLUTTERTAMP_API Eigen::Vector3d cabinet_size(const ShelfSpec& spec);

/// Places the cylinders uniformly at random without overlap (same seed, same scene);
/// the target is the object nearest the middle of the back wall. Adds the cabinet's
/// boards, a buffer table with a placement region beside the robot, the exit pose in
/// front of the opening, and a camera above the robot. Throws std::runtime_error when
/// the objects do not fit after many attempts.
CLUTTERTAMP_API Scene generate_shelf_scene(const ShelfSpec& spec, std::uint64_t seed);

/// A shelf for reaching by pushing as Papallas & Dogar (ICRA 2020, Section VI-B)
/// describe theirs: "the goal object at the back of the shelf in a random position",
/// then the movable obstacles placed one by one wherever they collide with nothing.
/// Sizes are those of the paper's public setup as far as it gives them.
struct PushShelfSpec {
  int obstacles = 10;
  double depth = 0.59;   ///< interior along x, m
  double width = 0.584;  ///< interior along y, m
  double height = 0.26;  ///< interior along z, m
  double front = 0.6;         ///< x of the open side
  double floor_height = 0.4;  ///< z of the floor's top
  double radius = 0.03, object_height = 0.10;  ///< every cylinder's, m
  double mass = 10.0;       ///< kg (the paper's code: 10)
  double friction = 0.4;    ///< the cylinders' coefficient
  double shelf_friction = 0.5;  ///< the boards' coefficient
  /// The target's centre at most this far in front of where it would touch the back
  /// wall, m (the paper's ten scenes, in its public code: 0 to 0.09).
  double back_band = 0.09;
  /// The obstacles' centres at least this far behind the opening, m: the paper's scenes
  /// crowd all ten into the back part of the shelf (0.25 to 0.56 m deep, a few mm
  /// apart), leaving the front free. 0: anywhere in the shelf.
  double clutter_from = 0.25;
  double min_gap = 0.0;  ///< m between cylinders and to the walls
  double exit_distance = 0.2;  ///< m in front of the opening where the hand starts (x_s)
};

/// Draws a PushShelfSpec shelf (same seed, same scene): the target first, then the
/// obstacles o1... uniformly where they fit from clutter_from to the back. The cabinet alone, no buffer table. Throws
/// std::runtime_error when the obstacles do not fit after many attempts.
CLUTTERTAMP_API Scene generate_push_shelf(const PushShelfSpec& spec, std::uint64_t seed);

/// How an occlusion shelf is laid out.
enum class OcclusionLayout {
  /// Columns of cylinders, each on a line from the camera so that each object is hidden
  /// by the one in front of it (the paper's "each object is occluded by the object in
  /// front of it"); the front row is larger (radius 4.5 cm, 33 cm tall) and is all the
  /// camera sees at first; the target is at the back of a column drawn by the seed.
  columns,
  /// The cylinders of a Table I shelf (generate_shelf_scene, no minimum gap) drawn at
  /// random; the target is the hidden object nearest the middle of the back wall.
  random,
};

/// A shelf where objects hide one another from the camera (Tian et al., Section V-A,
/// Fig. 7 and Table II). The camera stands 0.5 m behind the robot at the height of the
/// objects (15 cm above the floor), looking into the cabinet.
struct OcclusionSpec {
  OcclusionLayout layout = OcclusionLayout::columns;
  int objects = 12;  ///< random layout: how many cylinders (the cabinet as for a Table I shelf)
  int columns = 3;   ///< columns layout: columns × rows cylinders
  int rows = 4;
  double column_spacing = 0.14;  ///< m between the front objects
  double row_spacing = 0.16;     ///< m along x
  double front = 0.6;            ///< x of the cabinet's open side
  double floor_height = 0.4;     ///< z of the cabinet floor's top
};

/// A table reachable from every side for a mobile manipulator (Tian et al., Section
/// V-B, Fig. 9): `objects` standing cylinders (radius 3.5-4 cm, 24-29 cm tall, at
/// least `min_gap` apart) on a square table top, the target at its centre; the robot
/// base starts at the origin facing +x, the table's near edge `distance` ahead; the
/// exit x_s between them; a buffer table to the robot's right.
struct TableSpec {
  int objects = 20;
  /// m, the table top's side. (At 0.9 m, the density of the paper's 20-object
  /// shelves, the PR2 reached the middle less well: |O_r| 3.80 and 95 iterations
  /// against 3.95 and 9 at 0.7 m, over 20 tables.)
  double size = 0.7;
  double distance = 0.6;     ///< m from the robot base to the table's near edge
  double top_height = 0.4;   ///< z of the table top
  double min_gap = 0.01;
};

/// The table scene of `spec` (same seed, same scene). Throws std::runtime_error when
/// the objects do not fit.
CLUTTERTAMP_API Scene generate_table_scene(const TableSpec& spec, std::uint64_t seed);

/// The occlusion shelf of `spec` (same seed, same scene): objects "o1".. and "target".
/// Throws std::runtime_error for fewer than 1 column or 2 rows, or when the camera
/// would see more than the front row (a check of the columns layout); in the random
/// layout, when the camera sees every object (nothing hides a target).
CLUTTERTAMP_API Scene generate_occlusion_scene(const OcclusionSpec& spec, std::uint64_t seed);

}  // namespace cluttertamp::scenes
