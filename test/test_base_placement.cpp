// A mobile manipulator's base placed behind the tool: outside the table it reaches
// into, facing along the approach, the tool exactly where it was asked (FK∘IK = pose);
// and the fixed contacts that explain "fixed geometry is in the way".
#include <cmath>

#include <gtest/gtest.h>

#include "cluttertamp/io/robot_description_io.hpp"
#include "cluttertamp/collision/collision_world.hpp"
#include "cluttertamp/manipulation/base_placement.hpp"
#include "cluttertamp/robot/robot_description.hpp"
#include "test_fixtures.hpp"

namespace cluttertamp {
namespace {

using test::at;

class BasePlacementTable : public ::testing::Test {
 protected:
  void SetUp() override {
    // The bench mobile table: 0.7 m square, its top 0.4 m high, its near edge at x = 0.6.
    test::add_box(scene_, "table", {0.7, 0.7, 0.4}, {0.95, 0.0, 0.2});
    world_ = std::make_unique<collision::CollisionWorld>(scene_, robot_);
    checker_ = world_->make_context();
  }

  // A side grasp at the table's middle, 0.13 m above its top, approaching along `yaw`.
  static Eigen::Isometry3d side_grasp(double yaw) {
    const Eigen::Vector3d approach(std::cos(yaw), std::sin(yaw), 0.0), x(0, 0, -1);
    Eigen::Isometry3d tool = at(0.95, 0.0, 0.53);
    tool.linear().col(0) = x;
    tool.linear().col(1) = approach.cross(x);
    tool.linear().col(2) = approach;
    return tool;
  }

  bool base_touches_table(const Eigen::VectorXd& q) {
    const auto base = *robot_->model()->find_link("base_link");
    for (const collision::FixedContact& c : world_->fixed_contacts(q, *checker_)) {
      if (c.link == base) return true;
    }
    return false;
  }

  std::shared_ptr<const robot::RobotDescription> robot_ = std::make_shared<const robot::RobotDescription>(
      io::load_robot_description(std::filesystem::path(CLUTTERTAMP_SOURCE_DIR) / "domains/robots/pr2_mobile.yaml"));
  Scene scene_;
  std::unique_ptr<collision::CollisionWorld> world_;
  std::unique_ptr<collision::CollisionWorld::Context> checker_;
};

TEST_F(BasePlacementTable, FixedContactsNameTheLinkAndTheBody) {
  Eigen::VectorXd q = robot_->home();
  EXPECT_TRUE(world_->fixed_contacts(q, *checker_).empty());
  EXPECT_EQ(world_->describe_fixed_contacts(q, *checker_), "");
  q[0] = 0.5;  // the base's front edge 0.23 m into the table
  EXPECT_TRUE(base_touches_table(q));
  EXPECT_NE(world_->describe_fixed_contacts(q, *checker_).find("base_link on table"), std::string::npos)
      << world_->describe_fixed_contacts(q, *checker_);
  EXPECT_TRUE(world_->check(q, *checker_).fixed);  // the same contact check() reports
}

TEST_F(BasePlacementTable, TheBaseStandsOutsideTheTableFacingTheApproach) {
  const auto placement = manipulation::BasePlacement::of(*robot_);
  ASSERT_TRUE(placement.has_value());
  for (double yaw : {M_PI, -M_PI / 2, M_PI / 4, 0.0}) {
    SCOPED_TRACE("approach yaw " + std::to_string(yaw));
    const Eigen::Isometry3d tool = side_grasp(yaw);
    const auto solutions = placement->solve(*world_, *checker_, tool, robot_->home());
    ASSERT_FALSE(solutions.empty());
    for (const Eigen::VectorXd& q : solutions) {
      const auto [position, orientation] = robot::pose_error(world_->tool_pose(q, *checker_), tool);
      EXPECT_LT(position, 1e-6);
      EXPECT_LT(orientation, 1e-6);
      EXPECT_FALSE(base_touches_table(q));
      // Facing along the approach, or turned 30 degrees where the approach meets a corner.
      const double turn = std::abs(std::remainder(q[2] - yaw, 2 * M_PI));
      EXPECT_TRUE(turn < 1e-9 || std::abs(turn - M_PI / 6) < 1e-9) << turn;
      // On the approach line, at least the asked 0.6 m behind the tool.
      const Eigen::Vector2d behind = tool.translation().head<2>() - Eigen::Vector2d(q[0], q[1]);
      EXPECT_GE(behind.dot(Eigen::Vector2d(std::cos(yaw), std::sin(yaw))), 0.6 - 1e-9);
      EXPECT_NEAR(behind.x() * std::sin(yaw) - behind.y() * std::cos(yaw), 0.0, 1e-9);
      EXPECT_TRUE(world_->self_contacts(q, *checker_).empty());
      EXPECT_TRUE(robot_->model()->within_limits(q));  // the base's yaw wrapped into [-pi, pi]
    }
  }
  // 0.6 m behind a grasp at the middle puts the base's front edge 0.08 m into the table
  // when it approaches square to an edge: the base stands further back there.
  const auto square = placement->solve(*world_, *checker_, side_grasp(M_PI), robot_->home());
  ASSERT_FALSE(square.empty());
  EXPECT_GT(square[0][0] - 0.95, 0.6 + 0.05);
}

TEST_F(BasePlacementTable, TheArmAloneKeepsTheBaseWhereItIs) {
  const auto placement = manipulation::BasePlacement::of(*robot_);
  ASSERT_TRUE(placement.has_value());
  const auto placed = placement->solve(*world_, *checker_, side_grasp(M_PI / 2), robot_->home());
  ASSERT_FALSE(placed.empty());
  Eigen::Isometry3d lifted = side_grasp(M_PI / 2);
  lifted.translation().z() += 0.05;
  const auto arm = placement->solve_arm(scene_.world_T_robot_base, lifted, placed[0]);
  ASSERT_FALSE(arm.empty());
  EXPECT_EQ(arm[0].head<3>(), placed[0].head<3>());
  EXPECT_LT(robot::pose_error(world_->tool_pose(arm[0], *checker_), lifted).first, 1e-6);
}

// The robot's root turned and moved in the world: base variables are in the root's
// frame, the placement in the world's.
TEST(BasePlacement, PlacesTheBaseInTheWorldWhereverTheRobotsRootIs) {
  const auto robot = std::make_shared<const robot::RobotDescription>(
      io::load_robot_description(std::filesystem::path(CLUTTERTAMP_SOURCE_DIR) / "domains/robots/pr2_mobile.yaml"));
  Scene scene;
  scene.world_T_robot_base = at(2.0, -1.0, 0.0);
  scene.world_T_robot_base.linear() = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  test::add_box(scene, "table", {0.7, 0.7, 0.4}, {2.0, 0.0, 0.2});
  collision::CollisionWorld world(scene, robot);
  auto checker = world.make_context();
  // A side grasp at the table's middle approaching along world -y, from its +y side.
  Eigen::Isometry3d tool = at(2.0, 0.0, 0.53);
  tool.linear().col(0) = -Eigen::Vector3d::UnitZ();
  tool.linear().col(2) = -Eigen::Vector3d::UnitY();
  tool.linear().col(1) = tool.linear().col(2).cross(tool.linear().col(0));
  const auto placement = manipulation::BasePlacement::of(*robot);
  ASSERT_TRUE(placement.has_value());
  const auto solutions = placement->solve(world, *checker, tool, robot->home());
  ASSERT_FALSE(solutions.empty());
  const Eigen::VectorXd& q = solutions[0];
  EXPECT_TRUE(robot->model()->within_limits(q));
  EXPECT_LT(robot::pose_error(world.tool_pose(q, *checker), tool).first, 1e-6);
  const std::string contacts = world.describe_fixed_contacts(q, *checker);
  EXPECT_EQ(contacts.find("base_link"), std::string::npos) << contacts;
  // The base's centre in the world: on the line x = 2 beyond the table's +y edge (0.35).
  const Eigen::Vector3d base = scene.world_T_robot_base * Eigen::Vector3d(q[0], q[1], 0.0);
  EXPECT_NEAR(base.x(), 2.0, 1e-9);
  EXPECT_GE(base.y(), 0.6 - 1e-9);
  // Facing world -y, along the approach (the root is turned +90 degrees: root yaw pi).
  EXPECT_NEAR(std::abs(std::remainder(q[2] + M_PI / 2 - (-M_PI / 2), 2 * M_PI)), 0.0, 1e-9);
}

TEST(BasePlacement, OnlyForARobotOnAPlanarBase) {
  EXPECT_FALSE(manipulation::BasePlacement::of(*test::ur10()).has_value());
}

}  // namespace
}  // namespace cluttertamp
