// Planar pushing physics: a push moves what it touches, nothing else; the same state
// and control give the same outcome; walls and board edges are reported.

#include <cmath>
#include <optional>

#include <gtest/gtest.h>

#include "cluttertamp/physics/push_planning.hpp"
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
  s.workspace = Eigen::AlignedBox3d(Eigen::Vector3d(-0.5, -1, 0), Eigen::Vector3d(1.5, 1, 1.5));
  s.world_T_exit = Eigen::Translation3d(0.55, 0, 0.53);
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

// A can (r 3.5 cm, 26 cm tall, mu 0.5 on the board) tips when pushed above r / mu = 7 cm
// and slides when pushed below it. With a tip limit it may tip, and does when pushed high;
// without one it never does.
TEST(PushPhysics, AnObjectPushedHighTipsOnlyWhenAllowedToAndAPushLowSlidesIt) {
  const Scene scene = board_scene(0.80, 0.0);
  const WorldState initial = WorldState::initial(scene);
  const auto push = [&](double clearance, std::optional<double> tip_limit) {
    physics::PushSettings settings;
    settings.gripper_clearance = clearance;
    settings.tip_limit = tip_limit;
    const PushWorld world(scene, initial, settings);
    const physics::PushOutcome out = world.propagate(world.state_of(initial, {0.665, 0.0, 0.0}), PushControl{{0.1, 0, 0}, 1.5});
    EXPECT_EQ(out.touched, std::vector<ObjectIndex>{0}) << "clearance " << clearance;
    EXPECT_EQ(physics::valid_outcome(world, out), out.tipped.empty());
    return out;
  };
  EXPECT_EQ(push(0.17, 0.1).tipped, std::vector<ObjectIndex>{0}) << "pushed 17 to 23 cm up";
  const physics::PushOutcome upright = push(0.17, std::nullopt);
  EXPECT_TRUE(upright.tipped.empty());
  EXPECT_GT(upright.state.objects[0].pose.x(), 0.83) << "without tipping it slides";
  const physics::PushOutcome low = push(0.005, 0.02);
  EXPECT_TRUE(low.tipped.empty()) << "pushed 0.5 to 6.5 cm up it slides, tilting less than 0.02 rad";
  EXPECT_GT(low.state.objects[0].pose.x(), 0.83);
}

// A ball has no tilt to lose: with a tip limit it still slides where pushed, never tipped.
TEST(PushPhysics, ABallPushedUnderATipLimitSlidesAndNeverTips) {
  Scene scene = board_scene(0.80, 0.3);
  SceneObject ball;
  ball.id = "ball";
  ball.shape = Sphere{0.04};
  ball.world_T_object = Eigen::Isometry3d(Eigen::Translation3d(0.80, 0.0, kBoardTop + 0.04));
  ball.mass = 0.3;
  ball.friction = 0.5;
  scene.objects.push_back(ball);
  const WorldState initial = WorldState::initial(scene);
  physics::PushSettings settings;
  settings.tip_limit = 0.1;
  const PushWorld world(scene, initial, settings);
  const physics::PushOutcome out = world.propagate(world.state_of(initial, {0.665, 0.0, 0.0}), PushControl{{0.1, 0, 0}, 1.5});
  EXPECT_EQ(out.touched, std::vector<ObjectIndex>{1});
  EXPECT_TRUE(out.tipped.empty());
  EXPECT_GT(out.state.objects[1].pose.x(), 0.83);
  EXPECT_TRUE(physics::valid_outcome(world, out));
}

// Objects free to tip stand still when nothing touches them, and one pushed comes to
// rest and stays there: an object all but still at a control's end is at rest.
TEST(PushPhysics, ObjectsFreeToTipStandStillUntouchedAndComeToRestAfterAPush) {
  Scene scene = board_scene(0.80, 0.0, true);
  test::add_cylinder(scene, "thin", 0.7, 0.3, 0.02);
  const WorldState initial = WorldState::initial(scene);
  physics::PushSettings settings;
  settings.tip_limit = 0.005;
  const PushWorld world(scene, initial, settings);
  const physics::PushState start = world.state_of(initial, {0.65, -0.3, 0.0});
  const physics::PushOutcome out = world.propagate(start, PushControl{{0, 0, 0}, 2.0});
  EXPECT_TRUE(out.tipped.empty());
  for (std::size_t i = 0; i < scene.objects.size(); ++i) {
    EXPECT_LT((out.state.objects[i].pose - start.objects[i].pose).norm(), 1e-6) << scene.objects[i].id;
    EXPECT_TRUE(out.state.objects[i].velocity.isZero()) << scene.objects[i].id;
  }
  // The can pushed 1.5 cm, low, then left (the gripper backs off): it stops within a
  // control and stays.
  physics::PushState s = world.state_of(initial, {0.71, 0.0, 0.0});
  s = world.propagate(s, PushControl{{0.05, 0, 0}, 1.0}).state;
  EXPECT_GT(s.objects[0].pose.x(), 0.81);
  s = world.propagate(s, PushControl{{-0.1, 0, 0}, 1.0}).state;
  EXPECT_TRUE(s.objects[0].velocity.isZero()) << s.objects[0].velocity.transpose();
  const physics::PushOutcome later = world.propagate(s, PushControl{{0, 0, 0}, 1.0});
  EXPECT_LT((later.state.objects[0].pose - s.objects[0].pose).norm(), 1e-6);
  EXPECT_TRUE(later.tipped.empty());
}

// A can pushed into the wall presses on it, and the wall force limit makes that invalid
// and ends the simulation there; the board the can stands on, however heavy, takes no
// part in it.
TEST(PushPhysics, AWallTakesTheForceOfAnObjectPushedIntoItAndItsLimitEndsThePush) {
  Scene scene = board_scene(1.0, 0.0, true);  // the can's front 1.5 cm short of the wall (x = 1.05)
  scene.objects[0].mass = 10;
  const WorldState initial = WorldState::initial(scene);
  const physics::PushState start = [&] {
    const PushWorld world(scene, initial);
    return world.state_of(initial, {0.93, 0.0, 0.0});  // the palm's face 1.5 cm behind the can
  }();
  const PushControl into_wall{{0.05, 0, 0}, 0.7};  // the palm reaches the can after 0.3 s, the can the wall after 0.6 s
  const PushWorld unlimited(scene, initial);
  const physics::PushOutcome pressed = unlimited.propagate(start, into_wall);
  EXPECT_GT(pressed.wall_force, 9.0) << "the can against the wall";
  EXPECT_TRUE(physics::valid_outcome(unlimited, pressed)) << "no limit set";
  const physics::PushOutcome resting = unlimited.propagate(start, PushControl{{0.05, 0, 0}, 0.2});
  EXPECT_EQ(resting.wall_force, 0.0) << "short of the can: 98 N on the board, none on the wall";

  physics::PushSettings settings;
  settings.wall_force_limit = 9.0;
  const PushWorld limited(scene, initial, settings);
  const physics::PushOutcome stopped = limited.propagate(start, into_wall);
  EXPECT_GT(stopped.wall_force, 9.0);
  EXPECT_FALSE(physics::valid_outcome(limited, stopped));
  EXPECT_LT(stopped.state.gripper.x(), pressed.state.gripper.x()) << "the simulation ended when the wall took too much";
  EXPECT_TRUE(physics::valid_outcome(limited, limited.propagate(start, PushControl{{0.05, 0, 0}, 0.2})));
}

TEST(PushPhysics, AMovableObjectWithoutMassIsRefused) {
  Scene scene = board_scene(0.8, 0.0);
  scene.objects[0].mass = 0;
  EXPECT_THROW(PushWorld(scene, WorldState::initial(scene)), std::invalid_argument);
}

}  // namespace
}  // namespace cluttertamp
