// Planar pushing physics: a push moves what it touches, nothing else; the same state
// and control give the same outcome; walls and board edges are reported.

#include <cmath>

#include <gtest/gtest.h>

#include "cluttertamp/physics/push_world.hpp"
#include "test_fixtures.hpp"

namespace cluttertamp {
namespace {

using physics::PushControl;
using physics::PushWorld;

constexpr double kBoardTop = 0.40;  // m

// A board x in [0.6, 1.1], y in [-0.5, 0.5], top at kBoardTop; a cylinder (the target)
// standing on it at (x, y); optionally a wall along y at x = 1.06.
Scene board_scene(double x, double y, bool wall = false) {
  Scene s;
  s.name = "board";
  test::add_box(s, "board", {0.5, 1.0, 0.02}, {0.85, 0, kBoardTop - 0.01});
  if (wall) test::add_box(s, "wall", {0.02, 1.0, 0.5}, {1.06, 0, kBoardTop + 0.25});
  s.objects[test::add_cylinder(s, "can", x, y, 0.035)].friction = 0.5;
  s.target = 0;
  return s;
}

TEST(PushPhysics, APushMovesAnIsolatedCylinderAlongThePushAndOnlyWhatItTouches) {
  const Scene scene = board_scene(0.80, 0.0);
  const WorldState initial = WorldState::initial(scene);
  const PushWorld world(scene, initial);
  EXPECT_NEAR(world.plane_z(), kBoardTop + 0.01, 1e-9);
  // The gripper's front face starts 8 cm before the can and moves 15 cm forward.
  const physics::PushState start = world.state_of(initial, {0.665, 0.0, 0.0});
  const physics::PushOutcome out = world.propagate(start, PushControl{{0.1, 0, 0}, 1.5});
  EXPECT_NEAR(out.state.gripper.x(), 0.815, 1e-9);
  const Eigen::Vector3d can = out.state.objects[0].pose;
  EXPECT_GT(can.x(), 0.80 + 0.03) << "pushed forward";
  EXPECT_LT(can.x(), 0.90) << "not thrown";
  // A flat face on a round can is an unstable balance: it drifts a little sideways.
  EXPECT_GT(can.x() - 0.80, 2 * std::abs(can.y())) << "mostly along the push";
  EXPECT_EQ(out.touched, std::vector<ObjectIndex>{0});
  EXPECT_TRUE(out.fallen.empty());
  EXPECT_FALSE(out.gripper_hit_fixed);
}

TEST(PushPhysics, AGripperMovingInTheOpenLeavesTheObjectsWhereTheyStand) {
  const Scene scene = board_scene(0.80, 0.3);
  const WorldState initial = WorldState::initial(scene);
  const PushWorld world(scene, initial);
  const physics::PushOutcome out = world.propagate(world.state_of(initial, {0.65, -0.2, 0.3}), PushControl{{0.1, 0.05, 0.2}, 1.0});
  EXPECT_NEAR(out.state.gripper.x(), 0.75, 1e-9);
  EXPECT_NEAR(out.state.gripper.y(), -0.15, 1e-9);
  EXPECT_NEAR(out.state.gripper.z(), 0.5, 1e-9);
  EXPECT_NEAR(out.state.objects[0].pose.x(), 0.80, 1e-4);
  EXPECT_NEAR(out.state.objects[0].pose.y(), 0.30, 1e-4);
  EXPECT_TRUE(out.touched.empty());
}

TEST(PushPhysics, TheSameStateAndControlGiveTheSameOutcomeBitForBit) {
  const Scene scene = board_scene(0.80, 0.01);
  const WorldState initial = WorldState::initial(scene);
  const PushWorld world(scene, initial);
  const physics::PushState start = world.state_of(initial, {0.68, 0.0, 0.1});
  const PushControl control{{0.12, 0.02, -0.1}, 1.2};
  const physics::PushOutcome first = world.propagate(start, control);
  world.propagate(world.state_of(initial, {0.7, 0.05, 0.0}), PushControl{{0.2, 0, 0}, 0.5});  // something else between
  const physics::PushOutcome second = world.propagate(start, control);
  EXPECT_EQ(first.state.objects[0].pose, second.state.objects[0].pose);
  EXPECT_EQ(first.state.objects[0].velocity, second.state.objects[0].velocity);
  EXPECT_NE(first.state.objects[0].pose, start.objects[0].pose) << "the control pushes the can";
}

TEST(PushPhysics, APushOverTheBoardEdgeDropsTheObjectAndAWallStopsNothingButIsReported) {
  {
    const Scene scene = board_scene(0.70, 0.0);
    const WorldState initial = WorldState::initial(scene);
    const PushWorld world(scene, initial);
    // Backwards off the front edge (x = 0.6).
    const physics::PushOutcome out = world.propagate(world.state_of(initial, {0.76, 0.0, 0.0}), PushControl{{-0.2, 0, 0}, 1.5});
    EXPECT_EQ(out.fallen, std::vector<ObjectIndex>{0});
  }
  {
    const Scene scene = board_scene(0.80, 0.3, true);
    const WorldState initial = WorldState::initial(scene);
    const PushWorld world(scene, initial);
    const physics::PushOutcome out = world.propagate(world.state_of(initial, {0.9, 0.0, 0.0}), PushControl{{0.2, 0, 0}, 1.0});
    EXPECT_TRUE(out.gripper_hit_fixed) << "the gripper entered the wall at x = 1.05";
    const physics::PushOutcome short_of = world.propagate(world.state_of(initial, {0.9, 0.0, 0.0}), PushControl{{0.2, 0, 0}, 0.3});
    EXPECT_FALSE(short_of.gripper_hit_fixed) << "it stops at x = 0.96, the fingertips at 1.03";
    const physics::PushOutcome fingers_in = world.propagate(world.state_of(initial, {0.9, 0.0, 0.0}), PushControl{{0.2, 0, 0}, 0.5});
    EXPECT_TRUE(fingers_in.gripper_hit_fixed) << "at x = 1.0 the palm's face (1.02) is short of it, the fingertips (1.07) are not";
  }
}

TEST(PushPhysics, AMovableObjectWithoutMassIsRefused) {
  Scene scene = board_scene(0.8, 0.0);
  scene.objects[0].mass = 0;
  EXPECT_THROW(PushWorld(scene, WorldState::initial(scene)), std::invalid_argument);
}

}  // namespace
}  // namespace cluttertamp
