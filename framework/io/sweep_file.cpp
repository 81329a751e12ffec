#include "cluttertamp/io/sweep_file.hpp"

#include <algorithm>
#include <set>

#include "io/yaml_reader.hpp"

namespace cluttertamp::io {

namespace {

using detail::MapReader;
using detail::YamlFile;

// More planners than this (a grid's combinations, or all of them) is a mistake, not a sweep.
constexpr std::size_t kMaxGridPoints = 10000;
constexpr std::int64_t kMaxSeeds = 100000;

void read_problems(const YamlFile& file, const YAML::Node& node, SweepSpec& spec) {
  if (!node.IsDefined()) return;
  if (!node.IsSequence() || node.size() == 0) {
    file.error(node, "problems must be a list of problem files");
    return;
  }
  for (const YAML::Node& item : node) {
    const auto name = file.string(item, "problem file");
    if (!name) continue;
    const std::filesystem::path path = file.resolve(*name).lexically_normal();
    if (std::find(spec.problems.begin(), spec.problems.end(), path) != spec.problems.end()) {
      file.error(item, "problem file '" + *name + "' is listed twice");
      continue;
    }
    std::error_code error;
    if (!std::filesystem::is_regular_file(path, error)) {
      file.error(item, "problem file '" + *name + "' does not exist (" + path.string() + ")");
      continue;
    }
    spec.problems.push_back(path);
    spec.problem_where.push_back(file.at(item));
  }
}

// One grid axis: a key and its values, each a parameter value of its own.
struct Axis {
  std::string key;
  std::vector<Value> values;
};

std::vector<Axis> read_grid(const YamlFile& file, const YAML::Node& node, const std::string& what) {
  std::vector<Axis> axes;
  if (!node.IsDefined() || node.IsNull()) return axes;
  const auto grid = file.value(node, what + " grid");
  if (!grid) return axes;
  if (!grid->map()) {
    file.error(node, what + " grid must map parameter names to lists of values");
    return axes;
  }
  for (const auto& [key, values] : *grid->map()) {
    if (!values.list() || values.list()->empty()) {
      file.error(values.where(), what + " grid '" + key + "' must be a non-empty list of values");
      continue;
    }
    axes.push_back({key, *values.list()});
  }
  return axes;
}

void read_planner(const YamlFile& file, const YAML::Node& node, std::size_t number, SweepSpec& spec) {
  const std::string what = "planner #" + std::to_string(number);
  MapReader map(file, node, what, {"plugin", "name", "parameters", "grid"});
  if (!map.valid()) return;
  const auto plugin = file.string(map.required("plugin"), what + " plugin");
  std::string name = plugin.value_or("");
  if (map.has("name")) name = file.string(map.optional("name"), what + " name").value_or(name);
  const Parameters fixed = file.parameters(map.optional("parameters"), what + " parameters");
  const std::vector<Axis> axes = read_grid(file, map.optional("grid"), what);
  if (!plugin) return;
  std::size_t points = 1;
  for (const Axis& axis : axes) {
    if (fixed.contains(axis.key)) file.error(node, what + ": '" + axis.key + "' is both a fixed parameter and a grid axis");
    points *= axis.values.size();
    if (points > kMaxGridPoints) {
      file.error(map.optional("grid"), what + " grid has more than " + std::to_string(kMaxGridPoints) + " combinations");
      return;
    }
  }
  for (std::size_t point = 0; point < points; ++point) {
    SweepPlanner planner{name, *plugin, fixed, {}, file.at(node)};
    std::size_t rest = point;
    std::vector<std::size_t> choice(axes.size());  // the last axis varies fastest
    for (std::size_t k = axes.size(); k-- > 0;) {
      choice[k] = rest % axes[k].values.size();
      rest /= axes[k].values.size();
    }
    for (std::size_t k = 0; k < axes.size(); ++k) {
      const Value& value = axes[k].values[choice[k]];
      planner.parameters.set(axes[k].key, value);
      planner.grid_values.push_back(axes[k].key + "=" + value.to_yaml());
    }
    if (!planner.grid_values.empty()) {
      std::string joined;
      for (const std::string& v : planner.grid_values) joined += (joined.empty() ? "" : ",") + v;
      planner.label += "[" + joined + "]";
    }
    spec.planners.push_back(std::move(planner));
  }
}

void read_seeds(const YamlFile& file, const YAML::Node& node, SweepSpec& spec) {
  if (!node.IsDefined()) {
    spec.seeds = {0};
    return;
  }
  if (node.IsScalar()) {
    const auto count = file.integer(node, "seeds");
    if (!count) return;
    if (*count < 1 || *count > kMaxSeeds) {
      file.error(node, "seeds must be a count from 1 to " + std::to_string(kMaxSeeds) + " or a list of seeds");
      return;
    }
    for (std::int64_t s = 0; s < *count; ++s) spec.seeds.push_back(static_cast<std::uint64_t>(s));
    return;
  }
  if (!node.IsSequence() || node.size() == 0 || node.size() > static_cast<std::size_t>(kMaxSeeds)) {
    file.error(node, "seeds must be a count or a non-empty list of seeds");
    return;
  }
  std::set<std::uint64_t> seen;
  for (const YAML::Node& item : node) {
    const auto seed = file.integer(item, "seed");
    if (!seed) continue;
    if (*seed < 0) {
      file.error(item, "a seed must not be negative");
    } else if (!seen.insert(static_cast<std::uint64_t>(*seed)).second) {
      file.error(item, "seed " + std::to_string(*seed) + " is listed twice");
    } else {
      spec.seeds.push_back(static_cast<std::uint64_t>(*seed));
    }
  }
}

}  // namespace

SweepSpec load_sweep_file(const std::filesystem::path& file) {
  Diagnostics diagnostics;
  YamlFile yaml(file, diagnostics);
  SweepSpec spec;
  spec.file = std::filesystem::absolute(file).lexically_normal();
  if (yaml.loaded() && yaml.root().IsNull()) yaml.error(SourceLocation{file.string(), 1, 1}, "the sweep file is empty");
  if (yaml.loaded() && !yaml.root().IsNull()) {
    MapReader top(yaml, yaml.root(), "the sweep", {"version", "problems", "planners", "seeds", "time_limit"});
    if (top.valid()) {
      yaml.check_version(top.required("version"), "sweep", kSweepFormatVersion);
      read_problems(yaml, top.required("problems"), spec);
      const YAML::Node planners = top.required("planners");
      if (planners.IsDefined() && (!planners.IsSequence() || planners.size() == 0)) {
        yaml.error(planners, "planners must be a list of {plugin: NAME, parameters: {...}, grid: {...}}");
      } else if (planners.IsDefined()) {
        std::size_t number = 0;
        for (const YAML::Node& item : planners) {
          read_planner(yaml, item, ++number, spec);
          if (spec.planners.size() > kMaxGridPoints) {  // aliases can repeat a large entry
            yaml.error(planners, "planners make more than " + std::to_string(kMaxGridPoints) + " planners in all");
            spec.planners.clear();
            break;
          }
        }
      }
      std::set<std::string> labels;
      for (const SweepPlanner& p : spec.planners) {
        if (!labels.insert(p.label).second) yaml.error(p.where, "two planners are called '" + p.label + "': give one a name");
      }
      read_seeds(yaml, top.optional("seeds"), spec);
      if (top.has("time_limit")) spec.time_limit = yaml.positive(top.optional("time_limit"), "time_limit");
    }
  }
  diagnostics.throw_if_any();
  return spec;
}

}  // namespace cluttertamp::io
