#include "io/yaml_reader.hpp"

#include <cmath>
#include <fstream>
#include <map>
#include <sstream>

namespace cluttertamp::io::detail {

namespace fs = std::filesystem;

namespace {
std::string describe(const YAML::Node& node) {
  switch (node.Type()) {
    case YAML::NodeType::Map: return "a mapping";
    case YAML::NodeType::Sequence: return "a list of " + std::to_string(node.size()) + " items";
    case YAML::NodeType::Null: return "empty";
    case YAML::NodeType::Scalar: return "'" + node.Scalar() + "'";
    default: return "nothing";
  }
}
bool quoted(const YAML::Node& node) { return node.Tag() == "!"; }
}  // namespace

YamlFile::YamlFile(const fs::path& file, Diagnostics& diagnostics) : path_(file), diagnostics_(diagnostics) {
  std::ifstream in(file);
  if (!in) {
    diagnostics_.error({file.string(), 0, 0}, fs::exists(file) ? "cannot read the file" : "no such file");
    return;
  }
  std::stringstream text;
  text << in.rdbuf();
  try {
    root_ = YAML::Load(text.str());
    loaded_ = true;
  } catch (const YAML::Exception& e) {
    diagnostics_.error({file.string(), static_cast<std::size_t>(e.mark.line + 1),
                        static_cast<std::size_t>(e.mark.column + 1)},
                       "YAML syntax error: " + e.msg);
    root_ = YAML::Node();
  }
}

SourceLocation YamlFile::at(const YAML::Node& node) const {
  if (!node.IsDefined() || node.Mark().is_null()) return {path_.string(), 0, 0};
  const YAML::Mark mark = node.Mark();
  return {path_.string(), static_cast<std::size_t>(mark.line + 1), static_cast<std::size_t>(mark.column + 1)};
}

void YamlFile::error(const YAML::Node& node, const std::string& message) const { diagnostics_.error(at(node), message); }

fs::path YamlFile::resolve(const std::string& relative) const {
  fs::path p(relative);
  if (p.is_relative()) p = fs::absolute(path_).parent_path() / p;
  return p.lexically_normal();
}

std::optional<double> YamlFile::number(const YAML::Node& node, const std::string& what) const {
  double value = 0;
  if (node.IsScalar() && !quoted(node) && YAML::convert<double>::decode(node, value) && std::isfinite(value)) {
    return value;
  }
  error(node, what + " must be a finite number, not " + describe(node));
  return std::nullopt;
}

std::optional<double> YamlFile::positive(const YAML::Node& node, const std::string& what) const {
  auto value = number(node, what);
  if (value && *value <= 0) {
    error(node, what + " must be positive, not " + node.Scalar());
    return std::nullopt;
  }
  return value;
}

std::optional<std::int64_t> YamlFile::integer(const YAML::Node& node, const std::string& what) const {
  long long value = 0;
  if (node.IsScalar() && !quoted(node) && YAML::convert<long long>::decode(node, value)) return value;
  error(node, what + " must be an integer, not " + describe(node));
  return std::nullopt;
}

std::optional<bool> YamlFile::boolean(const YAML::Node& node, const std::string& what) const {
  bool value = false;
  if (node.IsScalar() && !quoted(node) && YAML::convert<bool>::decode(node, value)) return value;
  error(node, what + " must be true or false, not " + describe(node));
  return std::nullopt;
}

std::optional<std::string> YamlFile::string(const YAML::Node& node, const std::string& what) const {
  if (node.IsScalar() && !node.Scalar().empty()) return node.Scalar();
  error(node, what + " must be a non-empty string, not " + describe(node));
  return std::nullopt;
}

std::optional<std::vector<std::string>> YamlFile::strings(const YAML::Node& node, const std::string& what) const {
  if (!node.IsSequence()) {
    error(node, what + " must be a list of names, not " + describe(node));
    return std::nullopt;
  }
  std::vector<std::string> out;
  bool ok = true;
  for (const YAML::Node& item : node) {
    auto s = string(item, "each entry of " + what);
    if (s) out.push_back(*s); else ok = false;
  }
  if (!ok) return std::nullopt;
  return out;
}

std::optional<Eigen::Vector3d> YamlFile::vec3(const YAML::Node& node, const std::string& what) const {
  if (!node.IsSequence() || node.size() != 3) {
    error(node, what + " must be a list of 3 numbers, not " + describe(node));
    return std::nullopt;
  }
  Eigen::Vector3d v;
  bool ok = true;
  for (int i = 0; i < 3; ++i) {
    auto x = number(node[i], what + "[" + std::to_string(i) + "]");
    if (x) v[i] = *x; else ok = false;
  }
  if (!ok) return std::nullopt;
  return v;
}

std::optional<Eigen::Isometry3d> YamlFile::pose(const YAML::Node& node, const std::string& what) const {
  MapReader map(*this, node, what, {"xyz", "rpy"});
  if (!map.valid()) return std::nullopt;
  const YAML::Node xyz_node = map.required("xyz");
  std::optional<Eigen::Vector3d> xyz;
  if (xyz_node.IsDefined()) xyz = vec3(xyz_node, what + " xyz");
  std::optional<Eigen::Vector3d> rpy = Eigen::Vector3d::Zero().eval();
  if (map.has("rpy")) rpy = vec3(map.optional("rpy"), what + " rpy");
  if (!xyz || !rpy) return std::nullopt;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = *xyz;
  // URDF convention: R = Rz(yaw) * Ry(pitch) * Rx(roll).
  pose.linear() = (Eigen::AngleAxisd((*rpy)[2], Eigen::Vector3d::UnitZ()) *
                   Eigen::AngleAxisd((*rpy)[1], Eigen::Vector3d::UnitY()) *
                   Eigen::AngleAxisd((*rpy)[0], Eigen::Vector3d::UnitX()))
                      .toRotationMatrix();
  return pose;
}

Parameters YamlFile::parameters(const YAML::Node& node, const std::string& what) const {
  Parameters params;
  if (!node.IsDefined() || node.IsNull()) return params;
  if (!node.IsMap()) {
    error(node, what + " must be a mapping of names to values, not " + describe(node));
    return params;
  }
  for (const auto& item : node) {
    const std::string key = item.first.Scalar();
    const YAML::Node& value = item.second;
    const SourceLocation where = at(value);
    if (value.IsScalar()) {
      long long i = 0;
      double d = 0;
      bool b = false;
      if (quoted(value)) params.set(key, value.Scalar(), where);
      else if (YAML::convert<long long>::decode(value, i)) params.set(key, static_cast<std::int64_t>(i), where);
      else if (YAML::convert<double>::decode(value, d)) params.set(key, d, where);
      else if (YAML::convert<bool>::decode(value, b)) params.set(key, b, where);
      else params.set(key, value.Scalar(), where);
    } else if (value.IsSequence()) {
      std::vector<double> numbers;
      bool ok = true;
      for (const YAML::Node& x : value) {
        auto n = number(x, "each entry of parameter '" + key + "'");
        if (n) numbers.push_back(*n); else ok = false;
      }
      if (ok) params.set(key, numbers, where);
    } else {
      error(value, "parameter '" + key + "' must be a number, boolean, string or list of numbers, not " + describe(value));
    }
  }
  return params;
}

MapReader::MapReader(const YamlFile& file, const YAML::Node& node, std::string what,
                     std::initializer_list<const char*> allowed_keys)
    : file_(file), node_(node), what_(std::move(what)), allowed_(allowed_keys.begin(), allowed_keys.end()) {
  if (!node_.IsMap()) {
    file_.error(node_, what_ + " must be a mapping, not " + describe(node_));
    return;
  }
  valid_ = true;
  std::map<std::string, YAML::Node> first_seen;
  for (const auto& item : node_) {
    const std::string key = item.first.Scalar();
    auto [it, inserted] = first_seen.emplace(key, item.first);
    if (!inserted) {
      file_.error(item.first, "duplicate key '" + key + "' in " + what_ + " (first at line " +
                                  std::to_string(it->second.Mark().line + 1) + ")");
    }
  }
}

MapReader::~MapReader() {
  if (!valid_) return;
  for (const auto& item : node_) {
    const std::string key = item.first.Scalar();
    if (allowed_.count(key)) continue;
    std::string expected;
    for (const std::string& k : allowed_) expected += (expected.empty() ? "" : ", ") + k;
    file_.error(item.first, "unknown key '" + key + "' in " + what_ + " (expected one of: " + expected + ")");
  }
}

bool MapReader::has(const std::string& key) const { return valid_ && node_[key].IsDefined(); }

YAML::Node MapReader::optional(const std::string& key) const {
  if (!valid_) return YAML::Node();
  return node_[key];
}

YAML::Node MapReader::required(const std::string& key) const {
  if (!valid_) return YAML::Node();
  YAML::Node value = node_[key];
  if (!value.IsDefined()) file_.error(node_, what_ + " is missing the required key '" + key + "'");
  return value;
}

}  // namespace cluttertamp::io::detail
