#include <fstream>

#include <gtest/gtest.h>

#include "cluttertamp/io/problem_io.hpp"
#include "cluttertamp/io/sweep_file.hpp"
#include "cluttertamp/stream/stream_task.hpp"
#include "cluttertamp/robot/robot_description.hpp"
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
  EXPECT_TRUE(p.robot.description.is_absolute());
  ASSERT_NE(p.robot.loaded, nullptr);
  EXPECT_EQ(p.robot.loaded->name(), "ur10_ag95");
  EXPECT_EQ(robot::initial_configuration(p.robot), p.robot.loaded->home());
}

// A pddl task's files are parsed once, at load: the domain, the stream file, their warnings.
TEST(ProblemIo, APddlTasksFilesAreParsedAtLoad) {
  const Problem problem = io::load_problem(std::filesystem::path(CLUTTERTAMP_SOURCE_DIR) / "problems/stacked/stacked4.yaml");
  const auto* task = std::get_if<PddlTask>(&problem.task);
  ASSERT_NE(task, nullptr);
  ASSERT_TRUE(task->parsed);
  ASSERT_TRUE(task->parsed->streams);
  EXPECT_FALSE(task->parsed->domain.actions.empty());
  EXPECT_NE(task->parsed->streams->find("plan-place"), nullptr);
  EXPECT_EQ(stream::parsed_task(*task), task->parsed);  // no second parse
}

TEST(ProblemIo, DefaultProblemIsValid) {
  const Problem p = io::load_problem(std::filesystem::path(CLUTTERTAMP_SOURCE_DIR) / "problems/default.yaml");
  EXPECT_EQ(std::get<RetrievalTask>(p.task).target, "target");
  EXPECT_EQ(p.planner.name, "retrieval_graph");
}

TEST(ProblemIo, ReportsEveryProblemAtOnce) {
  const Diagnostics d = expect_input_error([] { io::load_problem(data("problems/bad_problem.yaml")); });
  EXPECT_EQ(d.size(), 5u) << d.str();
  EXPECT_TRUE(has_error(d, 3, 22, "robot description 'missing.yaml' does not exist"));
  EXPECT_TRUE(has_error(d, 4, 18, "retrieve names 'b' but the scene's target is 'a'"));
  EXPECT_TRUE(has_error(d, 7, 15, "time_limit must be positive"));
  EXPECT_TRUE(has_error(d, 8, 3, "unknown key 'speed' in planner"));
  EXPECT_TRUE(has_error(d, 10, 11, "plugin path 'no/such/dir' is not a directory"));
}

TEST(ProblemIo, TaskMustBeRetrieveReachOrPddl) {
  const Diagnostics d = expect_input_error([] { io::load_problem(data("problems/bad_task.yaml")); });
  EXPECT_TRUE(has_error(d, 4, 7, "task has more than one of 'retrieve', 'reach' and 'pddl'; give one"));
}

TEST(ProblemIo, SceneErrorsAreReportedWithTheScenesLocation) {
  const Diagnostics d = expect_input_error([] { io::load_problem(data("problems/bad_scene_inside.yaml")); });
  ASSERT_EQ(d.size(), 1u);
  EXPECT_NE(d.items()[0].location.file.str().find("bad_interpenetrating.yaml"), std::string::npos);
  EXPECT_EQ(d.items()[0].location.line, 7u);
}

TEST(ProblemIo, DetectsFileKind) {
  EXPECT_EQ(io::detect_file_kind(data("problems/good.yaml")), io::FileKind::problem);
  EXPECT_EQ(io::detect_file_kind(data("scenes/good.yaml")), io::FileKind::scene);
}

}  // namespace
}  // namespace cluttertamp

namespace cluttertamp {
namespace {

TEST(ProblemIo, MissingKeysWrongTypesAndNoTask) {
  const Diagnostics d = test::expect_input_error([] { io::load_problem(test::data("problems/bad_fields.yaml")); });
  EXPECT_EQ(d.size(), 4u) << d.str();
  EXPECT_TRUE(test::has_error(d, 3, 77, "robot configuration must list 7 joint values (shoulder_pan_joint"));
  EXPECT_TRUE(test::has_error(d, 4, 7, "task needs 'retrieve: <target object>', 'reach: <target object>' or 'pddl:"));
  EXPECT_TRUE(test::has_error(d, 5, 39, "planner seed must be a decimal integer, not '010'"));
  EXPECT_TRUE(test::has_error(d, 5, 56, "planner time_limit must be a finite number, not 'soon'"));
}

TEST(ProblemIo, AReachTaskNamesTheScenesTarget) {
  const Problem p = io::load_problem(std::filesystem::path(CLUTTERTAMP_SOURCE_DIR) / "problems/push/easy.yaml");
  EXPECT_EQ(std::get<ReachTask>(p.task).target, "target");
  EXPECT_EQ(p.planner.name, "rtc_ompl");
}

// The plugins block takes any kind as a key; the task planner, stream samplers and
// names that cannot be kinds are refused where they stand.
TEST(ProblemIo, PluginKindKeysAreCheckedWhereTheyStand) {
  const Diagnostics d = test::expect_input_error([] { io::load_problem(test::data("problems/bad_plugin_keys.yaml")); });
  EXPECT_TRUE(test::has_error(d, 7, 3, "the task planner is chosen by 'planner: plugin:'"));
  EXPECT_TRUE(test::has_error(d, 8, 3, "stream samplers are bound to streams under 'plugins: streams:'"));
  EXPECT_TRUE(test::has_error(d, 9, 3, "'grasp-sampler' is not a plugin kind"));
  EXPECT_TRUE(test::has_error(d, 10, 3, "'bad__kind' is not a plugin kind"));
  EXPECT_EQ(d.size(), 4u);
}

TEST(ProblemIo, PddlTaskWithStreamsAndEveryPluginRole) {
  const Problem p = io::load_problem(test::data("problems/pddl_ok.yaml"));
  const auto& task = std::get<PddlTask>(p.task);
  EXPECT_EQ(task.domain.filename(), "domain.pddl");
  EXPECT_EQ(task.problem->filename(), "problem.pddl");
  ASSERT_TRUE(task.streams.has_value());
  EXPECT_EQ(task.streams->filename(), "stream.pddl");
  EXPECT_EQ(p.samplers.at("grasp_sampler").name, "test_grasp");
  const PluginChoice& pruner = p.samplers.at("object_pruner");
  EXPECT_EQ(pruner.name, "corridor");
  EXPECT_DOUBLE_EQ(pruner.parameters.get_double("finger_thickness", 0), 0.01);
  ASSERT_EQ(p.streams.size(), 2u);
  EXPECT_EQ(p.streams.at("sample-grasp").parameters.get_int("rings", 0), 3);
  EXPECT_EQ(p.streams.at("test-free").name, "toy_stream");
  // Planner parameters keep their YAML types; a quoted number stays a string.
  EXPECT_DOUBLE_EQ(p.planner.parameters.get_double("weight", 0), 1.5);
  EXPECT_TRUE(p.planner.parameters.get_bool("verbose", false));
  EXPECT_EQ(p.planner.parameters.get_string("tag", ""), "7");
  ASSERT_EQ(p.plugin_paths.size(), 1u);
}

}  // namespace
}  // namespace cluttertamp

namespace cluttertamp {
namespace {

// A PDDL task with its own problem file needs no scene and no robot; its objects'
// values and its plugins' parameters are any YAML, nested, each part located.
TEST(ProblemIo, ASymbolicStreamProblemHasValuesAndNestedParameters) {
  const Problem p = io::load_problem(test::data("problems/symbolic_values.yaml"));
  EXPECT_TRUE(p.scene.objects.empty());
  EXPECT_FALSE(p.robot.loaded);
  const auto& task = std::get<PddlTask>(p.task);
  ASSERT_EQ(task.values.size(), 3u);
  const Value& o1 = task.values.at("o1");
  ASSERT_NE(o1.map(), nullptr);
  EXPECT_EQ(*o1.find("width")->integer(), 2);
  const Value::List& corners = *o1.find("corners")->list();
  ASSERT_EQ(corners.size(), 2u);
  EXPECT_EQ(corners[1].numbers(), (std::vector<double>{1, 0.5}));
  EXPECT_EQ(*o1.find("label")->string(), "a b");
  EXPECT_EQ(o1.where().line, 7u);
  EXPECT_EQ(o1.find("corners")->where().column, 31u);
  EXPECT_EQ(task.values.at("p0").numbers(), (std::vector<double>{0.5, -1}));
  EXPECT_EQ(task.values.at("home").number(), 3.0);
  EXPECT_EQ(o1.to_yaml(), "{width: 2, corners: [[0, 0], [1, 0.5]], label: a b}");
  // Aliases give both bindings the same choice (so the runner shares one object).
  const Value* shape = p.streams.at("b").parameters.get("shape");
  ASSERT_NE(shape, nullptr);
  EXPECT_EQ(shape->find("radii")->numbers(), (std::vector<double>{1, 2}));
  EXPECT_EQ(p.streams.at("a").parameters.to_yaml(), p.streams.at("b").parameters.to_yaml());
}

TEST(ProblemIo, BadValuesAndAMissingSceneAreLocated) {
  const Diagnostics d = test::expect_input_error([] { io::load_problem(test::data("problems/bad_values.yaml")); });
  EXPECT_TRUE(test::has_error(d, 7, 13, "task pddl values need a PDDL problem")) << d.str();
  EXPECT_TRUE(test::has_error(d, 8, 60, "planner parameters.nested.a must be a finite number, not .inf")) << d.str();
  const Diagnostics e = test::expect_input_error([] { io::load_problem(test::data("problems/no_scene_retrieve.yaml")); });
  EXPECT_TRUE(test::has_error(e, 1, 1, "missing the required key 'scene'")) << e.str();
  EXPECT_TRUE(test::has_error(e, 1, 1, "missing the required key 'robot'")) << e.str();
}

}  // namespace
}  // namespace cluttertamp

namespace cluttertamp {
namespace {

// A misspelt target is an unknown object, with the near names of the scene's objects.
TEST(ProblemIo, AMisspeltTargetSuggestsTheNearObjectNames) {
  const std::filesystem::path file = std::filesystem::temp_directory_path() / "cluttertamp_misspelt_target.yaml";
  std::string text = test::replaced(test::read_text(test::data("problems/good.yaml")), "retrieve: a", "retrieve: aa");
  text = test::replaced(text, "../scenes/good.yaml", test::data("scenes/good.yaml").string());
  text = test::replaced(text, "../../../domains/", std::string(CLUTTERTAMP_SOURCE_DIR) + "/domains/");
  std::ofstream(file) << text;
  const Diagnostics d = test::expect_input_error([&] { io::load_problem(file); });
  EXPECT_TRUE(test::has_error(d, 4, 0, "names 'aa', which is not an object of scene")) << d.str();
  EXPECT_TRUE(test::has_error(d, 4, 0, "(did you mean 'a'")) << d.str();
  std::filesystem::remove(file);
}

}  // namespace
}  // namespace cluttertamp

namespace cluttertamp {
namespace {

std::filesystem::path written(const std::string& name, const std::string& text) {
  const std::filesystem::path file = std::filesystem::temp_directory_path() / name;
  std::ofstream(file) << text;
  return file;
}

// A grid is every combination of its lists (in file order, the last varying fastest), each a
// planner with the fixed parameters under it; seeds count from 0 or are listed.
TEST(SweepFile, AGridIsEveryCombinationOfItsLists) {
  const std::string problem = std::string(CLUTTERTAMP_SOURCE_DIR) + "/problems/default.yaml";
  const io::SweepSpec spec = io::load_sweep_file(written("grid_sweep.yaml", "version: 1\n"
                                                                           "problems: [" + problem + "]\n"
                                                                           "planners:\n"
                                                                           "  - plugin: retrieval_graph\n"
                                                                           "    parameters: {grasp_orders: 3}\n"
                                                                           "    grid: {initial_L: [one, objects], area_margin: [0.1, 0.2, 0.3]}\n"
                                                                           "  - {plugin: exhaustive, name: ex}\n"
                                                                           "seeds: [4, 8]\n"
                                                                           "time_limit: 30\n"));
  ASSERT_EQ(spec.planners.size(), 7u);
  EXPECT_EQ(spec.planners[0].label, "retrieval_graph[initial_L=one,area_margin=0.1]");
  EXPECT_EQ(spec.planners[1].label, "retrieval_graph[initial_L=one,area_margin=0.2]");
  EXPECT_EQ(spec.planners[5].label, "retrieval_graph[initial_L=objects,area_margin=0.3]");
  EXPECT_EQ(spec.planners[5].parameters.get_double("area_margin", 0), 0.3);
  EXPECT_EQ(spec.planners[5].parameters.get_int("grasp_orders", 0), 3);
  EXPECT_EQ(spec.planners[6].label, "ex");
  EXPECT_EQ(spec.planners[6].parameters.size(), 0u);
  EXPECT_EQ(spec.seeds, (std::vector<std::uint64_t>{4, 8}));
  EXPECT_EQ(spec.time_limit, 30.0);
  EXPECT_EQ(spec.runs(), 14u);
  const io::SweepSpec counted = io::load_sweep_file(
      written("count_sweep.yaml", "version: 1\nproblems: [" + problem + "]\nplanners: [{plugin: exhaustive}]\nseeds: 3\n"));
  EXPECT_EQ(counted.seeds, (std::vector<std::uint64_t>{0, 1, 2}));
  EXPECT_FALSE(counted.time_limit);
}

TEST(SweepFile, EveryMistakeIsReportedWhereItStands) {
  const Diagnostics d = test::expect_input_error([] {
    io::load_sweep_file(written("bad_sweep.yaml", "version: 1\n"
                                                  "problems: [no/such.yaml]\n"
                                                  "planners:\n"
                                                  "  - {plugin: a, grid: {x: 3}}\n"
                                                  "  - {plugin: b, parameters: {x: 1}, grid: {x: [1, 2]}}\n"
                                                  "  - {plugin: c, speed: 2}\n"
                                                  "  - {plugin: c}\n"
                                                  "seeds: [1, -2, 1]\n"
                                                  "time_limit: -1\n"
                                                  "extra: 1\n"));
  });
  EXPECT_TRUE(test::has_error(d, 2, 12, "problem file 'no/such.yaml' does not exist")) << d.str();
  EXPECT_TRUE(test::has_error(d, 4, 27, "planner #1 grid 'x' must be a non-empty list of values"));
  EXPECT_TRUE(test::has_error(d, 5, 5, "planner #2: 'x' is both a fixed parameter and a grid axis"));
  EXPECT_TRUE(test::has_error(d, 6, 17, "unknown key 'speed' in planner #3"));
  EXPECT_TRUE(test::has_error(d, 7, 5, "two planners are called 'c'"));
  EXPECT_TRUE(test::has_error(d, 8, 12, "a seed must not be negative"));
  EXPECT_TRUE(test::has_error(d, 8, 16, "seed 1 is listed twice"));
  EXPECT_TRUE(test::has_error(d, 9, 13, "time_limit must be positive"));
  EXPECT_TRUE(test::has_error(d, 10, 1, "unknown key 'extra' in the sweep"));
  EXPECT_TRUE(test::has_error(test::expect_input_error([] { io::load_sweep_file(written("empty_sweep.yaml", "")); }), 1, 1,
                              "the sweep file is empty"));
  // A problem twice; an entry of 10,000 planners repeated by aliases.
  const std::string problem = std::string(CLUTTERTAMP_SOURCE_DIR) + "/problems/default.yaml";
  std::string big = "version: 1\nproblems: [" + problem + ", " + problem + "]\nplanners:\n  - &p {plugin: a, grid: {x: [";
  for (int i = 0; i < 100; ++i) big += (i ? ", " : "") + std::to_string(i);
  big += "], y: [";
  for (int i = 0; i < 100; ++i) big += (i ? ", " : "") + std::to_string(i);
  big += "]}}\n  - *p\n  - *p\n";
  const Diagnostics many = test::expect_input_error([&] { io::load_sweep_file(written("alias_sweep.yaml", big)); });
  EXPECT_TRUE(test::has_error(many, 2, 0, "is listed twice")) << many.str();
  EXPECT_TRUE(test::has_error(many, 4, 3, "planners make more than 10000 planners in all")) << many.str();
}

}  // namespace
}  // namespace cluttertamp
