// The plan viewer's replay (where it draws things) and the operator's guided session.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "cluttertamp/io/guidance_io.hpp"
#include "cluttertamp/io/problem_io.hpp"
#include "cluttertamp/io/result_json.hpp"
#include "cluttertamp/io/robot_description_io.hpp"
#include "cluttertamp/robot/mesh.hpp"
#include "cluttertamp/robot/robot_description.hpp"
#include "cluttertamp/physics/push_world.hpp"
#include "cluttertamp/run/guided_session.hpp"
#include "cluttertamp/run/runner.hpp"
#include "cluttertamp/viewer/plan_html.hpp"
#include "test_support.hpp"

namespace cluttertamp {
namespace {

using Json = nlohmann::json;
const std::filesystem::path kProblems = std::filesystem::path(CLUTTERTAMP_SOURCE_DIR) / "problems";

// The last pose a replay gives object `id` (its scene pose when no frame moves it).
Eigen::Vector3d last_position(const Json& replay, const std::string& id) {
  Eigen::Vector3d at = Eigen::Vector3d::Constant(NAN);
  for (const Json& o : replay["scene"]["objects"]) {
    if (o["id"] == id) at = {o["pose"][0].get<double>(), o["pose"][1].get<double>(), o["pose"][2].get<double>()};
  }
  for (const Json& f : replay["frames"]) {
    if (f.contains("objects") && f["objects"].contains(id)) {
      const Json& p = f["objects"][id];
      if (p.is_null()) return Eigen::Vector3d::Constant(INFINITY);  // carried out of the workspace
      at = {p[0].get<double>(), p[1].get<double>(), p[2].get<double>()};
    }
  }
  return at;
}

class ViewerTest : public ::testing::Test {
 protected:
  plugin::Registry registry_{plugin::Registry::default_search_paths()};
};

// A pushed object ends where the physics left it in the plan; a retrieved target is
// carried by the hand to the exit x_s; the frames are in time order.
TEST_F(ViewerTest, ReplayMovesPushedAndHeldObjectsToWhereThePlanLeavesThem) {
  const Problem problem = io::load_problem(kProblems / "push/retrieve-push.yaml");
  const run::RunOutcome run = run::plan(problem, registry_, {});
  ASSERT_TRUE(run.result.solved) << run.result.reason;
  const Json replay = Json::parse(viewer::replay_json(problem, {io::result_to_json(problem, run.result, run.info),
                                                                io::drawings_to_json(run.result), "memory"}));
  ASSERT_EQ(replay["steps"].size(), 2u);
  EXPECT_EQ(replay["steps"][0]["action"], "push");
  // The pusher drawn as the physics' gripper: the palm, then a finger either side ahead.
  const physics::PushSettings gripper;
  ASSERT_EQ(replay["pusher"]["parts"].size(), 3u);
  EXPECT_EQ(replay["pusher"]["parts"][0]["offset"], Json::array({0.0, 0.0, 0.0}));
  EXPECT_EQ(replay["pusher"]["parts"][0]["rotation"], Json::array({0.0, 0.0, 0.0, 1.0}));
  for (const int k : {1, 2}) {
    const Json& finger = replay["pusher"]["parts"][k];
    EXPECT_DOUBLE_EQ(finger["offset"][0].get<double>(), gripper.gripper_size.x() / 2 + gripper.finger_length / 2);
    EXPECT_NEAR(std::abs(finger["offset"][1].get<double>()), (gripper.gripper_size.y() - gripper.finger_width) / 2, 1e-12);
  }
  EXPECT_EQ(replay["steps"][1]["action"], "retrieve");
  const std::vector<double>& pushed = run.result.plan[0].values.at("o3");
  const Eigen::Vector3d o3 = last_position(replay, "o3");
  EXPECT_NEAR(o3.x(), pushed[0], 1e-3);
  EXPECT_NEAR(o3.y(), pushed[1], 1e-3);
  EXPECT_TRUE(replay["warnings"].empty()) << replay["warnings"];

  // The push recorded where o3 was at every time of the step: from its scene pose to
  // where the physics left it, which the page draws without running the physics.
  const Json result = Json::parse(io::result_to_json(problem, run.result, run.info));
  const Json& trajectory = result["plan"][0]["trajectory"];
  ASSERT_TRUE(trajectory["objects"].contains("o3")) << trajectory;
  const Json& path = trajectory["objects"]["o3"];
  ASSERT_EQ(path.size(), trajectory["times"].size());
  const Eigen::Vector3d start = problem.scene.objects[*problem.scene.find_object("o3")].world_T_object.translation();
  EXPECT_NEAR(path.front()[0].get<double>(), start.x(), 1e-9);
  EXPECT_NEAR(path.front()[1].get<double>(), start.y(), 1e-9);
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(path.back()[i].get<double>(), pushed[static_cast<std::size_t>(i)], 1e-12);
  const Eigen::Vector3d exit = problem.scene.world_T_exit.translation();
  EXPECT_LT((last_position(replay, "target") - exit).norm(), 0.01);
  double t = -1;
  for (const Json& f : replay["frames"]) {
    EXPECT_GE(f["t"].get<double>(), t);
    t = f["t"].get<double>();
  }
  EXPECT_NEAR(t, replay["duration"].get<double>(), 1e-6);
  EXPECT_EQ(replay["drawings"].size(), run.result.drawings.size());
  EXPECT_FALSE(replay["robot"].is_null());  // the retrieval moves the arm
}

// A target beyond the arm's reach fails before planning, saying where both are: no
// grasp sampling until the time limit.
TEST_F(ViewerTest, ATargetOutOfReachFailsBeforePlanningSayingSo) {
  Problem problem = io::load_problem(kProblems / "default.yaml");
  problem.scene.world_T_robot_base.translation().x() -= 3.0;
  const run::RunOutcome run = run::plan(problem, registry_, {});
  EXPECT_FALSE(run.result.solved);
  EXPECT_EQ(run.info.exit_code, run::ExitCode::no_plan);
  EXPECT_NE(run.result.reason.find("the target 'target' at ("), std::string::npos) << run.result.reason;
  EXPECT_NE(run.result.reason.find("is out of the robot's reach from its base at ("), std::string::npos) << run.result.reason;
  EXPECT_TRUE(run.result.counters.empty() || run.result.counters.at("samples") == 0);
}

// A link's <visual> meshes are drawn, simplified to the page's budget; a link with none
// is drawn from its collision shapes.
TEST_F(ViewerTest, VisualMeshesAreDrawnAndSimplified) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / "cluttertamp_viewer_meshes";
  fs::remove_all(dir);
  fs::create_directories(dir);
  // A finely tessellated sphere-ish blob: 80 x 160 quads, 25,600 triangles.
  robot::TriangleMesh blob;
  const int rows = 80, cols = 160;
  for (int i = 0; i <= rows; ++i) {
    for (int j = 0; j < cols; ++j) {
      const double theta = M_PI * i / rows, phi = 2 * M_PI * j / cols;
      blob.vertices.emplace_back(0.08 * std::sin(theta) * std::cos(phi), 0.08 * std::sin(theta) * std::sin(phi), 0.08 * std::cos(theta));
    }
  }
  for (int i = 0; i < rows; ++i) {
    for (int j = 0; j < cols; ++j) {
      const auto a = static_cast<std::uint32_t>(i * cols + j), b = static_cast<std::uint32_t>(i * cols + (j + 1) % cols);
      const auto c = a + static_cast<std::uint32_t>(cols), d = b + static_cast<std::uint32_t>(cols);
      blob.triangles.push_back({a, c, b});
      blob.triangles.push_back({b, c, d});
    }
  }
  std::ofstream(dir / "blob.stl") << robot::to_ascii_stl(blob, "blob");
  std::ifstream urdf_in(fs::path(CLUTTERTAMP_SOURCE_DIR) / "domains/robots/ur10_ag95.urdf");
  std::stringstream urdf;
  urdf << urdf_in.rdbuf();
  std::string text = urdf.str();
  const std::string shoulder = "<link name=\"shoulder_link\">";
  text.insert(text.find(shoulder) + shoulder.size(), "<visual><geometry><mesh filename=\"blob.stl\"/></geometry></visual>");
  std::ofstream(dir / "ur10.urdf") << text;
  std::ifstream yaml_in(fs::path(CLUTTERTAMP_SOURCE_DIR) / "domains/robots/ur10_ag95.yaml");
  std::stringstream yaml;
  yaml << yaml_in.rdbuf();
  std::string description = yaml.str();
  description.replace(description.find("urdf: ur10_ag95.urdf"), std::string("urdf: ur10_ag95.urdf").size(), "urdf: ur10.urdf");
  std::ofstream(dir / "ur10.yaml") << description;

  Problem problem = io::load_problem(kProblems / "default.yaml");
  problem.robot.loaded = std::make_shared<const robot::RobotDescription>(io::load_robot_description(dir / "ur10.yaml"));
  const run::RunOutcome run = run::plan(problem, registry_, {});
  ASSERT_TRUE(run.result.solved) << run.result.reason;
  const Json replay = Json::parse(viewer::replay_json(problem, {io::result_to_json(problem, run.result, run.info), "", "r.json"}));
  bool drew_mesh = false, drew_primitive = false;
  for (const Json& link : replay["robot"]["links"]) {
    for (const Json& shape : link["shapes"]) {
      if (link["name"] == "shoulder_link") {
        ASSERT_TRUE(shape["shape"].contains("mesh")) << shape;
        const std::size_t triangles = shape["shape"]["mesh"]["triangles"].size() / 3;
        EXPECT_LE(triangles, 20000u);
        EXPECT_GT(triangles, 1000u);
        EXPECT_EQ(shape["shape"]["mesh"]["vertices"].size() % 3, 0u);
        drew_mesh = true;
      } else {
        drew_primitive = drew_primitive || shape["shape"].contains("cylinder") || shape["shape"].contains("box");
      }
    }
  }
  EXPECT_TRUE(drew_mesh);
  EXPECT_TRUE(drew_primitive);
  fs::remove_all(dir);
}

// A result without object paths (written by 0.1.0) still draws: the pushed object jumps
// to its end pose at the end of the push, and the page says why.
TEST_F(ViewerTest, APushWithoutObjectPathsMovesItsObjectsToTheirEndPosesAndSaysSo) {
  const Problem problem = io::load_problem(kProblems / "push/retrieve-push.yaml");
  const run::RunOutcome run = run::plan(problem, registry_, {});
  ASSERT_TRUE(run.result.solved) << run.result.reason;
  Json result = Json::parse(io::result_to_json(problem, run.result, run.info));
  result["plan"][0]["trajectory"].erase("objects");
  const Json replay = Json::parse(viewer::replay_json(problem, {result.dump(), "", "old.json"}));
  ASSERT_EQ(replay["warnings"].size(), 1u);
  EXPECT_NE(replay["warnings"][0].get<std::string>().find("no object paths"), std::string::npos) << replay["warnings"];
  const std::vector<double>& pushed = run.result.plan[0].values.at("o3");
  const Eigen::Vector3d o3 = last_position(replay, "o3");
  EXPECT_NEAR(o3.x(), pushed[0], 1e-5);  // the page rounds to 10 µm
  EXPECT_NEAR(o3.y(), pushed[1], 1e-5);
}

// The pusher is drawn from what the result recorded (its parts, or an older result's
// boxes, and its height), not from the physics' settings: a result that records other
// parts gets other parts, at the recorded height; one that records none is replayed
// without a pusher, and says so.
TEST_F(ViewerTest, ThePusherIsDrawnFromTheResultAlone) {
  const Problem problem = io::load_problem(kProblems / "push/retrieve-push.yaml");
  const run::RunOutcome run = run::plan(problem, registry_, {});
  ASSERT_TRUE(run.result.solved) << run.result.reason;
  Json result = Json::parse(io::result_to_json(problem, run.result, run.info));
  Json& values = result["plan"][0]["values"];
  ASSERT_EQ(values["pusher_boxes"].size(), 15u);  // palm and two fingers, 5 numbers each
  ASSERT_EQ(values["pusher_parts"].size(), 33u);  // the same, 11 numbers each
  ASSERT_EQ(values["pusher_z"].size(), 1u);
  // A cylinder standing 2 cm up, turned a quarter about x.
  values["pusher_parts"] = Json::array({1, 0.03, 0.2, 0, 0.01, 0.0, 0.02, std::sqrt(0.5), 0, 0, std::sqrt(0.5)});
  values["pusher_z"] = Json::array({0.5});
  const Json turned = Json::parse(viewer::replay_json(problem, {result.dump(), "", "edited.json"}));
  ASSERT_EQ(turned["pusher"]["parts"].size(), 1u);
  EXPECT_EQ(turned["pusher"]["parts"][0]["offset"], Json::array({0.01, 0.0, 0.02}));
  EXPECT_TRUE(turned["pusher"]["parts"][0]["shape"].contains("cylinder")) << turned["pusher"]["parts"][0];
  EXPECT_NEAR(turned["pusher"]["parts"][0]["rotation"][0].get<double>(), std::sqrt(0.5), 1e-12);
  values["pusher_parts"] = Json::array({1, 0.03});  // not eleven numbers per part
  EXPECT_THROW(viewer::replay_json(problem, {result.dump(), "", "bad.json"}), InputError);

  values.erase("pusher_parts");  // an older result: boxes only
  values["pusher_boxes"] = Json::array({0.1, 0.2, 0.05, 0.01, 0.0});  // one box, off centre
  const Json replay = Json::parse(viewer::replay_json(problem, {result.dump(), "", "edited.json"}));
  ASSERT_EQ(replay["pusher"]["parts"].size(), 1u);
  EXPECT_EQ(replay["pusher"]["parts"][0]["offset"], Json::array({0.01, 0.0, 0.0}));
  int with_pusher = 0;
  for (const Json& f : replay["frames"]) {
    if (!f.contains("pusher")) continue;
    ++with_pusher;
    EXPECT_DOUBLE_EQ(f["pusher"][2].get<double>(), 0.5);
  }
  EXPECT_GT(with_pusher, 0);

  values.erase("pusher_boxes");
  values.erase("pusher_z");
  const Json bare = Json::parse(viewer::replay_json(problem, {result.dump(), "", "old.json"}));
  EXPECT_FALSE(bare.contains("pusher"));
  for (const Json& f : bare["frames"]) EXPECT_FALSE(f.contains("pusher"));
  ASSERT_EQ(bare["warnings"].size(), 1u);
  EXPECT_NE(bare["warnings"][0].get<std::string>().find("does not record the pusher"), std::string::npos);

  values["pusher_boxes"] = Json::array({0.1, 0.2});  // not five numbers per box
  values["pusher_z"] = Json::array({0.5});
  EXPECT_THROW(viewer::replay_json(problem, {result.dump(), "", "bad.json"}), InputError);
}

// Objects that do not fit the buffer are carried out of the workspace (a pick with no
// place after it): the replay takes them out of the picture; placed ones stay on it.
TEST_F(ViewerTest, ObjectsCarriedOutOfTheWorkspaceLeaveThePicture) {
  const Problem problem = io::load_problem(kProblems / "occlusion/occ12.yaml");
  const run::RunOutcome run = run::plan(problem, registry_, {});
  ASSERT_TRUE(run.result.solved) << run.result.reason;
  const Json replay = Json::parse(viewer::replay_json(problem, {io::result_to_json(problem, run.result, run.info), "", "memory"}));
  int carried_out = 0, placed = 0;
  for (std::size_t k = 0; k + 1 < run.result.plan.size(); ++k) {
    const PlanStep& step = run.result.plan[k];
    if (step.action != "pick") continue;
    const std::string& id = problem.scene.objects[step.objects.front()].id;
    const bool is_placed = run.result.plan[k + 1].action == "place";
    const Eigen::Vector3d at = last_position(replay, id);
    if (is_placed) {
      ++placed;
      const Region& buffer = *problem.scene.find_region("buffer");
      const Eigen::Vector3d local = buffer.world_T_region.inverse() * at;  // placed objects stand in the buffer
      EXPECT_TRUE((local.array().abs() <= buffer.size.array() / 2 + 1e-3).all()) << id << " at " << at.transpose();
    } else {
      ++carried_out;
      EXPECT_FALSE(at.allFinite()) << id << " was carried out but is still drawn";
    }
  }
  EXPECT_GT(carried_out, 0);  // the large front objects do not fit the buffer
  EXPECT_GT(placed, 0);
}

TEST_F(ViewerTest, AResultThatIsNotJsonOrNamesAnUnknownObjectIsBadInputNamingIt) {
  const Problem problem = io::load_problem(kProblems / "push/retrieve-push.yaml");
  try {
    viewer::replay_json(problem, {"{ not json", "", "out/result.json"});
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("out/result.json"), std::string::npos) << e.what();
  }
  const std::string unknown = R"({"plan": [{"index": 0, "action": "pick", "objects": ["ghost"], "values": {},
    "trajectory": {"joint_names": ["shoulder_pan_joint"], "times": [0, 1], "positions": [[0], [1]]}}]})";
  try {
    viewer::replay_json(problem, {unknown, "", "r.json"});
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("'ghost'"), std::string::npos) << e.what();
  }
}

// GRTC-HITL: refused inputs are not inputs; a push that works moves its object into
// the region and is recorded; the record reaches result.json.
TEST_F(ViewerTest, AGuidedSessionRecordsItsInputsAndPushesIntoTheRegion) {
  Problem problem = io::load_problem(kProblems / "push/shelf10/p01.yaml");
  problem.time_limit = 60;
  run::GuidedSession session(problem, registry_);
  EXPECT_FALSE(session.guide("ghost", {0.8, 0.0}).planned);
  EXPECT_FALSE(session.guide("o3", {2.0, 0.0}).planned);
  const run::GuidedSession::Outcome out = session.guide("o3", {0.78, 0.06});
  ASSERT_TRUE(out.ok) << out.message;
  const Json state = Json::parse(session.state_json());
  ASSERT_EQ(state["inputs"].size(), 1u);
  EXPECT_EQ(state["gripper"]["boxes"].size(), 3u) << "the page draws the palm and two fingers";
  for (const Json& o : state["objects"]) {
    if (o["id"] == "o3") EXPECT_LE(std::hypot(o["pose"][0].get<double>() - 0.78, o["pose"][1].get<double>() - 0.06), 0.05);
  }
  // The session's guidance is a guidance file grtc reads.
  const std::filesystem::path file = std::filesystem::temp_directory_path() / "cluttertamp_session_guidance.yaml";
  std::ofstream(file) << session.guidance_yaml();
  const Guidance guidance = io::load_guidance(
      file, problem.scene, physics::PushWorld(problem.scene, WorldState::initial(problem.scene)).support_region());
  ASSERT_EQ(guidance.size(), 1u);
  EXPECT_EQ(problem.scene.objects[guidance[0].object].id, "o3");
  EXPECT_TRUE(guidance[0].centre.isApprox(Eigen::Vector2d(0.78, 0.06)));
  const Json result = Json::parse(session.result_json());
  EXPECT_FALSE(result["solved"].get<bool>());  // not finished yet
  EXPECT_EQ(result["human_guidance"]["successful_inputs"], 1);
  EXPECT_EQ(result["human_guidance"]["failed_inputs"], 0);
  EXPECT_EQ(result["plan"].size(), 1u);
  EXPECT_LT(session.time_left(), 60.0);
}

}  // namespace
}  // namespace cluttertamp
