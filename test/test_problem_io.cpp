#include <gtest/gtest.h>

#include "cluttertamp/io/problem_io.hpp"
#include "test_support.hpp"

namespace cluttertamp {
namespace {

using test::data;
using test::expect_input_error;
using test::has_error;

TEST(ProblemIo, LoadsAGoodProblem) {
  const Problem p = io::load_problem(data("problems/good.yaml"));
  EXPECT_EQ(p.name, "good");
  EXPECT_EQ(std::get<RetrievalTask>(p.task).target, "a");
  EXPECT_EQ(p.planner.name, "test_planner");
  EXPECT_EQ(p.planner.parameters.get_string("outcome", ""), "solve");
  EXPECT_DOUBLE_EQ(p.time_limit, 5.0);
  EXPECT_EQ(p.seed, 3u);
  EXPECT_EQ(p.scene.objects.size(), 4u);
  EXPECT_TRUE(p.robot.urdf.is_absolute());
  EXPECT_TRUE(std::filesystem::exists(p.robot.urdf));
}

TEST(ProblemIo, DefaultProblemIsValid) {
  const Problem p = io::load_problem(std::filesystem::path(CLUTTERTAMP_SOURCE_DIR) / "problems/default.yaml");
  EXPECT_EQ(std::get<RetrievalTask>(p.task).target, "target");
  EXPECT_EQ(p.planner.name, "retrieval_graph");
}

TEST(ProblemIo, ReportsEveryProblemAtOnce) {
  const Diagnostics d = expect_input_error([] { io::load_problem(data("problems/bad_problem.yaml")); });
  EXPECT_EQ(d.size(), 5u) << d.str();
  EXPECT_TRUE(has_error(d, 3, 32, "robot urdf 'missing.urdf' does not exist"));
  EXPECT_TRUE(has_error(d, 4, 18, "retrieve names 'b' but the scene's target is 'a'"));
  EXPECT_TRUE(has_error(d, 7, 15, "time_limit must be positive"));
  EXPECT_TRUE(has_error(d, 8, 3, "unknown key 'speed' in planner"));
  EXPECT_TRUE(has_error(d, 10, 11, "plugin path 'no/such/dir' is not a directory"));
}

TEST(ProblemIo, TaskMustBeRetrieveOrPddl) {
  const Diagnostics d = expect_input_error([] { io::load_problem(data("problems/bad_task.yaml")); });
  EXPECT_TRUE(has_error(d, 4, 7, "both 'retrieve' and 'pddl'"));
}

TEST(ProblemIo, SceneErrorsAreReportedWithTheScenesLocation) {
  const Diagnostics d = expect_input_error([] { io::load_problem(data("problems/bad_scene_inside.yaml")); });
  ASSERT_EQ(d.size(), 1u);
  EXPECT_NE(d.items()[0].location.file.find("bad_interpenetrating.yaml"), std::string::npos);
  EXPECT_EQ(d.items()[0].location.line, 7u);
}

TEST(ProblemIo, DetectsFileKind) {
  EXPECT_EQ(io::detect_file_kind(data("problems/good.yaml")), io::FileKind::problem);
  EXPECT_EQ(io::detect_file_kind(data("scenes/good.yaml")), io::FileKind::scene);
}

}  // namespace
}  // namespace cluttertamp
