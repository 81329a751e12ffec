// The collision world: full collision sets, fixed vs movable geometry, held objects,
// footprint sweeps (exact against dense sampling), threads.
#include <random>
#include <set>
#include <thread>

#include <gtest/gtest.h>

#include "cluttertamp/io/robot_description_io.hpp"
#include "cluttertamp/collision/collision_world.hpp"
#include "test_fixtures.hpp"

namespace cluttertamp::collision {
namespace {

using test::ur10;
using test::at;

SceneObject cylinder(const std::string& id, const Eigen::Isometry3d& pose, double radius = 0.02, double height = 0.1) {
  SceneObject o;
  o.id = id;
  o.shape = Cylinder{radius, height};
  o.world_T_object = pose;
  o.mass = 0.3;
  return o;
}

// World pose of the axis point at fraction t along a link's (first) cylinder.
Eigen::Vector3d along_link_cylinder(const robot::RobotDescription& robot, const Eigen::VectorXd& q,
                                    const std::string& link, double t) {
  const robot::RobotModel& model = *robot.model();
  std::vector<Eigen::Isometry3d> poses;
  model.link_poses(q, poses);
  const robot::LinkIndex l = *model.find_link(link);
  const robot::CollisionShape& shape = model.links()[l].collision.at(0);
  const double height = std::get<Cylinder>(shape.shape).height;
  return poses[l] * shape.link_T_shape * Eigen::Vector3d(0, 0, (t - 0.5) * height);
}

class UrWorld : public ::testing::Test {
 protected:
  void SetUp() override {
    const Eigen::VectorXd q = ur10()->home();
    // Two thin cylinders standing across the forearm, and three well clear of the robot.
    scene_.objects.push_back(cylinder("on_forearm_1", at(0, 0, 0) * Eigen::Translation3d(along_link_cylinder(*ur10(), q, "forearm_link", 0.3))));
    scene_.objects.push_back(cylinder("on_forearm_2", at(0, 0, 0) * Eigen::Translation3d(along_link_cylinder(*ur10(), q, "forearm_link", 0.7))));
    scene_.objects.push_back(cylinder("far_1", at(1.5, 1.0, 0.5)));
    scene_.objects.push_back(cylinder("far_2", at(1.5, -1.0, 0.5)));
    scene_.objects.push_back(cylinder("far_3", at(-1.5, 0.0, 0.5)));
    FixedBody wall;
    wall.id = "wall";
    wall.shape = Box{{0.02, 2.0, 2.0}};
    wall.world_T_body = at(1.0, 0, 1.0);
    scene_.fixed.push_back(wall);
    world_ = std::make_unique<CollisionWorld>(scene_, ur10());
    context_ = world_->make_context();
  }

  Scene scene_;
  std::unique_ptr<CollisionWorld> world_;
  std::unique_ptr<CollisionWorld::Context> context_;
};

TEST_F(UrWorld, ReportsExactlyTheTwoCylindersTheArmPassesThrough) {
  const CollisionReport report = world_->check(ur10()->home(), *context_);
  EXPECT_EQ(report.objects, (ObjectSet{0, 1}));
  EXPECT_FALSE(report.self);
  EXPECT_FALSE(report.fixed);
  EXPECT_FALSE(world_->is_valid(ur10()->home(), *context_));
}

TEST_F(UrWorld, RemovingMovingAndIgnoringObjectsIsCheap) {
  const Eigen::VectorXd q = ur10()->home();
  world_->remove_object(0);
  EXPECT_EQ(world_->check(q, *context_).objects, (ObjectSet{1}));
  world_->set_object_pose(1, at(1.5, 0.5, 0.5));
  EXPECT_TRUE(world_->is_valid(q, *context_));
  world_->restore_object(0);
  EXPECT_EQ(world_->check(q, *context_).objects, (ObjectSet{0}));
  const ObjectIndex ignored[] = {0};
  EXPECT_TRUE(world_->is_valid(q, *context_, ignored));
}

TEST_F(UrWorld, FixedGeometryIsReportedApartFromObjects) {
  world_->remove_object(0);
  world_->remove_object(1);
  Eigen::VectorXd reach(7);
  reach << M_PI, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0475;  // arm stretched out towards +x, through the wall at x = 1.0
  const CollisionReport report = world_->check(reach, *context_);
  EXPECT_TRUE(report.fixed);
  EXPECT_TRUE(report.objects.empty());
  EXPECT_FALSE(report.valid());
}

TEST_F(UrWorld, SelfCollisionOfAFoldedArm) {
  world_->remove_object(0);
  world_->remove_object(1);
  Eigen::VectorXd q = ur10()->home();
  EXPECT_FALSE(world_->check(q, *context_).self);
  q[2] = 2.6;  // elbow bent further: still clear
  EXPECT_FALSE(world_->check(q, *context_).self);
  q[2] = 2.8;  // folded onto itself: the wrist meets the upper arm
  EXPECT_TRUE(world_->check(q, *context_).self);
  EXPECT_FALSE(world_->is_valid(q, *context_));
}

TEST_F(UrWorld, HeldObjectTravelsWithTheTool) {
  world_->remove_object(0);
  world_->remove_object(1);
  const Eigen::VectorXd q = ur10()->home();
  ASSERT_TRUE(world_->is_valid(q, *context_));
  // Hold far_1 0.3 m ahead of the tool: it now sits where the arm reaches, not at (1.5, 1, 0.5).
  world_->attach(2, at(0, 0, 0.3));
  EXPECT_EQ(world_->held(), 2u);
  EXPECT_FALSE(world_->present(2));
  EXPECT_TRUE(world_->is_valid(q, *context_));
  // Put an obstacle where the held object is: only the held object touches it.
  const Eigen::Isometry3d held_pose = world_->tool_pose(q, *context_) * at(0, 0, 0.3);
  world_->set_object_pose(3, held_pose * at(0.0, 0.03, 0.0));
  EXPECT_EQ(world_->check(q, *context_).objects, (ObjectSet{3}));
  world_->detach(held_pose);
  EXPECT_TRUE(world_->present(2));
  EXPECT_FALSE(world_->held().has_value());
}

TEST_F(UrWorld, HeldObjectBetweenTheFingersIsNotACollision) {
  world_->remove_object(0);
  world_->remove_object(1);
  Eigen::VectorXd q = ur10()->home();
  q[6] = 0.02;  // fingers closed on a cylinder of radius 0.02 (far_1), held at the tool centre
  world_->attach(2, Eigen::Isometry3d(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitX())));
  EXPECT_TRUE(world_->is_valid(q, *context_));
  // Swung down into the arm's own upper arm, the held object is a self collision.
  Eigen::VectorXd folded = q;
  folded[3] = M_PI / 2;
  folded[4] = M_PI;
  int self = 0;
  for (double wrist = -M_PI; wrist < M_PI; wrist += 0.1) {
    folded[3] = wrist;
    const CollisionReport report = world_->check(folded, *context_);
    self += report.self;
  }
  EXPECT_GT(self, 0);
}

TEST_F(UrWorld, SyncAttachesTheHeldObjectWhereTheStateHasIt) {
  WorldState state = WorldState::initial(scene_);
  state.robot_configuration = ur10()->home();
  state.removed[0] = state.removed[1] = true;
  const Eigen::Isometry3d tool = world_->tool_pose(state.robot_configuration, *context_);
  state.held = 2;
  state.world_T_objects[2] = tool * at(0, 0, 0.3);
  world_->sync(state);
  EXPECT_EQ(world_->held(), 2u);
  // The held object moves with the tool: turn the base and it hits an obstacle placed there.
  Eigen::VectorXd turned = state.robot_configuration;
  turned[0] += M_PI / 2;
  const Eigen::Isometry3d moved = world_->tool_pose(turned, *context_) * at(0, 0, 0.3);
  world_->set_object_pose(3, moved);
  EXPECT_EQ(world_->check(turned, *context_).objects, (ObjectSet{3}));
  EXPECT_TRUE(world_->check(state.robot_configuration, *context_).objects.empty());
}

TEST_F(UrWorld, MinimumDistanceShrinksToContact) {
  world_->remove_object(0);
  world_->remove_object(1);
  const Eigen::VectorXd q = ur10()->home();
  const Eigen::Isometry3d tool = world_->tool_pose(q, *context_);
  double previous = 1e9;
  for (double gap : {0.30, 0.20, 0.10, 0.05}) {
    world_->set_object_pose(3, tool * at(0, 0, gap + 0.02 + 0.01));  // 0.02 radius, fingertips 0.01 past the TCP
    const double d = world_->min_distance(q, *context_);
    EXPECT_LT(d, previous);
    EXPECT_GT(d, 0.0);
    previous = d;
  }
  world_->set_object_pose(3, tool);
  EXPECT_EQ(world_->min_distance(q, *context_), 0.0);
  EXPECT_FALSE(world_->is_valid(q, *context_));
}

TEST_F(UrWorld, ConcurrentQueriesAgreeWithSequentialOnes) {
  std::vector<Eigen::VectorXd> configurations;
  std::mt19937_64 rng(9);
  for (int i = 0; i < 400; ++i) {
    Eigen::VectorXd q = ur10()->home();
    for (int j = 0; j < 6; ++j) q[j] = std::uniform_real_distribution<double>(-M_PI, M_PI)(rng);
    configurations.push_back(q);
  }
  std::vector<ObjectSet> expected;
  for (const auto& q : configurations) expected.push_back(world_->check(q, *context_).objects);
  std::vector<std::vector<ObjectSet>> got(2);
  std::vector<std::thread> threads;
  const CollisionWorld& world = *world_;
  for (int t = 0; t < 2; ++t) {
    threads.emplace_back([&, t] {
      auto context = world.make_context();
      for (const auto& q : configurations) got[t].push_back(world.check(q, *context).objects);
    });
  }
  for (auto& thread : threads) thread.join();
  EXPECT_EQ(got[0], expected);
  EXPECT_EQ(got[1], expected);
}

TEST_F(UrWorld, ValidityAgreesWithTheFullReport) {
  std::mt19937_64 rng(13);
  int invalid = 0;
  for (int i = 0; i < 1000; ++i) {
    Eigen::VectorXd q = ur10()->home();
    for (int j = 0; j < 6; ++j) q[j] = std::uniform_real_distribution<double>(-M_PI, M_PI)(rng);
    const bool valid = world_->is_valid(q, *context_);
    EXPECT_EQ(valid, world_->check(q, *context_).valid()) << q.transpose();
    invalid += !valid;
  }
  EXPECT_GT(invalid, 50);
  EXPECT_LT(invalid, 950);
}

TEST_F(UrWorld, SyncFollowsAWorldState) {
  WorldState state = WorldState::initial(scene_);
  state.robot_configuration = ur10()->home();
  state.removed[0] = true;
  state.world_T_objects[1] = at(1.5, 0.3, 0.5);
  world_->sync(state);
  EXPECT_FALSE(world_->present(0));
  EXPECT_TRUE(world_->is_valid(ur10()->home(), *context_));
}

TEST_F(UrWorld, ShapeContactsAnswerPlacementQueriesWithoutChangingTheWorld) {
  const Cylinder probe{0.05, 0.1};
  EXPECT_TRUE(world_->shape_contacts(probe, at(0, 2, 2)).valid());
  const CollisionReport on_two = world_->shape_contacts(Box{{0.02, 0.02, 2.0}}, world_->object_pose(0));
  EXPECT_EQ(on_two.objects, (ObjectSet{0}));
  EXPECT_TRUE(world_->shape_contacts(probe, at(1.0, 0, 1.0)).fixed);  // inside the wall
  const ObjectIndex ignored[] = {0};
  EXPECT_TRUE(world_->shape_contacts(Box{{0.02, 0.02, 0.02}}, world_->object_pose(0), ignored).valid());
}

class BundledRobots : public ::testing::TestWithParam<std::string> {};

TEST_P(BundledRobots, HomeIsFreeAndMostConfigurationsAreFreeOfSelfCollision) {
  const auto robot = std::make_shared<const robot::RobotDescription>(io::load_robot_description(
      std::filesystem::path(CLUTTERTAMP_SOURCE_DIR) / "domains/robots" / GetParam()));
  const Scene empty;
  const CollisionWorld world(empty, robot);
  auto context = world.make_context();
  EXPECT_TRUE(world.is_valid(robot->home(), *context));
  const robot::RobotModel& model = *robot->model();
  std::mt19937_64 rng(21);
  int free = 0;
  const int samples = 1000;
  for (int i = 0; i < samples; ++i) {
    Eigen::VectorXd q(static_cast<Eigen::Index>(model.variable_count()));
    for (Eigen::Index j = 0; j < q.size(); ++j) {
      q[j] = std::uniform_real_distribution<double>(model.lower_limits()[j], model.upper_limits()[j])(rng);
    }
    free += world.is_valid(q, *context);
  }
  EXPECT_GT(free, samples / 2) << "primitive shapes of links two joints apart overlap too often";
}

INSTANTIATE_TEST_SUITE_P(Robots, BundledRobots, ::testing::Values("ur10_ag95.yaml", "panda.yaml", "pr2_mobile.yaml"));

// ---- footprints ---------------------------------------------------------------------

class Footprints : public ::testing::Test {
 protected:
  void SetUp() override {
    std::mt19937_64 rng(4);
    std::uniform_real_distribution<double> x(0.0, 1.0), r(0.02, 0.05), yaw(-M_PI, M_PI);
    for (int i = 0; i < 20; ++i) {
      const Eigen::Isometry3d pose = at(x(rng), x(rng), 0.15);
      if (i % 4 == 3) {
        SceneObject box;
        box.id = "box" + std::to_string(i);
        box.shape = Box{{2 * r(rng), 3 * r(rng), 0.3}};
        box.world_T_object = pose * Eigen::AngleAxisd(yaw(rng), Eigen::Vector3d::UnitZ());
        scene_.objects.push_back(box);
      } else {
        scene_.objects.push_back(cylinder("c" + std::to_string(i), pose, r(rng), 0.3));
      }
    }
    // One object above the footprint's height band never counts.
    scene_.objects.push_back(cylinder("high", at(0.5, 0.5, 0.8), 0.3, 0.1));
    world_ = std::make_unique<CollisionWorld>(scene_, nullptr);
  }
  Scene scene_;
  std::unique_ptr<CollisionWorld> world_;
};

TEST_F(Footprints, SweepsAgreeWithDenseSampling) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> x(-0.1, 1.1);
  const Footprint footprint{0.045, 0.0, 0.3};
  const int samples = 4000;
  int compared = 0;
  for (int trial = 0; trial < 300; ++trial) {
    const Eigen::Vector2d from(x(rng), x(rng)), to(x(rng), x(rng));
    const ObjectSet swept = world_->swept_objects(from, to, footprint);
    // Independent oracle: dense points along the segment, each point's distance to each
    // object's outline. Everything clearly inside must be swept; everything swept must
    // be within the sampling step of the footprint.
    const double step = (to - from).norm() / samples;
    std::set<ObjectIndex> inner, outer;
    for (int k = 0; k <= samples; ++k) {
      const Eigen::Vector2d p = from + (to - from) * (double(k) / samples);
      for (ObjectIndex i = 0; i < scene_.objects.size(); ++i) {
        const SceneObject& o = scene_.objects[i];
        if (o.world_T_object.translation().z() > 0.5) continue;  // above the band
        const Eigen::Vector2d local =
            o.world_T_object.linear().topLeftCorner<2, 2>().transpose() * (p - o.world_T_object.translation().head<2>());
        double d;
        if (const auto* c = std::get_if<Cylinder>(&o.shape)) {
          d = std::max(0.0, local.norm() - c->radius);
        } else {
          d = (local.cwiseAbs() - std::get<Box>(o.shape).size.head<2>() / 2).cwiseMax(0.0).norm();
        }
        if (d < footprint.radius - step) inner.insert(i);
        if (d < footprint.radius + step) outer.insert(i);
      }
    }
    for (ObjectIndex i : inner) EXPECT_TRUE(std::binary_search(swept.begin(), swept.end(), i)) << trial;
    for (ObjectIndex i : swept) EXPECT_TRUE(outer.count(i)) << trial;
    compared += static_cast<int>(swept.size());
  }
  EXPECT_GT(compared, 300);
  EXPECT_EQ(world_->footprint_objects({0.5, 0.5}, {0.01, 0.0, 0.3}, {}).size() <= 1, true);
}

TEST_F(Footprints, CylinderSweepIsExactAtTheBoundary) {
  Scene scene;
  scene.objects.push_back(cylinder("c", at(0.0, 0.1, 0.15), 0.04, 0.3));
  const CollisionWorld world(scene, nullptr);
  // Passing at distance 0.1 from the centre: touches when r_b + 0.04 > 0.1.
  EXPECT_EQ(world.swept_objects({-1, 0}, {1, 0}, {0.0600001, 0, 0.3}).size(), 1u);
  EXPECT_EQ(world.swept_objects({-1, 0}, {1, 0}, {0.0599999, 0, 0.3}).size(), 0u);
  // Stopping short of it: only the end point matters.
  EXPECT_EQ(world.swept_objects({-1, 0}, {-0.2, 0}, {0.0600001, 0, 0.3}).size(), 0u);
  // Another height band: never.
  EXPECT_EQ(world.swept_objects({-1, 0}, {1, 0}, {0.5, 0.31, 0.6}).size(), 0u);
}

TEST_F(Footprints, FixedGeometryBlocksSweeps) {
  Scene scene;
  FixedBody wall;
  wall.id = "wall";
  wall.shape = Box{{0.02, 1.0, 0.5}};
  wall.world_T_body = at(0.5, 0, 0.25);
  scene.fixed.push_back(wall);
  FixedBody floor;
  floor.id = "floor";
  floor.shape = Box{{2.0, 2.0, 0.02}};
  floor.world_T_body = at(0, 0, -0.01);
  scene.fixed.push_back(floor);
  const CollisionWorld world(scene, nullptr);
  EXPECT_TRUE(world.sweep_hits_fixed({0, 0}, {1, 0}, {0.04, 0.0, 0.3}));
  EXPECT_FALSE(world.sweep_hits_fixed({0, 0}, {0.4, 0}, {0.04, 0.0, 0.3}));  // the floor is below the band
  // A band reaching into the floor by less than scene files accept as resting contact
  // (an object standing 10 um into its board) stands on it; 2 mm into it does not.
  EXPECT_FALSE(world.sweep_hits_fixed({0, 0}, {0.4, 0}, {0.04, -1e-5, 0.3}));
  EXPECT_FALSE(world.sweep_hits_fixed({0, 0}, {0.4, 0}, {0.04, -0.9 * kContactTolerance, 0.3}));
  EXPECT_TRUE(world.sweep_hits_fixed({0, 0}, {0.4, 0}, {0.04, -0.002, 0.3}));
}

}  // namespace
}  // namespace cluttertamp::collision
