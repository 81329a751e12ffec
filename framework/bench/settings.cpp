#include "bench/settings.hpp"

#include <filesystem>

namespace cluttertamp::bench {

namespace {

namespace fs = std::filesystem;

// Calls visit(name, field) for each field of BenchArgs that settings carry: one list for
// writing and reading them.
template <class Args, class Visit>
void each_setting(Args& a, Visit&& visit) {
  visit("what", a.what);
  visit("seed", a.seed);
  visit("samples", a.samples);
  visit("objects", a.objects);
  visit("robot", a.robot);
  visit("pddl_instances", a.pddl_instances);
  visit("per_domain", a.per_domain);
  visit("reference_costs", a.reference_costs);
  visit("searches", a.searches);
  visit("parse_objects", a.parse_objects);
  visit("time_limit", a.time_limit);
  visit("instances", a.instances);
  visit("sizes", a.sizes);
  visit("push_scenes", a.push_scenes);
  visit("push_overrides", a.push_overrides);
  visit("pusher", a.pusher);
  visit("tables", a.tables);
  visit("planners", a.planners);
  visit("table_vi_scenes", a.table_vi_scenes);
  visit("min_gap", a.min_gap);
  visit("fit_to_robot", a.fit_to_robot);
  visit("table_v_width", a.table_v_width);
  visit("mobile_tables", a.mobile_tables);
  visit("mobile_table_seeds", a.mobile_table_seeds);
  visit("sweep_file", a.sweep_file);
  visit("problems", a.problems);
  visit("plugin_paths", a.plugin_paths);
  visit("occlusion_layouts", a.occlusion_layouts);
  visit("runs", a.runs);
}

// Settings that records written before them do not have; reading those, they keep their defaults.
bool added_later(const std::string& name) {
  return name == "mobile_table_seeds" || name == "sweep_file" || name == "problems" || name == "plugin_paths" ||
         name == "push_overrides" || name == "pusher";
}

fs::path absolute_path(const fs::path& p) { return p.empty() ? p : fs::absolute(p).lexically_normal(); }

nlohmann::ordered_json to_json(const fs::path& p) { return absolute_path(p).string(); }
nlohmann::ordered_json to_json(const std::vector<fs::path>& paths) {
  nlohmann::ordered_json out = nlohmann::ordered_json::array();
  for (const fs::path& p : paths) out.push_back(to_json(p));
  return out;
}
template <class T>
nlohmann::ordered_json to_json(const T& value) {
  return value;
}

void from_json(const nlohmann::ordered_json& j, fs::path& p) { p = j.get<std::string>(); }
void from_json(const nlohmann::ordered_json& j, std::vector<fs::path>& paths) {
  paths.clear();
  for (const auto& p : j) paths.emplace_back(p.get<std::string>());
}
template <class T>
void from_json(const nlohmann::ordered_json& j, T& value) {
  value = j.get<T>();
}

}  // namespace

nlohmann::ordered_json settings_of(const BenchArgs& args) {
  nlohmann::ordered_json out = nlohmann::ordered_json::object();
  each_setting(args, [&](const char* name, const auto& field) { out[name] = to_json(field); });
  return out;
}

BenchArgs args_of(const nlohmann::ordered_json& settings, const SourceLocation& where) {
  BenchArgs args;
  each_setting(args, [&](const char* name, auto& field) {
    const auto it = settings.find(name);
    if (it == settings.end() && added_later(name)) return;  // records of an earlier version: the default
    if (it == settings.end()) throw InputError(where, std::string("the settings have no '") + name + "'");
    try {
      from_json(*it, field);
    } catch (const nlohmann::json::exception&) {
      throw InputError(where, std::string("the settings' '") + name + "' is of the wrong type: " + it->dump());
    }
  });
  return args;
}

namespace {

// Makes every path field it is shown absolute, and leaves the other fields.
struct MakeAbsolute {
  void operator()(const char*, fs::path& p) const { p = absolute_path(p); }
  void operator()(const char*, std::vector<fs::path>& paths) const {
    for (fs::path& p : paths) p = absolute_path(p);
  }
  template <class T>
  void operator()(const char*, T&) const {}
};

}  // namespace

BenchArgs with_absolute_paths(BenchArgs args) {
  each_setting(args, MakeAbsolute{});
  return args;
}

}  // namespace cluttertamp::bench
