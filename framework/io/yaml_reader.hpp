#pragma once
// Internal: reading YAML with located, accumulated errors. Every reader reports
// into one Diagnostics object and keeps going, so a file's problems are listed
// together; getters return std::nullopt where a value was missing or wrong.

#include <filesystem>
#include <initializer_list>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <yaml-cpp/yaml.h>

#include "cluttertamp/core/diagnostics.hpp"
#include "cluttertamp/core/parameters.hpp"

namespace cluttertamp::io::detail {

/// Physical bounds on what files may say, so that no value reaches geometry code as
/// an absurd magnitude (metres, radians).
inline constexpr double kMaxCoordinate = 1000.0;
inline constexpr double kMaxAngle = 1000.0;
inline constexpr double kMinSize = 1e-4;
inline constexpr double kMaxSize = 100.0;

/// A parsed YAML file and the sink for its problems.
class YamlFile {
 public:
  /// Parses `file`; a missing file or a syntax error is reported, and root() is null.
  YamlFile(const std::filesystem::path& file, Diagnostics& diagnostics);

  /// False when the file could not be read or parsed (the problem is reported).
  bool loaded() const { return loaded_; }
  const YAML::Node& root() const { return root_; }
  const std::filesystem::path& path() const { return path_; }
  SourceLocation at(const YAML::Node& node) const;
  void error(const YAML::Node& node, const std::string& message) const;
  void error(const SourceLocation& where, const std::string& message) const { diagnostics_.error(where, message); }

  /// A path written in the file, made absolute relative to the file's directory.
  std::filesystem::path resolve(const std::string& relative) const;

  // Typed reads of one node; each reports a type error with `what` naming the value.
  std::optional<double> number(const YAML::Node& node, const std::string& what) const;
  std::optional<double> positive(const YAML::Node& node, const std::string& what) const;
  /// A number in [lo, hi]; the message names the range and `unit` (e.g. "m").
  std::optional<double> number_in(const YAML::Node& node, const std::string& what, double lo, double hi,
                                  const std::string& unit) const;
  std::optional<std::int64_t> integer(const YAML::Node& node, const std::string& what) const;
  std::optional<bool> boolean(const YAML::Node& node, const std::string& what) const;
  std::optional<std::string> string(const YAML::Node& node, const std::string& what) const;
  std::optional<std::vector<std::string>> strings(const YAML::Node& node, const std::string& what) const;
  std::optional<Eigen::Vector3d> vec3(const YAML::Node& node, const std::string& what) const;
  /// Three numbers in [lo, hi].
  std::optional<Eigen::Vector3d> vec3_in(const YAML::Node& node, const std::string& what, double lo, double hi,
                                         const std::string& unit) const;
  /// `{xyz: [x, y, z], rpy: [roll, pitch, yaw]}`; rpy in radians, optional (zero).
  /// Coordinates within +-kMaxCoordinate metres, angles within +-kMaxAngle radians.
  std::optional<Eigen::Isometry3d> pose(const YAML::Node& node, const std::string& what) const;
  /// Reports a `version` node that is not the integer `expected`, naming the `format`
  /// ("scene", "problem", ...); a missing node (undefined) is left to the caller.
  void check_version(const YAML::Node& version, const std::string& format, int expected) const;
  /// Any YAML value as a Value tree (scalars typed as Value documents); reports
  /// duplicate or non-string keys and non-finite numbers.
  std::optional<Value> value(const YAML::Node& node, const std::string& what) const;
  /// A map of plugin parameters, each any Value but null.
  Parameters parameters(const YAML::Node& node, const std::string& what) const;

 private:
  std::filesystem::path path_;
  Diagnostics& diagnostics_;
  YAML::Node root_;
  bool loaded_ = false;
};

/// One YAML mapping with a fixed set of allowed keys. Reports a non-map node,
/// duplicate keys, missing required keys and, when destroyed, every key that was
/// not allowed.
class MapReader {
 public:
  MapReader(const YamlFile& file, const YAML::Node& node, std::string what,
            std::initializer_list<const char*> allowed_keys);
  ~MapReader();
  MapReader(const MapReader&) = delete;
  MapReader& operator=(const MapReader&) = delete;

  bool valid() const { return valid_; }
  const YAML::Node& node() const { return node_; }
  bool has(const std::string& key) const;
  /// The value of `key`, or a null node when absent.
  YAML::Node optional(const std::string& key) const;
  /// The value of `key`; reports "missing key" when absent.
  YAML::Node required(const std::string& key) const;
  /// Reports keys that are not allowed; done once, at the latest by the destructor.
  void report_unknown_keys();

 private:
  const YamlFile& file_;
  YAML::Node node_;
  std::string what_;
  std::set<std::string> allowed_;
  bool valid_ = false;
  bool reported_ = false;
};

}  // namespace cluttertamp::io::detail
