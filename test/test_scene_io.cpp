#include <fstream>

#include <gtest/gtest.h>

#include "cluttertamp/io/problem_io.hpp"

#include "cluttertamp/core/world_state.hpp"
#include "cluttertamp/io/scene_io.hpp"
#include "test_support.hpp"

namespace cluttertamp {
namespace {

using test::data;
using test::expect_input_error;
using test::has_error;

Diagnostics scene_errors(const std::string& name) {
  return expect_input_error([&] { io::load_scene(data("scenes/" + name)); });
}

TEST(SceneIo, LoadsAGoodSceneWithEveryPart) {
  const Scene scene = io::load_scene(data("scenes/good.yaml"));
  ASSERT_EQ(scene.objects.size(), 4u);
  EXPECT_EQ(scene.objects[scene.target].id, "a");
  EXPECT_EQ(scene.fixed.size(), 1u);
  ASSERT_EQ(scene.regions.size(), 1u);
  EXPECT_EQ(scene.regions[0].id, "buffer");
  const SceneObject& lid = scene.objects[*scene.find_object("lid")];
  EXPECT_EQ(lid.supports, (std::vector<ObjectIndex>{1, 2}));
  EXPECT_TRUE(std::holds_alternative<Box>(lid.shape));
  EXPECT_DOUBLE_EQ(lid.friction, 0.5);  // documented default
  EXPECT_TRUE(lid.movable);             // documented default
  EXPECT_FALSE(scene.world_T_camera.has_value());
  EXPECT_TRUE(scene.world_T_exit.translation().isApprox(Eigen::Vector3d(0.3, 0, 0.5)));
  const WorldState state = WorldState::initial(scene);
  EXPECT_EQ(state.world_T_objects.size(), 4u);
  EXPECT_FALSE(state.held.has_value());
}

TEST(SceneIo, DefaultShelfSceneIsValid) {
  const Scene scene = io::load_scene(std::filesystem::path(CLUTTERTAMP_SOURCE_DIR) / "problems/scenes/shelf12.yaml");
  EXPECT_EQ(scene.objects.size(), 12u);
  EXPECT_TRUE(scene.world_T_camera.has_value());
  // The camera's optical axis (+z) looks forward (+x) and down.
  const Eigen::Vector3d view = scene.world_T_camera->linear().col(2);
  EXPECT_GT(view.x(), 0.8);
  EXPECT_LT(view.z(), -0.4);
}

TEST(SceneIo, UnknownKey) {
  EXPECT_TRUE(has_error(scene_errors("bad_unknown_key.yaml"), 6, 107, "unknown key 'colour'"));
}

TEST(SceneIo, WrongType) {
  EXPECT_TRUE(has_error(scene_errors("bad_wrong_type.yaml"), 6, 88, "mass must be a finite number, not 'heavy'"));
}

TEST(SceneIo, NonPositiveSizes) {
  const Diagnostics d = scene_errors("bad_nonpositive_size.yaml");
  EXPECT_TRUE(has_error(d, 6, 32, "cylinder radius must be positive"));
  EXPECT_TRUE(has_error(d, 7, 25, "box size must be positive"));
}

TEST(SceneIo, InterpenetratingObjects) {
  EXPECT_TRUE(has_error(scene_errors("bad_interpenetrating.yaml"), 7, 5,
                        "object 'b' interpenetrates object 'a' (by 30.0 mm)"));
}

TEST(SceneIo, TouchingObjectsAreNotInterpenetrating) {
  // good.yaml stacks a lid exactly on two cylinders and stands them on the floor.
  EXPECT_NO_THROW(io::load_scene(data("scenes/good.yaml")));
}

TEST(SceneIo, ObjectOutsideWorkspace) {
  EXPECT_TRUE(has_error(scene_errors("bad_outside_workspace.yaml"), 6, 5, "outside the workspace"));
}

TEST(SceneIo, MissingTarget) {
  EXPECT_TRUE(has_error(scene_errors("bad_missing_target.yaml"), 6, 3, "no object is marked 'target: true'"));
}

TEST(SceneIo, DuplicateTarget) {
  EXPECT_TRUE(has_error(scene_errors("bad_duplicate_target.yaml"), 7, 5, "second target"));
}

TEST(SceneIo, UnknownNameInOn) {
  EXPECT_TRUE(has_error(scene_errors("bad_unknown_on.yaml"), 7, 101, "'ghost', which is not declared"));
}

TEST(SceneIo, StackedObjectNotResting) {
  EXPECT_TRUE(has_error(scene_errors("bad_not_resting.yaml"), 7, 5,
                        "does not rest on object 'a': its bottom is 50.0 mm above"));
}

TEST(SceneIo, DuplicateId) {
  EXPECT_TRUE(has_error(scene_errors("bad_duplicate_id.yaml"), 7, 10, "duplicate id 'a'"));
}

TEST(SceneIo, YamlSyntaxError) {
  EXPECT_TRUE(has_error(scene_errors("bad_syntax.yaml"), 7, 1, "YAML syntax error"));
}

TEST(SceneIo, UnsupportedVersion) {
  EXPECT_TRUE(has_error(scene_errors("bad_version.yaml"), 1, 10, "unsupported scene format version 7"));
}

TEST(SceneIo, MissingFile) {
  const Diagnostics d = scene_errors("no_such_scene.yaml");
  ASSERT_EQ(d.size(), 1u);
  EXPECT_EQ(d.items()[0].message, "no such file");
}

TEST(SceneIo, ReportsEveryProblemAtOnce) {
  const Diagnostics d = scene_errors("bad_many.yaml");
  EXPECT_EQ(d.size(), 6u) << d.str();
  EXPECT_TRUE(has_error(d, 1, 1, "missing the required key 'robot_base'"));
  EXPECT_TRUE(has_error(d, 3, 35, "exit rpy must be a list of 3 numbers"));
  EXPECT_TRUE(has_error(d, 6, 89, "mass must be positive"));
  EXPECT_TRUE(has_error(d, 6, 5, "interpenetrates"));
  EXPECT_TRUE(has_error(d, 7, 13, "unknown key 'cone'"));
  EXPECT_TRUE(has_error(d, 7, 5, "needs a shape"));
}

}  // namespace
}  // namespace cluttertamp

namespace cluttertamp {
namespace {

TEST(SceneIo, EmptyFile) {
  const Diagnostics d = test::expect_input_error([] { io::load_scene(test::data("scenes/bad_empty.yaml")); });
  ASSERT_EQ(d.size(), 1u);
  EXPECT_TRUE(test::has_error(d, 1, 1, "the scene file is empty"));
}

}  // namespace
}  // namespace cluttertamp

namespace cluttertamp {
namespace {

Diagnostics scene_errors2(const std::string& name) {
  return test::expect_input_error([&] { io::load_scene(test::data("scenes/" + name)); });
}

TEST(SceneIo, ObjectInterpenetratingAFixedBody) {
  EXPECT_TRUE(test::has_error(scene_errors2("bad_fixed_overlap.yaml"), 8, 5,
                              "object 'a' interpenetrates fixed body 'wall' (by 30.0 mm)"));
}

TEST(SceneIo, ExitAndRegionOutsideTheWorkspace) {
  const Diagnostics d = scene_errors2("bad_outside.yaml");
  EXPECT_TRUE(test::has_error(d, 4, 7, "exit pose x_s lies outside the workspace"));
  EXPECT_TRUE(test::has_error(d, 6, 5, "region 'buffer' lies (partly) outside the workspace"));
}

TEST(SceneIo, FixedTarget) {
  EXPECT_TRUE(test::has_error(scene_errors2("bad_fixed_target.yaml"), 6, 5, "the target 'a' must be movable"));
}

TEST(SceneIo, DuplicateKey) {
  EXPECT_TRUE(test::has_error(scene_errors2("bad_duplicate_key.yaml"), 6, 93, "duplicate key 'mass'"));
}

TEST(SceneIo, LyingCylinderOnTheFloorIsInsideTheWorkspace) {
  // Rotated by a rounded pi/2, its bounds poke past the floor by less than the 1 mm tolerance.
  const Scene scene = io::load_scene(test::data("scenes/good_lying_cylinder.yaml"));
  EXPECT_EQ(scene.objects.size(), 2u);
}

// Malformed, hostile or absurd files: every one is either valid or an InputError;
// nothing crashes, hangs or escapes as another exception.
TEST(SceneIo, NastyFilesNeverCrash) {
  std::vector<std::filesystem::path> files;
  for (const auto& entry : std::filesystem::directory_iterator(test::data("nasty"))) files.push_back(entry.path());
  ASSERT_GE(files.size(), 15u);
  // Generated: nesting far deeper than any real file.
  const auto deep = std::filesystem::temp_directory_path() / "cluttertamp_deep.yaml";
  std::ofstream(deep) << "version: 1\nobjects: " << std::string(20000, '[') << std::string(20000, ']') << "\n";
  files.push_back(deep);
  files.push_back(test::data("."));  // a directory
  for (const auto& file : files) {
    try {
      if (io::detect_file_kind(file) == io::FileKind::problem) {
        io::load_problem(file);
      } else {
        io::load_scene(file);
      }
    } catch (const InputError& e) {
      EXPECT_FALSE(e.diagnostics().empty()) << file;
    } catch (const std::exception& e) {
      ADD_FAILURE() << file << ": " << e.what();
    }
  }
  std::filesystem::remove(deep);
}

}  // namespace
}  // namespace cluttertamp
