#pragma once

#include <cstdint>
#include <map>
#include <set>
#include <string>
#include <variant>
#include <vector>

#include "cluttertamp/core/diagnostics.hpp"
#include "cluttertamp/export.hpp"

namespace cluttertamp {

/// A value given to a plugin in a problem file.
using ParameterValue = std::variant<bool, std::int64_t, double, std::string, std::vector<double>>;

/// Named plugin parameters that remember where each was written, so a plugin can
/// reject a bad value with the file, line and column of the value.
///
/// Reading a key marks it used; after a plugin is configured, the registry reports
/// every key it never read as an unknown parameter.
class CLUTTERTAMP_API Parameters {
 public:
  void set(std::string key, ParameterValue value, SourceLocation where = {});

  bool contains(const std::string& key) const;
  std::size_t size() const { return values_.size(); }

  /// Each getter returns `fallback` when the key is absent and throws InputError
  /// (naming the value's location) when the value has another type. Integers are
  /// accepted where a double is asked for.
  double get_double(const std::string& key, double fallback) const;
  std::int64_t get_int(const std::string& key, std::int64_t fallback) const;
  bool get_bool(const std::string& key, bool fallback) const;
  std::string get_string(const std::string& key, const std::string& fallback) const;
  std::vector<double> get_vector(const std::string& key, const std::vector<double>& fallback) const;

  /// Throws InputError naming the value when `ok` is false, e.g.
  /// `params.require(params.get_double("step", 0.02) > 0, "step", "must be positive")`.
  void require(bool ok, const std::string& key, const std::string& what) const;

  /// Keys that no getter has read.
  std::vector<std::string> unused() const;
  SourceLocation location(const std::string& key) const;

 private:
  struct Entry {
    ParameterValue value;
    SourceLocation where;
  };
  const Entry* find(const std::string& key) const;

  std::map<std::string, Entry> values_;
  mutable std::set<std::string> used_;
};

}  // namespace cluttertamp
