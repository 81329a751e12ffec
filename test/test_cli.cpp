// End-to-end runs of the `cluttertamp` program: exit codes, output and result.json.
#include <sys/wait.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "bench/statistics.hpp"
#include "bench/svg_plot.hpp"
#include "cluttertamp/collision/collision_world.hpp"
#include "cluttertamp/core/memory_limit.hpp"
#include "cluttertamp/robot/robot_description.hpp"
#include "cluttertamp/io/guidance_io.hpp"
#include "cluttertamp/io/problem_io.hpp"
#include "cluttertamp/io/robot_description_io.hpp"
#include "cluttertamp/io/scene_io.hpp"
#include "cluttertamp/robot/mesh.hpp"
#include "cluttertamp/perception/visibility.hpp"
#include "cluttertamp/physics/push_planning.hpp"
#include "test_support.hpp"

namespace cluttertamp {
namespace {

namespace fs = std::filesystem;

// The RTC goal with the default tolerances, checked without ReachGoal: the target's
// centre between the fingers (within 5 mm), from the palm's face to the fingertips and
// no nearer a finger than its radius, and within 0.5 rad of the gripper's heading.
void expect_target_between_fingers(const Scene& scene, const physics::PushState& state) {
  const physics::PushSettings g;
  const Eigen::Vector2d to = state.objects[scene.target].pose.head<2>() - state.gripper.head<2>();
  const Eigen::Vector2d local = Eigen::Rotation2Dd(-state.gripper.z()) * to;
  const double radius = std::get<Cylinder>(scene.objects[scene.target].shape).radius;
  EXPECT_GE(local.x(), g.gripper_size.x() / 2 - 0.005 - 1e-6);
  EXPECT_LE(local.x(), g.gripper_size.x() / 2 + g.finger_length + 0.005 + 1e-6);
  EXPECT_LE(std::abs(local.y()), g.gripper_size.y() / 2 - g.finger_width - radius + 0.005 + 1e-6);
  EXPECT_LE(std::abs(std::remainder(std::atan2(to.y(), to.x()) - state.gripper.z(), 2 * M_PI)), 0.5 + 1e-6);
}

// A plan step's "controls" values ([vx vy yaw-rate duration] per control) as controls.
std::vector<physics::PushControl> push_controls(const std::vector<double>& values) {
  std::vector<physics::PushControl> controls;
  for (std::size_t i = 0; i + 3 < values.size(); i += 4) {
    controls.push_back({{values[i], values[i + 1], values[i + 2]}, values[i + 3]});
  }
  return controls;
}

using test::CliRun;
using test::run_command;

CliRun run(const std::string& arguments) { return test::run_cli(arguments); }

class Cli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("cluttertamp_cli_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { if (!HasFailure()) fs::remove_all(dir_); }

  // A problem on the good test scene whose test planner ends with `outcome`.
  fs::path problem(const std::string& outcome, const std::string& planner = "test_planner") {
    const fs::path file = dir_ / ("problem_" + outcome + ".yaml");
    std::ofstream(file) << "version: 1\n"
                        << "scene: " << test::data("scenes/good.yaml").string() << "\n"
                        << "robot: {description: " << CLUTTERTAMP_SOURCE_DIR
                        << "/domains/robots/ur10_ag95.yaml}\n"
                        << "task: {retrieve: a}\n"
                        << "planner: {plugin: " << planner << ", time_limit: 10, parameters: {outcome: " << outcome
                        << "}}\n"
                        << "plugins: {paths: [" << test::plugin_dir("good").string() << "]}\n";
    return file;
  }

  // A retrieval of 'a' from the good test scene by the UR10, with these planner and
  // plugins lines (YAML flow maps).
  fs::path retrieval_problem(const std::string& name, const std::string& planner, const std::string& plugins) {
    const fs::path file = dir_ / name;
    std::ofstream(file) << "version: 1\n"
                        << "scene: " << test::data("scenes/good.yaml").string() << "\n"
                        << "robot: {description: " << CLUTTERTAMP_SOURCE_DIR << "/domains/robots/ur10_ag95.yaml}\n"
                        << "task: {retrieve: a}\n"
                        << "planner: " << planner << "\n"
                        << "plugins: " << plugins << "\n";
    return file;
  }

  CliRun plan(const fs::path& problem_file, const std::string& extra = "") {
    return run("plan " + problem_file.string() + " --output " + (dir_ / "out").string() + " " + extra);
  }

  // A bundled problem file copied into the test's directory with `edits` (text, its
  // replacement) applied and its relative paths (scene, robot, guidance, PDDL) made absolute.
  fs::path bundled_copy(const fs::path& source, const std::string& name,
                        const std::vector<std::pair<std::string, std::string>>& edits) {
    std::string yaml = test::read_text(source);
    for (const auto& [from, to] : edits) yaml = test::replaced(yaml, from, to);
    // Relative paths after these keys are made absolute (a comment with one of the keys
    // would be edited too; the bundled problems have none).
    const std::string dir = (source.parent_path() / "").string();
    for (const std::string key : {"\nscene: ", "description: ", "guidance: ", "domain: ", "streams: "}) {
      for (std::size_t at = yaml.find(key); at != std::string::npos; at = yaml.find(key, at + key.size())) {
        const std::size_t value = at + key.size();
        if (yaml[value] != '/' && yaml.compare(value, 4, "auto") != 0) yaml.insert(value, dir);
      }
    }
    const fs::path file = dir_ / name;
    std::ofstream(file) << yaml;
    return file;
  }

  nlohmann::json result() const {
    std::ifstream in(dir_ / "out" / "result.json");
    return nlohmann::json::parse(in);
  }

  // `plan problem_file` into the test's directory `name`: the run and, when it wrote
  // one, its result.json (else null).
  struct Planned {
    CliRun run;
    nlohmann::json result;
  };
  Planned planned(const fs::path& problem_file, const std::string& name, const std::string& extra = "") {
    const fs::path out = dir_ / name;
    Planned p{run("plan " + problem_file.string() + " -o " + out.string() + " " + extra), nullptr};
    if (fs::exists(out / "result.json")) p.result = nlohmann::json::parse(test::read_text(out / "result.json"));
    return p;
  }

  fs::path dir_;
};

// The rows of a CSV file after its header, split at commas (no quoted fields).
std::vector<std::vector<std::string>> csv_rows(const fs::path& csv) {
  std::ifstream in(csv);
  std::string line;
  std::getline(in, line);
  std::vector<std::vector<std::string>> rows;
  while (std::getline(in, line)) {
    std::vector<std::string>& cells = rows.emplace_back();
    std::stringstream cols(line);
    for (std::string cell; std::getline(cols, cell, ',');) cells.push_back(cell);
  }
  return rows;
}

TEST_F(Cli, VersionAndHelp) {
  const CliRun version = run("--version");
  EXPECT_EQ(version.exit_code, 0);
  EXPECT_NE(version.output.find("0."), std::string::npos);
  const CliRun help = run("--help");
  EXPECT_EQ(help.exit_code, 0);
  EXPECT_NE(help.output.find("Exit codes: 0 solved"), std::string::npos);
  for (const char* sub : {"plan", "validate", "plugins"}) EXPECT_NE(help.output.find(sub), std::string::npos);
  const CliRun plan_help = run("plan --help");
  for (const char* option : {"--seed", "--time-limit", "--output", "--quiet", "--verbose"}) {
    EXPECT_NE(plan_help.output.find(option), std::string::npos) << option;
  }
}

TEST_F(Cli, UsageErrorsAreBadInput) {
  EXPECT_EQ(run("").exit_code, 2);
  EXPECT_EQ(run("plan").exit_code, 2);
  EXPECT_EQ(run("plan --no-such-option x.yaml").exit_code, 2);
  EXPECT_EQ(run("fly").exit_code, 2);
}

TEST_F(Cli, ValidatePrintsEveryErrorWithItsLocation) {
  EXPECT_EQ(run("validate " + test::data("scenes/good.yaml").string()).exit_code, 0);
  const CliRun bad = run("validate --plugin-path " + test::plugin_dir("good").string() + " " +
                         test::data("scenes/bad_many.yaml").string() + " " + test::data("problems/good.yaml").string());
  EXPECT_EQ(bad.exit_code, 2);
  const std::string file = test::data("scenes/bad_many.yaml").string();
  for (const char* where : {":1:1: error:", ":3:35: error:", ":6:5: error:", ":6:89: error:", ":7:5: error:",
                            ":7:13: error:"}) {
    EXPECT_NE(bad.output.find(file + where), std::string::npos) << where << "\n" << bad.output;
  }
  EXPECT_NE(bad.output.find("valid problem 'good'"), std::string::npos);  // later files are still checked
}

TEST_F(Cli, ValidateChecksThePluginsAProblemNames) {
  const std::string problem = test::data("problems/good.yaml").string();
  const CliRun missing = run("validate " + problem);  // test_planner is not on the default paths
  EXPECT_EQ(missing.exit_code, 2) << missing.output;
  EXPECT_NE(missing.output.find("no usable task_planner plugin named 'test_planner'"), std::string::npos);
  EXPECT_EQ(run("validate --no-plugins " + problem).exit_code, 0);
  EXPECT_EQ(run("validate --plugin-path " + test::plugin_dir("good").string() + " " + problem).exit_code, 0);
}

// A problem without a sampler its planner needs passed validate, and plan then failed
// as a planning failure (exit 1). Now both refuse it as bad input, naming the kind.
TEST_F(Cli, APlannerWithoutTheSamplersItNeedsIsBadInput) {
  const fs::path problem =
      retrieval_problem("no_grasps.yaml", "{plugin: retrieval_graph, time_limit: 5}", "{motion_sampler: motion_ompl}");
  for (const std::string& command : {"validate " + problem.string(), "plan " + problem.string() + " -o " + (dir_ / "o").string()}) {
    const CliRun r = run(command);
    EXPECT_EQ(r.exit_code, 2) << command << "\n" << r.output;
    EXPECT_NE(r.output.find("no_grasps.yaml:5:19: error: planner 'retrieval_graph' needs a grasp_sampler: add "
                            "`grasp_sampler: NAME` to the problem's plugins block (found: grasp_side)"),
              std::string::npos)
        << r.output;
    EXPECT_NE(r.output.find("needs a placement_sampler"), std::string::npos) << r.output;
  }
  const std::string reach = (fs::path(CLUTTERTAMP_SOURCE_DIR) / "problems/push/easy.yaml").string();
  const CliRun grtc = run("plan " + reach + " --planner grtc -o " + (dir_ / "g").string());
  EXPECT_EQ(grtc.exit_code, 2) << grtc.output;
  EXPECT_NE(grtc.output.find("planner 'grtc' needs a push_sampler"), std::string::npos) << grtc.output;
}

// Misspelt plugin names used to be reported one per run, with no suggestion.
TEST_F(Cli, ValidateReportsEveryMisspeltPluginWithTheNearName) {
  const fs::path problem = retrieval_problem(
      "misspelt.yaml", "{plugin: retrieval_grap, time_limit: 5}",
      "{grasp_sampler: grasp_sid, motion_sampler: motion_omp, placement_sampler: placement_regio}");
  const CliRun r = run("validate " + problem.string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  for (const char* near : {"'retrieval_grap' (did you mean 'retrieval_graph'?)", "'grasp_sid' (did you mean 'grasp_side'?)",
                           "'motion_omp' (did you mean 'motion_ompl'?)",
                           "'placement_regio' (did you mean 'placement_region'?)"}) {
    EXPECT_NE(r.output.find(near), std::string::npos) << near << "\n" << r.output;
  }
  EXPECT_NE(r.output.find("misspelt.yaml:5:"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("misspelt.yaml:6:"), std::string::npos) << r.output;
}

// A problem whose scene had an error was reported without its plugins' errors: those
// came one run later. Now each check runs on the parts that read.
TEST_F(Cli, ValidateChecksThePluginsOfAProblemWhoseOtherFilesHaveErrors) {
  const fs::path problem = dir_ / "bad_scene.yaml";
  std::ofstream(problem) << "version: 1\n"
                         << "scene: " << test::data("scenes/bad_many.yaml").string() << "\n"
                         << "robot: {description: " << CLUTTERTAMP_SOURCE_DIR << "/domains/robots/ur10_ag95.yaml}\n"
                         << "task: {retrieve: a}\n"
                         << "planner: {plugin: retrieval_graph, time_limit: 5}\n"
                         << "plugins: {grasp_sampler: grasp_sid, motion_sampler: motion_ompl}\n";
  const CliRun r = run("validate " + problem.string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find(test::data("scenes/bad_many.yaml").string() + ":6:89: error:"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("bad_scene.yaml:6:26: error:"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("'grasp_sid' (did you mean 'grasp_side'?)"), std::string::npos) << r.output;
  // The planner's needs are checked on the plugins block, which read whole; a kind it
  // names is reported by its own error only.
  EXPECT_NE(r.output.find("planner 'retrieval_graph' needs a placement_sampler"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("needs a grasp_sampler"), std::string::npos) << r.output;
  // plan refuses the same problem as bad input.
  EXPECT_EQ(plan(problem).exit_code, 2);

  // A plugins block with an error of its own: the names that read are still checked, and
  // no kind is called missing for the choice that did not read.
  const fs::path broken = dir_ / "bad_plugins.yaml";
  std::ofstream(broken) << "version: 1\n"
                        << "scene: " << test::data("scenes/good.yaml").string() << "\n"
                        << "robot: {description: " << CLUTTERTAMP_SOURCE_DIR << "/domains/robots/ur10_ag95.yaml}\n"
                        << "task: {retrieve: a}\n"
                        << "planner: {plugin: retrieval_graph, time_limit: 5}\n"
                        << "plugins: {grasp_sampler: [1, 2], motion_sampler: motion_omp, placement_sampler: "
                           "placement_region}\n";
  const CliRun b = run("validate " + broken.string());
  EXPECT_EQ(b.exit_code, 2) << b.output;
  EXPECT_NE(b.output.find("bad_plugins.yaml:6:26: error:"), std::string::npos) << b.output;
  EXPECT_NE(b.output.find("'motion_omp' (did you mean 'motion_ompl'?)"), std::string::npos) << b.output;
  EXPECT_EQ(b.output.find("needs a grasp_sampler"), std::string::npos) << b.output;
}

TEST_F(Cli, BadNumbersOnTheCommandLineAreBadInput) {
  const std::string problem_file = problem("solve").string();
  for (const char* option : {"--seed -1", "--seed 99999999999999999999", "--seed 1.5", "--time-limit nan",
                             "--time-limit 0", "--time-limit -3", "--time-limit inf"}) {
    const CliRun r = plan(problem_file, option);
    EXPECT_EQ(r.exit_code, 2) << option << "\n" << r.output;
  }
}

// NaN passed CLI11's PositiveNumber and Range, and "-1" read as 2^64 - 1 expansions.
TEST_F(Cli, NanAndNegativeCountsAreBadInputEverywhere) {
  const std::string pddl = "pddl " + test::data("pddl/blocks/domain.pddl").string() + " " +
                           test::data("pddl/blocks/p4-1.pddl").string() + " ";
  for (const char* option : {"--time-limit nan", "--weight nan", "--weight inf", "--max-expansions -1",
                             "--max-expansions 1.5"}) {
    const CliRun r = run(pddl + option);
    EXPECT_EQ(r.exit_code, 2) << option << "\n" << r.output;
  }
  EXPECT_EQ(run(pddl + "--max-expansions 100000 --weight 2").exit_code, 0);
  const std::string scene = (fs::path(CLUTTERTAMP_SOURCE_DIR) / "problems/default.yaml").string();
  for (const std::string& command :
       {std::string("bench push --time-limit nan"), std::string("generate --output x.yaml --width nan"),
        std::string("generate --output x.yaml --min-gap nan"), std::string("compare --time-limit nan"),
        "observe " + scene + " --min-visible nan"}) {
    const CliRun r = run(command);
    EXPECT_EQ(r.exit_code, 2) << command << "\n" << r.output;
  }
}

TEST_F(Cli, UnwritableOutputIsBadInput) {
  const fs::path file = dir_ / "a_file";
  std::ofstream(file) << "x";
  const CliRun r = run("plan " + problem("solve").string() + " --output " + file.string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("a_file: error: the output directory (--output) is a file, not a directory"), std::string::npos)
      << r.output;
}

TEST_F(Cli, ValidateReportsParametersNoPluginReads) {
  // Every plugin of pddl_ok.yaml exists; the test planner reads only 'outcome'.
  const CliRun r = run("validate --plugin-path " + test::plugin_dir("good").string() + " " +
                       test::data("problems/pddl_ok.yaml").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  for (const char* text : {"pddl_ok.yaml:6:70: error: unknown parameter 'weight' for task_planner 'test_planner'",
                           "pddl_ok.yaml:6:84: error: unknown parameter 'verbose'",
                           "pddl_ok.yaml:6:95: error: unknown parameter 'tag'"}) {
    EXPECT_NE(r.output.find(text), std::string::npos) << text << "\n" << r.output;
  }
}

TEST_F(Cli, SolvedPlanExitsZeroAndWritesResult) {
  const CliRun r = plan(problem("solve"));
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("SOLVED"), std::string::npos);
  EXPECT_NE(r.output.find("result.json"), std::string::npos);
  const auto json = result();
  EXPECT_EQ(json["solved"], true);
  EXPECT_EQ(json["exit_code"], 0);
  EXPECT_EQ(json["plan"][0]["action"], "retrieve");
  EXPECT_EQ(json["moved_objects"][0], "a");
  EXPECT_EQ(json["counters"]["samples"], 7);
  EXPECT_GE(json["time"]["total"].get<double>(), 0.0);
}

TEST_F(Cli, SeedAndTimeLimitOverrideTheProblemFile) {
  ASSERT_EQ(plan(problem("solve"), "--seed 42 --time-limit 2.5").exit_code, 0);
  EXPECT_EQ(result()["seed"], 42);
  EXPECT_EQ(result()["time_limit"], 2.5);
}

TEST_F(Cli, NoPlanExitsOneWithAReason) {
  const CliRun r = plan(problem("fail"));
  EXPECT_EQ(r.exit_code, 1) << r.output;
  const auto json = result();
  EXPECT_EQ(json["solved"], false);
  EXPECT_EQ(json["reason"], "scripted: no plan");
  EXPECT_EQ(json["failures"][0]["blocking_objects"][0], "a");
}

TEST_F(Cli, TimeLimitIsHonoured) {
  const CliRun r = plan(problem("wait"), "--time-limit 0.3");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_EQ(result()["reason"], "time limit reached");
  EXPECT_LT(result()["time"]["total"].get<double>(), 5.0);
}

TEST_F(Cli, PluginExceptionIsAnInternalError) {
  const CliRun r = plan(problem("throw"));
  EXPECT_EQ(r.exit_code, 3) << r.output;
  EXPECT_NE(result()["reason"].get<std::string>().find("scripted failure"), std::string::npos);
}

TEST_F(Cli, MissingPluginIsBadInputAndListsTheSearch) {
  const CliRun r = plan(problem("solve", "no_such_planner"));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("no usable task_planner plugin named 'no_such_planner'"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find(test::plugin_dir("good").string()), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("task_planner 'test_planner'"), std::string::npos) << r.output;
  EXPECT_EQ(result()["exit_code"], 2);
}

TEST_F(Cli, InvalidProblemIsBadInput) {
  const CliRun r = plan(test::data("problems/bad_problem.yaml"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("bad_problem.yaml:7:15: error:"), std::string::npos) << r.output;
}

TEST_F(Cli, DefaultProblemIsSolvedWithEveryMotion) {
  const CliRun r = plan(fs::path(CLUTTERTAMP_SOURCE_DIR) / "problems/default.yaml", "--time-limit 60");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("SOLVED"), std::string::npos) << r.output;
  const auto json = result();
  EXPECT_EQ(json["solved"], true);
  ASSERT_GE(json["plan"].size(), 1u);
  EXPECT_EQ(json["plan"].back()["action"], "retrieve");
  EXPECT_EQ(json["moved_objects"].back(), "target");
  for (const auto& step : json["plan"]) {
    ASSERT_FALSE(step["trajectory"].is_null()) << step["action"];
    EXPECT_GE(step["trajectory"]["positions"].size(), 2u);
  }
  EXPECT_GT(json["counters"]["motion_planning_calls"].get<int>(), 0);
}

// Tian et al., Fig. 10: the lid on the two front objects goes first, then one front
// object, then the target comes out; every motion starts and ends at home, so the
// trajectories join up. With 12 more cylinders along the walls (stacked16) the pruner
// keeps the same three movable and the plan is the same.
TEST_F(Cli, StackedObjectsAreMovedInOrderWithStreams) {
  for (const char* name : {"stacked8", "stacked16"}) {
    SCOPED_TRACE(name);
    const CliRun r = plan(fs::path(CLUTTERTAMP_SOURCE_DIR) / "problems/stacked" / (std::string(name) + ".yaml"), "--time-limit 120");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_EQ(r.output.find("\rplanning"), std::string::npos) << "the elapsed-time line is for terminals only";
    const auto json = result();
    const auto& moved = json["moved_objects"];
    ASSERT_EQ(moved.size(), 3u) << r.output;
    EXPECT_EQ(moved[0], "lid");
    EXPECT_TRUE(moved[1] == "front_left" || moved[1] == "front_right") << moved[1];
    EXPECT_EQ(moved[2], "target");
    ASSERT_EQ(json["plan"].size(), 5u);
    std::vector<double> home;
    for (const auto& step : json["plan"]) {
      ASSERT_FALSE(step["trajectory"].is_null()) << step["action"];
      const auto& q = step["trajectory"]["positions"];
      ASSERT_GE(q.size(), 2u);
      if (home.empty()) home = q.front().get<std::vector<double>>();
      for (const auto* end : {&q.front(), &q.back()}) {
        const auto v = end->get<std::vector<double>>();
        for (std::size_t j = 0; j + 1 < v.size(); ++j) EXPECT_NEAR(v[j], home[j], 1e-6) << step["action"];  // arm joints
      }
    }
    EXPECT_GT(json["counters"]["stream_calls"].get<int>(), 0);
    EXPECT_EQ(json["counters"]["movable_objects"], 3);
    // The symbolic arguments of each step, in result.json and on the terminal.
    const auto& first = json["plan"][0]["arguments"];
    ASSERT_EQ(first.size(), 4u) << json["plan"][0];  // (pick ?o ?p ?g ?t)
    EXPECT_EQ(first[0], "lid");
    EXPECT_EQ(first[1], "p0-lid");
    EXPECT_NE(r.output.find("1. pick lid p0-lid "), std::string::npos) << r.output;
  }
}

// With an unchecked pruner, stacked8's target path is free in the plane, so no obstacle
// is movable: the run cannot succeed, and its failures say why.
TEST_F(Cli, AStreamRunWithNothingMovableSaysSo) {
  const fs::path file =
      bundled_copy(fs::path(CLUTTERTAMP_SOURCE_DIR) / "problems/stacked/stacked8.yaml", "unchecked.yaml",
                   {{"object_pruner: retrieval_graph", "object_pruner: {plugin: retrieval_graph, parameters: {checked: false}}"}});
  const CliRun r = plan(file, "--time-limit 10");  // the search goes on until its limit
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("the object pruner's sequences named no object to move"), std::string::npos) << r.output;
  EXPECT_EQ(result()["counters"]["movable_objects"], 0);
}

// validate reads the PDDL and stream files of a stream problem and checks its bindings.
TEST_F(Cli, ValidateChecksTheStreamFilesAndBindingsOfAStreamProblem) {
  const fs::path source = fs::path(CLUTTERTAMP_SOURCE_DIR) / "problems/stacked/stacked4.yaml";
  EXPECT_EQ(run("validate " + source.string()).exit_code, 0);
  const fs::path file = bundled_copy(source, "bad_streams.yaml", {{"plan-place: clutter_streams", "plan-plaice: clutter_streams"}});
  const CliRun r = run("validate " + file.string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("stream.pddl:11:3: error: 'plan-place' is bound to no stream_sampler"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("stream 'plan-plaice' is not declared in"), std::string::npos) << r.output;
  // plan reads the same parse at load: the same errors, before any planning.
  const CliRun planned = plan(file, "");
  EXPECT_EQ(planned.exit_code, 2) << planned.output;
  EXPECT_NE(planned.output.find("stream.pddl:11:3: error: 'plan-place' is bound to no stream_sampler"), std::string::npos)
      << planned.output;
  EXPECT_NE(planned.output.find("stream 'plan-plaice' is not declared in"), std::string::npos) << planned.output;
}

// compare: four settings, one seed each, as a table, JSON, CSV and SVG.
TEST_F(Cli, CompareRunsTheFourSettingsAndWritesTheirFiles) {
  const fs::path json_file = dir_ / "c.json", csv_file = dir_ / "c.csv", svg_file = dir_ / "c.svg";
  const CliRun r = run("compare " + (fs::path(CLUTTERTAMP_SOURCE_DIR) / "problems/stacked/stacked8.yaml").string() +
                       " --runs 1 --time-limit 30 -q --json " + json_file.string() + " --csv " + csv_file.string() +
                       " --svg " + svg_file.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;  // it ran (solved or not: --check-goals asks)
  for (const char* setting : {"adaptive + pruning", "adaptive, all movable", "incremental + pruning", "incremental, all movable"}) {
    EXPECT_NE(r.output.find(setting), std::string::npos) << r.output;
  }
  std::ifstream in(json_file);
  const auto json = nlohmann::json::parse(in);
  ASSERT_EQ(json.size(), 4u);
  for (const auto& row : json) {
    EXPECT_EQ(row["objects"], 8);
    EXPECT_EQ(row["runs"], 1);
    EXPECT_EQ(row["paper_mean_time_s"], row["pruned"].get<bool>() ? "28.82" : ">120");
  }
  std::ifstream csv(csv_file);
  std::string line;
  int lines = 0;
  while (std::getline(csv, line)) ++lines;
  EXPECT_EQ(lines, 5);  // header and four runs
  std::ifstream svg(svg_file);
  EXPECT_TRUE(std::getline(svg, line) && line.rfind("<svg", 0) == 0);
  // A retrieval problem is no stream problem.
  EXPECT_EQ(run("compare " + (fs::path(CLUTTERTAMP_SOURCE_DIR) / "problems/default.yaml").string() + " -q").exit_code, 2);
}

// Table IV's 4-object scene: both algorithms solve it pruned and with every object
// movable (with --check-goals, exit code 0: every run solved).
TEST_F(Cli, CompareSolvesStacked4InEverySetting) {
  const CliRun r = run("compare " + (fs::path(CLUTTERTAMP_SOURCE_DIR) / "problems/stacked/stacked4.yaml").string() +
                       " --runs 1 --time-limit 60 --check-goals");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  for (const char* setting : {"adaptive + pruning", "adaptive, all movable", "incremental + pruning", "incremental, all movable"}) {
    const std::size_t row = r.output.find(setting);
    ASSERT_NE(row, std::string::npos) << r.output;
    EXPECT_NE(r.output.find("100%", row), std::string::npos) << setting << "\n" << r.output;
  }
}

// generate writes a scene the target cannot leave directly and a problem that plans on it.
TEST_F(Cli, GeneratedShelfProblemIsSolved) {
  const fs::path scene = dir_ / "shelf.yaml", problem_file = dir_ / "shelf_problem.yaml";
  const CliRun g = run("generate --objects 12 --seed 1 --output " + scene.string() + " --problem " + problem_file.string());
  ASSERT_EQ(g.exit_code, 0) << g.output;
  EXPECT_EQ(run("validate " + scene.string() + " " + problem_file.string()).exit_code, 0);
  const CliRun r = plan(problem_file, "--time-limit 60");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  const auto json = result();
  EXPECT_EQ(json["moved_objects"].back(), "target");
  EXPECT_GE(json["moved_objects"].size(), 2u);  // something had to move first
}

// For the Panda the shelf moves to where it reaches it, and since its home would stand
// among the front objects there, the problem starts it drawn back; the plan starts
// there. Without that start, validate and plan refuse the problem, naming every body
// the home overlaps with its line in the scene file.
TEST_F(Cli, GenerateForAnotherRobotGivesAStartClearOfTheShelf) {
  const fs::path scene = dir_ / "shelf.yaml", problem_file = dir_ / "shelf_problem.yaml";
  const std::string panda = (fs::path(CLUTTERTAMP_SOURCE_DIR) / "domains/robots/panda.yaml").string();
  const CliRun g = run("generate --objects 12 --seed 1 --robot " + panda + " --output " + scene.string() + " --problem " +
                       problem_file.string());
  ASSERT_EQ(g.exit_code, 0) << g.output;
  EXPECT_NE(g.output.find("the problem starts with the tool drawn back"), std::string::npos) << g.output;
  const std::string problem_text = test::read_text(problem_file);
  const std::size_t from = problem_text.find(", configuration: [");
  ASSERT_NE(from, std::string::npos) << problem_text;
  EXPECT_EQ(run("validate " + problem_file.string()).exit_code, 0);

  const CliRun r = plan(problem_file, "--time-limit 120");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto json = result();
  EXPECT_EQ(json["moved_objects"].back(), "target");
  const std::size_t to = problem_text.find(']', from);
  std::stringstream values(problem_text.substr(from + 18, to - from - 18));
  const auto& first = json["plan"][0]["trajectory"]["positions"][0];
  std::size_t i = 0;
  for (std::string value; std::getline(values, value, ','); ++i) {
    ASSERT_LT(i, first.size());
    EXPECT_NEAR(first[i].get<double>(), std::stod(value), 1e-6) << i;
  }
  EXPECT_EQ(i, first.size());

  const fs::path at_home = dir_ / "at_home.yaml";
  std::ofstream(at_home) << problem_text.substr(0, from) + problem_text.substr(to + 1);
  const CliRun refused = run("validate " + at_home.string());
  EXPECT_EQ(refused.exit_code, 2) << refused.output;
  EXPECT_NE(refused.output.find(scene.string() + ":"), std::string::npos) << refused.output;
  EXPECT_NE(refused.output.find("overlaps the robot's start configuration (its description's `home`)"), std::string::npos)
      << refused.output;
  const Planned planned_at_home = planned(at_home, "out_at_home");
  EXPECT_EQ(planned_at_home.run.exit_code, 2) << planned_at_home.run.output;
}

// The bench's 90th percentile: linear between the closest ranks, as NumPy's default.
TEST(BenchStatistics, PercentileInterpolatesBetweenRanks) {
  EXPECT_DOUBLE_EQ(bench::percentile({}, 90), 0.0);
  EXPECT_DOUBLE_EQ(bench::percentile({3.0}, 90), 3.0);
  EXPECT_DOUBLE_EQ(bench::percentile({4.0, 1.0, 3.0, 2.0}, 0), 1.0);
  EXPECT_DOUBLE_EQ(bench::percentile({4.0, 1.0, 3.0, 2.0}, 100), 4.0);
  EXPECT_DOUBLE_EQ(bench::percentile({4.0, 1.0, 3.0, 2.0}, 50), 2.5);
  EXPECT_NEAR(bench::percentile({1, 2, 3, 4, 5, 6, 7, 8, 9, 10}, 90), 9.1, 1e-12);
}

// The benches' plots: y axes in round steps, each tick labelled with a grid line.
TEST(BenchPlots, AxesRunInRoundStepsWithGridLines) {
  EXPECT_DOUBLE_EQ(bench::tick_step(100), 25.0);
  EXPECT_DOUBLE_EQ(bench::tick_step(0.8), 0.2);
  EXPECT_DOUBLE_EQ(bench::tick_step(17.3), 5.0);
  EXPECT_DOUBLE_EQ(bench::tick_step(0), 1.0);
  EXPECT_DOUBLE_EQ(bench::tick_step(std::nan("")), 1.0);
  bench::SvgPlot plot(400, 300);
  const bench::SvgPlot::Panel panel = plot.panel(50, 30, 300, 200, 17.3, "time <s>", "");
  EXPECT_DOUBLE_EQ(panel.y_max, 20.0);
  EXPECT_DOUBLE_EQ(panel.y(0), 230.0);
  EXPECT_DOUBLE_EQ(panel.y(20), 30.0);
  plot.bar(panel, 60, 10, 25.0, "#000000");  // clipped to the axis
  const fs::path file = fs::temp_directory_path() / "cluttertamp_bench_plot_test.svg";
  plot.write(file);
  std::ifstream in(file);
  const std::string svg((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  fs::remove(file);
  for (const char* tick : {">0<", ">5<", ">10<", ">15<", ">20<"}) EXPECT_NE(svg.find(tick), std::string::npos) << tick;
  EXPECT_NE(svg.find("time &lt;s&gt;"), std::string::npos);
  EXPECT_NE(svg.find("<rect x='60' y='30' width='10' height='200'"), std::string::npos) << svg;
  std::size_t grid_lines = 0;
  for (std::size_t at = svg.find("#dddddd"); at != std::string::npos; at = svg.find("#dddddd", at + 1)) ++grid_lines;
  EXPECT_EQ(grid_lines, 4u) << svg;  // at 5, 10, 15 and 20
}

// generate --min-gap: the least distance between cylinders (default 0, the paper's
// recipe); out of range is bad input. result.json says where the work went, by phase.
TEST_F(Cli, GenerateTakesAMinimumGapAndResultsSayWhereTheWorkWent) {
  const fs::path scene = dir_ / "gap.yaml", problem_file = dir_ / "gap_problem.yaml";
  EXPECT_EQ(run("generate --objects 12 --min-gap -0.01 --output " + scene.string()).exit_code, 2);
  EXPECT_EQ(run("generate --objects 12 --min-gap 0.5 --output " + scene.string()).exit_code, 2);
  const CliRun g = run("generate --objects 12 --min-gap 0.03 --seed 3 --output " + scene.string() + " --problem " +
                       problem_file.string());
  ASSERT_EQ(g.exit_code, 0) << g.output;
  const Scene s = io::load_scene(scene);
  for (std::size_t i = 0; i < s.objects.size(); ++i) {
    for (std::size_t j = 0; j < i; ++j) {
      const double gap = (s.objects[i].world_T_object.translation() - s.objects[j].world_T_object.translation()).head<2>().norm() -
                         std::get<Cylinder>(s.objects[i].shape).radius - std::get<Cylinder>(s.objects[j].shape).radius;
      EXPECT_GE(gap, 0.03 - 1e-6);
    }
  }
  const CliRun r = plan(problem_file, "--time-limit 60");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto json = result();
  ASSERT_TRUE(json["phases"].is_object());
  ASSERT_TRUE(json["phases"].contains("check.retrieve"));
  std::uint64_t motion_checks = 0;
  for (const auto& [name, phase] : json["phases"].items()) {
    EXPECT_GE(phase["calls"].get<std::uint64_t>(), 1u) << name;
    EXPECT_GE(phase["time"].get<double>(), 0.0) << name;
    EXPECT_LE(phase["collision_checks"].get<std::uint64_t>(), json["counters"]["collision_checks"].get<std::uint64_t>()) << name;
    if (name.rfind("motion.", 0) == 0) motion_checks += phase["collision_checks"].get<std::uint64_t>();
  }
  EXPECT_LE(motion_checks, json["counters"]["collision_checks"].get<std::uint64_t>());
}

// --min-removals keeps a scene whose optimum the exhaustive planner proved; plan
// --planner runs the baselines on it: none moves fewer objects than that optimum.
TEST_F(Cli, GeneratedSceneWithAKnownMinimumAndThePlannersOnIt) {
  const fs::path scene = dir_ / "min2.yaml", problem_file = dir_ / "min2_problem.yaml";
  const CliRun g = run("generate -q --objects 12 --min-removals 2 --seed 1 --attempts 20 --output " + scene.string() +
                       " --problem " + problem_file.string());
  ASSERT_EQ(g.exit_code, 0) << g.output;
  EXPECT_FALSE(fs::exists(scene.string() + ".tmp"));
  const std::string header = test::read_text(problem_file);
  EXPECT_NE(header.find("fewest objects to move, target included: 2"), std::string::npos) << header;

  const CliRun best = plan(problem_file, "--planner exhaustive --seed 0");
  ASSERT_EQ(best.exit_code, 0) << best.output;
  EXPECT_EQ(result()["planner"], "exhaustive");
  EXPECT_EQ(result()["moved_objects"].size(), 2u);
  for (const std::string name : {"retrieval_graph", "traversability_graph"}) {
    const CliRun r = plan(problem_file, "--planner " + name + " --seed 0");
    ASSERT_TRUE(r.exit_code == 0 || r.exit_code == 1) << r.output;
    if (r.exit_code == 0) EXPECT_GE(result()["moved_objects"].size(), 2u) << name;
  }
  const CliRun missing = plan(problem_file, "--planner no_such_planner");
  EXPECT_EQ(missing.exit_code, 2) << missing.output;
  EXPECT_NE(missing.output.find("exhaustive"), std::string::npos) << missing.output;  // lists what exists
}

// self-collisions counts touching link pairs; pairs the description disables are not
// checked, and those never touching are listed for disabled_collisions.
TEST_F(Cli, SelfCollisionsCountsPairsAndSkipsDisabledOnes) {
  const std::string robot = (fs::path(CLUTTERTAMP_SOURCE_DIR) / "domains/robots/ur10_ag95.yaml").string();
  const CliRun r = run("self-collisions " + robot + " --samples 3000");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("3000 random configurations"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("forearm_link          gripper_base"), std::string::npos) << r.output;  // folds onto itself
  EXPECT_EQ(r.output.find("left_finger           right_finger"), std::string::npos) << r.output;  // disabled
  EXPECT_NE(r.output.find("never touched"), std::string::npos);
  EXPECT_NE(r.output.find("home: clear of itself"), std::string::npos) << r.output;
  EXPECT_EQ(run("self-collisions " + (dir_ / "missing.yaml").string()).exit_code, 2);
}

// A home in self collision (the left finger's box made so wide that the fingers
// overlap at every opening, and the pair not disabled): generate refuses the robot,
// naming the links, before drawing a shelf that every command would then refuse;
// self-collisions says so, and lists the pair among those touching in (nearly) every
// configuration.
TEST_F(Cli, AHomeInSelfCollisionIsNamedAndGenerateRefusesIt) {
  const fs::path robots = fs::path(CLUTTERTAMP_SOURCE_DIR) / "domains/robots";
  std::ofstream(dir_ / "pinched.urdf") << test::replaced(test::read_text(robots / "ur10_ag95.urdf"), "<box size=\"0.02 0.012 0.06\"/>",
                                                         "<box size=\"0.02 0.25 0.06\"/>");  // the left finger's, the first
  std::string yaml = test::replaced(test::read_text(robots / "ur10_ag95.yaml"), "urdf: ur10_ag95.urdf", "urdf: pinched.urdf");
  std::ofstream(dir_ / "pinched.yaml") << test::replaced(yaml, "  - [left_finger, right_finger]\n", "");
  const std::string robot = (dir_ / "pinched.yaml").string();
  const CliRun g = run("generate --robot " + robot + " --objects 4 --seed 1 --output " + (dir_ / "s.yaml").string());
  EXPECT_EQ(g.exit_code, 2) << g.output;
  EXPECT_NE(g.output.find("pinched.yaml: error: the robot's home is in self collision: 'left_finger' touches 'right_finger'"),
            std::string::npos) << g.output;
  EXPECT_FALSE(fs::exists(dir_ / "s.yaml"));
  const CliRun r = run("self-collisions " + robot + " --samples 200");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("home: in self collision, 'left_finger' touches 'right_finger'"), std::string::npos) << r.output;
  const std::size_t always = r.output.find("touched in 99 % of the configurations or more");
  ASSERT_NE(always, std::string::npos) << r.output;
  EXPECT_NE(r.output.find("  - [left_finger, right_finger]", always), std::string::npos) << r.output;
}

// A hand too small for every object retrieves no target, with or without the others:
// generate used to take such a scene for one that needs a removal and write it, exit 0.
TEST_F(Cli, GenerateRejectsScenesWhoseTargetTheRobotCannotRetrieveAtAll) {
  const fs::path robots = fs::path(CLUTTERTAMP_SOURCE_DIR) / "domains/robots";
  std::string yaml = test::replaced(test::read_text(robots / "ur10_ag95.yaml"), "urdf: ur10_ag95.urdf",
                                    "urdf: " + (robots / "ur10_ag95.urdf").string());
  std::ofstream(dir_ / "small_hand.yaml") << test::replaced(yaml, "stroke: 0.095", "stroke: 0.02");
  const CliRun g = run("generate -v --robot " + (dir_ / "small_hand.yaml").string() + " --objects 4 --seed 1 --attempts 2 --output " +
                       (dir_ / "s.yaml").string());
  EXPECT_EQ(g.exit_code, 1) << g.output;
  EXPECT_NE(g.output.find("seed 2: the robot cannot retrieve the target even with every other object gone; next"), std::string::npos)
      << g.output;
  EXPECT_NE(g.output.find("none of 2 scenes qualified (a removal needed); in 2 of them the robot cannot retrieve the target even "
                          "from the shelf emptied of the others"),
            std::string::npos) << g.output;
  EXPECT_FALSE(fs::exists(dir_ / "s.yaml"));
}

// A URDF nested 50,000 deep used to end self-collisions with SIGSEGV; a device as the
// URDF was read without end. Both are bad input, located.
TEST_F(Cli, HostileUrdfsAreBadInputNotCrashes) {
  {
    std::ofstream urdf(dir_ / "deep.urdf");
    urdf << "<robot name=\"deep\"><link name=\"base\"/>";
    for (int i = 0; i < 50000; ++i) urdf << "<gazebo>";
    for (int i = 0; i < 50000; ++i) urdf << "</gazebo>";
    urdf << "</robot>\n";
  }
  for (const char* urdf : {"deep.urdf", "/dev/zero"}) {
    const std::string ur10 = test::read_text(fs::path(CLUTTERTAMP_SOURCE_DIR) / "domains/robots/ur10_ag95.yaml");
    std::ofstream(dir_ / "r.yaml") << test::replaced(ur10, "urdf: ur10_ag95.urdf",
                                                     "urdf: " + (std::string(urdf) == "/dev/zero" ? std::string(urdf)
                                                                                                   : (dir_ / urdf).string()));
    const CliRun r = run("self-collisions " + (dir_ / "r.yaml").string() + " --samples 100");
    EXPECT_EQ(r.exit_code, 2) << urdf << ": " << r.output;
    EXPECT_NE(r.output.find(std::string(urdf) == "/dev/zero" ? "/dev/zero: error: the URDF is not a regular file"
                                                              : "deep.urdf:1:"),
              std::string::npos)
        << r.output;
  }
}

TEST_F(Cli, GenerateAndBenchRetrievalRejectBadArguments) {
  EXPECT_EQ(run("generate --objects 12").exit_code, 2);                      // no --output
  EXPECT_EQ(run("generate --objects 0 --output x.yaml").exit_code, 2);       // out of range
  EXPECT_EQ(run("bench retrieval --scenes 0").exit_code, 2);
  // More cylinders than the cabinet holds: bad input that says why, not a crash.
  const CliRun crowded = run("generate --objects 100 --width 0.9 --depth 0.6 --attempts 1 --output " + (dir_ / "x.yaml").string());
  EXPECT_EQ(crowded.exit_code, 2) << crowded.output;
  EXPECT_NE(crowded.output.find("cannot place 100 cylinders"), std::string::npos) << crowded.output;
  EXPECT_EQ(run("bench retrieval --sizes 12 --time-limit -1").exit_code, 2);
  EXPECT_EQ(run("bench retrieval --table VII").exit_code, 2);
  // An unwritable --json file is bad input that names it (every bench writes it one way):
  // here its directory would have to be made inside a file. (A missing directory is made.)
  std::ofstream(dir_ / "a-file") << "x";
  const CliRun unwritable = run("bench collision --samples 500 --json " + (dir_ / "a-file" / "c.json").string());
  EXPECT_EQ(unwritable.exit_code, 2) << unwritable.output;
  EXPECT_NE(unwritable.output.find("c.json: error: cannot write the JSON file"), std::string::npos) << unwritable.output;
  EXPECT_EQ(run("bench retrieval --table VI --table6-scenes " + (dir_ / "none").string()).exit_code, 2);
  EXPECT_EQ(run("generate --objects 12 --min-removals 1 --output x.yaml").exit_code, 2);  // 2 at least
}

// IK on reachable poses: the share solved does not depend on the machine (the poses
// and the restarts are seeded), only the times do.
TEST_F(Cli, BenchCollisionSolvesReachablePosesWithTheNumericIk) {
  const fs::path json_file = dir_ / "c.json";
  const CliRun r = run("bench collision --samples 500 --robot " + (fs::path(CLUTTERTAMP_SOURCE_DIR) / "domains/robots/panda.yaml").string() +
                       " --json " + json_file.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;  // a speed goal missed on this machine is no failure without --check-goals
  EXPECT_NE(r.output.find("numeric IK on 500 reachable poses"), std::string::npos) << r.output;
  std::ifstream in(json_file);
  const nlohmann::json j = nlohmann::json::parse(in);
  EXPECT_EQ(j["ik_reachable"]["poses"].get<int>(), 500);
  EXPECT_GE(j["ik_reachable"]["solved_percent"].get<double>(), 98.0);
}

// A robot whose meshes are in a package: found through --package-path, and without it
// an error that says where to give one.
TEST_F(Cli, PackagePathFindsARobotsMeshes) {
  robot::TriangleMesh box;
  for (int i = 0; i < 8; ++i) box.vertices.emplace_back(i & 1 ? 0.05 : -0.05, i & 2 ? 0.05 : -0.05, i & 4 ? 0.2 : 0.0);
  box.triangles = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4}, {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  fs::create_directories(dir_ / "ws/src/my_robot/meshes");
  std::ofstream(dir_ / "ws/src/my_robot/meshes/link.stl") << robot::to_ascii_stl(box, "link");
  const std::string link = R"(<collision><geometry><mesh filename="package://my_robot/meshes/link.stl"/></geometry></collision>)";
  std::ofstream(dir_ / "r.urdf") << R"(<?xml version="1.0"?>
<robot name="r">
  <link name="base">)" << link << R"(</link>
  <link name="a">)" << link << R"(</link>
  <link name="b">)" << link << R"(</link>
  <link name="tcp"/>
  <joint name="j1" type="revolute"><parent link="base"/><child link="a"/><origin xyz="0 0 0.2"/><axis xyz="0 1 0"/><limit lower="-2" upper="2" velocity="1" effort="1"/></joint>
  <joint name="j2" type="revolute"><parent link="a"/><child link="b"/><origin xyz="0 0 0.2"/><axis xyz="0 1 0"/><limit lower="-2.5" upper="2.5" velocity="1" effort="1"/></joint>
  <joint name="t" type="fixed"><parent link="b"/><child link="tcp"/><origin xyz="0 0 0.2"/></joint>
</robot>
)";
  std::ofstream(dir_ / "r.yaml") << "version: 1\nurdf: r.urdf\nbase_link: base\ntip_link: tcp\nik: numeric\n"
                                    "gripper: {finger_thickness: 0.01, base_half_length: 0.05, stroke: 0.08}\n";
  const CliRun found = run("self-collisions " + (dir_ / "r.yaml").string() + " --samples 300 --package-path " + (dir_ / "ws").string());
  EXPECT_EQ(found.exit_code, 0) << found.output;
  EXPECT_NE(found.output.find("base"), std::string::npos) << found.output;
  const CliRun missing = run("self-collisions " + (dir_ / "r.yaml").string() + " --samples 300");
  EXPECT_EQ(missing.exit_code, 2) << missing.output;
  EXPECT_NE(missing.output.find("r.urdf:3:"), std::string::npos) << missing.output;
  EXPECT_NE(missing.output.find("no package path to find package 'my_robot'"), std::string::npos) << missing.output;
}

// Table V compares retrieval_graph with the traversability graph run by run: the JSON's
// `paired` figures are the means over the runs both solved, as the CSV gives them.
TEST_F(Cli, BenchRetrievalPairsTableFiveWithItsBaseline) {
  const fs::path csv = dir_ / "v.csv", json_file = dir_ / "v.json";
  const CliRun r = run("bench retrieval -q --table V --table5-width 4.5 --min-gap 0.01 --scenes 2 --runs 1 --csv " + csv.string() +
                       " --json " + json_file.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("paired with traversability_graph on the"), std::string::npos) << r.output;
  std::map<std::string, std::map<std::string, int>> removed;  // planner -> scene -> |O_r| when solved
  for (const auto& cells : csv_rows(csv)) {
    ASSERT_EQ(cells.size(), 16u);
    if (cells[4] == "1") removed[cells[11]][cells[15]] = std::stoi(cells[5]);
  }
  int both = 0;
  double ours = 0, theirs = 0;
  for (const auto& [scene, n] : removed["retrieval_graph"]) {
    if (!removed["traversability_graph"].count(scene)) continue;
    ++both;
    ours += n;
    theirs += removed["traversability_graph"][scene];
  }
  std::ifstream jin(json_file);
  const auto json = nlohmann::json::parse(jin);
  ASSERT_EQ(json.size(), 2u);
  EXPECT_TRUE(json[0]["paired"].is_null());  // the baseline's own row
  const auto& paired = json[1]["paired"];
  EXPECT_EQ(paired["against"], "traversability_graph");
  EXPECT_EQ(paired["runs"], both);
  // The baseline fails the first of these scenes, which the pairing leaves out.
  EXPECT_LT(both, static_cast<int>(removed["retrieval_graph"].size()));
  if (both > 0) {
    EXPECT_DOUBLE_EQ(paired["removed"].get<double>(), ours / both);
    EXPECT_DOUBLE_EQ(paired["against_removed"].get<double>(), theirs / both);
  }
}

// One scene, one run per L strategy: the table, CSV and JSON say the same thing.
TEST_F(Cli, BenchRetrievalWritesTableCsvAndJson) {
  const fs::path csv = dir_ / "r.csv", json_file = dir_ / "r.json";
  const CliRun r = run("bench retrieval -q --sizes 12 --scenes 1 --runs 1 --time-limit 30 --csv " + csv.string() +
                       " --json " + json_file.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("nodecol"), std::string::npos) << r.output;
  std::ifstream in(csv);
  std::string line;
  int rows = 0, solved = 0;
  std::getline(in, line);
  EXPECT_EQ(line,
            "objects,initial_L,instance,run,solved,removed,time_s,task_s,motion_s,iterations,table,planner,scenes,sequences,"
            "seed,scene");
  while (std::getline(in, line)) {
    ++rows;
    EXPECT_NE(line.find(",1,\"shelf12-seed"), std::string::npos) << line;  // run seed 1, the scene's name
    if (line.rfind("12,", 0) == 0 && line.find(",0,0,1,") != std::string::npos) ++solved;
  }
  EXPECT_EQ(rows, 4);  // three initial limits and the traversability graph
  std::ifstream jin(json_file);
  const auto json = nlohmann::json::parse(jin);
  ASSERT_EQ(json.size(), 4u);
  double rate = 0;
  for (const auto& row : json) {
    EXPECT_EQ(row["objects"], 12);
    EXPECT_EQ(row["table"], "I");
    rate += row["success_rate"].get<double>();
  }
  EXPECT_EQ(json[0]["planner"], "retrieval_graph");
  EXPECT_EQ(json[0]["initial_L"], "one");
  EXPECT_DOUBLE_EQ(json[0]["paper"]["removed"]["mean"].get<double>(), 2.14);
  EXPECT_EQ(json[3]["planner"], "traversability_graph");
  EXPECT_DOUBLE_EQ(rate, 100.0 * solved);
}

TEST_F(Cli, PluginsListsKindsAndVersions) {
  const CliRun r = run("plugins --plugin-path " + test::plugin_dir("good").string() + " --plugin-path " +
                    test::plugin_dir("abi").string());
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("task_planner      test_planner          1.2.3"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("grasp_sampler     test_grasp"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("plugin ABI version 999"), std::string::npos) << r.output;
}

// plugins NAME shows only that name (every kind of it) and, with -v, its parameters; a
// name no plugin has is bad input naming what exists.
TEST_F(Cli, PluginsByNameShowsTheirParameters) {
  const CliRun r = run("plugins -v retrieval_graph");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("task_planner      retrieval_graph"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("object_pruner     retrieval_graph"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("grasp_side"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("initial_L"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("region"), std::string::npos) << r.output;

  const CliRun missing = run("plugins retrieval_grahp");
  EXPECT_EQ(missing.exit_code, 2) << missing.output;
  EXPECT_NE(missing.output.find("no plugin named 'retrieval_grahp'; found: "), std::string::npos) << missing.output;
  EXPECT_NE(missing.output.find("retrieval_graph"), std::string::npos) << missing.output;
}

// Guided planning (grtc) on a bundled shelf with its guidance file: one push step per
// guide, then the reach; replayed step by step through the physics, each guide's object
// ends in its region, nothing falls, and the gripper ends at the target.
TEST_F(Cli, GuidedPlansSatisfyEveryGuideAndReachTheTargetWhenReplayed) {
  const fs::path source = fs::path(CLUTTERTAMP_SOURCE_DIR) / "problems/push/shelf10/p06.yaml";
  const fs::path file = bundled_copy(source, "guided.yaml",
                                     {{"plugin: rtc_ompl", "plugin: grtc"},
                                      {"parameters: {planner: rrt, max_propagations: 20000}",
                                       "parameters: {planner: rrt, max_propagations: 20000, guidance: p06-guidance.yaml}\n"
                                       "plugins: {push_sampler: push_ompl}"}});
  const CliRun r = plan(file, "--seed 1 --time-limit 300");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json j = result();
  const Problem problem = io::load_problem(file);
  const Scene& scene = problem.scene;
  const auto guidance = io::load_guidance(source.parent_path() / "p06-guidance.yaml", scene,
                                          physics::PushWorld(scene, WorldState::initial(scene)).support_region());
  ASSERT_FALSE(guidance.empty());
  ASSERT_EQ(j["plan"].size(), guidance.size() + 1) << "a push per guide, then the reach";
  WorldState state = WorldState::initial(scene);
  Eigen::Vector3d gripper = physics::gripper_at_exit(scene);
  for (std::size_t k = 0; k < j["plan"].size(); ++k) {
    SCOPED_TRACE("step " + std::to_string(k + 1));
    const nlohmann::json& step = j["plan"][k];
    EXPECT_EQ(step["action"], "push");
    const physics::PushWorld world(scene, state);
    const physics::Replay replay = physics::replay(world, world.state_of(state, gripper),
                                                   push_controls(step["values"]["controls"].get<std::vector<double>>()),
                                                   step["values"]["step"][0].get<double>());
    EXPECT_TRUE(replay.valid);
    if (k < guidance.size()) {
      EXPECT_EQ(step["values"]["guide"][0].get<double>(), double(k + 1));
      const Eigen::Vector2d object = replay.end.objects[guidance[k].object].pose.head<2>();
      EXPECT_LE((object - guidance[k].centre).norm(), guidance[k].diameter / 2 + 1e-9) << "the guide holds";
    } else {
      expect_target_between_fingers(scene, replay.end);
    }
    state = physics::world_state_of(state, replay.end);
    gripper = replay.end.gripper;
  }
  EXPECT_EQ(j["counters"]["guides_satisfied"], guidance.size());
}

// Tian et al. VI-G: the retrieval planner pushes o3 aside instead of picking and
// placing it. Replayed, the push moves o3 alone and stays valid; the retrieval's
// configurations do not touch o3 where the push left it. Without a push sampler the
// run says what is missing.
TEST_F(Cli, RetrievalWithPushesPushesAsideWhatItCanAndRetrievesTheTarget) {
  const fs::path source = fs::path(CLUTTERTAMP_SOURCE_DIR) / "problems/push/retrieve-push.yaml";
  const CliRun r = plan(source, "--seed 0");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json j = result();
  ASSERT_EQ(j["plan"].size(), 2u) << j["plan"].dump();
  EXPECT_EQ(j["plan"][0]["action"], "push");
  EXPECT_EQ(j["plan"][0]["objects"], nlohmann::json::array({"o3"}));
  EXPECT_EQ(j["plan"][1]["action"], "retrieve");
  EXPECT_EQ(j["counters"]["pushes"], 1);

  const Problem problem = io::load_problem(source);
  const Scene& scene = problem.scene;
  WorldState state = WorldState::initial(scene);
  state.robot_configuration = robot::initial_configuration(problem.robot);
  const physics::PushWorld world(scene, state);
  const physics::Replay replay =
      physics::replay(world, world.state_of(state, physics::gripper_at_exit(scene)), push_controls(j["plan"][0]["values"]["controls"].get<std::vector<double>>()),
                      j["plan"][0]["values"]["step"][0].get<double>());
  EXPECT_TRUE(replay.valid);
  const ObjectIndex o3 = *scene.find_object("o3");
  for (ObjectIndex i = 0; i < scene.objects.size(); ++i) {
    const double moved = (replay.end.objects[i].pose.head<2>() - state.world_T_objects[i].translation().head<2>()).norm();
    if (i == o3) EXPECT_GT(moved, 0.05); else EXPECT_LT(moved, 0.01) << scene.objects[i].id;
  }
  state = physics::world_state_of(state, replay.end);
  collision::CollisionWorld collisions(scene, problem.robot.loaded);
  collisions.sync(state);
  const auto context = collisions.make_context();
  std::vector<ObjectIndex> others;
  for (ObjectIndex i = 0; i < scene.objects.size(); ++i) {
    if (i != o3) others.push_back(i);
  }
  for (const auto& q : j["plan"][1]["trajectory"]["positions"]) {
    const std::vector<double> v = q.get<std::vector<double>>();
    EXPECT_FALSE(collisions.touches_object(Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size())), *context, others));
  }

  const fs::path without = bundled_copy(source, "no-push-sampler.yaml", {{"  push_sampler: push_ompl\n", ""}});
  const CliRun missing = plan(without);  // bad input, found before planning
  EXPECT_EQ(missing.exit_code, 2) << missing.output;
  EXPECT_NE(missing.output.find("planner 'retrieval_graph' needs a push_sampler"), std::string::npos) << missing.output;
}

// Fisher's exact test as bench push reports it, against the exact sums of binomial
// coefficients (computed apart, in Python) and the tea-tasting table; equal rates give 1.
TEST(BenchStatistics, FishersExactTestMatchesKnownValues) {
  EXPECT_NEAR(bench::fisher_exact_p(3, 4, 1, 4), 0.4857, 1e-4);
  EXPECT_NEAR(bench::fisher_exact_p(38, 60, 30, 60), 0.19701, 1e-5);
  EXPECT_NEAR(bench::fisher_exact_p(10, 10, 0, 10), 1.0825e-5, 1e-8);
  EXPECT_NEAR(bench::fisher_exact_p(5, 10, 5, 10), 1.0, 1e-12);
  EXPECT_NEAR(bench::fisher_exact_p(0, 10, 10, 10), bench::fisher_exact_p(10, 10, 0, 10), 1e-15);
}

// A guide that cannot be satisfied (its region is where a fixed post stands) is kept as
// a failure and passed over by default (no parameter): the run still reaches the
// target. With `unsatisfied_guides: stop` it ends the run with the guide's reason.
TEST_F(Cli, AGuideThatCannotBeSatisfiedIsSkippedUnlessTheProblemSaysStop) {
  const fs::path push_dir = fs::path(CLUTTERTAMP_SOURCE_DIR) / "problems/push";
  const fs::path scene = dir_ / "post-scene.yaml";
  std::ofstream(scene) << test::read_text(push_dir / "easy-scene.yaml")
                       << "  - {id: post, cylinder: {radius: 0.04, height: 0.26}, pose: {xyz: [0.95, 0.25, 0.53]}, "
                          "mass: 1, movable: false}\n";
  const fs::path guidance = dir_ / "post-guidance.yaml";
  std::ofstream(guidance) << "version: 1\nguides:\n  - {object: o3, centre: [0.95, 0.25], diameter: 0.04}\n";
  for (const std::string mode : {"skip", "stop"}) {
    SCOPED_TRACE(mode);
    const fs::path file = bundled_copy(push_dir / "easy-guided.yaml", "post-" + mode + ".yaml",
                                       {{"scene: easy-scene.yaml", "scene: " + scene.string()},
                                        {"guidance: auto", "guidance: " + guidance.string() + ", steer: 0.3" +
                                                               (mode == "stop" ? ", unsatisfied_guides: stop" : "")},
                                        // A small work budget for the guide that cannot be satisfied.
                                        {"push_sampler: push_ompl",
                                         "push_sampler: {plugin: push_ompl, parameters: {max_propagations: 2000}}"}});
    const CliRun r = plan(file, "--seed 1 --time-limit 300");
    const nlohmann::json j = result();
    EXPECT_EQ(j["counters"]["guides_satisfied"], 0);
    ASSERT_FALSE(j["failures"].empty());
    EXPECT_EQ(j["failures"][0]["reason"].get<std::string>().rfind("guide 1 (push 'o3'", 0), 0u) << j["failures"].dump();
    if (mode == "skip") {
      ASSERT_EQ(r.exit_code, 0) << r.output;
      EXPECT_EQ(j["counters"]["guides_skipped"], 1);
      ASSERT_EQ(j["plan"].size(), 1u) << "the reach alone";
      EXPECT_EQ(j["plan"][0]["values"].count("guide"), 0u);
    } else {
      EXPECT_EQ(r.exit_code, 1) << r.output;
      EXPECT_EQ(j["counters"]["guides_skipped"], 0);
      EXPECT_EQ(j["reason"].get<std::string>().rfind("guide 1 (push 'o3'", 0), 0u) << j["reason"];
    }
  }
}

// A guidance file naming an unknown object, or a region off the shelf, is bad input.
TEST_F(Cli, ABadGuidanceFileIsBadInputWithItsLine) {
  const fs::path source = fs::path(CLUTTERTAMP_SOURCE_DIR) / "problems/push/shelf10/p06.yaml";
  const fs::path guidance = dir_ / "bad-guidance.yaml";
  std::ofstream(guidance) << "version: 1\nguides:\n  - {object: o3, centre: [0.7, 0.1], diameter: 0.1}\n"
                             "  - {object: o99, centre: [0.7, 0.1], diameter: 0.1}\n"
                             "  - {object: o2, centre: [2.5, 0.1], diameter: 0.1}\n";
  const fs::path file = bundled_copy(source, "bad-guided.yaml",
                                     {{"plugin: rtc_ompl", "plugin: grtc"},
                                      {"parameters: {planner: rrt, max_propagations: 20000}", "parameters: {guidance: " + guidance.string() +
                                                                         "}\nplugins: {push_sampler: push_ompl}"}});
  const CliRun r = plan(file, "--time-limit 10");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("bad-guidance.yaml:4:14: error: guide #2: unknown object 'o99'"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("bad-guidance.yaml:5:26: error: guide #3: the region about (2.5, 0.1)"), std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("is not inside the shelf"), std::string::npos) << r.output;
  // validate reads the planner's guidance file as plan does: the same errors, first.
  const CliRun v = run("validate " + file.string());
  EXPECT_EQ(v.exit_code, 2) << v.output;
  EXPECT_NE(v.output.find("bad-guidance.yaml:4:14: error: guide #2: unknown object 'o99'"), std::string::npos) << v.output;
  EXPECT_NE(v.output.find("bad-guidance.yaml:5:26: error: guide #3"), std::string::npos) << v.output;
}

// `guide` writes the automatic guidance, which load_guidance reads back.
// Algorithm 4 end to end: the bundled 12-object occlusion shelf is solved, and every
// object the plan moves had been seen (or found) by the time it was moved.
TEST_F(Cli, TheOcclusionPlannerRetrievesAHiddenTargetMovingOnlyWhatItHadSeen) {
  const fs::path problem_file = fs::path(CLUTTERTAMP_SOURCE_DIR) / "problems/occlusion/occ12.yaml";
  const auto [r, result] = planned(problem_file, "occ");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::vector<std::string> moved = result["moved_objects"];
  ASSERT_FALSE(moved.empty());
  EXPECT_EQ(moved.back(), "target");
  EXPECT_EQ(result["counters"]["observed_initially"], 3);
  EXPECT_GT(result["counters"]["revealed"].get<int>(), 0);
  const Problem problem = io::load_problem(problem_file);
  perception::ObservedWorld world(problem.scene, WorldState::initial(problem.scene));
  EXPECT_FALSE(world.known(problem.scene.target));  // hidden at the start
  const bool touched = result["counters"].value("found_by_touch", 0) > 0;
  for (const std::string& id : moved) {
    const ObjectIndex o = *problem.scene.find_object(id);
    if (!touched) EXPECT_TRUE(world.known(o)) << id << " moved before it was seen";
    world.remove(o);
  }
}

// Occlusion shelves drawn as Table I's, solved where the planner once gave up: 12
// objects seed 2 (the object hiding the target waits on a neighbour's removal: its
// blocker goes first, and a temporary goal with no way there is given up for the next),
// 20 objects seed 3 (the target and a neighbour block each other's grasps: another grasp
// of the neighbour, whose blockers go first), 16 objects seed 8 (the graph has no way
// left once an object the target blocks is given up on: the robot retrieves the target
// past it). The final removal sequence is a part of what was moved, the target in it.
TEST_F(Cli, TheOcclusionPlannerSolvesRandomShelvesAndCountsTheFinalSequence) {
  for (const auto& [objects, seed] : {std::pair{12, 2}, std::pair{20, 3}, std::pair{16, 8}}) {
    const std::string name = "occr" + std::to_string(objects) + "-" + std::to_string(seed);
    const fs::path problem = dir_ / (name + "-problem.yaml");
    const CliRun g = run("generate --occlusion --occlusion-layout random --objects " + std::to_string(objects) + " --seed " +
                         std::to_string(seed) + " --any --attempts 1 -q --output " + (dir_ / (name + ".yaml")).string() +
                         " --problem " + problem.string());
    ASSERT_EQ(g.exit_code, 0) << g.output;
    const auto [r, result] = planned(problem, name, "-q");
    ASSERT_EQ(r.exit_code, 0) << name << ": " << r.output;
    const std::vector<std::string> moved = result["moved_objects"];
    EXPECT_EQ(moved.back(), "target") << name;
    const int final_sequence = result["counters"]["final_sequence"];
    EXPECT_GE(final_sequence, 2) << name;  // the target was hidden: something in front had to go
    EXPECT_LE(final_sequence, static_cast<int>(moved.size())) << name;
  }
  // --occlusion-layout belongs to --occlusion.
  EXPECT_EQ(run("generate --occlusion-layout random --objects 12 -q --output " + (dir_ / "x.yaml").string()).exit_code, 2);
}

// Algorithm 4's x_temp lies behind the deepest observed object; among equally deep
// ones (the front row of occ16, all four at the same depth) it looks behind the one
// nearest the line from x_s first: a middle column, reached straightest.
TEST_F(Cli, TheOcclusionPlannerLooksBehindTheMiddleColumnsFirst) {
  const fs::path problem_file = fs::path(CLUTTERTAMP_SOURCE_DIR) / "problems/occlusion/occ16.yaml";
  const auto [r, result] = planned(problem_file, "occ16");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::vector<std::string> moved = result["moved_objects"];
  ASSERT_FALSE(moved.empty());
  EXPECT_TRUE(moved.front() == "o4" || moved.front() == "o8") << moved.front();  // the middle fronts (y = -0.07, 0.07)
  EXPECT_EQ(moved.back(), "target");
}

// On a table the carry may lift the target over its neighbours: with grasp_orders, the
// blockers of one of its grasps alone replace the graph's longer way (table seed 45:
// o1 alone, where the target's footprint path needs two).
TEST_F(Cli, OnATableOneGraspsBlockersCanReplaceTheGraphsLongerWay) {
  const fs::path scene = dir_ / "t45.yaml", with = dir_ / "p45.yaml", without = dir_ / "p45-off.yaml";
  ASSERT_EQ(run("generate --table --objects 20 --seed 45 --any --attempts 1 -q --output " + scene.string() + " --problem " +
                with.string())
                .exit_code,
            0);
  const std::string text = test::read_text(with);
  ASSERT_NE(text.find("grasp_orders: 3"), std::string::npos) << text;
  std::ofstream(without) << test::replaced(text, "grasp_orders: 3", "grasp_orders: 0");
  // A generous work budget per try.
  std::ofstream(with) << test::replaced(text, "grasp_orders: 3", "grasp_orders: 3, shorten_max_checks: 3000000");
  auto plan_of = [&](const fs::path& problem) {
    const auto [r, result] = planned(problem, problem.stem().string(), "-q");
    EXPECT_EQ(r.exit_code, 0) << r.output;
    return result;
  };
  const auto on = plan_of(with), off = plan_of(without);
  EXPECT_EQ(on["counters"].value("grasp_orders_taken", 0), 1);
  EXPECT_FALSE(off["counters"].contains("grasp_orders_taken"));
  EXPECT_LT(on["moved_objects"].size(), off["moved_objects"].size()) << on["moved_objects"] << off["moved_objects"];
  EXPECT_EQ(on["moved_objects"].back(), "target");
}

// Section V-B: a mobile manipulator that plans from every side of a table takes the
// target out by the side that needs fewest removals: one, where planning from the
// robot's side needs more.
TEST_F(Cli, AMobileManipulatorTakesTheTargetOutWhereFewestObjectsBlock) {
  const fs::path dir = fs::path(CLUTTERTAMP_SOURCE_DIR) / "problems/mobile";
  auto moved = [&](const std::string& problem) {
    const auto [r, result] = planned(dir / problem, problem);
    EXPECT_EQ(r.exit_code, 0) << r.output;
    return result["moved_objects"].get<std::vector<std::string>>();
  };
  const std::vector<std::string> all_sides = moved("ring-all-sides.yaml");
  const std::vector<std::string> one_side = moved("ring-one-side.yaml");
  ASSERT_EQ(all_sides.size(), 2u) << "one removal, then the target";
  EXPECT_EQ(all_sides.back(), "target");
  EXPECT_EQ(all_sides.front().rfind("inner", 0), 0u) << all_sides.front();  // through the inner ring only
  EXPECT_GE(one_side.size(), 3u);
}

// bench mobile keeps only tables like the paper's Fig. 9 unless told otherwise: it says
// why it passes each seed over (-v) and keeps the first it does not; on the one kept,
// L = 1 moves at least the one object in the way and the target. Which seeds qualify
// depends on the shipped samplers, so the test reads them from the output.
TEST_F(Cli, BenchMobileRunsOnTablesLikeTheFigureNine) {
  const fs::path csv = dir_ / "m.csv", json_file = dir_ / "m.json";
  // The checks and runs are finite work: the time limit is an outer limit only, never
  // reached, even by a sanitizer build.
  const CliRun r = run("bench mobile -v --seed 0 --scenes 1 --runs 1 --time-limit 3000 --csv " + csv.string() + " --json " + json_file.string());
  EXPECT_EQ(r.exit_code, 0) << r.output;
  std::string sentences = r.output;  // the header is wrapped to 100 columns
  std::replace(sentences.begin(), sentences.end(), '\n', ' ');
  EXPECT_NE(sentences.find("like the paper's Fig. 9"), std::string::npos) << r.output;
  int passed_over = 0;
  for (std::size_t at = 0; (at = r.output.find("table seed " + std::to_string(passed_over) + ": ", at)) != std::string::npos;) {
    const std::string why = r.output.substr(at, r.output.find('\n', at) - at);
    EXPECT_TRUE(why.find("no single object frees the target") != std::string::npos ||
                why.find("comes out directly") != std::string::npos || why.find("one object frees the target from the robot's side") != std::string::npos)
        << why;
    EXPECT_EQ(why.find("time limit"), std::string::npos) << why;
    ++passed_over;
  }
  // Seed 0's table fails the filter with today's samplers; should it pass one day, start
  // this test at a seed that does not, so that the filter is exercised.
  EXPECT_GE(passed_over, 1) << r.output;
  const auto json = nlohmann::json::parse(test::read_text(json_file));
  EXPECT_EQ(json["table_selection"], "fig9");
  EXPECT_EQ(json["tables"], 1);
  const auto rows = csv_rows(csv);
  ASSERT_EQ(rows.size(), 3u);  // the three initial limits
  for (const auto& cells : rows) {
    ASSERT_GE(cells.size(), 6u);
    EXPECT_EQ(cells[1], std::to_string(passed_over)) << cells[0];  // the first seed not passed over
    if (cells[3] == "1") EXPECT_GE(std::stoi(cells[5]), 2) << cells[0];
  }
  const fs::path random_csv = dir_ / "r.csv";
  const CliRun random =
      run("bench mobile -q --seed 0 --scenes 1 --runs 1 --time-limit 3000 --mobile-tables random --csv " + random_csv.string() + " --json " + json_file.string());
  EXPECT_EQ(random.exit_code, 0) << random.output;
  EXPECT_EQ(nlohmann::json::parse(test::read_text(json_file))["table_selection"], "random");
  const auto random_rows = csv_rows(random_csv);
  ASSERT_EQ(random_rows.size(), 3u);
  for (const auto& cells : random_rows) EXPECT_EQ(cells.at(1), "0") << cells[0];  // the first seed, whatever it is like
  // A check the time limit ends is no verdict on the table: the bench stops rather than
  // choose other tables on a slower machine. No check finishes within a nanosecond.
  const CliRun undecided = run("bench mobile -q --seed 0 --scenes 1 --runs 1 --time-limit 1e-9");
  EXPECT_EQ(undecided.exit_code, 1) << undecided.output;
  EXPECT_NE(undecided.output.find("table seed 0: whether one object frees the target from some side was not decided"), std::string::npos)
      << undecided.output;
  // A goal missed is exit code 1 only when asked: no run is solved within a nanosecond.
  const std::string unsolved = "bench mobile -q --seed 0 --scenes 1 --runs 1 --time-limit 1e-9 --mobile-tables random";
  EXPECT_EQ(run(unsolved).exit_code, 0);
  const CliRun checked = run(unsolved + " --check-goals");
  EXPECT_EQ(checked.exit_code, 1) << checked.output;
  EXPECT_NE(checked.output.find("goal (L = 1): |O_r| <= 2.2 and median <= 1 s: NOT met"), std::string::npos) << checked.output;
  EXPECT_EQ(run("bench mobile --mobile-tables some").exit_code, 2);
}

TEST_F(Cli, ObserveSaysWhatTheCameraSeesAndWhatARemovalReveals) {
  const fs::path scene = fs::path(CLUTTERTAMP_SOURCE_DIR) / "problems/occlusion/occ12-scene.yaml";
  const CliRun before = run("observe " + scene.string() + " --json");
  ASSERT_EQ(before.exit_code, 0) << before.output;
  int observed = 0;
  for (const auto& v : nlohmann::json::parse(before.output)) observed += v["observed"].get<bool>() ? 1 : 0;
  EXPECT_EQ(observed, 3);  // the front row
  const CliRun after = run("observe " + scene.string() + " --remove o1");
  ASSERT_EQ(after.exit_code, 0) << after.output;
  EXPECT_NE(after.output.find("o2          observed"), std::string::npos) << after.output;
  EXPECT_EQ(run("observe " + scene.string() + " --remove nothing").exit_code, 2);
  const CliRun blind = run("observe " + (fs::path(CLUTTERTAMP_TEST_DATA) / "scenes/good.yaml").string());
  EXPECT_EQ(blind.exit_code, 2) << blind.output;
  EXPECT_NE(blind.output.find("no camera"), std::string::npos) << blind.output;
}

TEST_F(Cli, GuideWritesTheAutomaticGuidance) {
  const fs::path source = fs::path(CLUTTERTAMP_SOURCE_DIR) / "problems/push/shelf10/p06.yaml";
  const CliRun r = run("guide " + source.string() + " --auto --output " + (dir_ / "g.yaml").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("wrote " + (dir_ / "g.yaml").string() + ": "), std::string::npos) << r.output;
  EXPECT_EQ(test::read_text(dir_ / "g.yaml"), test::read_text(source.parent_path() / "p06-guidance.yaml"))
      << "the bundled guidance is the generator's (scripts/make-push-scenes.sh)";
  const Problem problem = io::load_problem(source);
  const auto guidance = io::load_guidance(dir_ / "g.yaml", problem.scene,
                                          physics::PushWorld(problem.scene, WorldState::initial(problem.scene)).support_region());
  EXPECT_FALSE(guidance.empty());
  // Without --auto, guide serves a session into a directory: a guidance file named
  // as the output is refused rather than served into.
  const CliRun serve = run("guide " + source.string() + " --output " + (dir_ / "h.yaml").string());
  EXPECT_EQ(serve.exit_code, 2) << serve.output;
  EXPECT_NE(serve.output.find("add --auto"), std::string::npos) << serve.output;
}

TEST_F(Cli, PlanHtmlAndViewWriteAReplayPageAndABadResultIsBadInput) {
  const fs::path source = fs::path(CLUTTERTAMP_SOURCE_DIR) / "problems/push/retrieve-push.yaml";
  const CliRun r = run("plan " + source.string() + " --html -o " + (dir_ / "out").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::string page = test::read_text(dir_ / "out/plan.html");
  EXPECT_NE(page.find("THREE.WebGLRenderer"), std::string::npos);  // three.js is inlined
  EXPECT_EQ(page.find("src=\"http"), std::string::npos);           // and nothing is fetched
  EXPECT_NE(page.find("\"action\":\"push\""), std::string::npos);
  EXPECT_TRUE(fs::exists(dir_ / "out/drawings.json"));

  const CliRun view = run("view " + (dir_ / "out/result.json").string() + " -o " + (dir_ / "again.html").string());
  ASSERT_EQ(view.exit_code, 0) << view.output;
  EXPECT_TRUE(fs::exists(dir_ / "again.html"));

  std::ofstream(dir_ / "bad.json") << "{\"problem\": 3}";
  const CliRun bad = run("view " + (dir_ / "bad.json").string());
  EXPECT_EQ(bad.exit_code, 2) << bad.output;
  EXPECT_NE(bad.output.find((dir_ / "bad.json").string()), std::string::npos) << bad.output;
}

}  // namespace
}  // namespace cluttertamp

namespace cluttertamp {
namespace {

std::string pddl_file(const std::string& relative) { return test::data("pddl/" + relative).string(); }

TEST(CliPddl, PrintsAnIpcPlanThatValidatePlanAccepts) {
  const auto plan_file = std::filesystem::temp_directory_path() / "cluttertamp_cli_gripper.plan";
  const CliRun r = run("pddl " + pddl_file("gripper/domain-untyped.pddl") + " " + pddl_file("gripper/p4.pddl") +
                       " --search astar-lmcut --plan " + plan_file.string());
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("(pick ball"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("; cost = 11 (unit cost)"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("grounding: "), std::string::npos);  // statistics on stderr
  EXPECT_NE(r.output.find(" expanded, "), std::string::npos);
  const CliRun valid = run("validate-plan " + pddl_file("gripper/domain-untyped.pddl") + " " +
                           pddl_file("gripper/p4.pddl") + " " + plan_file.string());
  EXPECT_EQ(valid.exit_code, 0) << valid.output;
  EXPECT_NE(valid.output.find("plan valid: 11 steps, cost 11"), std::string::npos) << valid.output;
  std::ofstream(plan_file) << "(pick ball1 rooma left)\n(drop ball1 roomb left)\n";
  const CliRun invalid = run("validate-plan " + pddl_file("gripper/domain-untyped.pddl") + " " +
                             pddl_file("gripper/p4.pddl") + " " + plan_file.string());
  EXPECT_EQ(invalid.exit_code, 1) << invalid.output;
  EXPECT_NE(invalid.output.find("plan invalid: step 2 (drop ball1 roomb left): precondition not satisfied"), std::string::npos);
  std::filesystem::remove(plan_file);
}

TEST(CliPddl, AnytimePrintsEachBetterPlanAndLeavesTheBestInThePlanFile) {
  const auto plan_file = std::filesystem::temp_directory_path() / "cluttertamp_cli_anytime.plan";
  const CliRun r = run("pddl " + pddl_file("gripper/domain-untyped.pddl") + " " + pddl_file("gripper/p6.pddl") +
                       " --search lama-first --anytime --max-expansions 1000000 --plan " + plan_file.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("plan 1: cost "), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("; cost = 17 (unit cost)"), std::string::npos) << r.output;  // the optimum
  EXPECT_NE(r.output.find("stopped: no cheaper plan exists"), std::string::npos) << r.output;
  const CliRun valid = run("validate-plan " + pddl_file("gripper/domain-untyped.pddl") + " " +
                           pddl_file("gripper/p6.pddl") + " " + plan_file.string());
  EXPECT_NE(valid.output.find("plan valid: 17 steps, cost 17"), std::string::npos) << valid.output;
  std::filesystem::remove(plan_file);
  const CliRun full = run("pddl " + pddl_file("gripper/domain-untyped.pddl") + " " + pddl_file("gripper/p4.pddl") +
                          " --plan /dev/full");
  EXPECT_EQ(full.exit_code, 3) << "a write failing during the run is a fault: " << full.output;
  EXPECT_NE(full.output.find("/dev/full"), std::string::npos) << full.output;
}

// A tree in the IPC layout made here: one folder with a shared domain.pddl (problems
// p2 and p10, natural order), one with a domain file per problem, one problem that
// cannot be read.
TEST_F(Cli, BenchPddlRunsAnIpcTreeWithCoverageScoresAndValidation) {
  const std::string gripper_domain = test::read_text(test::data("pddl/gripper/domain-untyped.pddl"));
  fs::create_directories(dir_ / "tree/gripper");
  fs::create_directories(dir_ / "tree/pairs");
  std::ofstream(dir_ / "tree/gripper/domain.pddl") << gripper_domain;
  fs::copy_file(test::data("pddl/gripper/p4.pddl"), dir_ / "tree/gripper/p2.pddl");
  fs::copy_file(test::data("pddl/gripper/p6.pddl"), dir_ / "tree/gripper/p10.pddl");
  std::ofstream(dir_ / "tree/gripper/p3.pddl") << "(define (problem broken) (:domain gripper-strips)";
  std::ofstream(dir_ / "tree/pairs/domain_p01.pddl") << gripper_domain;
  fs::copy_file(test::data("pddl/gripper/p4.pddl"), dir_ / "tree/pairs/p01.pddl");
  std::ofstream(dir_ / "costs.txt") << "# best known\ngripper/p2 11\ngripper/p10 15\n";  // 15: better than any plan
  const CliRun r = run("bench pddl --instances " + (dir_ / "tree").string() + " --search lama-first --search astar-lmcut" +
                       " --runs 1 --parse-objects 0 --reference-costs " + (dir_ / "costs.txt").string() + " --csv " +
                       (dir_ / "runs.csv").string() + " --json " + (dir_ / "runs.json").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;  // the broken file, after the rest ran
  EXPECT_NE(r.output.find("p3.pddl:1:"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("1 problem file(s) refused"), std::string::npos) << r.output;
  EXPECT_LT(r.output.find("gripper/p2 "), r.output.find("gripper/p10 ")) << r.output;
  // Coverage per folder: p2, p3 (refused), p10; astar-lmcut scores 11/11 + 15/17.
  EXPECT_NE(r.output.find("gripper                           astar-lmcut          2/3     1.88"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("pairs                             astar-lmcut          1/1     1.00"), std::string::npos) << r.output;
  const std::string csv = test::read_text(dir_ / "runs.csv");
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 1 + 4 * 2);  // header, 4 problems x 2 searches
  EXPECT_NE(csv.find("\"gripper\",\"gripper/p10\",\"astar-lmcut\",1,1,\"\",17."), std::string::npos) << csv;
  const auto json = nlohmann::json::parse(test::read_text(dir_ / "runs.json"));
  EXPECT_EQ(json.at("runs").size(), 8u);
  EXPECT_EQ(json.at("per_domain").size(), 4u);  // 2 folders x 2 searches
  for (const auto& run : json.at("runs")) {
    if (run.at("solved").get<bool>()) EXPECT_TRUE(run.at("valid").get<bool>()) << run.dump();
  }
  std::ofstream(dir_ / "bad-costs.txt") << "gripper/p2 eleven\n";
  const CliRun bad = run("bench pddl --instances " + (dir_ / "tree").string() + " --runs 1 --parse-objects 0 --reference-costs " +
                         (dir_ / "bad-costs.txt").string());
  EXPECT_EQ(bad.exit_code, 2) << bad.output;
  EXPECT_NE(bad.output.find("bad-costs.txt:1:1: error: expected 'folder/problem cost'"), std::string::npos) << bad.output;
}

TEST(CliPddl, ExitCodesForBadInputAndNoPlan) {
  const CliRun bad = run("pddl " + pddl_file("clutter/paper-verbatim.pddl") + " " + pddl_file("clutter/stacked4.pddl"));
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.output.find("paper-verbatim.pddl:9:35: error: undeclared predicate 'at-pose'"), std::string::npos) << bad.output;
  EXPECT_NE(bad.output.find("^"), std::string::npos);
  const CliRun limited = run("pddl " + pddl_file("blocks/domain.pddl") + " " + pddl_file("blocks/p9-5.pddl") +
                             " --search astar-blind --max-expansions 50");
  EXPECT_EQ(limited.exit_code, 1) << limited.output;
  EXPECT_NE(limited.output.find("no plan: expansion limit"), std::string::npos) << limited.output;
  EXPECT_EQ(run("pddl " + pddl_file("blocks/domain.pddl") + " " + pddl_file("blocks/p4-1.pddl") + " --search magic").exit_code, 2);
  EXPECT_EQ(run("pddl " + pddl_file("blocks/domain.pddl") + " /no/such/problem.pddl").exit_code, 2);
}

// Reaching through clutter by pushing: both kinodynamic planners solve the easy shelf,
// and replaying the plan's controls through the physics from the start reaches the
// target with nothing off the shelf and no wall entered.
TEST_F(Cli, PushPlansReachTheTargetWhenTheirControlsAreReplayed) {
  const fs::path problem_file = fs::path(CLUTTERTAMP_SOURCE_DIR) / "problems/push/easy.yaml";
  const Problem problem = io::load_problem(problem_file);
  const Scene& scene = problem.scene;
  const WorldState initial = WorldState::initial(scene);
  const physics::PushWorld world(scene, initial);
  for (const std::string planner : {"rrt", "kpiece"}) {
    SCOPED_TRACE(planner);
    const fs::path file = bundled_copy(problem_file, "push_" + planner + ".yaml", {{"planner: rrt", "planner: " + planner}});
    const CliRun r = plan(file, "--seed 1");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const nlohmann::json j = result();
    EXPECT_EQ(j["task"]["type"], "reach");
    ASSERT_EQ(j["plan"].size(), 1u);
    const std::vector<double> controls = j["plan"][0]["values"]["controls"].get<std::vector<double>>();
    ASSERT_FALSE(controls.empty());
    ASSERT_EQ(controls.size() % 4, 0u);
    const double step = j["plan"][0]["values"]["step"][0].get<double>();
    // OMPL propagates a control step by step: replay() does the same.
    const physics::Replay replay =
        physics::replay(world, world.state_of(initial, physics::gripper_at_exit(scene)), push_controls(controls), step);
    EXPECT_TRUE(replay.valid) << "nothing fell, left the shelf or entered a wall";
    const physics::PushState& state = replay.end;
    const Eigen::Vector2d target = state.objects[scene.target].pose.head<2>();
    expect_target_between_fingers(scene, state);
    const auto& last = j["plan"][0]["trajectory"]["positions"].back();
    EXPECT_NEAR(last[0].get<double>(), state.gripper.x(), 1e-3) << "the replay ends where the plan says";
  }
}

// bench push reaches within the tolerances it is given, for every planner, and says
// which; a tolerance that is not positive is bad input. One easy scene, one seed, 3 s.
// bench push plans each problem with its own planner parameters (here a work budget of
// one propagation), and the bench's options override them for every run.
TEST_F(Cli, BenchPushTakesEachProblemsParametersAndItsOwnOverrides) {
  const fs::path scenes = dir_ / "push";
  fs::create_directories(scenes);
  bundled_copy(fs::path(CLUTTERTAMP_SOURCE_DIR) / "problems/push/easy.yaml", "push/p01.yaml",
               {{"max_propagations: 20000", "max_propagations: 1"}});
  const fs::path csv = dir_ / "push.csv";
  const CliRun own = run("bench push -q --runs 1 --time-limit 30 --push-scenes " + scenes.string() + " --csv " + csv.string());
  EXPECT_EQ(own.exit_code, 0) << own.output;
  const auto unwrapped = [](std::string text) {
    std::replace(text.begin(), text.end(), '\n', ' ');
    return text;
  };
  EXPECT_NE(unwrapped(own.output).find("each problem's physics and planner parameters as written"), std::string::npos) << own.output;
  std::string rows = test::read_text(csv);
  for (const char* planner : {",rrt,", ",kpiece,"}) {
    const std::size_t row = rows.find(planner);
    ASSERT_NE(row, std::string::npos) << rows;
    EXPECT_NE(rows.substr(row, rows.find('\n', row) - row).find("propagation budget (1) used up"), std::string::npos) << rows;
  }

  const fs::path json_file = dir_ / "push.json";
  const CliRun r = run("bench push -q --runs 1 --time-limit 30 --goal-distance 0.02 --goal-heading 0.4 --steer 0.25 "
                       "--param max_propagations=2 --param max_guides=1 --push-scenes " + scenes.string() + " --json " + json_file.string() +
                       " --csv " + csv.string());
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(unwrapped(r.output).find("with goal_distance = 0.02, goal_heading = 0.4, max_guides = 1, max_propagations = 2, steer = 0.25 for every run"),
            std::string::npos) << r.output;
  rows = test::read_text(csv);
  EXPECT_NE(rows.find(",rrt,"), std::string::npos) << rows;
  EXPECT_NE(rows.find("propagation budget (2) used up"), std::string::npos) << rows;
  EXPECT_EQ(rows.find("propagation budget (1) used up"), std::string::npos) << rows;
  const auto json = nlohmann::json::parse(test::read_text(json_file));
  EXPECT_EQ(json["overrides"]["goal_distance"], "0.02") << json.dump();
  EXPECT_EQ(json["overrides"]["max_propagations"], "2") << json.dump();
  EXPECT_TRUE(json["goal_p_values"].contains("rrt") && json["goal_p_values"].contains("kpiece")) << json.dump();
  EXPECT_NE(r.output.find("Fisher's exact p "), std::string::npos) << r.output;
  EXPECT_EQ(json["planners"].size(), 3u);
  EXPECT_TRUE(json["goal_met"].is_boolean()) << json.dump();

  // --planner runs only the planners named; the goal, which needs all three, is not judged.
  const CliRun two = run("bench push -q --runs 1 --time-limit 30 --planner guided --planner kpiece --push-scenes " + scenes.string() +
                         " --json " + json_file.string() + " --csv " + csv.string());
  EXPECT_EQ(two.exit_code, 0) << two.output;
  rows = test::read_text(csv);
  EXPECT_EQ(rows.find(",rrt,"), std::string::npos) << rows;
  EXPECT_NE(rows.find(",kpiece,"), std::string::npos) << rows;
  EXPECT_NE(rows.find(",guided,"), std::string::npos) << rows;
  const auto only_two = nlohmann::json::parse(test::read_text(json_file));
  ASSERT_EQ(only_two["planners"].size(), 2u) << only_two.dump();
  EXPECT_EQ(only_two["planners"][0]["planner"], "kpiece");
  EXPECT_EQ(only_two["planners"][1]["planner"], "guided");
  EXPECT_TRUE(only_two["goal_met"].is_null()) << only_two.dump();
  EXPECT_NE(unwrapped(two.output).find("not judged"), std::string::npos) << two.output;
  EXPECT_EQ(run("bench push --planner rrt --check-goals --push-scenes " + scenes.string()).exit_code, 2);
  EXPECT_EQ(run("bench push --planner prm --push-scenes " + scenes.string()).exit_code, 2);
  EXPECT_EQ(run("bench push --goal-distance 0 --push-scenes " + scenes.string()).exit_code, 2);
  EXPECT_EQ(run("bench push --goal-heading -1 --push-scenes " + scenes.string()).exit_code, 2);
  EXPECT_EQ(run("bench push --steer 1.5 --push-scenes " + scenes.string()).exit_code, 2);
  EXPECT_EQ(run("bench push --param max_propagations --push-scenes " + scenes.string()).exit_code, 2);
  EXPECT_EQ(run("bench push --param planner=kpiece --push-scenes " + scenes.string()).exit_code, 2);
  const CliRun unknown = run("bench push --runs 1 --param max_propagation=3 --push-scenes " + scenes.string());
  EXPECT_EQ(unknown.exit_code, 2) << unknown.output;
  EXPECT_NE(unknown.output.find("max_propagation"), std::string::npos) << unknown.output;
}

// A description whose base_link is not the URDF's root (the arm on a pedestal that
// raises it 5 cm and turns it 0.3 rad): the scene places the root, and every grasp is
// where the hand really is. IK used to take the root's frame for the base link's, and
// the plan "grasped" the first object 29 cm from the hand.
TEST_F(Cli, AnArmOnAPedestalGraspsWhereItsHandIs) {
  const fs::path robots = fs::path(CLUTTERTAMP_SOURCE_DIR) / "domains/robots";
  std::ofstream(dir_ / "pedestal.urdf") << test::replaced(
      test::read_text(robots / "ur10_ag95.urdf"), "<link name=\"base_link\">",
      "<link name=\"world\"/>\n  <joint name=\"pedestal\" type=\"fixed\"><parent link=\"world\"/><child link=\"base_link\"/>"
      "<origin xyz=\"0 0 0.05\" rpy=\"0 0 0.3\"/></joint>\n  <link name=\"base_link\">");
  std::ofstream(dir_ / "pedestal.yaml") << test::replaced(test::read_text(robots / "ur10_ag95.yaml"), "urdf: ur10_ag95.urdf",
                                                          "urdf: " + (dir_ / "pedestal.urdf").string());
  const fs::path problem = bundled_copy(fs::path(CLUTTERTAMP_SOURCE_DIR) / "problems/default.yaml", "pedestal-problem.yaml",
                                        {{"../domains/robots/ur10_ag95.yaml", (dir_ / "pedestal.yaml").string()}});
  const CliRun r = plan(problem, "-q");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json j = result();
  const robot::RobotDescription robot = io::load_robot_description(dir_ / "pedestal.yaml");
  ASSERT_NE(robot.root_T_ik_base().translation().z(), 0.0);
  const Problem loaded = io::load_problem(problem);
  const int finger = *robot.finger_variable();
  int picks = 0;
  for (const auto& step : j["plan"]) {
    if (step["action"] != "pick") continue;
    // The grasp: where the fingers close with the arm standing still, on the object as it stood.
    const auto& positions = step["trajectory"]["positions"];
    std::optional<Eigen::VectorXd> grasp;
    for (std::size_t i = 1; i < positions.size() && !grasp; ++i) {
      const std::vector<double> before = positions[i - 1].get<std::vector<double>>(), after = positions[i].get<std::vector<double>>();
      bool arm_still = true;
      for (std::size_t v = 0; v < before.size(); ++v) arm_still = arm_still && (int(v) == finger || before[v] == after[v]);
      if (arm_still && after[finger] < before[finger] - 1e-6) grasp = Eigen::Map<const Eigen::VectorXd>(before.data(), robot.home().size());
    }
    ASSERT_TRUE(grasp) << step.dump();
    std::vector<Eigen::Isometry3d> root_T_links;
    robot.model()->link_poses(*grasp, root_T_links);
    const Eigen::Vector3d hand = loaded.scene.world_T_robot_base * root_T_links[static_cast<std::size_t>(robot.tip_link())].translation();
    const SceneObject& object = loaded.scene.objects[*loaded.scene.find_object(step["objects"][0].get<std::string>())];
    EXPECT_LT((hand - object.world_T_object.translation()).head<2>().norm(), 0.01) << step["objects"][0];
    if (++picks == 1) break;  // later objects may have been moved by earlier steps
  }
  EXPECT_EQ(picks, 1);
}

// plan --repeat plans again and finds the same result; --expect finds where an earlier
// result differs (exit code 3), and what is only timing is not a difference.
TEST_F(Cli, RepeatAndExpectCompareResultsApartFromTimeFields) {
  const fs::path problem = fs::path(CLUTTERTAMP_SOURCE_DIR) / "problems/table6/min2.yaml";
  const CliRun repeated = plan(problem, "--repeat 3 --load 1 -q");
  ASSERT_EQ(repeated.exit_code, 0) << repeated.output;
  EXPECT_NE(repeated.output.find("3 runs, 1 busy threads on its CPU: identical apart from time fields"), std::string::npos)
      << repeated.output;
  nlohmann::json earlier = result();
  ASSERT_TRUE(earlier["solved"].get<bool>());
  earlier["time"]["total"] = 1234.5;  // timing only: still the same
  std::ofstream(dir_ / "timing.json") << earlier.dump();
  const CliRun same = run("plan " + problem.string() + " -q -o " + (dir_ / "again").string() + " --expect " +
                          (dir_ / "timing.json").string());
  EXPECT_EQ(same.exit_code, 0) << same.output;
  EXPECT_NE(same.output.find("identical to"), std::string::npos) << same.output;
  earlier["counters"]["collision_checks"] = earlier["counters"]["collision_checks"].get<std::uint64_t>() + 1;
  std::ofstream(dir_ / "other.json") << earlier.dump();
  const CliRun other = run("plan " + problem.string() + " -q -o " + (dir_ / "again").string() + " --expect " +
                           (dir_ / "other.json").string());
  EXPECT_EQ(other.exit_code, 3) << other.output;
  EXPECT_NE(other.output.find("DIFFERENT from"), std::string::npos) << other.output;
  EXPECT_NE(other.output.find("/counters/collision_checks"), std::string::npos) << other.output;
  std::ofstream(dir_ / "not.json") << "{ not json";
  EXPECT_EQ(run("plan " + problem.string() + " -q -o " + (dir_ / "again").string() + " --expect " +
                (dir_ / "not.json").string())
                .exit_code,
            2);
}

// Budgets that were seconds are work now: the old keys are refused, naming the new one.
TEST_F(Cli, TimeBudgetKeysAreRefusedNamingTheirWorkBudget) {
  const fs::path source = fs::path(CLUTTERTAMP_SOURCE_DIR) / "problems/default.yaml";
  const std::vector<std::tuple<std::string, std::string, std::string>> cases{
      {"motion_sampler: motion_ompl", "motion_sampler: {plugin: motion_ompl, parameters: {time_limit: 1}}", "max_checks"},
      {"motion_sampler: motion_ompl", "motion_sampler: {plugin: motion_ompl, parameters: {planner: prm}}", "rrtconnect"},
      {"seed: 0", "seed: 0\n  parameters: {shorten_time: 0.5}", "shorten_max_checks"}};
  for (const auto& [from, to, hint] : cases) {
    SCOPED_TRACE(to);
    const CliRun r = plan(bundled_copy(source, "old.yaml", {{from, to}}), "-q");
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find("old.yaml:"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find(hint), std::string::npos) << r.output;
  }
}

// A stream whose input no :domain fact binds (PDDLStream warns and goes on) ranges over
// every object: its optimistic instances multiply without bound. The memory limit ends
// the run cleanly, with its reason and a result.json, wherever the machine's speed puts
// the time.
TEST_F(Cli, AStreamWhoseInputsNothingBindsEndsAtTheMemoryLimit) {
  if (!memory_limit_supported()) GTEST_SKIP() << "no address-space limit in a build with AddressSanitizer";
  const fs::path stacked = fs::path(CLUTTERTAMP_SOURCE_DIR) / "problems/stacked/stacked8.yaml";
  const fs::path streams = fs::path(CLUTTERTAMP_SOURCE_DIR) / "domains/pddl/clutter-streams/stream.pddl";
  std::ofstream(dir_ / "unbound-streams.pddl")
      << test::replaced(test::read_text(streams), ":domain (and (Grasp ?o ?g) (Region ?r))", "");
  const fs::path file = bundled_copy(stacked, "unbound.yaml", {{"streams: ../../domains/pddl/clutter-streams/stream.pddl",
                                                                "streams: " + (dir_ / "unbound-streams.pddl").string()}});
  const CliRun r = plan(file, "-q --time-limit 3000 --memory-limit 1500");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  const nlohmann::json j = result();
  EXPECT_FALSE(j["solved"].get<bool>());
  EXPECT_EQ(j["reason"], "memory limit reached (1500 MiB)") << j.dump();
}

// Valid PDDL that outgrows the grounder is a planning failure (exit 1) with the place,
// not bad input; suspect but accepted declarations are warnings with their place.
TEST_F(Cli, PddlThatOutgrowsTheGrounderIsAFailureAndDuplicatesAreWarnings) {
  std::string objects;
  for (int i = 0; i < 120; ++i) objects += " o" + std::to_string(i);
  std::ofstream(dir_ / "x.pddl") << "(define (domain x) (:requirements :adl) (:predicates (p ?a) (r ?a) (q) (q))\n"
                                    "(:action a :parameters () :precondition (not (exists (?x) (and (p ?x) (r ?x)))) :effect (q))\n"
                                    "(:action b :parameters (?x) :precondition () :effect (and (not (p ?x)) (not (r ?x)))))";
  std::string init;
  for (int i = 0; i < 120; ++i) init += " (p o" + std::to_string(i) + ") (r o" + std::to_string(i) + ")";
  std::ofstream(dir_ / "y.pddl") << "(define (problem y) (:domain x) (:objects" << objects << ") (:init" << init << ") (:goal (q)))";
  const CliRun r = run("pddl " + (dir_ / "x.pddl").string() + " " + (dir_ / "y.pddl").string());
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("no plan: grounding: " + (dir_ / "x.pddl").string() + ":2:1: the precondition of 'a' has more than 10000"),
            std::string::npos) << r.output;
  EXPECT_NE(r.output.find((dir_ / "x.pddl").string() + ":1:72: warning: predicate 'q' is declared twice (first at line 1)"),
            std::string::npos) << r.output;
}

// The PDDL searches keep their time limit and say so; a memory limit too is a reason.
TEST_F(Cli, PddlSearchesEndAtTheirLimitsWithTheReason) {
  const fs::path dir = fs::path(CLUTTERTAMP_SOURCE_DIR) / "test/data/pddl/blocks";
  const CliRun timed = run("pddl " + (dir / "domain.pddl").string() + " " + (dir / "p14-6.pddl").string() +
                           " --search astar-blind --time-limit 0.5");
  EXPECT_EQ(timed.exit_code, 1) << timed.output;
  EXPECT_NE(timed.output.find("no plan: time limit"), std::string::npos) << timed.output;
  if (!memory_limit_supported()) GTEST_SKIP() << "no address-space limit in a build with AddressSanitizer";
  const CliRun memory = run("pddl " + (dir / "domain.pddl").string() + " " + (dir / "p14-6.pddl").string() +
                            " --search astar-blind --time-limit 3000 --memory-limit 300");
  EXPECT_EQ(memory.exit_code, 1) << memory.output;
  EXPECT_NE(memory.output.find("memory limit reached (300 MiB)"), std::string::npos) << memory.output;
}

}  // namespace

}  // namespace cluttertamp

namespace cluttertamp {

namespace {
// A bash command line's exit code and output (stdout and stderr together).
CliRun shell(const std::string& command_line) { return run_command("bash -c '" + command_line + "' 2>&1"); }
}  // namespace

// An unwritable output path is bad input found before planning: exit 2, nothing planned.
TEST_F(Cli, AnUnwritableOutputIsRefusedBeforePlanning) {
  std::ofstream(dir_ / "a-file") << "x";
  const CliRun r = run("plan " + problem("solve").string() + " --output " + (dir_ / "a-file" / "out").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("a-file/out: error: cannot create the output directory (--output)"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("SOLVED"), std::string::npos) << "planned although the result could not be kept: " << r.output;
  const CliRun pddl = run("pddl " + test::data("pddl/domain.pddl").string() + " " + test::data("pddl/problem.pddl").string() +
                          " --plan " + dir_.string() + " -q");
  EXPECT_EQ(pddl.exit_code, 2) << pddl.output;
  EXPECT_NE(pddl.output.find("the plan file (--plan) is a directory"), std::string::npos) << pddl.output;
  const CliRun bench = run("bench collision --json " + (dir_ / "a-file" / "x.json").string());
  EXPECT_EQ(bench.exit_code, 2) << bench.output;
  EXPECT_NE(bench.output.find("a-file is not a directory"), std::string::npos) << bench.output;
}

// A write failing during the run (here a full device) is a fault, exit 3, never success.
TEST_F(Cli, APlanThatCannotBeWrittenIsAFaultNotASuccess) {
  const CliRun r = run("pddl " + test::data("pddl/domain.pddl").string() + " " + test::data("pddl/problem.pddl").string() +
                       " --plan /dev/full -q");
  EXPECT_EQ(r.exit_code, 3) << r.output;
  EXPECT_NE(r.output.find("/dev/full: error: cannot write the plan file: No space left on device"), std::string::npos) << r.output;
}

// Files are replaced whole: when the drawings do not fit (a file size limit stands in
// for a full disk), result.json says exit code 3 and why, as the process does; when
// result.json itself does not fit, the previous one stays, complete.
TEST_F(Cli, OutputsAreWholeAndResultJsonSaysTheProcessExitCode) {
  const fs::path out = dir_ / "out";
  const std::string plan = std::string(CLUTTERTAMP_CLI) + " plan " + CLUTTERTAMP_SOURCE_DIR + "/problems/default.yaml -q --output " + out.string();
  ASSERT_EQ(run("plan " + std::string(CLUTTERTAMP_SOURCE_DIR) + "/problems/default.yaml -q --output " + out.string()).exit_code, 0);
  ASSERT_GT(fs::file_size(out / "drawings.json"), 120u * 1024) << "the test needs drawings larger than the limit below";
  const std::string before = test::read_text(out / "result.json");
  ASSERT_LT(before.size(), 100u * 1024);
  fs::remove(out / "drawings.json");
  // SIGXFSZ ignored: a write beyond the limit fails with EFBIG instead of killing the process.
  const CliRun small = shell("trap \"\" XFSZ; ulimit -f 100; " + plan);
  EXPECT_EQ(small.exit_code, 3) << small.output;
  EXPECT_NE(small.output.find("drawings.json: error: cannot write the drawings file: File too large"), std::string::npos) << small.output;
  EXPECT_FALSE(fs::exists(out / "drawings.json")) << "no partial drawings";
  const nlohmann::json result = nlohmann::json::parse(test::read_text(out / "result.json"));
  EXPECT_EQ(result["exit_code"], 3);
  EXPECT_NE(result["reason"].get<std::string>().find("drawings could not be written"), std::string::npos) << result["reason"];

  ASSERT_EQ(run("plan " + std::string(CLUTTERTAMP_SOURCE_DIR) + "/problems/default.yaml -q --output " + out.string()).exit_code, 0);
  const std::string complete = test::read_text(out / "result.json");
  const CliRun tiny = shell("trap \"\" XFSZ; ulimit -f 8; " + plan);
  EXPECT_EQ(tiny.exit_code, 3) << tiny.output;
  EXPECT_NE(tiny.output.find("result.json: error: cannot write the result file: File too large"), std::string::npos) << tiny.output;
  EXPECT_EQ(test::read_text(out / "result.json"), complete) << "the previous result.json, whole";
  for (const auto& entry : fs::directory_iterator(out)) {
    EXPECT_EQ(entry.path().filename().string().find(".partial"), std::string::npos) << "left behind: " << entry.path();
  }
}

// plan --expect: a different result is exit code 3, and result.json says 3 as well.
TEST_F(Cli, AnExpectationNotMetIsInResultJsonToo) {
  const fs::path expected = dir_ / "expected.json";
  ASSERT_EQ(plan(problem("solve")).exit_code, 0);
  nlohmann::json other = nlohmann::json::parse(test::read_text(dir_ / "out" / "result.json"));
  other["seed"] = 999;
  std::ofstream(expected) << other.dump();
  const CliRun r = plan(problem("solve"), "--expect " + expected.string());
  EXPECT_EQ(r.exit_code, 3) << r.output;
  const nlohmann::json result = nlohmann::json::parse(test::read_text(dir_ / "out" / "result.json"));
  EXPECT_EQ(result["exit_code"], 3);
  EXPECT_NE(result["reason"].get<std::string>().find("plan --expect: different from"), std::string::npos) << result["reason"];
}

}  // namespace cluttertamp
