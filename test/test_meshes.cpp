// Robot meshes: STL, OBJ and COLLADA files of our own making read with their transforms
// and units, package:// and other URIs resolved (and every directory searched named
// when not), convex hulls, meshed links colliding as the primitives they model, and
// MoveIt SRDF files' disabled pairs.
#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <random>
#include <sstream>

#include <gtest/gtest.h>

#include "cluttertamp/collision/collision_world.hpp"
#include "cluttertamp/io/robot_description_io.hpp"
#include "cluttertamp/io/srdf.hpp"
#include "cluttertamp/robot/mesh.hpp"
#include "cluttertamp/robot/robot_model.hpp"
#include "test_support.hpp"

namespace cluttertamp::robot {
namespace {

namespace fs = std::filesystem;

// A box centred at the origin, 12 outward triangles.
TriangleMesh box_mesh(const Eigen::Vector3d& size) {
  TriangleMesh m;
  for (int i = 0; i < 8; ++i) {
    m.vertices.emplace_back((i & 1 ? 0.5 : -0.5) * size.x(), (i & 2 ? 0.5 : -0.5) * size.y(), (i & 4 ? 0.5 : -0.5) * size.z());
  }
  m.triangles = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                 {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  return m;
}

void write(const fs::path& file, const std::string& text) {
  fs::create_directories(file.parent_path());
  std::ofstream(file) << text;
}

// A fresh directory per test, removed afterwards.
class TestDirectory : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("cluttertamp_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->test_suite_name()) +
                                        "_" + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  fs::path dir_;
};

class MeshFiles : public TestDirectory {
 protected:

  void expect_bounds(const TriangleMesh& m, const Eigen::Vector3d& min, const Eigen::Vector3d& max) {
    Eigen::Vector3d lo, hi;
    m.bounds(lo, hi);
    // assimp reads single precision
    EXPECT_LT((lo - min).cwiseAbs().maxCoeff(), 1e-6) << lo.transpose() << " vs " << min.transpose();
    EXPECT_LT((hi - max).cwiseAbs().maxCoeff(), 1e-6) << hi.transpose() << " vs " << max.transpose();
  }
};

TEST_F(MeshFiles, AsciiStlRoundTripsAndScales) {
  write(dir_ / "box.stl", to_ascii_stl(box_mesh({0.1, 0.2, 0.3}), "box"));
  const TriangleMesh m = load_mesh(dir_ / "box.stl", {2.0, 1.0, 0.5}, {});
  EXPECT_EQ(m.triangles.size(), 12u);
  expect_bounds(m, {-0.1, -0.1, -0.075}, {0.1, 0.1, 0.075});
}

TEST_F(MeshFiles, ObjFacesAreTriangulated) {
  // A unit square split into two triangles by the reader, lifted by 0.5.
  write(dir_ / "quad.obj", "v 0 0 0.5\nv 1 0 0.5\nv 1 1 0.5\nv 0 1 0.5\nf 1 2 3 4\n");
  const TriangleMesh m = load_mesh(dir_ / "quad.obj", Eigen::Vector3d::Ones(), {});
  EXPECT_EQ(m.triangles.size(), 2u);
  expect_bounds(m, {0, 0, 0.5}, {1, 1, 0.5});
}

// One triangle in centimetres, placed by a node matrix (a 90 degree turn about z and a
// shift of 100 cm along x), declared Z_UP: the unit applies, the up axis does not.
TEST_F(MeshFiles, ColladaNodeTransformAndUnitApplyUpAxisDoesNot) {
  write(dir_ / "tri.dae", R"(<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><unit name="centimeter" meter="0.01"/><up_axis>Z_UP</up_axis></asset>
  <library_geometries>
    <geometry id="tri" name="tri"><mesh>
      <source id="tri-pos"><float_array id="tri-pos-array" count="9">0 0 0 10 0 0 0 20 5</float_array>
        <technique_common><accessor source="#tri-pos-array" count="3" stride="3">
          <param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/>
        </accessor></technique_common></source>
      <vertices id="tri-vtx"><input semantic="POSITION" source="#tri-pos"/></vertices>
      <triangles count="1"><input semantic="VERTEX" source="#tri-vtx" offset="0"/><p>0 1 2</p></triangles>
    </mesh></geometry>
  </library_geometries>
  <library_visual_scenes><visual_scene id="scene">
    <node id="n"><matrix>0 -1 0 100  1 0 0 0  0 0 1 0  0 0 0 1</matrix><instance_geometry url="#tri"/></node>
  </visual_scene></library_visual_scenes>
  <scene><instance_visual_scene url="#scene"/></scene>
</COLLADA>
)");
  const TriangleMesh m = load_mesh(dir_ / "tri.dae", Eigen::Vector3d::Ones(), {});
  ASSERT_EQ(m.triangles.size(), 1u);
  // (x, y, z) cm -> (1 - 0.01 y, 0.01 x, 0.01 z) m
  expect_bounds(m, {0.8, 0.0, 0.0}, {1.0, 0.1, 0.05});
}

TEST_F(MeshFiles, UnreadableAndEmptyMeshesAreLocatedErrors) {
  write(dir_ / "junk.stl", "this is not a mesh\n");
  const SourceLocation where{"robot.urdf", 7, 19};
  auto d = test::expect_input_error([&] { load_mesh(dir_ / "junk.stl", Eigen::Vector3d::Ones(), where); });
  EXPECT_TRUE(test::has_error(d, 7, 19, "cannot read mesh")) << d.str();
  TriangleMesh flat;
  flat.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}};
  flat.triangles = {{0, 1, 2}, {1, 3, 2}};
  d = test::expect_input_error([&] { convex_hull(flat, where); });
  EXPECT_TRUE(test::has_error(d, 7, 19, "no convex hull")) << d.str();
  flat.vertices.pop_back();  // three points: qhull is not even started
  flat.triangles.pop_back();
  d = test::expect_input_error([&] { convex_hull(flat, where); });
  EXPECT_TRUE(test::has_error(d, 7, 19, "fewer than 4 vertices")) << d.str();
}

TEST_F(MeshFiles, ConvexHullOfPointsInsideABoxIsTheBox) {
  TriangleMesh cloud = box_mesh({0.4, 0.2, 0.1});
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-0.04, 0.04);
  for (int i = 0; i < 200; ++i) cloud.vertices.emplace_back(u(rng), u(rng), u(rng));  // interior points
  const TriangleMesh hull = convex_hull(cloud, {});
  EXPECT_EQ(hull.vertices.size(), 8u);
  EXPECT_EQ(hull.triangles.size(), 12u);
  for (const auto& t : hull.triangles) {  // outward: the centre is behind every face
    const Eigen::Vector3d& a = hull.vertices[t[0]];
    const Eigen::Vector3d n = (hull.vertices[t[1]] - a).cross(hull.vertices[t[2]] - a);
    EXPECT_LT(n.dot(-a), 0.0);
  }
}

// A dumbbell: a 0.5 m bar (0.06 m square) between two 0.1 x 0.2 x 0.2 m blocks, along x,
// three closed boxes in one mesh. Its hull is a 0.7 x 0.2 x 0.2 m box, three times its volume.
TriangleMesh dumbbell() {
  TriangleMesh m;
  auto add = [&m](const Eigen::Vector3d& size, double x) {
    TriangleMesh b = box_mesh(size);
    const auto base = static_cast<std::uint32_t>(m.vertices.size());
    for (const Eigen::Vector3d& v : b.vertices) m.vertices.push_back(v + Eigen::Vector3d(x, 0, 0));
    for (const auto& t : b.triangles) m.triangles.push_back({base + t[0], base + t[1], base + t[2]});
  };
  add({0.5, 0.06, 0.06}, 0.0);
  add({0.1, 0.2, 0.2}, -0.3);
  add({0.1, 0.2, 0.2}, 0.3);
  return m;
}

bool in_convex(const TriangleMesh& hull, const Eigen::Vector3d& p) {
  for (const auto& t : hull.triangles) {
    const Eigen::Vector3d& a = hull.vertices[t[0]];
    const Eigen::Vector3d n = (hull.vertices[t[1]] - a).cross(hull.vertices[t[2]] - a).normalized();
    if (n.dot(p - a) > 1e-9) return false;
  }
  return true;
}

TEST_F(MeshFiles, ConvexPiecesHugADumbbellAndStillCoverAllOfIt) {
  const TriangleMesh mesh = dumbbell();
  const double hull_volume = enclosed_volume(convex_hull(mesh, {}));
  EXPECT_NEAR(hull_volume, 0.7 * 0.2 * 0.2, 1e-9);
  const std::vector<TriangleMesh> pieces = convex_pieces(mesh, {});
  ASSERT_GE(pieces.size(), 3u);
  ASSERT_LE(pieces.size(), 6u);
  double volume = 0;
  for (const TriangleMesh& piece : pieces) volume += enclosed_volume(piece);
  // The solid is 0.0098 m^3: the pieces hold little more, the hull nearly three times it.
  EXPECT_LT(volume, 0.5 * hull_volume);
  EXPECT_GE(volume, 0.0098 - 1e-9);
  auto covered = [&](const Eigen::Vector3d& p) {
    return std::any_of(pieces.begin(), pieces.end(), [&](const TriangleMesh& piece) { return in_convex(piece, p); });
  };
  for (const Eigen::Vector3d& v : mesh.vertices) EXPECT_TRUE(covered(v)) << v.transpose();
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int i = 0; i < 2000; ++i) {  // points of the solid: the bar and the blocks
    const Eigen::Vector3d bar(0.25 * u(rng), 0.03 * u(rng), 0.03 * u(rng));
    const Eigen::Vector3d block((i % 2 ? 0.3 : -0.3) + 0.05 * u(rng), 0.1 * u(rng), 0.1 * u(rng));
    EXPECT_TRUE(covered(bar)) << bar.transpose();
    EXPECT_TRUE(covered(block)) << block.transpose();
  }
  EXPECT_FALSE(covered({0.0, 0.08, 0.0}));  // beside the bar: in the hull, not in the dumbbell

  // The same pieces every time; a convex mesh is its own one piece.
  const std::vector<TriangleMesh> again = convex_pieces(mesh, {});
  ASSERT_EQ(again.size(), pieces.size());
  for (std::size_t i = 0; i < pieces.size(); ++i) EXPECT_EQ(again[i].vertices, pieces[i].vertices);
  const std::vector<TriangleMesh> box = convex_pieces(box_mesh({0.1, 0.2, 0.3}), {});
  ASSERT_EQ(box.size(), 1u);
  EXPECT_NEAR(enclosed_volume(box[0]), 0.006, 1e-12);
}

std::string arm_urdf(const std::string& geometry);

// A box whose faces are each split into n x n squares (2 n^2 triangles per face).
TriangleMesh fine_box(int n) {
  TriangleMesh m;
  for (int axis = 0; axis < 3; ++axis) {
    for (const double side : {-0.5, 0.5}) {
      const auto base = static_cast<std::uint32_t>(m.vertices.size());
      for (int i = 0; i <= n; ++i) {
        for (int j = 0; j <= n; ++j) {
          Eigen::Vector3d v;
          v[axis] = side;
          v[(axis + 1) % 3] = -0.5 + double(i) / n;
          v[(axis + 2) % 3] = -0.5 + double(j) / n;
          m.vertices.push_back(v);
        }
      }
      for (int i = 0; i < n; ++i) {
        for (int j = 0; j < n; ++j) {
          const std::uint32_t a = base + static_cast<std::uint32_t>(i * (n + 1) + j), b = a + 1, c = a + static_cast<std::uint32_t>(n + 1), d = c + 1;
          m.triangles.push_back({a, c, b});
          m.triangles.push_back({b, c, d});
        }
      }
    }
  }
  return m;
}

TEST_F(MeshFiles, SimplifiedMeshesFitTheBudgetAndKeepTheirExtent) {
  const TriangleMesh fine = fine_box(40);  // 19200 triangles
  ASSERT_EQ(fine.triangles.size(), 19200u);
  EXPECT_EQ(simplified(fine, 20000).triangles.size(), 19200u);  // fits: unchanged
  const TriangleMesh coarse = simplified(fine, 2000);
  EXPECT_LE(coarse.triangles.size(), 2000u);
  EXPECT_GT(coarse.triangles.size(), 100u);
  Eigen::Vector3d lo, hi;
  coarse.bounds(lo, hi);
  EXPECT_LT((lo - Eigen::Vector3d::Constant(-0.5)).cwiseAbs().maxCoeff(), 0.05);
  EXPECT_LT((hi - Eigen::Vector3d::Constant(0.5)).cwiseAbs().maxCoeff(), 0.05);
  const TriangleMesh again = simplified(fine, 2000);
  EXPECT_EQ(again.triangles, coarse.triangles);  // deterministic
}

TEST_F(MeshFiles, VisualMeshesAreFoundAtLoadAndReadWhenDrawn) {
  write(dir_ / "meshes/look.stl", to_ascii_stl(box_mesh({0.1, 0.2, 0.3}), "look"));
  std::string urdf = arm_urdf(R"(<box size="0.1 0.2 0.3"/>)");
  const std::string visual = R"(<visual><origin xyz="0 0 0.1"/><geometry><mesh filename="meshes/look.stl" scale="2 2 2"/></geometry></visual>
    <visual><geometry><sphere radius="0.05"/></geometry></visual>
    <collision>)";
  urdf.replace(urdf.find("<collision>"), std::string("<collision>").size(), visual);
  write(dir_ / "look.urdf", urdf);
  const RobotModel model = RobotModel::load_urdf(dir_ / "look.urdf", UrdfOptions{});
  const Link& link = model.links()[*model.find_link("arm")];
  ASSERT_EQ(link.visual.size(), 2u);
  EXPECT_TRUE(fs::equivalent(link.visual[0].mesh_file, dir_ / "meshes/look.stl"));
  EXPECT_EQ(link.visual[0].mesh_scale, Eigen::Vector3d(2, 2, 2));
  EXPECT_NEAR(link.visual[0].link_T_visual.translation().z(), 0.1, 1e-12);
  ASSERT_TRUE(link.visual[1].primitive.has_value());
  EXPECT_EQ(std::get<Sphere>(*link.visual[1].primitive).radius, 0.05);

  fs::remove(dir_ / "meshes/look.stl");
  const Diagnostics d = test::expect_input_error([&] { RobotModel::load_urdf(dir_ / "look.urdf", UrdfOptions{}); });
  EXPECT_TRUE(test::has_error(d, 5, 52, "mesh 'meshes/look.stl' not found")) << d.str();
}

TEST_F(MeshFiles, PackageUrisAreFoundEveryWayRosUsersWriteThem) {
  write(dir_ / "ws/src/arm_description/meshes/link.stl", to_ascii_stl(box_mesh({0.1, 0.1, 0.1}), "link"));
  const fs::path expected = dir_ / "ws/src/arm_description/meshes/link.stl";
  const std::string uri = "package://arm_description/meshes/link.stl";
  for (const fs::path& root : {dir_ / "ws/src", dir_ / "ws", dir_ / "ws/src/arm_description"}) {
    EXPECT_TRUE(fs::equivalent(resolve_mesh_uri(uri, "/nowhere", PackagePaths{{dir_ / "empty", root}}, {}), expected)) << root;
  }
  EXPECT_TRUE(fs::equivalent(resolve_mesh_uri("file://" + expected.string(), "/nowhere", {}, {}), expected));
  EXPECT_TRUE(fs::equivalent(resolve_mesh_uri("meshes/link.stl", dir_ / "ws/src/arm_description", {}, {}), expected));
  ::setenv("ROS_PACKAGE_PATH", ("/nonexistent:" + (dir_ / "ws/src").string()).c_str(), 1);
  const PackagePaths from_environment = PackagePaths::with_environment({});
  ::unsetenv("ROS_PACKAGE_PATH");
  EXPECT_TRUE(fs::equivalent(resolve_mesh_uri(uri, "/nowhere", from_environment, {}), expected));

  // Missing: the error names the URI and every directory looked in.
  const SourceLocation where{"arm.urdf", 12, 27};
  auto d = test::expect_input_error(
      [&] { resolve_mesh_uri("package://arm_description/meshes/gone.stl", "/nowhere", PackagePaths{{dir_ / "ws"}}, where); });
  EXPECT_TRUE(test::has_error(d, 12, 27, "mesh 'package://arm_description/meshes/gone.stl' not found")) << d.str();
  EXPECT_NE(d.str().find((dir_ / "ws/src/arm_description").string()), std::string::npos) << d.str();
  EXPECT_NE(d.str().find((dir_ / "ws/arm_description").string()), std::string::npos) << d.str();
  d = test::expect_input_error([&] { resolve_mesh_uri(uri, "/nowhere", PackagePaths{}, where); });
  EXPECT_TRUE(test::has_error(d, 12, 27, "no package path")) << d.str();
  d = test::expect_input_error([&] { resolve_mesh_uri("http://example.com/x.stl", "/nowhere", {}, where); });
  EXPECT_TRUE(test::has_error(d, 12, 27, "scheme")) << d.str();
}

// A one-joint arm whose link is a 0.1 x 0.2 x 0.3 m box, written as a mesh or a primitive.
std::string arm_urdf(const std::string& geometry) {
  return R"(<?xml version="1.0"?>
<robot name="boxarm">
  <link name="base"/>
  <link name="arm">
    <collision><origin xyz="0.3 0 0.2" rpy="0 0 0.3"/>
      <geometry>)" + geometry + R"(</geometry></collision>
  </link>
  <link name="tool"/>
  <joint name="j1" type="revolute">
    <parent link="base"/><child link="arm"/>
    <axis xyz="0 0 1"/><limit lower="-3" upper="3" velocity="1" effort="1"/>
  </joint>
  <joint name="tool_joint" type="fixed"><parent link="arm"/><child link="tool"/><origin xyz="0.5 0 0"/></joint>
</robot>
)";
}

std::shared_ptr<const RobotDescription> arm(const fs::path& dir, const std::string& name, const std::string& geometry,
                                             const std::string& extra = "") {
  write(dir / (name + ".urdf"), arm_urdf(geometry));
  write(dir / (name + ".yaml"), "version: 1\nurdf: " + name + ".urdf\nbase_link: base\ntip_link: tool\nik: numeric\n"
                                "gripper: {finger_thickness: 0.01, base_half_length: 0.05, stroke: 0.08}\n" + extra);
  return std::make_shared<const RobotDescription>(io::load_robot_description(dir / (name + ".yaml")));
}

// Whether the robot at q is clear of a ball of radius r (m) at world_p_ball.
bool valid_beside_ball(const std::shared_ptr<const RobotDescription>& robot, const Eigen::VectorXd& q, double r,
                       const Eigen::Vector3d& world_p_ball) {
  Scene scene;
  SceneObject ball;
  ball.id = "ball";
  ball.shape = Sphere{r};
  ball.world_T_object = Eigen::Translation3d(world_p_ball) * Eigen::Isometry3d::Identity();
  ball.mass = 0.1;
  scene.objects.push_back(ball);
  collision::CollisionWorld world(scene, robot);
  auto context = world.make_context();
  return world.is_valid(q, *context);
}

TEST_F(MeshFiles, AMeshedLinkCollidesAsThePrimitiveItModels) {
  write(dir_ / "pkg/boxarm/meshes/arm.stl", to_ascii_stl(box_mesh({1.0, 1.0, 1.0}), "arm"));
  const auto primitive = arm(dir_, "primitive", R"(<box size="0.1 0.2 0.3"/>)");
  const std::string mesh = R"(<mesh filename="package://boxarm/meshes/arm.stl" scale="0.1 0.2 0.3"/>)";
  const auto hull = arm(dir_, "hull", mesh, "package_paths: [pkg]\n");
  const auto triangles = arm(dir_, "triangles", mesh, "package_paths: [pkg]\nmesh_collision: triangles\n");
  ASSERT_TRUE(hull->model()->links()[*hull->model()->find_link("arm")].collision.at(0).convex);
  ASSERT_FALSE(triangles->model()->links()[*triangles->model()->find_link("arm")].collision.at(0).convex);

  std::mt19937 rng(5);
  std::uniform_real_distribution<double> offset(-1.0, 1.0), angle(-3.0, 3.0);
  const robot::LinkIndex link = *primitive->model()->find_link("arm");
  int collisions = 0, compared_triangles = 0;
  for (int i = 0; i < 400; ++i) {
    Eigen::VectorXd q(1);
    q << angle(rng);
    std::vector<Eigen::Isometry3d> poses;
    primitive->model()->link_poses(q, poses);
    const Eigen::Isometry3d world_T_box = poses[link] * primitive->model()->links()[link].collision[0].link_T_shape;
    // A ball of radius 0.04 m about the box (half sizes 0.05, 0.1, 0.15 m): within
    // 0.1 m of each face, so that it often touches.
    const Eigen::Vector3d p(0.15 * offset(rng), 0.2 * offset(rng), 0.25 * offset(rng));
    auto valid = [&](const std::shared_ptr<const RobotDescription>& robot) {
      return valid_beside_ball(robot, q, 0.04, world_T_box * p);
    };
    const bool expected = valid(primitive);
    collisions += !expected;
    EXPECT_EQ(valid(hull), expected) << "sample " << i;
    // The triangles are a surface: a ball wholly inside the box touches none of them.
    const bool inside = (p.cwiseAbs().array() + 0.04 < Eigen::Array3d(0.05, 0.1, 0.15)).all();
    if (!inside) {
      EXPECT_EQ(valid(triangles), expected) << "sample " << i;
      ++compared_triangles;
    }
  }
  EXPECT_GT(collisions, 100);  // the samples are not all clear
  EXPECT_LT(collisions, 300);  // nor all in collision
  EXPECT_GT(compared_triangles, 300);
}

// Beside the dumbbell's bar a ball touches its hull but not the dumbbell: convex pieces
// let it be, the hull does not; at a block both collide.
TEST_F(MeshFiles, ALinkOfConvexPiecesCollidesNearlyAsItsMesh) {
  write(dir_ / "meshes/dumbbell.stl", to_ascii_stl(dumbbell(), "dumbbell"));
  const std::string mesh = R"(<mesh filename="meshes/dumbbell.stl"/>)";
  const auto hull = arm(dir_, "hull", mesh, "mesh_collision: convex_hull\n");
  const auto pieces = arm(dir_, "pieces", mesh);  // the default
  const auto& links = pieces->model()->links();
  const auto& shapes = links[*pieces->model()->find_link("arm")].collision;
  ASSERT_GE(shapes.size(), 3u);
  for (const CollisionShape& c : shapes) EXPECT_TRUE(c.convex);
  EXPECT_EQ(hull->model()->links()[*hull->model()->find_link("arm")].collision.size(), 1u);

  const Eigen::VectorXd q = Eigen::VectorXd::Zero(1);
  std::vector<Eigen::Isometry3d> poses;
  pieces->model()->link_poses(q, poses);
  const Eigen::Isometry3d world_T_mesh = poses[*pieces->model()->find_link("arm")] * shapes[0].link_T_mesh;
  auto valid = [&](const std::shared_ptr<const RobotDescription>& robot, const Eigen::Vector3d& mesh_p_ball) {
    return valid_beside_ball(robot, q, 0.02, world_T_mesh * mesh_p_ball);
  };
  EXPECT_FALSE(valid(hull, {0.0, 0.07, 0.0}));
  EXPECT_TRUE(valid(pieces, {0.0, 0.07, 0.0}));
  EXPECT_FALSE(valid(pieces, {0.0, 0.045, 0.0}));  // touching the bar
  EXPECT_FALSE(valid(pieces, {0.3, 0.115, 0.0}));  // touching a block
  EXPECT_FALSE(valid(hull, {0.3, 0.115, 0.0}));
}

TEST_F(MeshFiles, AMissingMeshIsLocatedInTheUrdf) {
  write(dir_ / "gone.urdf", arm_urdf(R"(<mesh filename="package://boxarm/meshes/gone.stl"/>)"));
  UrdfOptions options{PackagePaths{{dir_}}};
  const Diagnostics d = test::expect_input_error([&] { RobotModel::load_urdf(dir_ / "gone.urdf", options); });
  // Line 6, column 23: where filename= stands.
  EXPECT_TRUE(test::has_error(d, 6, 23, "mesh 'package://boxarm/meshes/gone.stl' not found")) << d.str();
  EXPECT_NE(d.str().find((dir_ / "boxarm").string()), std::string::npos) << d.str();

  write(dir_ / "meshes/arm.stl", to_ascii_stl(box_mesh({1, 1, 1}), "arm"));
  write(dir_ / "flat.urdf", arm_urdf(R"(<mesh filename="meshes/arm.stl" scale="1 0 1"/>)"));
  const Diagnostics flat = test::expect_input_error([&] { RobotModel::load_urdf(dir_ / "flat.urdf", options); });
  EXPECT_TRUE(test::has_error(flat, 6, 17, "<mesh scale='1 0 1'> must be 3 finite numbers, none zero")) << flat.str();
}

TEST_F(MeshFiles, DescriptionMeshKeysAreChecked) {
  const Diagnostics d = test::expect_input_error(
      [&] { arm(dir_, "bad", R"(<box size="0.1 0.2 0.3"/>)", "mesh_collision: exact\npackage_paths: 3\n"); });
  EXPECT_TRUE(test::has_error(d, 7, 17, "mesh_collision must be 'convex_hull', 'convex_pieces' or 'triangles', not 'exact'")) << d.str();
  EXPECT_TRUE(test::has_error(d, 8, 16, "package_paths")) << d.str();
}

TEST_F(MeshFiles, AMissingUrdfAndAPackagePathThatIsNotThereAreLocatedInTheDescription) {
  fs::create_directories(dir_ / "pkg");
  const Diagnostics typo = test::expect_input_error(
      [&] { arm(dir_, "typo", R"(<box size="0.1 0.2 0.3"/>)", "package_paths: [pkg, pgk]\n"); });
  EXPECT_TRUE(test::has_error(typo, 7, 22, "package_paths: no such directory 'pgk'")) << typo.str();
  EXPECT_EQ(typo.items().size(), 1u) << typo.str();  // pkg is there

  write(dir_ / "lost.yaml", "version: 1\nurdf: elsewhere/lost.urdf\nbase_link: base\ntip_link: tool\nik: numeric\n"
                            "gripper: {finger_thickness: 0.01, base_half_length: 0.05, stroke: 0.08}\n");
  const Diagnostics lost = test::expect_input_error([&] { io::load_robot_description(dir_ / "lost.yaml"); });
  EXPECT_TRUE(test::has_error(lost, 2, 7, "urdf: no such file 'elsewhere/lost.urdf'")) << lost.str();
  EXPECT_NE(lost.str().find((dir_ / "elsewhere/lost.urdf").string()), std::string::npos) << lost.str();
}

}  // namespace
}  // namespace cluttertamp::robot

namespace cluttertamp::io {
namespace {

namespace fs = std::filesystem;

class SrdfFiles : public robot::TestDirectory {
 protected:
  void SetUp() override {
    TestDirectory::SetUp();
    panda_ = std::make_shared<const robot::RobotDescription>(
        load_robot_description(fs::path(CLUTTERTAMP_SOURCE_DIR) / "domains/robots/panda.yaml"));
  }
  robot::LinkIndex link(const std::string& name) const { return *panda_->model()->find_link(name); }

  std::shared_ptr<const robot::RobotDescription> panda_;
};

TEST_F(SrdfFiles, DisabledPairsRoundTrip) {
  const std::vector<DisabledPair> pairs{{link("panda_link0"), link("panda_link3"), "Never"}, {link("panda_hand"), link("panda_link7"), "Adjacent"}};
  std::ofstream(dir_ / "p.srdf") << srdf_text(*panda_->model(), pairs);
  const std::vector<DisabledPair> back = load_srdf_disabled_collisions(dir_ / "p.srdf", *panda_->model());
  ASSERT_EQ(back.size(), 2u);
  for (std::size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(back[i].first, pairs[i].first);
    EXPECT_EQ(back[i].second, pairs[i].second);
    EXPECT_EQ(back[i].reason, pairs[i].reason);
  }
}

TEST_F(SrdfFiles, ErrorsAreLocatedAndAllReported) {
  std::ofstream(dir_ / "bad.srdf") << R"(<?xml version="1.0"?>
<robot name="panda">
  <group name="arm"><joint name="panda_joint1"/></group>
  <disable_collisions link1="panda_link0" link2="panda_link99" reason="Never"/>
  <disable_collisions link1="panda_link1" reason="Never"/>
</robot>
)";
  Diagnostics d = test::expect_input_error([&] { load_srdf_disabled_collisions(dir_ / "bad.srdf", *panda_->model()); });
  EXPECT_TRUE(test::has_error(d, 4, 3, "names link 'panda_link99', which the URDF (robot 'panda') does not have")) << d.str();
  EXPECT_TRUE(test::has_error(d, 5, 3, "needs a link2 attribute")) << d.str();
  std::ofstream(dir_ / "broken.srdf") << "<robot name=\"x\">\n  <disable_collisions link1=\"a\"\n</robot>\n";
  d = test::expect_input_error([&] { load_srdf_disabled_collisions(dir_ / "broken.srdf", *panda_->model()); });
  ASSERT_EQ(d.size(), 1u);
  EXPECT_NE(d.items()[0].message.find("malformed SRDF"), std::string::npos) << d.str();
  EXPECT_GT(d.items()[0].location.line, 0u) << d.str();
  std::ofstream(dir_ / "root.srdf") << "<robotx/>\n";
  d = test::expect_input_error([&] { load_srdf_disabled_collisions(dir_ / "root.srdf", *panda_->model()); });
  EXPECT_TRUE(test::has_error(d, 1, 1, "root element must be <robot>")) << d.str();
}

// An SRDF of our own for the bundled Panda, in the layout MoveIt's setup assistant writes.
constexpr const char* kPandaSrdf = R"(<?xml version="1.0"?>
<robot name="panda">
  <group name="panda_arm">
    <joint name="panda_joint1"/><joint name="panda_joint2"/><joint name="panda_joint3"/><joint name="panda_joint4"/>
    <joint name="panda_joint5"/><joint name="panda_joint6"/><joint name="panda_joint7"/><joint name="panda_joint8"/>
  </group>
  <group name="panda_manipulator">
    <chain base_link="panda_link0" tip_link="panda_hand_tcp"/>
  </group>
  <group name="hand">
    <link name="panda_hand"/><link name="panda_leftfinger"/><link name="panda_rightfinger"/>
    <joint name="panda_finger_joint1"/><joint name="panda_finger_joint2"/>
  </group>
  <group name="arm_and_hand"><group name="panda_arm"/><group name="hand"/></group>
  <group name="manipulator"><group name="panda_manipulator"/></group>
  <group name="to_tcp">
    <joint name="panda_joint1"/><joint name="panda_joint2"/><joint name="panda_joint3"/><joint name="panda_joint4"/>
    <joint name="panda_joint5"/><joint name="panda_joint6"/><joint name="panda_joint7"/><joint name="panda_hand_tcp_joint"/>
  </group>
  <group_state name="ready" group="panda_arm">
    <joint name="panda_joint1" value="0"/><joint name="panda_joint2" value="-0.785"/><joint name="panda_joint3" value="0"/>
    <joint name="panda_joint4" value="-2.356"/><joint name="panda_joint5" value="0"/><joint name="panda_joint6" value="1.571"/>
    <joint name="panda_joint7" value="0.785"/>
  </group_state>
  <group_state name="open" group="hand">
    <joint name="panda_finger_joint1" value="0.04"/><joint name="panda_finger_joint2" value="0.04"/>
  </group_state>
  <end_effector name="hand" parent_link="panda_link8" group="hand" parent_group="panda_arm"/>
</robot>
)";

// The bundled panda.yaml with `edit` applied to its text, written beside an SRDF.
fs::path panda_variant(const fs::path& dir, const std::string& name, const std::string& srdf,
                       const std::vector<std::pair<std::string, std::string>>& edits) {
  std::ifstream in(fs::path(CLUTTERTAMP_SOURCE_DIR) / "domains/robots/panda.yaml");
  std::stringstream yaml;
  yaml << in.rdbuf();
  std::string text = yaml.str();
  text.replace(text.find("urdf: panda.urdf"), std::string("urdf: panda.urdf").size(),
               "urdf: " + (fs::path(CLUTTERTAMP_SOURCE_DIR) / "domains/robots/panda.urdf").string());
  for (const auto& [from, to] : edits) {
    const auto at = text.find(from);
    if (at == std::string::npos) ADD_FAILURE() << "no '" << from << "' in panda.yaml";
    else text.replace(at, from.size(), to);
  }
  std::ofstream(dir / (name + ".srdf")) << srdf;
  std::ofstream(dir / (name + ".yaml")) << text;
  return dir / (name + ".yaml");
}

// The home line of panda.yaml, whatever its comment.
std::string home_line() {
  std::ifstream in(fs::path(CLUTTERTAMP_SOURCE_DIR) / "domains/robots/panda.yaml");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("home:", 0) == 0) return line;
  }
  return "home:";
}

TEST_F(SrdfFiles, AGroupGivesTheChainAndGroupStatesTheHome) {
  const fs::path file = panda_variant(dir_, "g", kPandaSrdf,
                                      {{"base_link: panda_link0\n", ""},
                                       {"tip_link: panda_hand_tcp\n", "srdf: g.srdf\ngroup: panda_manipulator\n"},
                                       {home_line(), "home: [ready, open]"}});
  const robot::RobotDescription d = load_robot_description(file);
  EXPECT_EQ(d.base_link(), panda_->base_link());
  EXPECT_EQ(d.tip_link(), panda_->tip_link());
  EXPECT_TRUE(d.home().isApprox(panda_->home(), 1e-12)) << d.home().transpose() << " vs " << panda_->home().transpose();
  // The IK chain is the group's: the home's tool pose solves back to a configuration with that pose.
  EXPECT_EQ(d.ik().base(), d.base_link());
  EXPECT_EQ(d.ik().tip(), d.tip_link());
  const Eigen::Isometry3d base_T_tool = d.ik().forward(d.home());
  const auto solutions = d.ik().solve(base_T_tool, d.home());
  ASSERT_FALSE(solutions.empty());
  EXPECT_TRUE(d.ik().forward(solutions.front()).isApprox(base_T_tool, 1e-6));

  const Srdf srdf = load_srdf(dir_ / "g.srdf", *panda_->model());
  EXPECT_EQ(srdf.groups.size(), 6u);
  EXPECT_EQ(srdf.end_effectors.size(), 1u);
  // A group of joints is the chain they form; a fixed joint at its end counts, and so
  // do fixed joints it leaves out on the way (to_tcp skips two).
  EXPECT_EQ(srdf_chain(srdf, *srdf.find_group("panda_arm"), *panda_->model()),
            std::make_pair(link("panda_link0"), link("panda_link8")));
  EXPECT_EQ(srdf_chain(srdf, *srdf.find_group("to_tcp"), *panda_->model()),
            std::make_pair(link("panda_link0"), link("panda_hand_tcp")));
  // A group of one subgroup with a chain is that chain.
  EXPECT_EQ(srdf_chain(srdf, *srdf.find_group("manipulator"), *panda_->model()),
            std::make_pair(link("panda_link0"), link("panda_hand_tcp")));
  // base_link and tip_link override the group's ends.
  const robot::RobotDescription arm = load_robot_description(
      panda_variant(dir_, "h", kPandaSrdf, {{"base_link: panda_link0\n", "srdf: h.srdf\ngroup: panda_arm\n"}}));
  EXPECT_EQ(arm.base_link(), link("panda_link0"));
  EXPECT_EQ(arm.tip_link(), link("panda_hand_tcp"));
  // Both named: a group that is no chain is fine (only its name is checked).
  const robot::RobotDescription named = load_robot_description(
      panda_variant(dir_, "i", kPandaSrdf, {{"base_link: panda_link0\n", "base_link: panda_link0\nsrdf: i.srdf\ngroup: arm_and_hand\n"}}));
  EXPECT_EQ(named.tip_link(), link("panda_hand_tcp"));
}

// An SRDF describes more than a robot description uses: what is not used is not
// checked (MoveIt's virtual joints take several numbers; an end effector may lack a
// parent link), and what is used is checked when used.
TEST_F(SrdfFiles, WhatADescriptionDoesNotUseIsNotChecked) {
  std::string srdf = kPandaSrdf;
  srdf.replace(srdf.find("</robot>"), 8, R"(<virtual_joint name="world_joint" type="planar" parent_frame="world" child_link="panda_link0"/>
  <group name="base"><joint name="world_joint"/></group>
  <group_state name="origin" group="base"><joint name="world_joint" value="0 0 0"/></group_state>
  <end_effector name="loose" group="hand"/>
</robot>)");
  const robot::RobotDescription d = load_robot_description(
      panda_variant(dir_, "u", srdf, {{"tip_link: panda_hand_tcp", "tip_link: panda_hand_tcp\nsrdf: u.srdf"}, {home_line(), "home: [ready, open]"}}));
  EXPECT_TRUE(d.home().isApprox(panda_->home(), 1e-12));
  const Diagnostics e = test::expect_input_error([&] {
    load_robot_description(panda_variant(dir_, "w", srdf, {{"tip_link: panda_hand_tcp", "tip_link: panda_hand_tcp\nsrdf: w.srdf"}, {home_line(), "home: origin"}}));
  });
  EXPECT_TRUE(test::has_error(e, 31, 43, "group state 'origin' sets joint 'world_joint', which the URDF (robot 'panda') does not have")) << e.str();
}

TEST_F(SrdfFiles, GroupAndGroupStateErrorsAreLocated) {
  // Line 5 of panda.yaml is base_link, 6 tip_link, 13 home; the edits below keep that numbering.
  Diagnostics d = test::expect_input_error([&] {
    load_robot_description(panda_variant(dir_, "a", kPandaSrdf,
                                         {{"base_link: panda_link0", "group: panda_manipulatr"},
                                          {"tip_link: panda_hand_tcp", "srdf: a.srdf"},
                                          {home_line(), "home: [ready, opened]"}}));
  });
  EXPECT_TRUE(test::has_error(d, 5, 8, "has no group 'panda_manipulatr' (did you mean 'panda_manipulator'?); its groups: panda_arm, "))
      << d.str();
  EXPECT_TRUE(test::has_error(d, 13, 15, "has no group state 'opened' (did you mean 'open'?); its group states: ready, open")) << d.str();

  d = test::expect_input_error([&] {
    load_robot_description(panda_variant(dir_, "b", kPandaSrdf, {{"base_link: panda_link0", "group: hand"}, {"tip_link: panda_hand_tcp", "srdf: b.srdf"}}));
  });
  EXPECT_TRUE(test::has_error(d, 10, 3, "group 'hand' of ")) << d.str();
  EXPECT_TRUE(test::has_error(d, 10, 3, "is no single serial chain (joint 'panda_finger_joint2' is off the chain from joint "
                                        "'panda_finger_joint1' to joint 'panda_finger_joint1'); name base_link and tip_link instead"))
      << d.str();

  d = test::expect_input_error([&] {
    load_robot_description(panda_variant(dir_, "c", kPandaSrdf, {{"base_link: panda_link0", "group: panda_arm"}}));
  });
  EXPECT_TRUE(test::has_error(d, 5, 8, "group 'panda_arm' is a group of an SRDF: give the SRDF with srdf:")) << d.str();

  std::string bad = kPandaSrdf;
  bad.replace(bad.find(R"(<joint name="panda_joint4" value="-2.356"/>)"), std::string(R"(<joint name="panda_joint4" value="-2.356"/>)").size(),
              R"(<joint name="panda_joint44" value="-2.356"/>)");
  bad.replace(bad.find(R"(<joint name="panda_joint5" value="0"/>)"), std::string(R"(<joint name="panda_joint5" value="0"/>)").size(),
              R"(<joint name="panda_hand_joint" value="0"/>)");
  d = test::expect_input_error([&] {
    load_robot_description(panda_variant(dir_, "e", bad, {{"tip_link: panda_hand_tcp", "tip_link: panda_hand_tcp\nsrdf: e.srdf"}, {home_line(), "home: ready"}}));
  });
  EXPECT_TRUE(test::has_error(d, 22, 5, "group state 'ready' sets joint 'panda_joint44', which the URDF (robot 'panda') does not have")) << d.str();
  EXPECT_TRUE(test::has_error(d, 22, 49, "group state 'ready' sets joint 'panda_hand_joint', which is fixed")) << d.str();
  EXPECT_EQ(d.size(), 2u) << d.str();  // no consequent "outside the joint limits"

  bad = kPandaSrdf;
  bad.replace(bad.find(R"(value="0.785")"), std::string(R"(value="0.785")").size(), R"(value="0.785rad")");
  d = test::expect_input_error([&] {
    load_robot_description(panda_variant(dir_, "v", bad, {{"tip_link: panda_hand_tcp", "tip_link: panda_hand_tcp\nsrdf: v.srdf"}, {home_line(), "home: ready"}}));
  });
  EXPECT_TRUE(test::has_error(d, 23, 5, "group state 'ready' gives joint 'panda_joint7' the value '0.785rad', which is not one finite number"))
      << d.str();
  // A chain whose tip is not below its base.
  bad = kPandaSrdf;
  bad.replace(bad.find(R"(<chain base_link="panda_link0" tip_link="panda_hand_tcp"/>)"),
              std::string(R"(<chain base_link="panda_link0" tip_link="panda_hand_tcp"/>)").size(),
              R"(<chain base_link="panda_hand" tip_link="panda_link3"/>)");
  std::ofstream(dir_ / "up.srdf") << bad;
  const Srdf up = load_srdf(dir_ / "up.srdf", *panda_->model());
  d = test::expect_input_error([&] { srdf_chain(up, *up.find_group("panda_manipulator"), *panda_->model()); });
  EXPECT_TRUE(test::has_error(d, 7, 3, "tip link 'panda_link3' does not hang below base link 'panda_hand'")) << d.str();
  // Values and names mixed.
  d = test::expect_input_error([&] {
    load_robot_description(panda_variant(dir_, "m", kPandaSrdf, {{"tip_link: panda_hand_tcp", "tip_link: panda_hand_tcp\nsrdf: m.srdf"}, {home_line(), "home: [ready, 0.04]"}}));
  });
  EXPECT_TRUE(test::has_error(d, 14, 7, "home mixes joint values and group state names")) << d.str();
  // A group state without its group.
  bad = kPandaSrdf;
  bad.replace(bad.find(R"(<group_state name="ready" group="panda_arm">)"), std::string(R"(<group_state name="ready" group="panda_arm">)").size(),
              R"(<group_state name="ready">)");
  d = test::expect_input_error([&] {
    load_robot_description(panda_variant(dir_, "g", bad, {{"tip_link: panda_hand_tcp", "tip_link: panda_hand_tcp\nsrdf: g.srdf"}, {home_line(), "home: ready"}}));
  });
  EXPECT_TRUE(test::has_error(d, 20, 3, "group state 'ready' has no group attribute")) << d.str();
}

TEST_F(SrdfFiles, ADescriptionsSrdfIsMergedWithItsOwnPairs) {
  ASSERT_FALSE(std::binary_search(panda_->disabled_collisions().begin(), panda_->disabled_collisions().end(),
                                  std::pair{link("panda_link0"), link("panda_link3")}));
  std::ofstream(dir_ / "p.srdf") << srdf_text(*panda_->model(), {{link("panda_link3"), link("panda_link0"), "Never"}});
  std::ifstream in(fs::path(CLUTTERTAMP_SOURCE_DIR) / "domains/robots/panda.yaml");
  std::stringstream yaml;
  yaml << in.rdbuf();
  std::string text = yaml.str();
  text.replace(text.find("urdf: panda.urdf"), std::string("urdf: panda.urdf").size(),
               "urdf: " + (fs::path(CLUTTERTAMP_SOURCE_DIR) / "domains/robots/panda.urdf").string() + "\nsrdf: p.srdf");
  std::ofstream(dir_ / "panda.yaml") << text;
  const robot::RobotDescription merged = load_robot_description(dir_ / "panda.yaml");
  const auto& pairs = merged.disabled_collisions();
  EXPECT_TRUE(std::binary_search(pairs.begin(), pairs.end(), std::pair{link("panda_link0"), link("panda_link3")}));
  EXPECT_EQ(pairs.size(), panda_->disabled_collisions().size() + 1);
}

}  // namespace
}  // namespace cluttertamp::io
