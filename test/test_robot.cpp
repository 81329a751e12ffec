// Robot models, forward kinematics against hand-computed poses, IK property tests.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include <unistd.h>

#include <gtest/gtest.h>

#include "cluttertamp/collision/collision_world.hpp"
#include "cluttertamp/io/robot_description_io.hpp"
#include "cluttertamp/robot/ik.hpp"
#include "cluttertamp/robot/robot_description.hpp"
#include "cluttertamp/scenes/shelf_fit.hpp"
#include "test_support.hpp"

namespace cluttertamp::robot {
namespace {

std::filesystem::path robot_file(const std::string& name) {
  return std::filesystem::path(CLUTTERTAMP_SOURCE_DIR) / "domains/robots" / name;
}

// Standard DH link transform, written out independently of the library.
Eigen::Matrix4d dh(double theta, double d, double a, double alpha) {
  Eigen::Matrix4d m;
  m << std::cos(theta), -std::sin(theta) * std::cos(alpha), std::sin(theta) * std::sin(alpha), a * std::cos(theta),
      std::sin(theta), std::cos(theta) * std::cos(alpha), -std::cos(theta) * std::sin(alpha), a * std::sin(theta), 0,
      std::sin(alpha), std::cos(alpha), d, 0, 0, 0, 1;
  return m;
}

// Modified (Craig) DH link transform: Rx(alpha) Tx(a) Rz(theta) Tz(d).
Eigen::Matrix4d mdh(double theta, double d, double a, double alpha) {
  const double ct = std::cos(theta), st = std::sin(theta), ca = std::cos(alpha), sa = std::sin(alpha);
  Eigen::Matrix4d m;
  m << ct, -st, 0, a, st * ca, ct * ca, -sa, -sa * d, st * sa, ct * sa, ca, ca * d, 0, 0, 0, 1;
  return m;
}

Eigen::VectorXd random_configuration(const RobotModel& model, std::mt19937_64& rng, double margin = 0.0) {
  Eigen::VectorXd q(static_cast<Eigen::Index>(model.variable_count()));
  for (Eigen::Index i = 0; i < q.size(); ++i) {
    const double lo = std::max(model.lower_limits()[i], -M_PI) + margin;
    const double hi = std::min(model.upper_limits()[i], M_PI) - margin;
    q[i] = std::uniform_real_distribution<double>(lo, hi)(rng);
  }
  return q;
}

double angle_distance(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  double worst = 0;
  for (Eigen::Index i = 0; i < a.size(); ++i) worst = std::max(worst, std::abs(std::remainder(a[i] - b[i], 2 * M_PI)));
  return worst;
}

class Ur10 : public ::testing::Test {
 protected:
  RobotDescription robot_ = io::load_robot_description(robot_file("ur10_ag95.yaml"));
  const RobotModel& model_ = *robot_.model();
  std::vector<Eigen::Isometry3d> poses_;

  Eigen::Isometry3d link(const Eigen::VectorXd& q, const std::string& name) {
    model_.link_poses(q, poses_);
    return poses_[*model_.find_link(name)];
  }
};

TEST_F(Ur10, LoadsWithSixArmJointsAndOneFingerJoint) {
  EXPECT_EQ(model_.variable_count(), 7u);
  EXPECT_EQ(model_.variable_names(), (std::vector<std::string>{"shoulder_pan_joint", "shoulder_lift_joint", "elbow_joint",
                                                               "wrist_1_joint", "wrist_2_joint", "wrist_3_joint",
                                                               "finger_joint"}));
  EXPECT_DOUBLE_EQ(model_.upper_limits()[0], 2 * M_PI);
  EXPECT_NEAR(model_.velocity_limits()[0], 2.0944, 1e-9);
  EXPECT_NEAR(model_.velocity_limits()[5], 3.1416, 1e-9);
  EXPECT_DOUBLE_EQ(robot_.gripper().finger_thickness, 0.012);
  EXPECT_DOUBLE_EQ(robot_.gripper().footprint_radius(0.04), 0.052);  // r_b = r_g + r_f
  const auto* ik = dynamic_cast<const UrAnalyticIk*>(&robot_.ik());
  ASSERT_NE(ik, nullptr);
  EXPECT_DOUBLE_EQ(ik->dh().d1, 0.1273);
  EXPECT_DOUBLE_EQ(ik->dh().a2, -0.612);
  EXPECT_DOUBLE_EQ(ik->dh().a3, -0.5723);
  EXPECT_DOUBLE_EQ(ik->dh().d4, 0.163941);
  EXPECT_DOUBLE_EQ(ik->dh().d5, 0.1157);
}

TEST_F(Ur10, ZeroConfigurationMatchesTheDhTable) {
  // All joints at zero: the flange sits at (a2 + a3, -(d4 + d6), d1 - d5).
  const Eigen::Isometry3d flange = link(Eigen::VectorXd::Zero(7), "tool0");
  EXPECT_TRUE(flange.translation().isApprox(Eigen::Vector3d(-1.1843, -0.256141, 0.0116), 1e-9))
      << flange.translation().transpose();
}

TEST_F(Ur10, ForwardKinematicsIsTheDhProduct) {
  std::mt19937_64 rng(1);
  for (int trial = 0; trial < 200; ++trial) {
    const Eigen::VectorXd q = random_configuration(model_, rng);
    const double d[6] = {0.1273, 0, 0, 0.163941, 0.1157, 0.0922};
    const double a[6] = {0, -0.612, -0.5723, 0, 0, 0};
    const double alpha[6] = {M_PI / 2, 0, 0, M_PI / 2, -M_PI / 2, 0};
    Eigen::Matrix4d expected = Eigen::Matrix4d::Identity();
    for (int i = 0; i < 6; ++i) expected = expected * dh(q[i], d[i], a[i], alpha[i]);
    EXPECT_TRUE(link(q, "tool0").matrix().isApprox(expected, 1e-12)) << q.transpose();
    // The TCP is 0.13 m past the flange along its z axis.
    const Eigen::Vector3d tcp = expected.block<3, 3>(0, 0) * Eigen::Vector3d(0, 0, 0.13) + expected.block<3, 1>(0, 3);
    EXPECT_TRUE(link(q, "gripper_tcp").translation().isApprox(tcp, 1e-12));
  }
}

TEST_F(Ur10, AnalyticIkRoundTripsOverThousandsOfPoses) {
  std::mt19937_64 rng(7);
  const IkSolver& ik = robot_.ik();
  int found_original = 0;
  const int trials = 3000;
  for (int trial = 0; trial < trials; ++trial) {
    const Eigen::VectorXd q = random_configuration(model_, rng);
    const Eigen::Isometry3d pose = ik.forward(q);
    const auto solutions = ik.solve(pose, Eigen::VectorXd::Zero(7));
    ASSERT_FALSE(solutions.empty()) << q.transpose();
    EXPECT_LE(solutions.size(), 8u);
    bool original = false;
    for (const Eigen::VectorXd& s : solutions) {
      const auto [position, orientation] = pose_error(ik.forward(s), pose);
      EXPECT_LT(position, 1e-6);
      EXPECT_LT(orientation, 1e-6);
      EXPECT_TRUE(model_.within_limits(s));
      original = original || angle_distance(s.head(6), q.head(6)) < 1e-6;
    }
    found_original += original;
  }
  // The configuration the pose came from is among the solutions (up to 2 pi), except
  // at a wrist singularity where joints 4 and 6 trade angles.
  EXPECT_GE(found_original, trials - 3);
}

TEST_F(Ur10, AnalyticIkFindsEverySolutionTheNumericSolverFinds) {
  NumericIk::Options options;
  options.restarts = 40;
  options.max_solutions = 16;
  const NumericIk numeric(robot_.model(), robot_.base_link(), robot_.tip_link(), options);
  std::mt19937_64 rng(11);
  int numeric_solutions = 0;
  for (int trial = 0; trial < 60; ++trial) {
    const Eigen::VectorXd q = random_configuration(model_, rng, 0.2);
    const Eigen::Isometry3d pose = numeric.forward(q);
    const auto analytic = robot_.ik().solve(pose, q);
    for (const Eigen::VectorXd& s : numeric.solve(pose, q, static_cast<std::uint64_t>(trial))) {
      ++numeric_solutions;
      const auto [position, orientation] = pose_error(numeric.forward(s), pose);
      EXPECT_LT(position, 1e-6);
      EXPECT_LT(orientation, 1e-6);
      double nearest = 1e9;
      for (const Eigen::VectorXd& a : analytic) nearest = std::min(nearest, angle_distance(a.head(6), s.head(6)));
      EXPECT_LT(nearest, 1e-5) << "numeric solution " << s.transpose() << " is not among the analytic ones";
    }
  }
  EXPECT_GT(numeric_solutions, 120);  // the comparison is not vacuous
}

TEST_F(Ur10, UnreachablePoseHasNoSolution) {
  Eigen::Isometry3d far = Eigen::Isometry3d::Identity();
  far.translation() << 3.0, 0, 0.5;
  EXPECT_TRUE(robot_.ik().solve(far, Eigen::VectorXd::Zero(7)).empty());
  EXPECT_THROW(robot_.ik().solve(far, Eigen::VectorXd::Zero(6)), std::invalid_argument);  // seed of the wrong size
}

TEST_F(Ur10, AnalyticIkPicksTheTurnNearestTheSeed) {
  // Base just past +pi: the same angle as -pi + 0.05, but a seed near +pi wants +pi + 0.05.
  Eigen::VectorXd q = robot_.home();
  q[0] = M_PI + 0.05;
  const Eigen::Isometry3d pose = robot_.ik().forward(q);
  const auto near_home = robot_.ik().solve(pose, robot_.home());
  ASSERT_FALSE(near_home.empty());
  EXPECT_NEAR(near_home.front()[0], M_PI + 0.05, 1e-6);  // nearest the seed comes first
  EXPECT_LT((near_home.front() - q).cwiseAbs().maxCoeff(), 1e-6);
  Eigen::VectorXd seed = robot_.home();
  seed[0] = -M_PI;
  EXPECT_NEAR(robot_.ik().solve(pose, seed).front()[0], -M_PI + 0.05, 1e-6);
  // Joints outside the chain (the fingers) keep the seed's values.
  seed[6] = 0.01;
  EXPECT_DOUBLE_EQ(robot_.ik().solve(pose, seed).front()[6], 0.01);
}

TEST_F(Ur10, FingersMoveSymmetrically) {
  Eigen::VectorXd q = robot_.home();
  q[6] = 0.03;
  const Eigen::Isometry3d base = link(q, "gripper_base");
  const Eigen::Vector3d left = base.inverse() * link(q, "left_finger").translation();
  const Eigen::Vector3d right = base.inverse() * link(q, "right_finger").translation();
  EXPECT_TRUE(left.isApprox(Eigen::Vector3d(0, 0.03, 0.10), 1e-12)) << left.transpose();
  EXPECT_TRUE(right.isApprox(Eigen::Vector3d(0, -0.03, 0.10), 1e-12)) << right.transpose();
  // Closed on a cylinder of radius r_g, the outer faces are r_g + r_f from the centre line.
  EXPECT_DOUBLE_EQ(robot_.gripper().footprint_radius(0.03), 0.03 + 0.012);
}

TEST_F(Ur10, AdjacentLinksAreDisabledPairs) {
  auto has = [&](const std::string& a, const std::string& b) {
    const LinkIndex i = *model_.find_link(a), j = *model_.find_link(b);
    const std::pair<LinkIndex, LinkIndex> pair{std::min(i, j), std::max(i, j)};
    const auto& adjacent = model_.adjacent_links();
    return std::find(adjacent.begin(), adjacent.end(), pair) != adjacent.end();
  };
  EXPECT_TRUE(has("upper_arm_link", "forearm_link"));
  EXPECT_TRUE(has("wrist_3_link", "gripper_base"));  // through tool0, which has no geometry
  EXPECT_TRUE(has("left_finger", "gripper_base"));  // one joint apart
  EXPECT_TRUE(has("wrist_2_link", "gripper_base"));  // one joint from the wrist_3 body, which holds the gripper
  EXPECT_FALSE(has("left_finger", "right_finger"));  // two joints apart: they must not close into each other
  EXPECT_FALSE(has("upper_arm_link", "wrist_1_link"));
  EXPECT_FALSE(has("base_link", "gripper_base"));
}

TEST(Panda, ForwardKinematicsIsTheModifiedDhProduct) {
  const RobotDescription robot = io::load_robot_description(robot_file("panda.yaml"));
  const RobotModel& model = *robot.model();
  ASSERT_EQ(model.variable_count(), 8u);  // seven arm joints and the fingers
  std::vector<Eigen::Isometry3d> poses;
  model.link_poses(Eigen::VectorXd::Zero(8), poses);
  // Zero configuration: flange 0.088 m forward, 0.926 m up, pointing down.
  EXPECT_TRUE(poses[*model.find_link("panda_link8")].translation().isApprox(Eigen::Vector3d(0.088, 0, 0.926), 1e-12));
  EXPECT_TRUE(poses[*model.find_link("panda_hand_tcp")].translation().isApprox(Eigen::Vector3d(0.088, 0, 0.8226), 1e-12));
  const double a[8] = {0, 0, 0, 0.0825, -0.0825, 0, 0.088, 0};
  const double d[8] = {0.333, 0, 0.316, 0, 0.384, 0, 0, 0.107};
  const double alpha[8] = {0, -M_PI / 2, M_PI / 2, M_PI / 2, -M_PI / 2, M_PI / 2, M_PI / 2, 0};
  std::mt19937_64 rng(3);
  for (int trial = 0; trial < 200; ++trial) {
    const Eigen::VectorXd q = random_configuration(model, rng);
    Eigen::Matrix4d expected = Eigen::Matrix4d::Identity();
    for (int i = 0; i < 8; ++i) expected = expected * mdh(i < 7 ? q[i] : 0.0, d[i], a[i], alpha[i]);
    model.link_poses(q, poses);
    EXPECT_TRUE(poses[*model.find_link("panda_link8")].matrix().isApprox(expected, 1e-12));
  }
}

TEST(Panda, NumericIkRoundTripsOverThousandsOfPoses) {
  const RobotDescription robot = io::load_robot_description(robot_file("panda.yaml"));
  const RobotModel& model = *robot.model();
  const IkSolver& ik = robot.ik();
  std::mt19937_64 rng(5);
  int solved = 0;
  const int trials = 1000;
  for (int trial = 0; trial < trials; ++trial) {
    const Eigen::VectorXd q = random_configuration(model, rng);
    const Eigen::Isometry3d pose = ik.forward(q);
    const auto solutions = ik.solve(pose, robot.home(), static_cast<std::uint64_t>(trial));
    for (const Eigen::VectorXd& s : solutions) {
      const auto [position, orientation] = pose_error(ik.forward(s), pose);
      EXPECT_LT(position, 1e-6);
      EXPECT_LT(orientation, 1e-6);
      EXPECT_TRUE(model.within_limits(s));
    }
    solved += !solutions.empty();
  }
  EXPECT_GE(solved, trials * 99 / 100);
}

TEST(Panda, NumericIkIsDeterministicForASeed) {
  const RobotDescription robot = io::load_robot_description(robot_file("panda.yaml"));
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() << 0.5, 0.2, 0.4;
  pose.linear() = Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()).toRotationMatrix();
  const Eigen::VectorXd seed = Eigen::VectorXd::Constant(8, -0.05);
  const auto first = robot.ik().solve(pose, seed, 42);
  const auto second = robot.ik().solve(pose, seed, 42);
  ASSERT_EQ(first.size(), second.size());
  ASSERT_FALSE(first.empty());
  EXPECT_EQ(first[0], second[0]);
}

TEST(MobileManipulator, BaseAndArmFormOneChain) {
  const RobotDescription robot = io::load_robot_description(robot_file("pr2_mobile.yaml"));
  const RobotModel& model = *robot.model();
  ASSERT_EQ(model.variable_count(), 11u);  // base x, y, yaw; seven arm joints; fingers
  std::vector<Eigen::Isometry3d> poses;
  model.link_poses(Eigen::VectorXd::Zero(11), poses);
  // Zero: torso at (-0.05, 0, 0.839675); shoulder 0.188 left; arm straight forward.
  EXPECT_TRUE(poses[*model.find_link("l_gripper_tool_frame")].translation().isApprox(
      Eigen::Vector3d(-0.05 + 0.1 + 0.4 + 0.321 + 0.18, 0.188, 0.839675), 1e-12));
  // Moving the base moves the tool by the same planar motion.
  Eigen::VectorXd q = Eigen::VectorXd::Zero(11);
  q << 1.0, 2.0, M_PI / 2, 0, 0, 0, 0, 0, 0, 0, 0;
  model.link_poses(q, poses);
  EXPECT_TRUE(poses[*model.find_link("l_gripper_tool_frame")].translation().isApprox(
      Eigen::Vector3d(1.0 - 0.188, 2.0 + 0.951, 0.839675), 1e-12));
  // Elbow flexed by -pi/2 about its y axis: the forearm points straight up.
  Eigen::VectorXd bent = Eigen::VectorXd::Zero(11);
  bent[6] = -M_PI / 2;
  model.link_poses(bent, poses);
  EXPECT_TRUE(poses[*model.find_link("l_gripper_tool_frame")].translation().isApprox(
      Eigen::Vector3d(-0.05 + 0.1 + 0.4, 0.188, 0.839675 + 0.321 + 0.18), 1e-12));
  model.link_poses(q, poses);
  // IK over all ten chain joints reaches a pose 2 m away.
  Eigen::Isometry3d goal = poses[*model.find_link("l_gripper_tool_frame")];
  const auto solutions = robot.ik().solve(goal, robot.home(), 1);
  ASSERT_FALSE(solutions.empty());
  const auto [position, orientation] = pose_error(robot.ik().forward(solutions[0]), goal);
  EXPECT_LT(position, 1e-6);
  EXPECT_LT(orientation, 1e-6);
}

TEST(RobotErrors, AMissingMeshIsLocatedWhereItsFilenameStands) {
  const Diagnostics d = test::expect_input_error([] { RobotModel::load_urdf(test::data("robots/mesh.urdf")); });
  ASSERT_EQ(d.size(), 1u);
  EXPECT_NE(d.items()[0].location.file.str().find("mesh.urdf"), std::string::npos);
  EXPECT_TRUE(test::has_error(d, 5, 32, "mesh 'arm.stl' not found: no file")) << d.str();
}

TEST(RobotErrors, MalformedUrdfSaysWhereAndWhy) {
  const Diagnostics d = test::expect_input_error([] { RobotModel::load_urdf(test::data("robots/malformed.urdf")); });
  EXPECT_TRUE(test::has_error(d, 4, 3, "joint 'j1' needs <limit velocity=... effort=...>")) << d.str();
  EXPECT_TRUE(test::has_error(d, 5, 26, "no link named 'nowhere'")) << d.str();
}

TEST(RobotErrors, JointWithoutVelocityLimit) {
  const Diagnostics d = test::expect_input_error([] { RobotModel::load_urdf(test::data("robots/no_velocity.urdf")); });
  EXPECT_TRUE(test::has_error(d, 7, 0, "<limit velocity> must be above zero")) << d.str();
}

// What urdfdom let pass or dropped silently, and what it reported without a position:
// every mistake of the file at its line, in one run.
TEST(RobotErrors, EveryUrdfMistakeIsReportedAtItsLine) {
  const Diagnostics d = test::expect_input_error([] { RobotModel::load_urdf(test::data("robots/mistakes.urdf")); });
  EXPECT_TRUE(test::has_error(d, 4, 0, "<box size='0.1 nan 0.1'> must be 3 finite numbers above zero")) << d.str();
  EXPECT_TRUE(test::has_error(d, 5, 0, "<origin xyz='0 0'> must be 3 finite numbers")) << d.str();
  EXPECT_TRUE(test::has_error(d, 6, 0, "<origin rpy='nan 0 0'> must be 3 finite numbers")) << d.str();
  EXPECT_TRUE(test::has_error(d, 7, 0, "<collision> has no <geometry>")) << d.str();
  EXPECT_TRUE(test::has_error(d, 8, 0, "<cylinder length='-1'> must be one finite number above zero")) << d.str();
  EXPECT_TRUE(test::has_error(d, 14, 0, "link 'a' is already the child of the joint at line 9")) << d.str();
  EXPECT_TRUE(test::has_error(d, 15, 0, "is planar; model a mobile base")) << d.str();
  EXPECT_TRUE(test::has_error(d, 15, 0, "no link named 'f'")) << d.str();
  EXPECT_EQ(d.size(), 8u) << d.str();
}

// XML parsers recurse once per nesting level: 50,000 levels used to end the process.
TEST(RobotErrors, DeeplyNestedUrdfIsRefusedWithoutRecursing) {
  const std::filesystem::path file = std::filesystem::temp_directory_path() / "cluttertamp_nested.urdf";
  {
    std::ofstream out(file);
    out << "<?xml version=\"1.0\"?>\n<robot name=\"deep\">\n  <link name=\"base\"/>\n";
    for (int i = 0; i < 50000; ++i) out << "<gazebo>";
    for (int i = 0; i < 50000; ++i) out << "</gazebo>";
    out << "\n</robot>\n";
  }
  const Diagnostics d = test::expect_input_error([&] { RobotModel::load_urdf(file); });
  EXPECT_TRUE(test::has_error(d, 4, 1 + 8 * 99, "elements nested more than 100 deep")) << d.str();
  std::filesystem::remove(file);
}

// A device is read without end: refused before reading, as scene and PDDL files are.
TEST(RobotErrors, AUrdfThatIsNotARegularFileIsRefused) {
  const Diagnostics d = test::expect_input_error([] { RobotModel::load_urdf("/dev/zero"); });
  EXPECT_TRUE(test::has_error(d, 0, 0, "the URDF is not a regular file")) << d.str();
  const Diagnostics missing = test::expect_input_error([] { RobotModel::load_urdf("/no/such/robot.urdf"); });
  EXPECT_TRUE(test::has_error(missing, 0, 0, "no such URDF file")) << missing.str();
}

// A chain of many links is ordered without recursion.
TEST(RobotModelTree, ALongChainLoads) {
  const std::filesystem::path file = std::filesystem::temp_directory_path() / "cluttertamp_chain.urdf";
  {
    std::ofstream out(file);
    out << "<robot name=\"chain\">\n<link name=\"l0\"/>\n";
    for (int i = 1; i <= 20000; ++i) {
      out << "<link name=\"l" << i << "\"/><joint name=\"j" << i << "\" type=\"fixed\"><parent link=\"l" << i - 1
          << "\"/><child link=\"l" << i << "\"/></joint>\n";
    }
    out << "</robot>\n";
  }
  const RobotModel model = RobotModel::load_urdf(file);
  EXPECT_EQ(model.links().size(), 20001u);
  std::filesystem::remove(file);
}

TEST(RobotErrors, DescriptionErrorsAreLocated) {
  const Diagnostics d = test::expect_input_error([] { io::load_robot_description(test::data("robots/bad_description.yaml")); });
  EXPECT_TRUE(test::has_error(d, 8, 1, "unknown key 'colour'"));
  EXPECT_TRUE(test::has_error(d, 6, 53, "gripper base_half_length must not be negative"));
}

// A copy of the bundled UR10 description, its URDF and YAML edited, in a directory of
// this process's own.
std::filesystem::path ur10_variant(const std::string& name, const std::vector<std::pair<std::string, std::string>>& urdf_edits,
                                   const std::vector<std::pair<std::string, std::string>>& yaml_edits) {
  const std::filesystem::path robots = std::filesystem::path(CLUTTERTAMP_SOURCE_DIR) / "domains/robots";
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / ("cluttertamp_ur10_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  std::string urdf = test::read_text(robots / "ur10_ag95.urdf");
  for (const auto& [from, to] : urdf_edits) urdf = test::replaced(urdf, from, to);
  std::ofstream(dir / (name + ".urdf")) << urdf;
  std::string yaml = test::replaced(test::read_text(robots / "ur10_ag95.yaml"), "urdf: ur10_ag95.urdf", "urdf: " + name + ".urdf");
  for (const auto& [from, to] : yaml_edits) yaml = test::replaced(yaml, from, to);
  std::ofstream(dir / (name + ".yaml")) << yaml;
  return dir / (name + ".yaml");
}

// The fingers open by half the stroke each along a prismatic joint: a stroke the joint
// cannot open, or a revolute jaw, would put every plan's finger values outside the
// URDF's limits, and is an error at the stroke. A home beyond the limits names the joint.
TEST(RobotErrors, FingersThatCannotOpenTheStrokeAndHomesBeyondTheLimitsAreLocated) {
  Diagnostics d = test::expect_input_error([] {
    io::load_robot_description(ur10_variant("wide", {}, {{"stroke: 0.095", "stroke: 0.12"}}));
  });
  EXPECT_TRUE(test::has_error(d, 11, 11, "a stroke of 0.12 m opens the finger joint 'finger_joint' 0.06 m, beyond its upper limit 0.0475 m: "
                                         "the stroke is at most 0.095 m")) << d.str();
  d = test::expect_input_error([] {
    io::load_robot_description(ur10_variant("jaw", {{"<joint name=\"finger_joint\" type=\"prismatic\">", "<joint name=\"finger_joint\" type=\"revolute\">"}}, {}));
  });
  EXPECT_TRUE(test::has_error(d, 11, 11, "the finger joint 'finger_joint' (the first movable joint below the tool that IK does not move) is revolute"))
      << d.str();
  d = test::expect_input_error([] {
    io::load_robot_description(ur10_variant("bent", {}, {{"home: [3.14159265, -2.0, 2.0,", "home: [3.14159265, -2.0, 4.0,"}}));
  });
  EXPECT_TRUE(test::has_error(d, 15, 7, "home lies outside the joint limits: 'elbow_joint' at 4 outside [-3.14159, 3.14159]")) << d.str();
  EXPECT_NO_THROW(io::load_robot_description(ur10_variant("as_bundled", {}, {})));
}

// A tool frame turned from the convention (z the approach, fingers closing along y)
// used to plan every grasp turned; it is an error at tip_link.
TEST(RobotErrors, AToolFrameTurnedFromTheConventionIsLocatedAtTheTipLink) {
  const std::string tcp = "<origin xyz=\"0 0 0.13\" rpy=\"0 0 0\"/>";
  Diagnostics d = test::expect_input_error([&] {
    io::load_robot_description(ur10_variant("turned", {{tcp, "<origin xyz=\"0 0 0.13\" rpy=\"0 0 1.5708\"/>"}}, {}));
  });
  EXPECT_TRUE(test::has_error(d, 6, 11, "the fingers ('finger_joint') close along the x axis of the tool frame 'gripper_tcp', not its y axis"))
      << d.str();
  d = test::expect_input_error([&] {
    io::load_robot_description(ur10_variant("sideways", {{tcp, "<origin xyz=\"0 0 0.13\" rpy=\"0 1.5708 0\"/>"}}, {}));
  });
  EXPECT_TRUE(test::has_error(d, 6, 11, "the hand's base 'gripper_base' lies along the x axis of the tool frame 'gripper_tcp', where -z is expected"))
      << d.str();
  // Turned half a turn about z the fingers still close along y (either way): as planned.
  EXPECT_NO_THROW(io::load_robot_description(ur10_variant("flipped", {{tcp, "<origin xyz=\"0 0 0.13\" rpy=\"0 0 3.14159265\"/>"}}, {})));
}

// An arm whose IK chain starts below the URDF's root (a pedestal that raises it and
// turns it): IK poses are the base link's, the scene places the root, and
// world_T_ik_base joins them.
TEST(RobotDescriptionFrames, AChainBelowTheRootSolvesInItsBaseLinksFrame) {
  const RobotDescription robot = io::load_robot_description(
      ur10_variant("pedestal", {{"<link name=\"base_link\">", "<link name=\"world\"/>\n  <joint name=\"pedestal\" type=\"fixed\"><parent "
                                                              "link=\"world\"/><child link=\"base_link\"/><origin xyz=\"0 0 0.3\" rpy=\"0 0 0.5\"/></joint>\n  "
                                                              "<link name=\"base_link\">"}},
                   {}));
  EXPECT_LT((robot.root_T_ik_base().translation() - Eigen::Vector3d(0, 0, 0.3)).norm(), 1e-12);
  EXPECT_NEAR(Eigen::AngleAxisd(robot.root_T_ik_base().linear()).angle(), 0.5, 1e-12);
  const Eigen::Isometry3d world_T_root = test::at(1.0, -0.5, 0.2) * Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitZ());
  std::vector<Eigen::Isometry3d> root_T_links;
  robot.model()->link_poses(robot.home(), root_T_links);
  const Eigen::Isometry3d world_T_tool = world_T_root * root_T_links[static_cast<std::size_t>(robot.tip_link())];
  const auto solutions = robot.ik().solve(robot.world_T_ik_base(world_T_root).inverse() * world_T_tool, robot.home());
  ASSERT_FALSE(solutions.empty());
  for (const Eigen::VectorXd& q : solutions) {
    robot.model()->link_poses(q, root_T_links);
    const auto [position, orientation] = pose_error(world_T_root * root_T_links[static_cast<std::size_t>(robot.tip_link())], world_T_tool);
    EXPECT_LT(position, 1e-6);
    EXPECT_LT(orientation, 1e-6);
  }
}

TEST(RobotErrors, DisabledCollisionsNameExistingLinkPairs) {
  const Diagnostics d = test::expect_input_error([] { io::load_robot_description(test::data("robots/bad_disabled.yaml")); });
  EXPECT_TRUE(test::has_error(d, 8, 19, "has no link 'panda_link99'"));
  EXPECT_TRUE(test::has_error(d, 9, 5, "each disabled_collisions entry names two links"));
}

// A UR10 in the layout of ROS-Industrial's files (axes along y, upright at zero, one
// axis reversed, a turned tool frame): the closed form reads its DH parameters through
// those frames and solves its poses as for a DH-laid-out arm.
TEST(UrAnalyticIk, ReadsAUrArmInTheFramesItsUrdfUses) {
  const RobotDescription robot = io::load_robot_description(test::data("robots/ur10_y_axes.yaml"));
  const auto* ik = dynamic_cast<const UrAnalyticIk*>(&robot.ik());
  ASSERT_NE(ik, nullptr);
  EXPECT_NEAR(ik->dh().d1, 0.1273, 1e-9);
  EXPECT_NEAR(std::abs(ik->dh().a2), 0.612, 1e-9);
  EXPECT_NEAR(std::abs(ik->dh().a3), 0.5723, 1e-9);
  EXPECT_NEAR(ik->dh().d4, 0.163941, 1e-9);  // 0.220941 - 0.1719 + 0.1149, the sideways offsets summed
  EXPECT_NEAR(ik->dh().d5, 0.1157, 1e-9);
  const RobotModel& model = *robot.model();
  std::mt19937_64 rng(3);
  int found_original = 0;
  const int trials = 1000;
  for (int trial = 0; trial < trials; ++trial) {
    const Eigen::VectorXd q = random_configuration(model, rng);
    const Eigen::Isometry3d pose = ik->forward(q);
    const auto solutions = ik->solve(pose, Eigen::VectorXd::Zero(6));
    ASSERT_FALSE(solutions.empty()) << q.transpose();
    EXPECT_LE(solutions.size(), 8u);
    bool original = false;
    for (const Eigen::VectorXd& s : solutions) {
      const auto [position, orientation] = pose_error(ik->forward(s), pose);
      EXPECT_LT(position, 1e-6);
      EXPECT_LT(orientation, 1e-6);
      EXPECT_TRUE(model.within_limits(s));
      original = original || angle_distance(s, q) < 1e-6;
    }
    found_original += original;
  }
  EXPECT_GE(found_original, trials - 3);
}

// Six revolute joints that do not stand as a UR arm's (the elbow turned about x) are
// refused, not solved wrongly.
TEST(UrAnalyticIk, RefusesSixJointsThatDoNotStandAsAUrArm) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "cluttertamp_ur_layout";
  std::filesystem::create_directories(dir);
  const std::string urdf = test::read_text(test::data("robots/ur10_y_axes.urdf"));
  std::ofstream(dir / "ur10_y_axes.urdf")
      << test::replaced(urdf, "<origin xyz=\"0 -0.1719 0.612\" rpy=\"0 0 0\"/><axis xyz=\"0 1 0\"/>",
                        "<origin xyz=\"0 -0.1719 0.612\" rpy=\"0 0 0\"/><axis xyz=\"1 0 0\"/>");
  std::filesystem::copy_file(test::data("robots/ur10_y_axes.yaml"), dir / "ur10_y_axes.yaml",
                             std::filesystem::copy_options::overwrite_existing);
  const Diagnostics d = test::expect_input_error([&] { io::load_robot_description(dir / "ur10_y_axes.yaml"); });
  EXPECT_TRUE(test::has_error(d, 7, 5, "do not stand as a UR arm's")) << d.str();
  std::filesystem::remove_all(dir);
}

TEST(RobotErrors, UrAnalyticIkRefusesANonUrArm) {
  const Diagnostics d = test::expect_input_error([] { io::load_robot_description(test::data("robots/panda_ur_ik.yaml")); });
  EXPECT_TRUE(test::has_error(d, 5, 5, "ur_analytic IK needs a chain of 6 movable joints"));
}

}  // namespace
}  // namespace cluttertamp::robot

namespace cluttertamp::robot {
namespace {

// Every tip position of every configuration lies in the reach ball, and some come close
// to its surface (it is not needlessly large for a serial arm).
TEST(RobotReach, TheReachBallHoldsEveryTipPosition) {
  for (const char* name : {"ur10_ag95", "panda", "pr2_mobile"}) {
    SCOPED_TRACE(name);
    const RobotDescription robot =
        io::load_robot_description(std::filesystem::path(CLUTTERTAMP_SOURCE_DIR) / "domains/robots" / (std::string(name) + ".yaml"));
    const IkSolver::Reach reach = robot.ik().reach();
    const RobotModel& model = *robot.model();
    std::mt19937_64 rng(9);
    double farthest = 0;
    for (int i = 0; i < 20000; ++i) {
      Eigen::VectorXd q(static_cast<Eigen::Index>(model.variable_count()));
      for (std::size_t v = 0; v < model.variable_count(); ++v) {
        const Joint& joint = model.joints()[model.variables()[v]];
        q[static_cast<Eigen::Index>(v)] = std::uniform_real_distribution<double>(joint.lower, joint.upper)(rng);
      }
      const double d = (robot.ik().forward(q).translation() - reach.centre).norm();
      EXPECT_LE(d, reach.radius + 1e-9);
      farthest = std::max(farthest, d);
    }
    if (std::string(name) != "pr2_mobile") EXPECT_GT(farthest, 0.75 * reach.radius);  // the base's travel dominates the PR2's
  }
}

}  // namespace
}  // namespace cluttertamp::robot

namespace cluttertamp::scenes {
namespace {

// The UR10 reaches all of the default shelf: it stays where it is. The Panda does not:
// the shelf moves to where it reaches more.
TEST(ShelfFit, AShelfMovesOnlyForARobotThatCannotReachIt) {
  const auto load = [](const char* name) {
    return std::make_shared<const robot::RobotDescription>(
        io::load_robot_description(std::filesystem::path(CLUTTERTAMP_SOURCE_DIR) / "domains/robots" / name));
  };
  const ShelfSpec given;
  const ShelfFit ur10 = fit_shelf_to_robot(given, load("ur10_ag95.yaml"));
  EXPECT_EQ(ur10.spec.front, given.front);
  EXPECT_EQ(ur10.spec.floor_height, given.floor_height);
  EXPECT_EQ(ur10.reached, ur10.tried);
  EXPECT_EQ(ur10.tried, 22);
  EXPECT_EQ(ur10.spec.exit_distance, given.exit_distance);
  const ShelfFit panda = fit_shelf_to_robot(given, load("panda.yaml"));
  EXPECT_LT(panda.reached_as_given, panda.tried);
  EXPECT_GT(panda.reached, panda.reached_as_given);
  EXPECT_TRUE(panda.spec.front != given.front || panda.spec.floor_height != given.floor_height);
}

// The Panda's home holds its hand where the fitted shelf's front objects stand: the fit
// gives a start drawn back out of the cabinet, which the home is not.
TEST(ShelfFit, ARobotWhoseHomeReachesIntoTheCabinetGetsAStartClearOfIt) {
  const auto panda = std::make_shared<const robot::RobotDescription>(
      io::load_robot_description(std::filesystem::path(CLUTTERTAMP_SOURCE_DIR) / "domains/robots/panda.yaml"));
  const ShelfFit fit = fit_shelf_to_robot(ShelfSpec{}, panda);
  ASSERT_TRUE(fit.start.has_value());
  EXPECT_GT(fit.start_drawn_back, 0.0);
  EXPECT_TRUE(panda->model()->within_limits(*fit.start));

  // The cabinet with its interior filled, as objects may fill it.
  ShelfSpec boards = fit.spec;
  const Eigen::Vector3d size = cabinet_size(fit.spec);
  boards.objects = 0;
  Scene scene = generate_shelf_scene(boards, 0);
  SceneObject interior;
  interior.id = "interior";
  interior.shape = Box{size};
  interior.world_T_object.translation() = Eigen::Vector3d(fit.spec.front + size.x() / 2, 0, fit.spec.floor_height + size.z() / 2);
  scene.objects = {interior};
  const collision::CollisionWorld world(scene, panda);
  auto context = world.make_context();
  EXPECT_FALSE(world.is_valid(panda->home(), *context));
  EXPECT_TRUE(world.is_valid(*fit.start, *context));
  // Drawn back, not turned away: the tool keeps the home's orientation.
  const Eigen::Isometry3d home_tool = world.tool_pose(panda->home(), *context);
  const Eigen::Isometry3d start_tool = world.tool_pose(*fit.start, *context);
  EXPECT_TRUE(start_tool.linear().isApprox(home_tool.linear(), 1e-4));
  EXPECT_LT(start_tool.translation().head<2>().norm(), home_tool.translation().head<2>().norm());
}

// The exit x_s stands in front of the robot's base, where the arm holds the largest
// target the shelf may hold (upright, taken out as grasped from the front) touching
// neither itself nor the cabinet.
TEST(ShelfFit, TheExitStandsWhereTheArmHoldsTheTargetInFrontOfItsBase) {
  const auto panda = std::make_shared<const robot::RobotDescription>(
      io::load_robot_description(std::filesystem::path(CLUTTERTAMP_SOURCE_DIR) / "domains/robots/panda.yaml"));
  ShelfSpec given;
  given.objects = 16;
  const ShelfFit fit = fit_shelf_to_robot(given, panda);
  const double exit_x = fit.spec.front - fit.spec.exit_distance;
  EXPECT_GE(exit_x, 0.05 - 1e-9);

  ShelfSpec boards = fit.spec;  // the furniture at the size 16 objects give it
  const Eigen::Vector3d size = cabinet_size(fit.spec);
  boards.depth = size.x();
  boards.width = size.y();
  boards.objects = 0;
  Scene scene = generate_shelf_scene(boards, 0);
  SceneObject target;
  target.id = "target";
  target.shape = Cylinder{fit.spec.radius_max, fit.spec.height_max};
  target.world_T_object.translation() = Eigen::Vector3d(0, 0, -10);
  scene.objects = {target};
  collision::CollisionWorld world(scene, panda);
  auto context = world.make_context();
  const Eigen::Vector3d exit = scene.world_T_exit.translation();
  EXPECT_NEAR(exit.x(), exit_x, 1e-9);
  int held = 0;
  for (const double up : {-1.0, 1.0}) {
    Eigen::Isometry3d tool = Eigen::Isometry3d::Identity();
    tool.linear() << 0, 0, 1,  //
        0, 1, 0,               //
        up, 0, 0;              // x up or down, z (the approach) along +x
    tool.linear().col(1) = tool.linear().col(2).cross(tool.linear().col(0));
    tool.translation() = exit;
    world.attach(0, tool.inverse() * Eigen::Translation3d(exit));
    for (const Eigen::VectorXd& q : panda->ik().solve(tool, fit.start.value_or(panda->home()), 1)) held += world.is_valid(q, *context);
    world.detach(target.world_T_object);
  }
  EXPECT_GT(held, 0);
}

}  // namespace
}  // namespace cluttertamp::scenes
