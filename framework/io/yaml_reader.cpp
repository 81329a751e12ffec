#include "io/yaml_reader.hpp"

#include <cctype>
#include <cmath>
#include <cstdio>
#include <limits>
#include <fstream>
#include <map>
#include <set>
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

// YAML files we read are small; anything larger is a mistake (e.g. /dev/zero).
constexpr std::uintmax_t kMaxFileSize = 64u << 20;

// A plain decimal integer: yaml-cpp would also read 010 as octal 8 and 0x10 as 16.
bool decimal_integer(const std::string& text) {
  std::size_t i = (!text.empty() && (text[0] == '-' || text[0] == '+')) ? 1 : 0;
  if (i >= text.size()) return false;
  if (text[i] == '0' && i + 1 < text.size()) return false;
  for (; i < text.size(); ++i) {
    if (!std::isdigit(static_cast<unsigned char>(text[i]))) return false;
  }
  return true;
}
}  // namespace

YamlFile::YamlFile(const fs::path& file, Diagnostics& diagnostics) : path_(file), diagnostics_(diagnostics) {
  std::error_code ec;
  if (!fs::exists(file, ec)) {
    diagnostics_.error({file.string(), 0, 0}, "no such file");
    return;
  }
  if (!fs::is_regular_file(file, ec)) {
    diagnostics_.error({file.string(), 0, 0}, "not a regular file");
    return;
  }
  if (fs::file_size(file, ec) > kMaxFileSize) {
    diagnostics_.error({file.string(), 0, 0}, "larger than " + std::to_string(kMaxFileSize >> 20) + " MiB; not a problem or scene file");
    return;
  }
  std::ifstream in(file);
  if (!in) {
    diagnostics_.error({file.string(), 0, 0}, "cannot read the file");
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

std::optional<double> YamlFile::number_in(const YAML::Node& node, const std::string& what, double lo, double hi,
                                          const std::string& unit) const {
  auto value = number(node, what);
  if (value && (*value < lo || *value > hi)) {
    char range[96];
    std::snprintf(range, sizeof range, " must lie in [%g, %g] %s, not ", lo, hi, unit.c_str());
    error(node, what + range + node.Scalar());
    return std::nullopt;
  }
  return value;
}

std::optional<std::int64_t> YamlFile::integer(const YAML::Node& node, const std::string& what) const {
  long long value = 0;
  if (node.IsScalar() && !quoted(node) && decimal_integer(node.Scalar()) &&
      YAML::convert<long long>::decode(node, value)) {
    return value;
  }
  error(node, what + " must be a decimal integer, not " + describe(node));
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
  return vec3_in(node, what, -std::numeric_limits<double>::max(), std::numeric_limits<double>::max(), "");
}

std::optional<Eigen::Vector3d> YamlFile::vec3_in(const YAML::Node& node, const std::string& what, double lo, double hi,
                                                 const std::string& unit) const {
  if (!node.IsSequence() || node.size() != 3) {
    error(node, what + " must be a list of 3 numbers, not " + describe(node));
    return std::nullopt;
  }
  Eigen::Vector3d v;
  bool ok = true;
  for (int i = 0; i < 3; ++i) {
    auto x = number_in(node[i], what + "[" + std::to_string(i) + "]", lo, hi, unit);
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
  if (xyz_node.IsDefined()) xyz = vec3_in(xyz_node, what + " xyz", -kMaxCoordinate, kMaxCoordinate, "m");
  std::optional<Eigen::Vector3d> rpy = Eigen::Vector3d::Zero().eval();
  if (map.has("rpy")) rpy = vec3_in(map.optional("rpy"), what + " rpy", -kMaxAngle, kMaxAngle, "rad");
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

void YamlFile::check_version(const YAML::Node& version, const std::string& format, int expected) const {
  if (!version.IsDefined()) return;
  const auto v = integer(version, "version");
  if (v && *v != expected) {
    error(version, "unsupported " + format + " format version " + std::to_string(*v) + " (this cluttertamp reads " +
                       std::to_string(expected) + ")");
  }
}

std::optional<Value> YamlFile::value(const YAML::Node& node, const std::string& what) const {
  const SourceLocation where = at(node);
  if (!node.IsDefined() || node.IsNull()) return Value({}, where);
  if (node.IsScalar()) {
    long long i = 0;
    double d = 0;
    bool b = false;
    if (quoted(node)) return Value(node.Scalar(), where);
    if (decimal_integer(node.Scalar()) && YAML::convert<long long>::decode(node, i)) {
      return Value(static_cast<std::int64_t>(i), where);
    }
    if (YAML::convert<double>::decode(node, d)) {
      if (std::isfinite(d)) return Value(d, where);
      error(node, what + " must be a finite number, not " + node.Scalar());
      return std::nullopt;
    }
    if (YAML::convert<bool>::decode(node, b)) return Value(b, where);
    return Value(node.Scalar(), where);
  }
  if (node.IsSequence()) {
    Value::List list;
    bool ok = true;
    for (std::size_t k = 0; k < node.size(); ++k) {
      auto v = value(node[k], what + "[" + std::to_string(k) + "]");
      if (v) list.push_back(std::move(*v)); else ok = false;
    }
    if (!ok) return std::nullopt;
    return Value(std::move(list), where);
  }
  if (node.IsMap()) {
    Value::Map map;
    std::set<std::string> seen;
    bool ok = true;
    for (const auto& item : node) {
      if (!item.first.IsScalar()) {
        error(item.first, what + ": keys must be plain strings");
        ok = false;
        continue;
      }
      const std::string key = item.first.Scalar();
      if (!seen.insert(key).second) {
        error(item.first, what + ": duplicate key '" + key + "'");
        ok = false;
        continue;
      }
      auto v = value(item.second, what + "." + key);
      if (v) map.emplace_back(key, std::move(*v)); else ok = false;
    }
    if (!ok) return std::nullopt;
    return Value(std::move(map), where);
  }
  error(node, what + " must be a value, not " + describe(node));
  return std::nullopt;
}

Parameters YamlFile::parameters(const YAML::Node& node, const std::string& what) const {
  Parameters params;
  if (!node.IsDefined() || node.IsNull()) return params;
  if (!node.IsMap()) {
    error(node, what + " must be a mapping of names to values, not " + describe(node));
    return params;
  }
  const auto all = value(node, what);
  if (!all) return params;
  for (const auto& [key, v] : *all->map()) {
    if (v.is_null()) error(v.where(), "parameter '" + key + "' has no value (leave it out for its default)");
    else params.set(key, v);
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
    if (!item.first.IsScalar()) {
      file_.error(item.first, "keys in " + what_ + " must be plain strings");
      continue;
    }
    const std::string key = item.first.Scalar();
    auto [it, inserted] = first_seen.emplace(key, item.first);
    if (!inserted) {
      file_.error(item.first, "duplicate key '" + key + "' in " + what_ + " (first at line " +
                                  std::to_string(it->second.Mark().line + 1) + ")");
    }
  }
}

MapReader::~MapReader() { report_unknown_keys(); }

void MapReader::report_unknown_keys() {
  if (!valid_ || reported_) return;
  reported_ = true;
  for (const auto& item : node_) {
    if (!item.first.IsScalar()) continue;  // reported by the constructor
    const std::string key = item.first.Scalar();
    if (allowed_.count(key)) continue;
    std::string expected;
    for (const std::string& k : allowed_) expected += (expected.empty() ? "" : ", ") + k;
    file_.error(item.first, "unknown key '" + key + "' in " + what_ + " (expected one of: " + expected + ")");
  }
}

bool MapReader::has(const std::string& key) const { return valid_ && node_[key].IsDefined(); }

// A missing key of a const node is a "zombie" that throws YAML::InvalidNode on any
// question but IsDefined(); an undefined node answers every question.
YAML::Node MapReader::optional(const std::string& key) const {
  if (!valid_) return YAML::Node(YAML::NodeType::Undefined);
  YAML::Node value = node_[key];
  return value.IsDefined() ? value : YAML::Node(YAML::NodeType::Undefined);
}

YAML::Node MapReader::required(const std::string& key) const {
  if (!valid_) return YAML::Node(YAML::NodeType::Undefined);
  YAML::Node value = node_[key];
  if (value.IsDefined()) return value;
  file_.error(node_, what_ + " is missing the required key '" + key + "'");
  return YAML::Node(YAML::NodeType::Undefined);
}

}  // namespace cluttertamp::io::detail
