#include "cluttertamp/io/result_json.hpp"

#include <cmath>
#include <fstream>

#include <nlohmann/json.hpp>

#include "cluttertamp/version.hpp"
#include "cluttertamp/io/text_file.hpp"

namespace cluttertamp::io {

namespace {
using Json = nlohmann::ordered_json;

Json names(const Scene& scene, const std::vector<ObjectIndex>& objects) {
  Json out = Json::array();
  for (ObjectIndex i : objects) out.push_back(i < scene.objects.size() ? scene.objects[i].id : std::string("#").append(std::to_string(i)));
  return out;
}

Json trajectory_json(const Scene& scene, const Trajectory& t) {
  Json positions = Json::array();
  for (const Eigen::VectorXd& q : t.positions) positions.push_back(std::vector<double>(q.data(), q.data() + q.size()));
  Json out{{"joint_names", t.joint_names}, {"times", t.times}, {"positions", positions}};
  if (!t.object_paths.empty()) {
    Json objects = Json::object();
    for (const auto& [object, poses] : t.object_paths) {
      Json path = Json::array();
      for (const Eigen::Vector3d& p : poses) path.push_back({p.x(), p.y(), p.z()});
      objects[names(scene, {object})[0].get<std::string>()] = std::move(path);
    }
    out["objects"] = std::move(objects);
  }
  return out;
}

Json task_json(const Task& task) {
  if (const auto* r = std::get_if<RetrievalTask>(&task)) return Json{{"type", "retrieve"}, {"target", r->target}};
  if (const auto* r = std::get_if<ReachTask>(&task)) return Json{{"type", "reach"}, {"target", r->target}};
  const auto& p = std::get<PddlTask>(task);
  Json out{{"type", "pddl"}, {"domain", p.domain.string()}};
  out["problem"] = p.problem ? Json(p.problem->string()) : Json(nullptr);
  out["streams"] = p.streams ? Json(p.streams->string()) : Json(nullptr);
  return out;
}
}  // namespace

std::string result_to_json(const Problem& problem, const Result& result, const RunInfo& run) {
  const Scene& scene = problem.scene;
  Json plan = Json::array();
  for (std::size_t i = 0; i < result.plan.size(); ++i) {
    const PlanStep& step = result.plan[i];
    Json s{{"index", i}, {"action", step.action}, {"arguments", step.arguments}, {"objects", names(scene, step.objects)},
           {"values", step.values}};
    s["trajectory"] = step.trajectory ? trajectory_json(scene, *step.trajectory) : Json(nullptr);
    plan.push_back(std::move(s));
  }
  Json failures = Json::array();
  for (const Failure& f : result.failures) {
    failures.push_back({{"stage", f.stage}, {"reason", f.reason}, {"blocking_objects", names(scene, f.blocking_objects)}});
  }
  Json out;
  out["schema"] = kResultSchema;
  out["cluttertamp_version"] = std::string(version());
  out["problem"] = problem.source_file.string();
  out["scene"] = problem.scene_file.string();
  out["task"] = task_json(problem.task);
  out["planner"] = run.planner;
  out["seed"] = run.seed;
  out["time_limit"] = run.time_limit;
  out["solved"] = result.solved;
  // A solved run that still ended in a fault (an output not written, a failed --expect)
  // says why beside its exit code.
  out["reason"] = result.solved && run.exit_code == 0 ? Json(nullptr) : Json(result.reason);
  out["exit_code"] = run.exit_code;
  out["plan"] = plan;
  out["cost"] = result.cost ? Json(*result.cost) : Json(nullptr);
  out["moved_objects"] = names(scene, result.moved_objects);
  out["time"] = {{"task_planning", result.time.task_planning},
                 {"motion_planning", result.time.motion_planning},
                 {"total", result.time.total}};
  Json counters = Json::object();
  for (const char* key : {counter::samples, counter::collision_checks, counter::motion_planning_calls}) counters[key] = 0;
  for (const auto& [key, value] : result.counters) counters[key] = value;
  out["counters"] = counters;
  Json phases = Json::object();
  for (const auto& [name, totals] : result.phases) {
    phases[name] = {{"calls", totals.calls}, {"collision_checks", totals.collision_checks}, {"time", totals.seconds}};
  }
  out["phases"] = phases;
  out["failures"] = failures;
  if (result.guidance) {
    Json guides = Json::array();
    for (const GuideRecord& g : result.guidance->guides) {
      guides.push_back({{"object", scene.objects.at(g.object).id}, {"centre", {g.centre.x(), g.centre.y()}}, {"diameter", g.diameter},
                        {"satisfied", g.satisfied}, {"reason", g.satisfied ? Json(nullptr) : Json(g.reason)}});
    }
    out["guidance"] = {{"source", result.guidance->source}, {"guides", guides}};
  }
  if (run.human_guidance) {
    const HumanGuidance& h = *run.human_guidance;
    Json inputs = Json::array();
    int satisfied = 0;
    double planning = 0.0;
    for (const OperatorInput& in : h.inputs) {
      satisfied += in.satisfied ? 1 : 0;
      planning += in.planning_time;
      inputs.push_back({{"object", in.object}, {"centre", {in.centre.x(), in.centre.y()}}, {"diameter", in.diameter},
                        {"satisfied", in.satisfied}, {"planning_time", in.planning_time},
                        {"reason", in.satisfied ? Json(nullptr) : Json(in.reason)}});
    }
    out["human_guidance"] = {{"successful_inputs", satisfied},
                             {"failed_inputs", static_cast<int>(h.inputs.size()) - satisfied},
                             {"interaction_time", h.interaction_time},
                             {"guidance_planning_time", planning},
                             {"inputs", inputs}};
  }
  // Invalid UTF-8 from a plugin's text is replaced rather than making the file unwritable.
  return out.dump(2, ' ', false, Json::error_handler_t::replace) + "\n";
}


std::string drawings_to_json(const Result& result) {
  Json drawings = Json::array();
  for (const PlaneDrawing& d : result.drawings) {
    Json nodes = Json::array();
    for (const Eigen::Vector2d& x : d.nodes) nodes.push_back({std::round(x.x() * 1e4) / 1e4, std::round(x.y() * 1e4) / 1e4});
    Json edges = Json::array();
    for (const auto& [a, b] : d.edges) edges.push_back({a, b});
    drawings.push_back({{"name", d.name}, {"nodes", nodes}, {"labels", d.labels}, {"edges", edges}, {"path", d.path}});
  }
  return Json{{"schema", "cluttertamp-drawings/1"}, {"drawings", drawings}}.dump(-1, ' ', false, Json::error_handler_t::replace) + "\n";
}

void write_result_json(const std::filesystem::path& file, const Problem& problem, const Result& result,
                       const RunInfo& run) {
  write_text_file(file, result_to_json(problem, result, run), "result file");
}

}  // namespace cluttertamp::io
