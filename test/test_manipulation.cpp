// Composite actions with the shipped samplers: pick, place and retrieve produce
// trajectories that are collision-free when re-checked densely, or fail naming the
// objects in the way; same seed, same trajectories.
#include <gtest/gtest.h>

#include "cluttertamp/collision/shared_world.hpp"
#include "cluttertamp/core/geometry.hpp"
#include "cluttertamp/manipulation/actions.hpp"
#include "cluttertamp/plugin/grasp_sampler.hpp"
#include "cluttertamp/plugin/motion_sampler.hpp"
#include "cluttertamp/plugin/placement_sampler.hpp"
#include "cluttertamp/plugin/registry.hpp"
#include "cluttertamp/robot/robot_description.hpp"
#include "test_fixtures.hpp"

namespace cluttertamp {
namespace {

using test::at;

class Manipulation : public ::testing::Test {
 protected:
  void SetUp() override {
    problem_.robot.loaded = test::ur10();
    test::add_box(problem_.scene, "table", {0.8, 1.4, 0.02}, {1.0, 0.0, 0.39});
    Region buffer;
    buffer.id = "buffer";
    buffer.size = {0.25, 0.25, 0.32};
    buffer.world_T_region = at(0.75, -0.5, 0.56);
    problem_.scene.regions.push_back(buffer);
    problem_.scene.world_T_exit = at(0.45, 0.0, 0.55);
    samplers_ = test::shipped_samplers(registry_);
  }

  ObjectIndex add(const std::string& id, double x, double y) { return test::add_cylinder(problem_.scene, id, x, y, 0.035); }

  plugin::PlanningContext& context(std::uint64_t seed = 3) {
    shared_ = std::make_unique<collision::SharedWorld>(problem_.scene, problem_.robot.loaded);
    world_ = &shared_->world();
    context_ = std::make_unique<plugin::PlanningContext>(
        plugin::PlanningContext{problem_, plugin::Deadline::after(30), seed, counters_, samplers_, shared_.get()});
    return *context_;
  }

  WorldState start() const {
    WorldState s = WorldState::initial(problem_.scene);
    s.robot_configuration = problem_.robot.loaded->home();
    return s;
  }

  // Every configuration along every segment, 10x finer than the planners check, is free
  // in the state it runs in: the object being grasped or released may touch the open
  // hand; it is held from the grasp until it is released.
  void expect_collision_free(const manipulation::ActionOutcome& out, const WorldState& before, ObjectIndex object) {
    auto checker = world_->make_context();
    const bool placing = before.held.has_value();
    bool held = placing;
    WorldState state = before;
    for (const manipulation::Segment& s : out.segments) {
      if (s.name == "lift") held = true;
      if (s.name == "release") held = false;
      state.robot_configuration = s.trajectory.positions.front();
      state.held = held ? std::optional<ObjectIndex>(object) : std::nullopt;
      if (placing && !held) state = out.after;  // released: the object stands where it was placed
      state.robot_configuration = s.trajectory.positions.front();
      world_->sync(state);
      const ObjectIndex none[] = {object};
      const std::span<const ObjectIndex> ignored =
          (s.name == "approach" || s.name == "grasp" || s.name == "release") ? std::span<const ObjectIndex>(none) : std::span<const ObjectIndex>();
      for (std::size_t k = 0; k + 1 < s.trajectory.positions.size(); ++k) {
        const Eigen::VectorXd& a = s.trajectory.positions[k];
        const Eigen::VectorXd& b = s.trajectory.positions[k + 1];
        const int steps = std::max(2, static_cast<int>((b - a).cwiseAbs().maxCoeff() / 0.002));
        for (int i = 0; i <= steps; ++i) {
          ASSERT_TRUE(world_->is_valid(a + (b - a) * (double(i) / steps), *checker, ignored)) << s.name << " " << k << " " << i;
        }
      }
      // The held object moves with the tool: carry its pose to the end of the segment.
      if (held) {
        auto c = world_->make_context();
        const Eigen::Isometry3d grip = world_->tool_pose(s.trajectory.positions.front(), *c).inverse() * state.world_T_objects[object];
        state.world_T_objects[object] = world_->tool_pose(s.trajectory.positions.back(), *c) * grip;
      }
    }
  }

  Problem problem_;
  plugin::Registry registry_{plugin::Registry::default_search_paths()};
  plugin::Samplers samplers_;
  std::unique_ptr<collision::SharedWorld> shared_;
  collision::CollisionWorld* world_ = nullptr;
  std::unique_ptr<plugin::PlanningContext> context_;
  std::map<std::string, std::uint64_t> counters_;
};

TEST_F(Manipulation, PicksAnUnobstructedCylinder) {
  const ObjectIndex cup = add("cup", 0.85, 0.1);
  add("other", 1.05, -0.25);
  const WorldState s = start();
  const manipulation::ActionOutcome out = manipulation::pick(context(), s, cup);
  ASSERT_TRUE(out.ok) << out.failure->reason;
  std::vector<std::string> names;
  for (const auto& seg : out.segments) names.push_back(seg.name);
  EXPECT_EQ(names, (std::vector<std::string>{"transfer", "approach", "grasp", "lift", "retreat"}));
  EXPECT_EQ(out.after.held, cup);
  EXPECT_GT(out.after.world_T_objects[cup].translation().z(), s.world_T_objects[cup].translation().z() + 0.02);
  expect_collision_free(out, s, cup);
}

TEST_F(Manipulation, ObstructedPickNamesExactlyTheBlockers) {
  const ObjectIndex target = add("target", 1.05, 0.0);
  // A tight arc of cylinders before the target, facing the robot.
  std::vector<ObjectIndex> arc;
  for (int k = -2; k <= 2; ++k) {
    const double a = k * 0.45;
    arc.push_back(add("arc" + std::to_string(k + 2), 1.05 - 0.12 * std::cos(a), -0.12 * std::sin(a)));
  }
  const ObjectIndex far = add("far", 1.3, 0.5);
  const manipulation::ActionOutcome out = manipulation::pick(context(), start(), target);
  ASSERT_FALSE(out.ok);
  ASSERT_TRUE(out.failure.has_value());
  EXPECT_EQ(out.failure->stage, "grasp");
  EXPECT_FALSE(out.failure->blocking_objects.empty()) << out.failure->reason;
  for (ObjectIndex o : out.failure->blocking_objects) {
    EXPECT_NE(o, far);
    EXPECT_TRUE(std::find(arc.begin(), arc.end(), o) != arc.end()) << o;
  }
}

TEST_F(Manipulation, PicksAndPlacesIntoTheBuffer) {
  const ObjectIndex cup = add("cup", 0.85, 0.1);
  const WorldState s = start();
  const manipulation::ActionOutcome picked = manipulation::pick(context(), s, cup);
  ASSERT_TRUE(picked.ok) << picked.failure->reason;
  const manipulation::ActionOutcome placed = manipulation::place(*context_, picked.after, "buffer");
  ASSERT_TRUE(placed.ok) << placed.failure->reason;
  EXPECT_FALSE(placed.after.held.has_value());
  const Eigen::Vector3d p = placed.after.world_T_objects[cup].translation();
  EXPECT_NEAR(p.z(), 0.40 + 0.13, 1e-9);  // standing on the table inside the region
  EXPECT_LT(std::abs(p.x() - 0.75), 0.125);
  EXPECT_LT(std::abs(p.y() + 0.5), 0.125);
  EXPECT_EQ(placed.segments.front().name, "transfer");
  expect_collision_free(placed, picked.after, cup);
}

TEST_F(Manipulation, RetrievesTheTargetToTheExitPose) {
  const ObjectIndex target = add("target", 0.9, 0.0);
  problem_.scene.target = target;
  const manipulation::ActionOutcome out = manipulation::retrieve(context(), start());
  ASSERT_TRUE(out.ok) << out.failure->reason;
  EXPECT_EQ(out.segments.back().name, "carry");
  EXPECT_TRUE(out.after.world_T_objects[target].translation().isApprox(problem_.scene.world_T_exit.translation()));
  expect_collision_free(out, start(), target);
}

// Far out to the side the arm cannot hold the target at x_s as it was grasped (from
// the front, the tool pointing along x); an upright cylinder may arrive turned about
// its axis, and so it does, by the least turn the arm holds free.
TEST_F(Manipulation, RetrieveTurnsAnUprightTargetWhereTheArmCannotHoldItAsGrasped) {
  const ObjectIndex target = add("target", 0.9, 0.0);
  problem_.scene.target = target;
  problem_.scene.world_T_exit = at(0.0, -1.2, 0.55);
  const manipulation::ActionOutcome out = manipulation::retrieve(context(), start());
  ASSERT_TRUE(out.ok) << out.failure->reason;
  const Eigen::Isometry3d& arrived = out.after.world_T_objects[target];
  EXPECT_TRUE(arrived.translation().isApprox(problem_.scene.world_T_exit.translation()));
  EXPECT_NEAR(arrived.linear()(2, 2), 1.0, 1e-9);  // still upright
  const double turn = std::abs(std::atan2(arrived.linear()(1, 0), arrived.linear()(0, 0)));
  EXPECT_GT(turn, M_PI / 8) << "arrived unturned";
  expect_collision_free(out, start(), target);
}

// Given the target's free way (here bent), the carry follows it: the held target on
// the way's lines at its lifted height, then at x_s, no motion planned; once an object
// stands on the way, the carry is planned. Both free.
TEST_F(Manipulation, RetrieveCarriesAlongAGivenWay) {
  const ObjectIndex target = add("target", 0.95, 0.0);
  problem_.scene.target = target;
  const std::vector<Eigen::Vector2d> way{{0.95, 0.0}, {0.85, 0.15}, {0.55, 0.15}, {0.45, 0.0}};
  std::map<std::string, PhaseTotals> phases;
  plugin::PlanningContext& c = context();
  c.phases = &phases;
  const manipulation::ActionOutcome out = manipulation::retrieve(c, start(), way);
  ASSERT_TRUE(out.ok) << out.failure->reason;
  EXPECT_EQ(out.segments.back().name, "carry");
  EXPECT_EQ(phases.count("retrieve.carry"), 0u) << "planned although the way was free";
  ASSERT_EQ(phases.count("retrieve.carry_along"), 1u);
  EXPECT_TRUE(out.after.world_T_objects[target].translation().isApprox(problem_.scene.world_T_exit.translation()));
  expect_collision_free(out, start(), target);
  // Every configuration of the carry holds the target over the way (the last leg only
  // lowers it to x_s).
  auto checker = world_->make_context();
  const Trajectory& carry = out.segments.back().trajectory;
  const Eigen::Isometry3d grip = out.grasp->gripper_T_object;
  for (std::size_t k = 0; k < carry.positions.size(); ++k) {
    const Eigen::Vector2d p = (world_->tool_pose(carry.positions[k], *checker) * grip).translation().head<2>();
    double nearest = 1e9;
    for (std::size_t i = 0; i + 1 < way.size(); ++i) nearest = std::min(nearest, distance_to_segment(p, way[i], way[i + 1]));
    EXPECT_LT(nearest, 1e-3) << "waypoint " << k;
  }

  add("on_the_way", 0.7, 0.15);
  phases.clear();
  plugin::PlanningContext& again = context();
  again.phases = &phases;
  const manipulation::ActionOutcome planned = manipulation::retrieve(again, start(), way);
  ASSERT_TRUE(planned.ok) << planned.failure->reason;
  EXPECT_EQ(phases.count("retrieve.carry"), 1u);
  expect_collision_free(planned, start(), target);
}

// Holding an object among neighbours, move_out backs the tool out along its approach
// axis in a straight line (horizontal, tool orientation kept) before the planned part,
// and the whole motion, held object included, is free.
TEST_F(Manipulation, MoveOutBacksOutAlongTheApproachFirst) {
  const ObjectIndex cup = add("cup", 0.95, 0.0);
  add("left", 0.97, 0.13);
  add("right", 0.97, -0.13);
  manipulation::ActionOutcome picked = manipulation::pick(context(), start(), cup);
  ASSERT_TRUE(picked.ok) << picked.failure->reason;
  const WorldState& holding = picked.after;
  std::optional<Failure> why;
  const auto out = manipulation::move_out(*context_, holding, problem_.robot.loaded->home(), why);
  ASSERT_TRUE(out.has_value()) << why->reason;
  EXPECT_TRUE(out->positions.front().isApprox(holding.robot_configuration));
  EXPECT_TRUE(out->positions.back().isApprox(problem_.robot.loaded->home()));
  auto checker = world_->make_context();
  const Eigen::Isometry3d first = world_->tool_pose(out->positions[0], *checker);
  const Eigen::Isometry3d fifth = world_->tool_pose(out->positions.at(4), *checker);
  Eigen::Vector3d back = -first.linear().col(2);
  back.z() = 0;
  const Eigen::Vector3d moved = fifth.translation() - first.translation();
  EXPECT_NEAR(moved.norm(), 0.08, 1e-6);                      // four 2 cm steps
  EXPECT_GT(moved.normalized().dot(back.normalized()), 1 - 1e-6);  // along the axis
  EXPECT_TRUE(fifth.linear().isApprox(first.linear(), 1e-6));
  manipulation::ActionOutcome carried;
  carried.segments.push_back({"transfer", *out});
  world_->sync(holding);
  expect_collision_free(carried, holding, cup);
}

TEST_F(Manipulation, SameSeedSameTrajectories) {
  const ObjectIndex cup = add("cup", 0.85, 0.1);
  const manipulation::ActionOutcome a = manipulation::pick(context(5), start(), cup);
  const manipulation::ActionOutcome b = manipulation::pick(context(5), start(), cup);
  ASSERT_TRUE(a.ok && b.ok);
  ASSERT_EQ(a.segments.size(), b.segments.size());
  for (std::size_t i = 0; i < a.segments.size(); ++i) {
    EXPECT_EQ(a.segments[i].trajectory.positions, b.segments[i].trajectory.positions) << a.segments[i].name;
  }
}

}  // namespace
}  // namespace cluttertamp
