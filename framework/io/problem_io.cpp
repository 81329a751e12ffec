#include "cluttertamp/io/problem_io.hpp"

#include <set>
#include <utility>

#include "cluttertamp/io/robot_description_io.hpp"
#include "cluttertamp/pddl/sexpr.hpp"
#include "cluttertamp/plugin/plugin.hpp"
#include "cluttertamp/stream/stream_task.hpp"
#include "io/joint_limits_text.hpp"
#include "io/readers.hpp"
#include "io/yaml_reader.hpp"

namespace cluttertamp::io {

namespace {

using detail::MapReader;
using detail::YamlFile;
namespace fs = std::filesystem;

constexpr double kDefaultTimeLimit = 60.0;  // s, the limit of Tian et al.'s experiments

std::optional<fs::path> existing_file(const YamlFile& file, const YAML::Node& node, const std::string& what) {
  auto text = file.string(node, what);
  if (!text) return std::nullopt;
  fs::path path = file.resolve(*text);
  std::error_code ec;
  if (!fs::exists(path, ec)) {
    file.error(node, what + " '" + *text + "' does not exist (looked for " + path.string() + ")");
    return std::nullopt;
  }
  if (!fs::is_regular_file(path, ec)) {
    file.error(node, what + " '" + *text + "' is not a regular file (" + path.string() + ")");
    return std::nullopt;
  }
  return path;
}

// `name` or `{plugin: name, parameters: {...}}`.
std::optional<PluginChoice> read_choice(const YamlFile& file, const YAML::Node& node, const std::string& what) {
  PluginChoice choice;
  choice.where = file.at(node);
  if (node.IsScalar()) {
    auto name = file.string(node, what);
    if (!name) return std::nullopt;
    choice.name = *name;
    return choice;
  }
  MapReader map(file, node, what, {"plugin", "parameters"});
  if (!map.valid()) return std::nullopt;
  const YAML::Node name = map.required("plugin");
  if (!name.IsDefined()) return std::nullopt;
  auto text = file.string(name, what + " plugin");
  if (!text) return std::nullopt;
  choice.name = *text;
  choice.parameters = file.parameters(map.optional("parameters"), what + " parameters");
  return choice;
}

class ProblemReader {
 public:
  ProblemReader(const fs::path& path, Diagnostics& diagnostics) : file_(path, diagnostics), diagnostics_(diagnostics) {}
  Problem read();
  bool plugins_whole() const { return plugins_whole_; }
  bool plugin_paths_whole() const { return plugin_paths_whole_; }

 private:
  bool symbolic_task(const MapReader& top) const;
  void read_robot(const YAML::Node& node);
  void read_task(const YAML::Node& node);
  void read_values(const YAML::Node& node, PddlTask& task);
  void read_planner(const YAML::Node& node);
  void read_plugins(const YAML::Node& node);
  void read_kind_choice(const YAML::Node& key_node, const YAML::Node& value);
  void read_plugin_paths(const YAML::Node& paths);
  void read_plugin_path_list(const YAML::Node& paths);
  void read_stream_bindings(const YAML::Node& streams);
  void check_target();

  YamlFile file_;
  Diagnostics& diagnostics_;
  Problem problem_;
  bool scene_ok_ = false;
  bool plugins_whole_ = false;
  bool plugin_paths_whole_ = true;
  YAML::Node retrieve_node_;
};

Problem ProblemReader::read() {
  problem_.source_file = fs::absolute(file_.path()).lexically_normal();
  problem_.name = file_.path().stem().string();
  problem_.time_limit = kDefaultTimeLimit;
  if (!file_.loaded()) return problem_;
  if (file_.root().IsNull()) {
    file_.error(SourceLocation{file_.path().string(), 1, 1}, "the problem file is empty");
    return problem_;
  }
  MapReader top(file_, file_.root(), "the problem", {"version", "name", "scene", "robot", "task", "planner", "plugins", "physics"});
  if (!top.valid()) return problem_;
  file_.check_version(top.required("version"), "problem", kProblemFormatVersion);
  if (top.has("name")) {
    if (auto name = file_.string(top.optional("name"), "name")) problem_.name = *name;
  }
  // A PDDL task with its own problem file may leave out the scene and the robot (a
  // purely symbolic stream problem); every other task needs both.
  const bool symbolic = symbolic_task(top);
  const YAML::Node scene = symbolic ? top.optional("scene") : top.required("scene");
  if (scene.IsDefined() && !scene.IsNull()) {
    if (auto path = existing_file(file_, scene, "scene file")) {
      problem_.scene_file = *path;
      const std::size_t before = diagnostics_.size();
      problem_.scene = detail::read_scene(*path, diagnostics_);
      scene_ok_ = diagnostics_.size() == before;
    }
  }
  read_robot(symbolic ? top.optional("robot") : top.required("robot"));
  read_task(top.required("task"));
  const std::size_t before_plugins = diagnostics_.size();
  read_planner(top.required("planner"));
  if (top.has("plugins")) read_plugins(top.optional("plugins"));
  if (top.has("physics")) problem_.physics = file_.parameters(top.optional("physics"), "physics");
  plugins_whole_ = diagnostics_.size() == before_plugins;
  check_target();
  return problem_;
}

bool ProblemReader::symbolic_task(const MapReader& top) const {
  const YAML::Node task = top.optional("task");
  if (!task.IsMap()) return false;
  const YAML::Node pddl = std::as_const(task)["pddl"];  // const: a missing key is an undefined node
  return pddl.IsDefined() && pddl.IsMap() && std::as_const(pddl)["problem"].IsDefined();
}

void ProblemReader::read_robot(const YAML::Node& node) {
  if (!node.IsDefined() || node.IsNull()) return;
  MapReader map(file_, node, "robot", {"description", "configuration"});
  if (!map.valid()) return;
  problem_.robot.where = file_.at(node);
  const YAML::Node description = map.required("description");
  if (!description.IsDefined()) return;
  const auto path = existing_file(file_, description, "robot description");
  if (!path) return;
  problem_.robot.description = *path;
  try {
    problem_.robot.loaded = std::make_shared<const robot::RobotDescription>(io::load_robot_description(*path));
  } catch (const InputError& e) {
    diagnostics_.append(e.diagnostics());
    return;
  }
  if (map.has("configuration")) {
    const YAML::Node q = map.optional("configuration");
    const robot::RobotModel& model = *problem_.robot.loaded->model();
    if (!q.IsSequence() || q.size() != model.variable_count()) {
      std::string names;
      for (const std::string& n : model.variable_names()) names += (names.empty() ? "" : ", ") + n;
      file_.error(q, "robot configuration must list " + std::to_string(model.variable_count()) + " joint values (" +
                         names + "), not " + std::to_string(q.IsSequence() ? q.size() : 0));
      return;
    }
    Eigen::VectorXd values(static_cast<Eigen::Index>(q.size()));
    bool ok = true;
    for (std::size_t i = 0; i < q.size(); ++i) {
      auto v = file_.number(q[i], "robot configuration[" + std::to_string(i) + "]");
      if (v) values[static_cast<Eigen::Index>(i)] = *v; else ok = false;
    }
    if (ok && !model.within_limits(values)) {
      file_.error(q, "robot configuration lies outside the joint limits: " + outside_limits(model, values));
    }
    if (ok) problem_.robot.configuration = values;
  }
}

void ProblemReader::read_task(const YAML::Node& node) {
  if (!node.IsDefined()) return;
  MapReader map(file_, node, "task", {"retrieve", "reach", "pddl"});
  if (!map.valid()) return;
  const int kinds = int(map.has("retrieve")) + int(map.has("reach")) + int(map.has("pddl"));
  if (kinds != 1) {
    file_.error(node, kinds > 1 ? "task has more than one of 'retrieve', 'reach' and 'pddl'; give one"
                                : "task needs 'retrieve: <target object>', 'reach: <target object>' or "
                                  "'pddl: {domain, problem, streams}'");
    return;
  }
  if (map.has("retrieve") || map.has("reach")) {
    const bool reach = map.has("reach");
    retrieve_node_ = map.optional(reach ? "reach" : "retrieve");
    const std::string target = file_.string(retrieve_node_, reach ? "task reach" : "task retrieve").value_or("");
    if (reach) problem_.task = ReachTask{target};
    else problem_.task = RetrievalTask{target};
    return;
  }
  MapReader pddl(file_, map.optional("pddl"), "task pddl", {"domain", "problem", "streams", "values"});
  if (!pddl.valid()) return;
  PddlTask task;
  if (const YAML::Node n = pddl.required("domain"); n.IsDefined()) task.domain = existing_file(file_, n, "PDDL domain").value_or("");
  if (pddl.has("problem")) task.problem = existing_file(file_, pddl.optional("problem"), "PDDL problem");
  if (pddl.has("streams")) task.streams = existing_file(file_, pddl.optional("streams"), "stream file");
  if (pddl.has("values")) read_values(pddl.optional("values"), task);
  problem_.task = task;
}

void ProblemReader::read_values(const YAML::Node& node, PddlTask& task) {
  if (!node.IsMap()) {
    file_.error(node, "task pddl values must map PDDL objects to values (any YAML), not " +
                          std::string(node.IsSequence() ? "a list" : "a scalar"));
    return;
  }
  if (!task.problem) {
    file_.error(node, "task pddl values need a PDDL problem (its objects); without one the facts come from the scene");
    return;
  }
  const auto values = file_.value(node, "task pddl values");
  if (!values) return;
  for (const auto& [object, value] : *values->map()) task.values.emplace(object, value);
}

void ProblemReader::read_planner(const YAML::Node& node) {
  if (!node.IsDefined()) return;
  MapReader map(file_, node, "planner", {"plugin", "time_limit", "seed", "parameters"});
  if (!map.valid()) return;
  problem_.planner.where = file_.at(node);
  const YAML::Node name = map.required("plugin");
  if (name.IsDefined()) {
    problem_.planner.name = file_.string(name, "planner plugin").value_or("");
    problem_.planner.where = file_.at(name);
  }
  if (map.has("time_limit")) problem_.time_limit = file_.positive(map.optional("time_limit"), "planner time_limit").value_or(kDefaultTimeLimit);
  if (map.has("seed")) {
    auto seed = file_.integer(map.optional("seed"), "planner seed");
    if (seed && *seed < 0) file_.error(map.optional("seed"), "planner seed must not be negative");
    problem_.seed = static_cast<std::uint64_t>(seed.value_or(0));
  }
  problem_.planner.parameters = file_.parameters(map.optional("parameters"), "planner parameters");
}

void ProblemReader::read_plugins(const YAML::Node& node) {
  if (!node.IsDefined()) return;
  if (!node.IsMap()) {
    file_.error(node, "plugins must be a map of 'paths', 'streams' and plugin kinds (grasp_sampler, ...)");
    return;
  }
  for (const auto& item : node) {
    if (!item.first.IsScalar()) {
      file_.error(item.first, "plugins keys must be plain strings");
      continue;
    }
    const std::string key = item.first.Scalar();
    if (key == "paths") read_plugin_paths(item.second);
    else if (key == "streams") read_stream_bindings(item.second);
    else read_kind_choice(item.first, item.second);
  }
}

// Any other key names a plugin kind: the bundled ones or one a plugin declares. A kind
// no plugin has is reported when the plugins are created (with the kinds found).
void ProblemReader::read_kind_choice(const YAML::Node& key_node, const YAML::Node& value) {
  const std::string kind = key_node.Scalar();
  if (kind == "task_planner") {
    file_.error(key_node, "the task planner is chosen by 'planner: plugin:', not under plugins");
  } else if (kind == "stream_sampler") {
    file_.error(key_node, "stream samplers are bound to streams under 'plugins: streams:'");
  } else if (!plugin::detail::valid_kind_name(kind)) {
    file_.error(key_node, "'" + kind + "' is not a plugin kind: plugins holds 'paths', 'streams' and kinds such as "
                          "grasp_sampler, placement_sampler, motion_sampler, push_sampler, object_pruner");
  } else if (problem_.samplers.count(kind)) {
    file_.error(key_node, "duplicate plugin kind '" + kind + "'");
  } else if (auto choice = read_choice(file_, value, "plugins " + kind)) {
    problem_.samplers[kind] = *choice;
  }
}

void ProblemReader::read_plugin_paths(const YAML::Node& paths) {
  const std::size_t before = diagnostics_.size();
  read_plugin_path_list(paths);
  plugin_paths_whole_ = diagnostics_.size() == before;
}

void ProblemReader::read_plugin_path_list(const YAML::Node& paths) {
  if (auto list = file_.strings(paths, "plugins paths")) {
    for (std::size_t i = 0; i < list->size(); ++i) {
      const fs::path dir = file_.resolve((*list)[i]);
      if (!fs::is_directory(dir)) file_.error(paths[i], "plugin path '" + (*list)[i] + "' is not a directory (" + dir.string() + ")");
      problem_.plugin_paths.push_back(dir);
    }
  }
}

void ProblemReader::read_stream_bindings(const YAML::Node& streams) {
  if (!streams.IsMap()) {
    file_.error(streams, "plugins streams must map stream names to stream_sampler plugins");
    return;
  }
  for (const auto& item : streams) {
    if (!item.first.IsScalar()) {
      file_.error(item.first, "stream names must be plain strings");
      continue;
    }
    const std::string stream = item.first.Scalar();
    if (problem_.streams.count(stream)) {
      file_.error(item.first, "duplicate stream '" + stream + "'");
      continue;
    }
    if (auto choice = read_choice(file_, item.second, "stream '" + stream + "'")) problem_.streams[stream] = *choice;
  }
}

void ProblemReader::check_target() {
  const auto* retrieve = std::get_if<RetrievalTask>(&problem_.task);
  const auto* reach = std::get_if<ReachTask>(&problem_.task);
  const std::string target = retrieve ? retrieve->target : reach ? reach->target : "";
  const char* key = retrieve ? "retrieve" : "reach";
  if (target.empty() || !scene_ok_) return;
  const Scene& scene = problem_.scene;
  if (!scene.find_object(target)) {
    std::vector<std::string> ids;
    for (const SceneObject& o : scene.objects) ids.push_back(o.id);
    file_.error(retrieve_node_, std::string(key) + " names '" + target + "', which is not an object of scene " +
                                    problem_.scene_file.string() + did_you_mean(target, ids));
  } else if (scene.objects[scene.target].id != target) {
    file_.error(retrieve_node_, std::string(key) + " names '" + target + "' but the scene's target is '" +
                                    scene.objects[scene.target].id + "'");
  }
}

}  // namespace

ProblemReading read_problem(const fs::path& file, Diagnostics& errors) {
  Diagnostics diagnostics;
  ProblemReader reader(file, diagnostics);
  ProblemReading reading{reader.read(), false, reader.plugins_whole(), reader.plugin_paths_whole()};
  Problem& problem = reading.problem;
  // A pddl task's files are parsed here, once: every error is a load error, and
  // whoever plans or checks the problem reads the same parse. They are parsed only when
  // the problem file named them without error.
  auto* task = std::get_if<PddlTask>(&problem.task);
  if (task && diagnostics.empty()) {
    try {
      task->parsed = stream::parse_task(*task);
    } catch (const InputError& e) {
      diagnostics.append(e.diagnostics());
    }
    if (task->parsed && task->parsed->streams) {
      std::set<std::string> bound;  // PDDL names ignore case
      for (const auto& [name, choice] : problem.streams) bound.insert(pddl::lower_name(name));
      stream::check_streams_bound(*task->parsed->streams, [&](const std::string& s) { return bound.count(s) > 0; },
                                  diagnostics);
      stream::check_bindings_declared(*task->parsed->streams, problem.streams, diagnostics);
    }
  }
  reading.whole = diagnostics.empty() && (!task || task->parsed);
  errors.append(diagnostics);
  return reading;
}

Problem load_problem(const fs::path& file) {
  Diagnostics errors;
  ProblemReading reading = read_problem(file, errors);
  errors.throw_if_any();
  return std::move(reading.problem);
}

FileKind detect_file_kind(const fs::path& file) {
  Diagnostics diagnostics;
  YamlFile yaml(file, diagnostics);
  diagnostics.throw_if_any();
  const YAML::Node& root = yaml.root();
  if (root.IsMap() && (root["task"].IsDefined() || root["scene"].IsDefined() || root["planner"].IsDefined())) {
    return FileKind::problem;
  }
  return FileKind::scene;
}

}  // namespace cluttertamp::io
