// The shipped sampler plugins on hand-built scenes: usable grasps, the exact objects
// that block a grasp, determinism.
#include <cmath>
#include <map>
#include <stdexcept>

#include <gtest/gtest.h>

#include "cluttertamp/collision/shared_world.hpp"
#include "cluttertamp/plugin/grasp_sampler.hpp"
#include "cluttertamp/plugin/motion_sampler.hpp"
#include "cluttertamp/plugin/registry.hpp"
#include "cluttertamp/robot/robot_description.hpp"
#include "test_fixtures.hpp"

namespace cluttertamp {
namespace {

using test::at;

// A UR10 before a table whose top is at z = 0.40, with standing cylinders on it.
class SamplerScene : public ::testing::Test {
 protected:
  void SetUp() override {
    problem_.robot.loaded = test::ur10();
    test::add_box(problem_.scene, "table", {0.8, 1.2, 0.02}, {1.0, 0.0, 0.39});
  }

  ObjectIndex add(const std::string& id, double x, double y, double radius = 0.035) {
    return test::add_cylinder(problem_.scene, id, x, y, radius);
  }

  plugin::GraspAnswer grasp(ObjectIndex object, const Parameters& parameters = {}, std::uint64_t seed = 1) {
    shared_ = std::make_unique<collision::SharedWorld>(problem_.scene, problem_.robot.loaded);
    world_ = &shared_->world();
    auto sampler = registry_.create<plugin::GraspSampler>("grasp_side", parameters);
    state_ = WorldState::initial(problem_.scene);
    state_.robot_configuration = problem_.robot.loaded->home();
    plugin::PlanningContext context{problem_, plugin::Deadline::after(10), seed, counters_, samplers_, shared_.get()};
    return sampler->sample(context, {object, state_});
  }

  plugin::MotionAnswer motion(const Eigen::VectorXd& start, const Eigen::VectorXd& goal, std::uint64_t seed = 1,
                              std::int64_t max_checks = 400000) {
    shared_ = std::make_unique<collision::SharedWorld>(problem_.scene, problem_.robot.loaded);
    world_ = &shared_->world();
    Parameters parameters;
    parameters.set("max_checks", max_checks);
    auto sampler = registry_.create<plugin::MotionSampler>("motion_ompl", parameters);
    state_ = WorldState::initial(problem_.scene);
    state_.robot_configuration = start;
    plugin::PlanningContext context{problem_, plugin::Deadline::after(600), seed, counters_, samplers_, shared_.get()};
    return sampler->plan(context, {start, goal, state_});
  }

  Problem problem_;
  plugin::Registry registry_{plugin::Registry::default_search_paths()};
  std::unique_ptr<collision::SharedWorld> shared_;
  collision::CollisionWorld* world_ = nullptr;
  WorldState state_;
  std::map<std::string, std::uint64_t> counters_;
  plugin::Samplers samplers_;
};

TEST_F(SamplerScene, GraspsAFreeCylinderWithCollisionFreeMotions) {
  const ObjectIndex cup = add("cup", 0.85, 0.0);
  const plugin::GraspAnswer answer = grasp(cup);
  ASSERT_FALSE(answer.usable.empty()) << (answer.failure ? answer.failure->reason : "");
  EXPECT_FALSE(answer.failure.has_value());
  const robot::RobotDescription& robot = *problem_.robot.loaded;
  auto checker = world_->make_context();
  world_->sync(state_);
  for (const plugin::Grasp& g : answer.usable) {
    ASSERT_FALSE(g.motions.empty());
    const plugin::GraspMotion& m = g.motions.front();
    // The grasp configuration puts the tool where the grasp says (world frame).
    const Eigen::Isometry3d tool = world_->tool_pose(m.grasp, *checker);
    EXPECT_TRUE(tool.isApprox(g.world_T_gripper, 1e-6));
    // Side grasp: the approach (tool z) is horizontal.
    EXPECT_NEAR(g.world_T_gripper.linear().col(2).z(), 0.0, 1e-9);
    // Re-checked densely, the approach touches nothing but the cup.
    const ObjectIndex ignored[] = {cup};
    for (int s = 0; s <= 100; ++s) {
      const Eigen::VectorXd q = m.pregrasp + (m.grasp - m.pregrasp) * (s / 100.0);
      EXPECT_TRUE(world_->is_valid(q, *checker, ignored)) << s;
    }
    EXPECT_DOUBLE_EQ(m.lift[*robot.finger_variable()], 0.035);  // closed on the cup
  }
  EXPECT_GT(counters_[counter::collision_checks], 0u);
}

TEST_F(SamplerScene, NamesExactlyTheCylindersBlockingTheGrasp) {
  const ObjectIndex target = add("target", 1.0, 0.0);
  const ObjectIndex front = add("front", 0.88, 0.0);
  add("aside", 1.0, 0.35);  // nowhere near the approach
  Parameters narrow;
  narrow.set("spread", 5.0);  // approach only straight from the robot
  narrow.set("wide_spread", 0.0);
  narrow.set("random", std::int64_t{0});
  const plugin::GraspAnswer answer = grasp(target, narrow);
  ASSERT_TRUE(answer.usable.empty());
  ASSERT_TRUE(answer.failure.has_value());
  EXPECT_EQ(answer.failure->blocking_objects, (std::vector<ObjectIndex>{front})) << answer.failure->reason;
  const plugin::BlockedGrasp* best = answer.least_blocked();
  ASSERT_NE(best, nullptr);
  EXPECT_EQ(best->blocking_objects, (std::vector<ObjectIndex>{front}));
  for (const plugin::BlockedGrasp& b : answer.blocked) {
    for (ObjectIndex o : b.blocking_objects) EXPECT_EQ(o, front);
  }
}

// A neighbour 2 mm away, well round from the robot's line of sight, blocks every grasp
// from the front (the fingers close across the line towards it): with nothing usable
// within the spread, the wide pass finds a grasp from further round.
TEST_F(SamplerScene, SideBySideCylindersAreGraspedFromFurtherRound) {
  // The neighbour stands 85 degrees round from the robot's line of sight, 2 mm away.
  const Eigen::Vector2d at(0.95, 0.0);
  const double phi = 85.0 * M_PI / 180.0;
  const ObjectIndex left = add("left", at.x(), at.y());
  const ObjectIndex right = add("right", at.x() + 0.072 * std::cos(phi), at.y() + 0.072 * std::sin(phi));
  for (ObjectIndex o : {left, right}) {  // tall, so that a grasp from the side keeps the forearm off the table
    problem_.scene.objects[o].shape = Cylinder{0.035, 0.5};
    problem_.scene.objects[o].world_T_object.translation().z() = 0.4 + 0.25;
  }
  Parameters front_only;
  front_only.set("wide_spread", 0.0);
  const plugin::GraspAnswer stuck = grasp(left, front_only);
  ASSERT_TRUE(stuck.usable.empty()) << "within +-60 degrees the fingers meet the neighbour";
  const plugin::GraspAnswer answer = grasp(left);
  ASSERT_FALSE(answer.usable.empty()) << answer.failure->reason;
  for (const plugin::Grasp& g : answer.usable) {
    const Eigen::Vector3d approach = g.world_T_gripper.linear().col(2);
    const double yaw = std::atan2(approach.y(), approach.x()) * 180.0 / M_PI;  // facing the robot is 0 here
    EXPECT_GT(std::abs(yaw), 60.0 + 1e-6);
    EXPECT_LE(std::abs(yaw), 100.0 + 1e-6);
  }
}

// spread 180 (a mobile robot's grasps from every side): the directions split the
// circle evenly, and -180 and 180 degrees are one direction, tried once.
TEST_F(SamplerScene, AllAroundGraspsSplitTheCircleEvenly) {
  const ObjectIndex cup = add("cup", 0.85, 0.0);  // straight ahead: facing is 0
  Parameters around;
  around.set("spread", 180.0);
  around.set("directions", std::int64_t{4});
  around.set("random", std::int64_t{0});
  around.set("max_usable", std::int64_t{100});
  const plugin::GraspAnswer answer = grasp(cup, around);
  std::vector<plugin::Grasp> all = answer.usable;
  for (const plugin::BlockedGrasp& b : answer.blocked) all.push_back(b.grasp);
  std::map<long, int> upright;  // direction (degrees) -> upright grasps tried
  for (const plugin::Grasp& g : all) {
    if (g.world_T_gripper.linear().col(0).z() > 0) continue;  // turned over
    const Eigen::Vector3d approach = g.world_T_gripper.linear().col(2);
    long d = std::lround(std::atan2(approach.y(), approach.x()) * 180.0 / M_PI);
    if (d == -180) d = 180;
    ++upright[d];
  }
  // One per height (three) in each of the four directions: 180 degrees not twice.
  EXPECT_EQ(upright, (std::map<long, int>{{-90, 3}, {0, 3}, {90, 3}, {180, 3}}));
}

TEST_F(SamplerScene, SameSeedSameGrasps) {
  const ObjectIndex cup = add("cup", 0.9, 0.1);
  const plugin::GraspAnswer a = grasp(cup, {}, 7);
  const plugin::GraspAnswer b = grasp(cup, {}, 7);
  ASSERT_EQ(a.usable.size(), b.usable.size());
  ASSERT_FALSE(a.usable.empty());
  EXPECT_TRUE(a.usable[0].world_T_gripper.isApprox(b.usable[0].world_T_gripper));
  EXPECT_EQ(a.usable[0].motions[0].grasp, b.usable[0].motions[0].grasp);
}

// A collision-free motion to the pre-grasp of a cylinder: dense re-checks, velocity
// limits, determinism.
TEST_F(SamplerScene, PlansACollisionFreeMotionWithinVelocityLimits) {
  const ObjectIndex cup = add("cup", 0.85, 0.0);
  add("left", 0.9, 0.25);
  add("right", 0.9, -0.25);
  const plugin::GraspAnswer grasps = grasp(cup);
  ASSERT_FALSE(grasps.usable.empty());
  const Eigen::VectorXd goal = grasps.usable[0].motions[0].pregrasp;
  const Eigen::VectorXd start = problem_.robot.loaded->home();
  const plugin::MotionAnswer answer = motion(start, goal);
  ASSERT_TRUE(answer.trajectory.has_value()) << answer.failure->reason;
  const Trajectory& t = *answer.trajectory;
  ASSERT_GE(t.positions.size(), 2u);
  EXPECT_TRUE(t.positions.front().isApprox(start));
  EXPECT_TRUE(t.positions.back().isApprox(goal));
  auto checker = world_->make_context();
  world_->sync(state_);
  const Eigen::VectorXd limits = problem_.robot.loaded->model()->velocity_limits();
  for (std::size_t k = 0; k + 1 < t.positions.size(); ++k) {
    const double dt = t.times[k + 1] - t.times[k];
    ASSERT_GT(dt, 0.0);
    const Eigen::VectorXd speed = (t.positions[k + 1] - t.positions[k]).cwiseAbs() / dt;
    EXPECT_TRUE((speed.array() <= limits.array() + 1e-9).all()) << speed.transpose();
    const Eigen::VectorXd step = t.positions[k + 1] - t.positions[k];
    const int n = std::max(2, static_cast<int>(step.cwiseAbs().maxCoeff() / 0.002));  // ten times finer than the planner
    for (int s = 0; s <= n; ++s) {
      const Eigen::VectorXd q = t.positions[k] + step * (double(s) / n);
      EXPECT_TRUE(world_->is_valid(q, *checker)) << "segment " << k << " step " << s;
    }
  }
  const plugin::MotionAnswer again = motion(start, goal);
  ASSERT_TRUE(again.trajectory.has_value());
  EXPECT_EQ(again.trajectory->positions.size(), t.positions.size());
  for (std::size_t k = 0; k < t.positions.size(); ++k) EXPECT_EQ(again.trajectory->positions[k], t.positions[k]);
}

// The trees' step `range` is read with its location and must be positive.
TEST_F(SamplerScene, MotionRangeMustBePositive) {
  for (double range : {0.0, -0.5}) {
    Parameters parameters;
    parameters.set("range", range, {"p.yaml", 4, 7});
    const Diagnostics d = test::expect_input_error([&] { registry_.create<plugin::MotionSampler>("motion_ompl", parameters); });
    EXPECT_TRUE(test::has_error(d, 4, 7, "parameter 'range' must be in (0, 100]")) << range;
  }
}

// A view answers for its own state whatever other views asked in between, and the
// shared world is left at the state of the last view to go.
TEST_F(SamplerScene, WorldViewsAnswerForTheirOwnState) {
  const ObjectIndex cup = add("cup", 0.85, 0.0);
  collision::SharedWorld shared(problem_.scene, problem_.robot.loaded);
  WorldState here = WorldState::initial(problem_.scene);
  here.robot_configuration = problem_.robot.loaded->home();
  WorldState gone = here;
  gone.removed[cup] = true;
  const Shape probe = Box{{0.02, 0.02, 0.05}};
  const Eigen::Isometry3d at_cup = here.world_T_objects[cup];
  const std::vector<ObjectIndex> cup_only{cup};

  auto with_cup = shared.at(here);
  auto without = shared.at(gone);
  for (int round = 0; round < 2; ++round) {
    EXPECT_EQ(with_cup->shape_contacts(probe, at_cup).objects, cup_only);
    EXPECT_TRUE(without->shape_contacts(probe, at_cup).objects.empty());
  }
  // Held, the cup travels with the hand and is no obstacle where it stood.
  auto holding = with_cup->holding(cup, Eigen::Isometry3d::Identity());
  EXPECT_TRUE(holding->shape_contacts(probe, at_cup).objects.empty());
  EXPECT_EQ(with_cup->shape_contacts(probe, at_cup).objects, cup_only);
  holding.reset();
  EXPECT_EQ(shared.world().held(), std::optional<ObjectIndex>(cup));
  without.reset();
  EXPECT_FALSE(shared.world().present(cup));
  EXPECT_FALSE(shared.world().held());
  with_cup.reset();
  EXPECT_TRUE(shared.world().present(cup));
  EXPECT_THROW(shared.at(WorldState{}), std::invalid_argument);  // no pose per object
}

// Every bad parameter of a plugin is reported in one go, each at its value.
TEST_F(SamplerScene, EveryBadGraspParameterIsReportedAtOnce) {
  Parameters parameters;
  parameters.set("approach", 2.0, {"p.yaml", 3, 15});
  parameters.set("directions", std::int64_t{0}, {"p.yaml", 4, 17});
  parameters.set("heights", std::vector<double>{0.5, std::nan("")}, {"p.yaml", 5, 14});
  parameters.set("tight_clearance", 0.02, {"p.yaml", 6, 22});
  const Diagnostics d = test::expect_input_error([&] { registry_.create<plugin::GraspSampler>("grasp_side", parameters); });
  EXPECT_EQ(d.size(), 4u) << d.str();
  EXPECT_TRUE(test::has_error(d, 3, 15, "parameter 'approach' must be in (0, 1), not 2")) << d.str();
  EXPECT_TRUE(test::has_error(d, 4, 17, "parameter 'directions' must be in [1, 64], not 0")) << d.str();
  EXPECT_TRUE(test::has_error(d, 5, 14, "parameter 'heights' must be in (0, 1), not nan")) << d.str();
  EXPECT_TRUE(test::has_error(d, 6, 22, "parameter 'tight_clearance' must be at most clearance")) << d.str();
}

TEST_F(SamplerScene, TakesAFreeStraightSegmentWithoutSearching) {
  // Home to a pre-grasp above an empty table: the straight joint-space segment is free,
  // so the motion is that segment; a cylinder on it forces a detour around.
  const ObjectIndex cup = add("cup", 0.85, 0.0);
  const plugin::GraspAnswer grasps = grasp(cup);
  ASSERT_FALSE(grasps.usable.empty());
  const Eigen::VectorXd start = problem_.robot.loaded->home();
  const Eigen::VectorXd goal = grasps.usable[0].motions[0].pregrasp;
  const plugin::MotionAnswer direct = motion(start, goal);
  ASSERT_TRUE(direct.trajectory.has_value()) << direct.failure->reason;
  ASSERT_EQ(direct.trajectory->positions.size(), 2u);
  EXPECT_TRUE(direct.trajectory->positions.back().isApprox(goal));

  // A thin fixed post where the segment's midpoint puts the tool: now a detour.
  Eigen::Vector3d mid;
  {
    collision::CollisionWorld before(problem_.scene, problem_.robot.loaded);
    auto c = before.make_context();
    mid = before.tool_pose((start + goal) / 2, *c).translation();
  }
  test::add_box(problem_.scene, "post", {0.06, 0.06, 0.3}, mid);
  {
    collision::CollisionWorld after(problem_.scene, problem_.robot.loaded);
    auto c = after.make_context();
    ASSERT_FALSE(after.is_valid((start + goal) / 2, *c));
    ASSERT_TRUE(after.is_valid(start, *c) && after.is_valid(goal, *c));
  }
  const plugin::MotionAnswer around = motion(start, goal, 1, 800000);
  ASSERT_TRUE(around.trajectory.has_value()) << around.failure->reason;
  EXPECT_GT(around.trajectory->positions.size(), 2u);
}

TEST_F(SamplerScene, NamesTheObjectsAGoalConfigurationTouches) {
  // The goal holds the gripper inside a ring of cylinders it passes through: the motion
  // fails at once and names exactly the ring cylinders the goal configuration touches.
  const ObjectIndex cup = add("cup", 0.85, 0.0);
  const plugin::GraspAnswer grasps = grasp(cup);
  ASSERT_FALSE(grasps.usable.empty());
  const Eigen::VectorXd goal = grasps.usable[0].motions[0].grasp;
  problem_.scene.objects.clear();
  std::vector<ObjectIndex> ring;
  for (int k = 0; k < 10; ++k) {
    const double a = 2 * M_PI * k / 10;
    ring.push_back(add("ring" + std::to_string(k), 0.85 + 0.2 * std::cos(a), 0.2 * std::sin(a), 0.05));
  }
  add("far", 1.1, 0.5);
  collision::CollisionWorld check(problem_.scene, problem_.robot.loaded);
  auto c = check.make_context();
  const collision::ObjectSet touched = check.check(goal, *c).objects;
  ASSERT_FALSE(touched.empty());
  const plugin::MotionAnswer answer = motion(problem_.robot.loaded->home(), goal, 1, 200000);
  ASSERT_FALSE(answer.trajectory.has_value());
  ASSERT_TRUE(answer.failure.has_value());
  EXPECT_NE(answer.failure->reason.find("the start or goal configuration is in collision"), std::string::npos) << answer.failure->reason;
  EXPECT_EQ(answer.failure->blocking_objects, touched);
}

}  // namespace
}  // namespace cluttertamp
