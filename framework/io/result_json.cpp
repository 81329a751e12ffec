#include "cluttertamp/io/result_json.hpp"

#include <fstream>

#include <nlohmann/json.hpp>

#include "cluttertamp/version.hpp"

namespace cluttertamp::io {

namespace {
using Json = nlohmann::ordered_json;

Json names(const Scene& scene, const std::vector<ObjectIndex>& objects) {
  Json out = Json::array();
  for (ObjectIndex i : objects) out.push_back(i < scene.objects.size() ? scene.objects[i].id : std::string("#").append(std::to_string(i)));
  return out;
}

Json trajectory_json(const Trajectory& t) {
  Json positions = Json::array();
  for (const Eigen::VectorXd& q : t.positions) positions.push_back(std::vector<double>(q.data(), q.data() + q.size()));
  return Json{{"joint_names", t.joint_names}, {"times", t.times}, {"positions", positions}};
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
    Json s{{"index", i}, {"action", step.action}, {"objects", names(scene, step.objects)}, {"values", step.values}};
    s["trajectory"] = step.trajectory ? trajectory_json(*step.trajectory) : Json(nullptr);
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
  out["reason"] = result.solved ? Json(nullptr) : Json(result.reason);
  out["exit_code"] = run.exit_code;
  out["plan"] = plan;
  out["moved_objects"] = names(scene, result.moved_objects);
  out["time"] = {{"task_planning", result.time.task_planning},
                 {"motion_planning", result.time.motion_planning},
                 {"total", result.time.total}};
  Json counters = Json::object();
  for (const char* key : {counter::samples, counter::collision_checks, counter::motion_planning_calls}) counters[key] = 0;
  for (const auto& [key, value] : result.counters) counters[key] = value;
  out["counters"] = counters;
  out["failures"] = failures;
  // Invalid UTF-8 from a plugin's text is replaced rather than making the file unwritable.
  return out.dump(2, ' ', false, Json::error_handler_t::replace) + "\n";
}

void write_result_json(const std::filesystem::path& file, const Problem& problem, const Result& result,
                       const RunInfo& run) {
  const std::string text = result_to_json(problem, result, run);
  std::error_code ec;
  if (file.has_parent_path()) std::filesystem::create_directories(file.parent_path(), ec);
  std::ofstream out(file);
  out << text;
  out.close();
  if (!out) throw InputError({file.string(), 0, 0}, "cannot write the result file (is the output directory writable?)");
}

}  // namespace cluttertamp::io
