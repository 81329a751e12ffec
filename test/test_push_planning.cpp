// Kinodynamic pushing: straight controls, a planned push that puts a cylinder in its
// region (checked by replaying its controls), the same seed giving the same plan, the
// push_ompl sampler, guidance files and the guidance generator.

#include <cmath>
#include <fstream>

#include <gtest/gtest.h>

#include "cluttertamp/io/guidance_io.hpp"
#include "cluttertamp/physics/guidance.hpp"
#include "cluttertamp/physics/push_planning.hpp"
#include "cluttertamp/plugin/push_sampler.hpp"
#include "cluttertamp/plugin/registry.hpp"
#include "test_fixtures.hpp"
#include "test_support.hpp"

namespace cluttertamp {
namespace {

using physics::PushWorld;

constexpr double kBoardTop = 0.40;  // m

// A board x in [0.6, 1.1], y in [-0.5, 0.5], top at kBoardTop, with a wall along its
// back; cylinders standing on it at `at` (the first is the target).
Scene board_scene(const std::vector<Eigen::Vector2d>& at) {
  Scene s;
  s.name = "board";
  s.workspace = Eigen::AlignedBox3d(Eigen::Vector3d(-0.5, -1, 0), Eigen::Vector3d(1.5, 1, 1.5));
  s.world_T_exit = Eigen::Translation3d(0.45, 0, 0.53);
  test::add_box(s, "board", {0.5, 1.0, 0.02}, {0.85, 0, kBoardTop - 0.01});
  test::add_box(s, "back", {0.02, 1.0, 0.5}, {1.09, 0, kBoardTop + 0.25});
  for (std::size_t i = 0; i < at.size(); ++i) {
    const ObjectIndex o = test::add_cylinder(s, i == 0 ? "target" : "o" + std::to_string(i), at[i].x(), at[i].y(), 0.035);
    s.objects[o].friction = 0.5;
  }
  s.target = 0;
  return s;
}

TEST(PushPlanning, StraightControlsStayInBoundsAndEndWhereAsked) {
  physics::KinodynamicSettings settings;
  const Eigen::Vector3d from(0.4, 0.1, 0.2), to(0.9, -0.05, -0.6);
  const auto controls = physics::straight_controls(from, to, settings);
  ASSERT_FALSE(controls.empty());
  Eigen::Vector3d end = from;
  for (const physics::PushControl& c : controls) {
    const double steps = c.duration / settings.step;
    EXPECT_NEAR(steps, std::round(steps), 1e-9) << "whole propagation steps";
    EXPECT_LE(std::round(steps), settings.max_steps);
    EXPECT_LE(c.velocity.x(), settings.max_speed + 1e-12);
    EXPECT_GE(c.velocity.x(), -settings.max_side_speed - 1e-12);
    EXPECT_LE(std::abs(c.velocity.y()), settings.max_side_speed + 1e-12);
    EXPECT_LE(std::abs(c.velocity.z()), settings.max_turn + 1e-12);
    end += c.velocity * c.duration;
  }
  EXPECT_LT((end - to).norm(), 1e-9);
  EXPECT_TRUE(physics::straight_controls(from, from, settings).empty());
}

TEST(PushPlanning, TheSupportRegionStopsAtTheWalls) {
  const Scene scene = board_scene({{0.8, 0.0}});
  const PushWorld world(scene, WorldState::initial(scene));
  EXPECT_NEAR(world.support_region().min().x(), 0.6, 1e-9);
  EXPECT_NEAR(world.support_region().max().x(), 1.08, 1e-9) << "the back wall's front face";
  EXPECT_NEAR(world.gripper_region().min().x(), 0.40, 1e-9) << "the exit, less 5 cm";
}

// The RTC goal is the target's centre between the fingers (Papallas & Dogar's "within
// the end-effector"): from the palm's face (2 cm ahead of the gripper's centre) to the
// fingertips (7 cm), at most the gap's half less the target's radius (4.5 - 3.5 cm)
// across. Without fingers it is the face at the target's surface.
TEST(PushPlanning, TheReachGoalIsTheTargetBetweenTheFingers) {
  const Scene scene = board_scene({{0.9, 0.0}});
  const WorldState initial = WorldState::initial(scene);
  const PushWorld world(scene, initial);
  const physics::ReachGoal goal(world, 0, physics::ReachTolerances{});
  const auto at = [&](double x, double y, double yaw) { return world.state_of(initial, {x, y, yaw}); };
  EXPECT_EQ(goal.distance(at(0.9 - 0.055, 0.0, 0.0)), 0.0) << "centre 5.5 cm ahead: in the pocket";
  EXPECT_EQ(goal.distance(at(0.9 - 0.069, 0.0, 0.0)), 0.0) << "centre 1 mm short of the fingertips' line";
  EXPECT_NEAR(goal.distance(at(0.9 - 0.08, 0.0, 0.0)), 0.01, 1e-9) << "1 cm beyond the fingertips";
  EXPECT_NEAR(goal.distance(at(0.9 - 0.055, 0.02, 0.0)), 0.01, 1e-9) << "2 cm across: 1 cm too near a finger";
  EXPECT_GT(goal.distance(at(0.9 + 0.055, 0.0, 0.0)), 0.1) << "behind the target, facing away";
  EXPECT_EQ(goal.distance(at(0.9, -0.055, M_PI / 2)), 0.0) << "from the side, turned towards it";
  const Eigen::Vector3d aim = goal.gripper_target(at(0.5, 0.0, 0.0));
  EXPECT_NEAR(aim.x(), 0.9 - 0.02 - 0.035, 1e-9) << "the palm's face at the target's surface";
  EXPECT_EQ(goal.distance(at(aim.x(), aim.y(), aim.z())), 0.0);

  physics::PushSettings box;
  box.finger_length = 0;
  const PushWorld box_world(scene, initial, box);
  const physics::ReachGoal face(box_world, 0, physics::ReachTolerances{});
  EXPECT_NEAR(face.distance(box_world.state_of(initial, {0.9 - 0.055, 0.0, 0.0})), 0.0, 1e-12) << "the face at its surface";
  EXPECT_NEAR(face.distance(box_world.state_of(initial, {0.9 - 0.075, 0.0, 0.0})), 0.02, 1e-9);
}

// A guide's goal steers the gripper to line up behind the object, its fingertips 1 cm
// short of it (approach: palm half depth 2 cm + radius 3.5 cm + fingers 5 cm + 1 cm),
// and, once on that line (within 2 cm aside and 0.3 rad, between touching and the
// approach point), to where the palm leaves the object at the region's centre.
TEST(PushPlanning, AGuideLinesUpWithTheFingertipsShortOfTheObjectThenPushesWithThePalm) {
  const Scene scene = board_scene({{0.95, 0.3}, {0.78, 0.0}});
  const WorldState initial = WorldState::initial(scene);
  const PushWorld world(scene, initial);
  const physics::ObjectInRegionGoal goal(world, 1, {0.88, 0.0}, 0.03);
  const auto aim = [&](double x, double y, double yaw) { return goal.gripper_target(world.state_of(initial, {x, y, yaw})); };
  const Eigen::Vector3d approach(0.78 - 0.115, 0.0, 0.0), push(0.88 - 0.055, 0.0, 0.0);
  EXPECT_LT((aim(0.5, 0.2, 0.0) - approach).norm(), 1e-9) << "from elsewhere: to the approach point";
  EXPECT_LT((aim(approach.x(), 0.0, 0.0) - push).norm(), 1e-9) << "lined up: push through";
  EXPECT_LT((aim(0.72, 0.0, 0.0) - push).norm(), 1e-9) << "on the line, fingers past the object's back";
  EXPECT_LT((aim(approach.x(), 0.03, 0.0) - approach).norm(), 1e-9) << "3 cm aside is not lined up";
  EXPECT_LT((aim(approach.x(), 0.0, 0.5) - approach).norm(), 1e-9) << "turned 0.5 rad is not lined up";
  EXPECT_LT((aim(0.79 + 0.1, 0.0, 0.0) - approach).norm(), 1e-9) << "beyond the object is not behind it";
  ASSERT_EQ(goal.goal_grippers(world.state_of(initial, {0.5, 0.0, 0.0})).size(), 1u);
  EXPECT_LT((goal.goal_grippers(world.state_of(initial, {0.5, 0.0, 0.0}))[0] - push).norm(), 1e-9);
}

// A cylinder alone on the board, pushed by the kinodynamic search (steered, Section
// V-A) into a 3 cm region 12 cm away and off the line it starts on.
TEST(PushPlanning, APlannedPushPutsTheCylinderInItsRegionWhenReplayed) {
  const Scene scene = board_scene({{0.95, 0.3}, {0.78, 0.0}});
  const WorldState initial = WorldState::initial(scene);
  const PushWorld world(scene, initial);
  const physics::PushState start = world.state_of(initial, {0.62, 0.0, 0.0});
  const Eigen::Vector2d centre(0.88, 0.06);
  const physics::ObjectInRegionGoal goal(world, 1, centre, 0.03);
  physics::KinodynamicSettings settings;
  settings.steer = 0.3;
  const physics::KinodynamicOutcome out = physics::plan_pushes(world, start, goal, settings, {60.0, 20000}, 7);
  ASSERT_TRUE(out.path) << out.reason;
  const physics::Replay replay = physics::replay(world, start, out.path->controls, out.path->step);
  EXPECT_TRUE(replay.valid);
  EXPECT_LE((replay.end.objects[1].pose.head<2>() - centre).norm(), 0.03);
  EXPECT_EQ(replay.end.objects[1].pose, out.path->states.back().objects[1].pose) << "the plan is its replay, bit for bit";
  EXPECT_EQ(replay.touched, std::vector<ObjectIndex>{1});

  const physics::KinodynamicOutcome again = physics::plan_pushes(world, start, goal, settings, {60.0, 20000}, 7);
  ASSERT_TRUE(again.path);
  EXPECT_EQ(again.propagations, out.propagations) << "same seed, same search";
  ASSERT_EQ(again.path->controls.size(), out.path->controls.size());
  for (std::size_t i = 0; i < out.path->controls.size(); ++i) {
    EXPECT_EQ(again.path->controls[i].velocity, out.path->controls[i].velocity);
    EXPECT_EQ(again.path->controls[i].duration, out.path->controls[i].duration);
  }
}

// A search stopped by its propagation budget ends the same way every time: no path, the
// budget named as the reason, and at most one extension's steps beyond it.
TEST(PushPlanning, APropagationBudgetEndsTheSearchTheSameWayEveryTime) {
  const Scene scene = board_scene({{0.95, 0.3}, {0.78, 0.0}});
  const WorldState initial = WorldState::initial(scene);
  const PushWorld world(scene, initial);
  const physics::PushState start = world.state_of(initial, {0.62, 0.0, 0.0});
  const physics::ObjectInRegionGoal goal(world, 1, Eigen::Vector2d(0.88, 0.06), 0.03);
  physics::KinodynamicSettings settings;
  const physics::KinodynamicOutcome out = physics::plan_pushes(world, start, goal, settings, {600.0, 5}, 7);
  ASSERT_FALSE(out.path);
  EXPECT_TRUE(out.budget_reached);
  EXPECT_FALSE(out.time_limit_reached);
  EXPECT_EQ(out.reason, "propagation budget (5) used up");
  EXPECT_GE(out.propagations, 5u);
  EXPECT_LE(out.propagations, 5u + static_cast<std::uint64_t>(settings.max_steps));
  const physics::KinodynamicOutcome again = physics::plan_pushes(world, start, goal, settings, {600.0, 5}, 7);
  EXPECT_EQ(again.propagations, out.propagations);
}

class PushSamplerTest : public ::testing::Test {
 protected:
  plugin::PushAnswer push(const Scene& scene, const plugin::PushQuery& query, const Parameters& parameters) {
    problem_.scene = scene;
    problem_.task = ReachTask{"target"};
    const auto sampler = registry_.create<plugin::PushSampler>("push_ompl", parameters);
    plugin::PlanningContext context{problem_, plugin::Deadline::after(60), 3, counters_, samplers_, nullptr};
    return sampler->push(context, query);
  }
  Problem problem_;
  std::map<std::string, std::uint64_t> counters_;
  plugin::Samplers samplers_;
  plugin::Registry registry_{plugin::Registry::default_search_paths()};
};

// The test: a single push moves an isolated cylinder into its goal region, by
// the quick pass and by the paper's approach states and kinodynamic search alone.
TEST_F(PushSamplerTest, ASinglePushMovesAnIsolatedCylinderIntoItsGoalRegion) {
  const Scene scene = board_scene({{1.0, -0.35}, {0.8, 0.0}});
  const WorldState initial = WorldState::initial(scene);
  const Eigen::Vector2d centre(0.85, 0.2);
  for (const bool quick : {true, false}) {
    SCOPED_TRACE(quick ? "quick pass" : "approach states and kinodynamic search");
    Parameters parameters;
    if (!quick) parameters.set("quick_rounds", std::int64_t{0});
    const plugin::PushQuery query{1, centre, 0.04, initial, {0.45, 0.0, 0.0}};
    counters_.clear();
    const plugin::PushAnswer answer = push(scene, query, parameters);
    EXPECT_EQ(counters_["quick_pushes"], quick ? 1u : 0u) << "the pass that pushed";
    ASSERT_TRUE(answer.step) << answer.failure->reason;
    ASSERT_TRUE(answer.resulting_state);
    EXPECT_LE((answer.resulting_state->world_T_objects[1].translation().head<2>() - centre).norm(), 0.04);
    EXPECT_NEAR(answer.resulting_state->world_T_objects[1].translation().z(), initial.world_T_objects[1].translation().z(), 1e-9)
        << "upright, at its height";
    EXPECT_EQ(answer.step->action, "push");
    ASSERT_TRUE(answer.step->trajectory);
    EXPECT_EQ(answer.step->trajectory->joint_names, (std::vector<std::string>{"gripper_x", "gripper_y", "gripper_yaw"}));
    // Its controls, replayed from the query's state, end where the answer says.
    const PushWorld world(scene, initial);
    const physics::Replay replay = physics::replay(world, world.state_of(initial, query.gripper),
                                                   physics::controls_of(*answer.step), answer.step->values.at("step")[0]);
    EXPECT_TRUE(replay.valid);
    EXPECT_LT((replay.end.gripper - answer.gripper_end).norm(), 1e-9);
    EXPECT_LT((replay.end.objects[1].pose.head<2>() - answer.resulting_state->world_T_objects[1].translation().head<2>()).norm(), 1e-9);
    EXPECT_EQ(answer.step->objects, std::vector<ObjectIndex>{1}) << "the target stays where it is";
  }
}

TEST_F(PushSamplerTest, APushOffTheShelfOrOfAFixedObjectIsRefusedWithAReason) {
  Scene scene = board_scene({{1.0, -0.35}, {0.8, 0.0}});
  const WorldState initial = WorldState::initial(scene);
  const plugin::PushAnswer off = push(scene, {1, {1.4, 0.0}, 0.03, initial, {0.45, 0, 0}}, {});
  ASSERT_TRUE(off.failure);
  EXPECT_NE(off.failure->reason.find("off the support the target stands on"), std::string::npos) << off.failure->reason;
  scene.objects[1].movable = false;
  const plugin::PushAnswer fixed = push(scene, {1, {0.8, 0.2}, 0.03, initial, {0.45, 0, 0}}, {});
  ASSERT_TRUE(fixed.failure);
  EXPECT_NE(fixed.failure->reason.find("cannot be pushed"), std::string::npos) << fixed.failure->reason;
}

TEST(Guidance, AGuidanceFileRoundTripsAndBadOnesNameTheirLines) {
  const Scene scene = board_scene({{1.0, -0.35}, {0.8, 0.0}, {0.7, 0.2}});
  const PushWorld world(scene, WorldState::initial(scene));
  const physics::Guidance guidance{{1, {0.75, -0.2}, 0.1, {}}, {2, {0.9, 0.3}, 0.08, {}}};
  const auto file = std::filesystem::temp_directory_path() / "cluttertamp_test_guidance.yaml";
  std::ofstream(file) << io::guidance_to_yaml(scene, guidance);
  const physics::Guidance read = io::load_guidance(file, scene, world.support_region());
  ASSERT_EQ(read.size(), 2u);
  for (std::size_t k = 0; k < 2; ++k) {
    EXPECT_EQ(read[k].object, guidance[k].object);
    EXPECT_LT((read[k].centre - guidance[k].centre).norm(), 1e-9);
    EXPECT_DOUBLE_EQ(read[k].diameter, guidance[k].diameter);
    EXPECT_EQ(read[k].where.line, 4 + k);
  }
  const auto error_of = [&](const std::string& text) {
    std::ofstream(file) << text;
    try {
      io::load_guidance(file, scene, world.support_region());
    } catch (const InputError& e) {
      return e.diagnostics().str();
    }
    return std::string("no error");
  };
  struct Remove {
    std::filesystem::path file;
    ~Remove() { std::filesystem::remove(file); }
  } remove_file{file};
  EXPECT_NE(error_of("version: 1\nguides:\n  - {object: o7, centre: [0.8, 0], diameter: 0.1}\n")
                .find("cluttertamp_test_guidance.yaml:3:14: error: guide #1: unknown object 'o7'"),
            std::string::npos);
  EXPECT_NE(error_of("version: 1\nguides:\n  - {object: o1, centre: [0.62, 0], diameter: 0.1}\n")
                .find("cluttertamp_test_guidance.yaml:3:26: error: guide #1: the region about (0.62, 0)"),
            std::string::npos)
      << "reaches over the front edge";
  EXPECT_NE(error_of("version: 1\nguides:\n  - {object: o1, centre: [0.8, 0]}\n").find("is missing the required key 'diameter'"),
            std::string::npos);
  EXPECT_NE(error_of("version: 2\nguides: []\n").find("cluttertamp_test_guidance.yaml:1:10: error: unsupported guidance format version 2"),
            std::string::npos);
  EXPECT_NE(error_of("version: 1\nguides:\n  - {object: o1, centre: [0.8], diameter: 0.1}\n").find("centre must be [x, y]"),
            std::string::npos);
}

// The generated guidance moves exactly the objects on the way to the target, nearest
// first, each off that way, with its region on the board.
TEST(Guidance, TheGeneratedGuidanceClearsTheWayToTheTarget) {
  const Scene scene = board_scene({{1.0, 0.0}, {0.8, 0.02}, {0.7, -0.03}, {0.8, 0.3}});
  const WorldState initial = WorldState::initial(scene);
  const PushWorld world(scene, initial);
  const Eigen::Vector2d from(0.45, 0.0);
  const physics::Guidance guidance =
      physics::generate_guidance(world, world.state_of(initial, {from.x(), from.y(), 0}), from, 3, 0.1);
  ASSERT_EQ(guidance.size(), 2u);
  EXPECT_EQ(guidance[0].object, 2u) << "the nearest blocker first";
  EXPECT_EQ(guidance[1].object, 1u);
  for (const physics::Guide& g : guidance) {
    EXPECT_GE(std::abs(g.centre.y()), 0.06 + 0.02 + 0.035) << "off the way";
    EXPECT_TRUE(world.support_region().contains(g.centre));
  }
  EXPECT_EQ(physics::generate_guidance(world, world.state_of(initial, {0.45, 0, 0}), from, 1, 0.1).size(), 1u);
}

}  // namespace
}  // namespace cluttertamp
