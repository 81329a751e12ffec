// Pushing with the robot's arm on a planar base (Papallas & Dogar's robot): the arm's
// links come from its kinematics, the hand is where the base carries it and swings on
// the lever when the base turns, links other than the hand push objects and hit walls,
// friction combines as the settings say, a problem's `physics:` block is read with
// every error located, a reach is planned and replayed, and `generate --push` draws the
// paper's shelves.

#include <cmath>
#include <fstream>

#include <gtest/gtest.h>

#include "cluttertamp/io/problem_io.hpp"
#include "cluttertamp/io/scene_io.hpp"
#include "cluttertamp/physics/push_planning.hpp"
#include "cluttertamp/plugin/registry.hpp"
#include "cluttertamp/run/runner.hpp"
#include "cluttertamp/scenes/shelf_generator.hpp"
#include "test_fixtures.hpp"
#include "test_support.hpp"

namespace cluttertamp {
namespace {

namespace fs = std::filesystem;
using physics::PushControl;
using physics::PushSettings;
using physics::PushWorld;

constexpr double kBoardTop = 0.40;  // m

// A board x in [0.6, 1.6], y in [-0.6, 0.6], top at kBoardTop; 26 cm cylinders on it
// at `at` (the first is the target).
Scene board_scene(const std::vector<Eigen::Vector2d>& at) {
  Scene s;
  s.name = "board";
  s.workspace = Eigen::AlignedBox3d(Eigen::Vector3d(-1.5, -1.5, -0.5), Eigen::Vector3d(2, 1.5, 1.5));
  s.world_T_exit = Eigen::Translation3d(0.45, 0, 0.53);
  test::add_box(s, "board", {1.0, 1.2, 0.02}, {1.1, 0, kBoardTop - 0.01});
  for (std::size_t i = 0; i < at.size(); ++i) {
    const ObjectIndex o = test::add_cylinder(s, i == 0 ? "target" : "o" + std::to_string(i), at[i].x(), at[i].y(), 0.035);
    s.objects[o].friction = 0.5;
  }
  s.target = 0;
  return s;
}

// The UR10's arm at home on a planar base, the hand 1.27 m from the base's centre.
PushSettings arm_settings() {
  PushSettings settings;
  auto arm = std::make_shared<physics::ArmPusher>(physics::arm_pusher(*test::ur10(), test::ur10()->home()));
  arm->base_offset.x() = physics::base_offset_for_lever(*arm, physics::kPaperLever);
  settings.arm = std::move(arm);
  settings.yaw_limits = {-M_PI / 4, M_PI / 4};
  return settings;
}

TEST(PushArm, TheArmHasEveryLinksGeometryAndItsToolWhereKinematicsPutsIt) {
  const robot::RobotDescription& robot = *test::ur10();
  const physics::ArmPusher arm = physics::arm_pusher(robot, robot.home());
  std::size_t shapes = 0;
  for (const robot::Link& link : robot.model()->links()) shapes += link.collision.size();
  EXPECT_EQ(arm.parts.size(), shapes);
  ASSERT_EQ(arm.hand.size(), shapes);
  const auto hand_parts = std::count(arm.hand.begin(), arm.hand.end(), true);
  EXPECT_GT(hand_parts, 0);
  EXPECT_LT(hand_parts, static_cast<long>(shapes));
  std::vector<Eigen::Isometry3d> poses;
  robot.model()->link_poses(robot.home(), poses);
  const Eigen::Isometry3d expected = poses[robot.base_link()].inverse() * poses[robot.tip_link()];
  EXPECT_TRUE(arm.arm_T_tcp.isApprox(expected, 1e-12));
  EXPECT_THROW(physics::arm_pusher(robot, Eigen::VectorXd::Zero(2)), std::invalid_argument);
  // The lever the base offset gives is the one asked for.
  physics::ArmPusher placed = arm;
  placed.base_offset.x() = physics::base_offset_for_lever(arm, 1.27);
  EXPECT_NEAR((placed.base_offset + arm.arm_T_tcp.translation().head<2>()).norm(), 1.27, 1e-9);
}

TEST(PushArm, TheHandIsWhereTheBaseCarriesItAndTurningTheBaseSwingsItOnTheLever) {
  const Scene scene = board_scene({{1.5, 0.4}});
  const WorldState initial = WorldState::initial(scene);
  const PushWorld world(scene, initial, arm_settings());
  // It starts with the hand at the exit, facing into the shelf.
  const Eigen::Vector3d start = world.start_pose();
  EXPECT_LT((world.hand(start) - Eigen::Vector3d(0.45, 0, 0)).norm(), 1e-9);
  EXPECT_NEAR(world.hand({0, 0, 0}).head<2>().norm(), physics::kPaperLever, 1e-9);
  for (const Eigen::Vector3d& p : {Eigen::Vector3d(0.1, -0.2, 0.3), Eigen::Vector3d(-0.4, 0.5, -0.7)}) {
    EXPECT_LT((world.pose_for_hand(world.hand(p)) - p).norm(), 1e-12);
  }
  // Yaw limits: +-pi/4 allowed, beyond clamped; a hand asked to face beyond them is
  // turned about its own point.
  EXPECT_TRUE(world.yaw_allowed(0.7));
  EXPECT_FALSE(world.yaw_allowed(0.9));
  EXPECT_DOUBLE_EQ(world.clamp_yaw(2.0), M_PI / 4);
  EXPECT_FALSE(world.hand_heading_allowed(1.2));
  const Eigen::Vector3d turned_in = world.pose_for_hand({0.5, 0.1, 1.2});
  EXPECT_TRUE(world.yaw_allowed(turned_in.z()));
  EXPECT_LT((world.hand(turned_in).head<2>() - Eigen::Vector2d(0.5, 0.1)).norm(), 1e-12);
  PushSettings askew = arm_settings();
  askew.start_hand = Eigen::Vector3d(0.45, 0.05, -1.0);
  const PushWorld started(scene, initial, askew);
  EXPECT_TRUE(started.yaw_allowed(started.start_pose().z()));
  EXPECT_LT((started.hand(started.start_pose()).head<2>() - Eigen::Vector2d(0.45, 0.05)).norm(), 1e-12);
  // Turning the base 0.1 rad moves the hand along a chord of the lever's circle.
  const physics::PushOutcome turned = world.propagate(world.state_of(initial, start), PushControl{{0, 0, 0.1}, 1.0});
  const Eigen::Vector3d moved = world.hand(turned.state.gripper) - world.hand(start);
  EXPECT_NEAR(moved.head<2>().norm(), 2 * physics::kPaperLever * std::sin(0.05), 1e-6);
  EXPECT_NEAR(moved.z(), 0.1, 1e-9);
  EXPECT_FALSE(turned.gripper_hit_fixed);
}

// Cans beside the hand's path, out of the floating gripper's reach: the arm's forearm
// and wrists sweep them, the floating gripper passes them by.
TEST(PushArm, LinksOtherThanTheHandPushWhatTheHandPassesBy) {
  const Eigen::Vector2d hand(0.95, 0.1);
  const Scene scene = board_scene({{1.55, -0.5}, {hand.x() - 0.1, hand.y() - 0.11}, {hand.x() - 0.1, hand.y() - 0.185},
                                   {hand.x() - 0.1, hand.y() - 0.26}});
  const WorldState initial = WorldState::initial(scene);
  const PushControl forward{{0.1, 0, 0}, 2.0};
  const PushWorld arm(scene, initial, arm_settings());
  const physics::PushState at_arm = arm.state_of(initial, arm.pose_for_hand({hand.x(), hand.y(), 0}));
  ASSERT_TRUE(arm.propagate(at_arm, PushControl{{0, 0, 0}, 0.01}).touched.empty()) << "nothing touched at the start";
  const physics::PushOutcome swept = arm.propagate(at_arm, forward);
  EXPECT_FALSE(swept.touched.empty());
  double moved = 0;
  for (ObjectIndex i = 1; i < 4; ++i) moved = std::max(moved, (swept.state.objects[i].pose - at_arm.objects[i].pose).head<2>().norm());
  EXPECT_GT(moved, 0.02);
  const PushWorld gripper(scene, initial);
  const physics::PushOutcome passed = gripper.propagate(gripper.state_of(initial, {hand.x(), hand.y(), 0}), forward);
  EXPECT_TRUE(passed.touched.empty());
}

// A board above the hand but at the wrist's height: entering it is a hit for the arm;
// raised 10 cm, nothing is hit.
TEST(PushArm, AnArmLinkEnteringFixedGeometryIsAHit) {
  const Eigen::Vector2d hand(0.9, 0.0);
  for (const double raise : {0.0, 0.1}) {
    Scene scene = board_scene({{1.55, -0.5}});
    const PushWorld probe(scene, WorldState::initial(scene), arm_settings());
    // The tool's height: the hand's lowest point at clearance above the board.
    const PushSettings settings = arm_settings();
    const Eigen::Isometry3d tcp = Eigen::Translation3d(settings.arm->base_offset.x(), 0, 0) * settings.arm->arm_T_tcp;
    const double tcp_z = probe.pusher_z() + tcp.translation().z();
    test::add_box(scene, "low_top", {0.45, 1.0, 0.2}, {hand.x() + 0.075, 0, tcp_z + 0.09 + raise + 0.1});
    const WorldState initial = WorldState::initial(scene);
    const PushWorld world(scene, initial, settings);
    const physics::PushState start = world.state_of(initial, world.pose_for_hand({hand.x() - 0.2, hand.y(), 0}));
    const physics::PushOutcome out = world.propagate(start, PushControl{{0.1, 0, 0}, 2.5});
    EXPECT_EQ(out.gripper_hit_fixed, raise == 0.0) << "raised " << raise;
  }
}

// An object set sliding at 0.5 m/s stops after v^2 / (2 mu g), without spinning up (its
// base's torsional friction): mu the product of its and the board's coefficients
// (0.4 x 0.5) or, MuJoCo's rule, the larger (0.5).
TEST(PushArm, FrictionCombinesAsTheSettingsSay) {
  Scene scene = board_scene({{0.9, 0.0}});
  scene.fixed[0].friction = 0.5;
  scene.objects[0].friction = 0.4;
  const WorldState initial = WorldState::initial(scene);
  for (const auto rule : {PushSettings::FrictionCombine::product, PushSettings::FrictionCombine::max}) {
    PushSettings settings;
    settings.friction_combine = rule;
    const PushWorld world(scene, initial, settings);
    physics::PushState start = world.state_of(initial, {0.3, 0.4, 0.0});
    start.objects[0].velocity = {0.5, 0.0, 0.0};
    const physics::PushOutcome out = world.propagate(start, PushControl{{0, 0, 0}, 1.0});
    const double slid = out.state.objects[0].pose.x() - 0.9;
    const double mu = rule == PushSettings::FrictionCombine::max ? 0.5 : 0.2;
    EXPECT_NEAR(slid, 0.25 / (2 * mu * 9.81), 0.1 * 0.25 / (2 * mu * 9.81)) << "mu " << mu;
    EXPECT_LT(out.state.objects[0].velocity.norm(), 1e-3) << "at rest after 1 s, not spinning";
  }
  // The settings' own coefficient for every fixed body replaces the scene's.
  PushSettings slippery;
  slippery.fixed_friction = 0.01;
  const PushWorld world(scene, initial, slippery);
  physics::PushState start = world.state_of(initial, {0.3, 0.4, 0.0});
  start.objects[0].velocity = {0.5, 0.0, 0.0};
  EXPECT_GT(world.propagate(start, PushControl{{0, 0, 0}, 1.0}).state.objects[0].pose.x() - 0.9, 0.4);
}

class PushArmFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("cluttertamp_push_arm_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // The bundled easy pushing problem with `physics` as its physics block and `parameters`
  // as its planner's.
  fs::path problem(const std::string& physics, const std::string& parameters) const {
    const fs::path push = fs::path(CLUTTERTAMP_SOURCE_DIR) / "problems/push";
    const fs::path file = dir_ / "problem.yaml";
    std::ofstream(file) << "version: 1\nname: arm\nscene: " << (push / "easy-scene.yaml").string()
                        << "\nrobot: {description: " << (fs::path(CLUTTERTAMP_SOURCE_DIR) / "domains/robots/ur10_ag95.yaml").string()
                        << "}\ntask: {reach: target}\n"
                        << "physics: " << physics << "\n"
                        << "planner: {plugin: rtc_ompl, time_limit: 120, seed: 0, parameters: " << parameters << "}\n";
    return file;
  }

  fs::path dir_;
};

TEST_F(PushArmFiles, APhysicsBlockIsReadAndEveryBadKeyReportedWithItsLine) {
  const Problem good = io::load_problem(problem("{pusher: arm, base_offset: [0.7, 0.05], friction_combine: max, fixed_friction: 0.6, object_mass: 0.2, "
                                                        "tip_limit: 0.1, wall_force_limit: 9}",
                                                "{planner: rrt}"));
  const PushSettings s = physics::push_settings(good);
  ASSERT_TRUE(s.arm);
  EXPECT_EQ(s.arm->base_offset, Eigen::Vector2d(0.7, 0.05));
  EXPECT_EQ(s.yaw_limits, Eigen::Vector2d(-M_PI / 4, M_PI / 4));
  EXPECT_EQ(s.friction_combine, PushSettings::FrictionCombine::max);
  EXPECT_EQ(s.fixed_friction, 0.6);
  EXPECT_EQ(s.object_mass, 0.2);
  EXPECT_EQ(s.tip_limit, 0.1);
  EXPECT_EQ(s.wall_force_limit, 9.0);
  EXPECT_FALSE(physics::push_settings(io::load_problem(problem("{pusher: gripper}", "{planner: rrt}"))).arm);

  const Problem bad = io::load_problem(
      problem("{pusher: gripper, base_ofset: [1, 0], hand_height: 0.05, object_mass: -1, friction_combine: min, tip_limit: 0, "
              "wall_force_limit: -9}",
              "{planner: rrt}"));
  try {
    physics::push_settings(bad);
    FAIL() << "no error";
  } catch (const InputError& e) {
    const std::string all = e.diagnostics().str();
    EXPECT_EQ(e.diagnostics().size(), 6u) << all;
    EXPECT_NE(all.find("unknown physics key 'base_ofset' (did you mean 'base_offset'?)"), std::string::npos) << all;
    EXPECT_NE(all.find("hand_height"), std::string::npos) << all;
    EXPECT_NE(all.find("applies to pusher: arm only"), std::string::npos) << all;
    EXPECT_NE(all.find("object_mass"), std::string::npos) << all;
    EXPECT_NE(all.find("friction_combine"), std::string::npos) << all;
    EXPECT_NE(all.find("tip_limit"), std::string::npos) << all;
    EXPECT_NE(all.find("wall_force_limit"), std::string::npos) << all;
    EXPECT_NE(all.find("problem.yaml:6:"), std::string::npos) << all;
  }
  // `plan` refuses it before planning, exit code 2, naming the file and line.
  const test::CliRun r = test::run_cli("plan " + (dir_ / "problem.yaml").string() + " -q -o " + (dir_ / "out").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("problem.yaml:6:"), std::string::npos) << r.output;
  // Postures the arm cannot push in are refused at the key, not when planning.
  for (const char* posture : {"[0, 1]", "[3.14159, -2, 2, -1.5708, 1.5708, 0, 0.0475]", "[3.14159, -2, 2, 0, 1.5708, 0, 5]"}) {
    const Problem p = io::load_problem(problem(std::string("{pusher: arm, posture: ") + posture + "}", "{planner: rrt}"));
    EXPECT_THROW(physics::push_settings(p), InputError) << posture;
  }
  const Problem up = io::load_problem(problem("{pusher: arm, posture: [3.14159, -2, 2, -1.5708, 1.5708, 0, 0.0475]}", "{planner: rrt}"));
  try {
    physics::push_settings(up);
  } catch (const InputError& e) {
    EXPECT_NE(e.diagnostics().str().find("points the tool up or down"), std::string::npos) << e.diagnostics().str();
  }
  EXPECT_THROW(physics::push_settings(io::load_problem(problem("{pusher: arm, hand_height: .inf}", "{planner: rrt}"))), InputError);
  // The planner's sample box must be a box.
  const test::CliRun box = test::run_cli("plan " + problem("{pusher: arm}", "{planner: rrt, sample_bounds: [1, 0, 0, 1]}").string() +
                                         " -q -o " + (dir_ / "box").string());
  EXPECT_EQ(box.exit_code, 2) << box.output;
  EXPECT_NE(box.output.find("sample_bounds"), std::string::npos) << box.output;
}

// The arm reaches the target on the easy shelf: the plan replays through the physics to
// the same end, valid all along, the base within its yaw limits, the hand's reach point
// within the goal's distance of the target.
TEST_F(PushArmFiles, TheArmReachesTheTargetAndThePlanReplays) {
  const Problem p = io::load_problem(problem("{pusher: arm, base_offset: [0.7, 0]}", "{planner: rrt, steer: 0.3, max_propagations: 20000, goal: point}"));
  const plugin::Registry registry(plugin::Registry::default_search_paths());
  const run::RunOutcome run = run::plan(p, registry, {});
  ASSERT_TRUE(run.result.solved) << run.result.reason;
  const PlanStep& step = run.result.plan.at(0);
  EXPECT_EQ(step.trajectory->joint_names, (std::vector<std::string>{"base_x", "base_y", "base_yaw"}));
  const WorldState initial = WorldState::initial(p.scene);
  const PushWorld world(p.scene, initial, physics::push_settings(p));
  const physics::Replay replay =
      physics::replay(world, world.state_of(initial, world.start_pose()), physics::controls_of(step), step.values.at("step").at(0));
  EXPECT_TRUE(replay.valid);
  EXPECT_LT((replay.end.gripper - step.trajectory->positions.back()).norm(), 1e-9);
  for (const Eigen::VectorXd& q : step.trajectory->positions) EXPECT_TRUE(world.yaw_allowed(q[2])) << q.transpose();
  const Eigen::Vector3d hand = world.hand(replay.end.gripper);
  EXPECT_LE((replay.end.objects[p.scene.target].pose.head<2>() - hand.head<2>()).norm(), 0.07);
  // Parts for the viewer: 11 numbers each.
  EXPECT_EQ(step.values.at("pusher_parts").size(), 11 * world.pusher_parts().size());
}

// The paper's first shelf, guided: its guide pushes o1 sideways (75 degrees off the
// shelf's axis), beyond the base's yaw limits to face; the arm's hand pushes it with
// its side, and the result records the guidance followed.
TEST_F(PushArmFiles, AGuidedArmPushesSidewaysWithItsHandsSide) {
  const fs::path paper = fs::path(CLUTTERTAMP_SOURCE_DIR) / "problems/push/paper10";
  Problem p = io::load_problem(paper / "p01.yaml");
  p.planner.name = "grtc";
  p.seed = 2;  // one of the quicker (413 propagations; seed 0 takes 3425)
  p.planner.parameters.set("guidance", (paper / "p01-guidance.yaml").string());
  const plugin::Registry registry(plugin::Registry::default_search_paths());
  const run::RunOutcome run = run::plan(p, registry, {});
  ASSERT_TRUE(run.result.solved) << run.result.reason;
  ASSERT_TRUE(run.result.guidance);
  EXPECT_EQ(run.result.guidance->source, (paper / "p01-guidance.yaml").string());
  ASSERT_EQ(run.result.guidance->guides.size(), 1u);
  const GuideRecord& guide = run.result.guidance->guides[0];
  EXPECT_TRUE(guide.satisfied) << guide.reason;
  EXPECT_EQ(run.result.counters.at("guides_satisfied"), 1u);
  // The guide's push ends with o1 in its disc.
  const WorldState initial = WorldState::initial(p.scene);
  const PushWorld world(p.scene, initial, physics::push_settings(p));
  const PlanStep& push = run.result.plan.at(0);
  const physics::Replay replay = physics::replay(world, world.state_of(initial, world.start_pose()), physics::controls_of(push),
                                                 push.values.at("step").at(0));
  EXPECT_TRUE(replay.valid);
  EXPECT_LE((replay.end.objects[guide.object].pose.head<2>() - guide.centre).norm(), guide.diameter / 2 + 1e-9);
}

// generate --push draws the paper's shelf (the target at the back, ten 3 cm obstacles
// that do not overlap) and a problem whose physics is the arm's; the same seed draws
// the same files.
TEST_F(PushArmFiles, GeneratePushDrawsThePapersShelfAndItsProblem) {
  const fs::path scene_file = dir_ / "s.yaml", problem_file = dir_ / "p.yaml";
  const test::CliRun r = test::run_cli("generate --push --seed 4 --output " + scene_file.string() + " --problem " + problem_file.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const Scene scene = io::load_scene(scene_file);
  const scenes::PushShelfSpec spec;
  ASSERT_EQ(scene.objects.size(), 11u);
  EXPECT_EQ(scene.objects[scene.target].id, "target");
  const double back = spec.front + spec.depth;
  EXPECT_GE(scene.objects[scene.target].world_T_object.translation().x(), back - spec.radius - spec.back_band - 1e-6);
  for (std::size_t i = 0; i < scene.objects.size(); ++i) {
    const auto* c = std::get_if<Cylinder>(&scene.objects[i].shape);
    ASSERT_TRUE(c);
    EXPECT_DOUBLE_EQ(c->radius, 0.03);
    EXPECT_DOUBLE_EQ(c->height, 0.10);
    EXPECT_DOUBLE_EQ(scene.objects[i].friction, 0.4);
    EXPECT_GE(scene.objects[i].world_T_object.translation().x(), spec.front + spec.clutter_from - 1e-9) << "in the back part";
    for (std::size_t k = 0; k < i; ++k) {
      EXPECT_GE((scene.objects[i].world_T_object.translation() - scene.objects[k].world_T_object.translation()).norm(), 0.06 - 1e-6);
    }
  }
  for (const FixedBody& f : scene.fixed) EXPECT_DOUBLE_EQ(f.friction, 0.5);
  const Problem p = io::load_problem(problem_file);
  const PushSettings s = physics::push_settings(p);
  ASSERT_TRUE(s.arm);
  EXPECT_EQ(s.friction_combine, PushSettings::FrictionCombine::max);
  EXPECT_EQ(s.tip_limit, 0.1);
  EXPECT_EQ(s.wall_force_limit, 9.0);
  const PushWorld world(p.scene, WorldState::initial(p.scene), s);
  EXPECT_NEAR(world.hand({0, 0, 0}).head<2>().norm(), physics::kPaperLever, 1e-3);
  const std::string first = test::read_text(scene_file);
  ASSERT_EQ(test::run_cli("generate --push --seed 4 -q --output " + scene_file.string()).exit_code, 0);
  EXPECT_EQ(test::read_text(scene_file), first);
  EXPECT_EQ(test::run_cli("generate --push --table --output " + scene_file.string()).exit_code, 2);
}

}  // namespace
}  // namespace cluttertamp
