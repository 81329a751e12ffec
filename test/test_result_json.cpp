#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cluttertamp/io/problem_io.hpp"
#include "cluttertamp/io/result_json.hpp"
#include "test_support.hpp"

namespace cluttertamp {
namespace {

TEST(ResultJson, WritesTheDocumentedSchema) {
  const Problem problem = io::load_problem(test::data("problems/good.yaml"));
  Result result;
  result.solved = true;
  PlanStep step;
  step.action = "pick";
  step.objects = {1};
  step.values["grasp"] = {0.1, 0.2, 0.3};
  step.trajectory = Trajectory{{"j1", "j2"}, {0.0, 0.5}, {Eigen::Vector2d(0, 0), Eigen::Vector2d(1, 2)}};
  result.plan.push_back(step);
  result.moved_objects = {1};
  result.time = {0.25, 0.5, 0.8};
  result.counters["motion_planning_calls"] = 3;
  result.failures.push_back({"grasp", "blocked", {2}});

  const auto json = nlohmann::json::parse(io::result_to_json(problem, result, {"test_planner", 5.0, 3, 0}));
  EXPECT_EQ(json["schema"], io::kResultSchema);
  EXPECT_EQ(json["solved"], true);
  EXPECT_TRUE(json["reason"].is_null());
  EXPECT_EQ(json["task"]["type"], "retrieve");
  EXPECT_EQ(json["planner"], "test_planner");
  EXPECT_EQ(json["seed"], 3);
  EXPECT_EQ(json["plan"][0]["action"], "pick");
  EXPECT_EQ(json["plan"][0]["objects"][0], "b");  // indices become the scene's ids
  EXPECT_EQ(json["plan"][0]["values"]["grasp"][2], 0.3);
  EXPECT_EQ(json["plan"][0]["trajectory"]["positions"][1][1], 2.0);
  EXPECT_EQ(json["moved_objects"][0], "b");
  EXPECT_EQ(json["time"]["motion_planning"], 0.5);
  EXPECT_EQ(json["counters"]["motion_planning_calls"], 3);
  EXPECT_EQ(json["counters"]["samples"], 0);  // standard counters are always present
  EXPECT_EQ(json["failures"][0]["blocking_objects"][0], "c");
}

}  // namespace
}  // namespace cluttertamp
