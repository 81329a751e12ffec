#pragma once

#include <cstdint>
#include <map>
#include <set>
#include <string_view>
#include <string>
#include <variant>
#include <vector>

#include "cluttertamp/core/diagnostics.hpp"
#include "cluttertamp/core/value.hpp"
#include "cluttertamp/export.hpp"

namespace cluttertamp {

/// A plain value for Parameters::set; a problem file can also give lists and maps (Value).
using ParameterValue = std::variant<bool, std::int64_t, double, std::string, std::vector<double>>;

/// A parameter a plugin reads in configure(): its key, type, value when absent and
/// help. `cluttertamp plugins -v` lists them, configuring each plugin with nothing set.
struct ParameterDeclaration {
  std::string key;
  std::string type;      ///< "number", "integer", "boolean", "string", "list of numbers", "any"
  std::string fallback;  ///< the default, in YAML ("" for get())
  std::string help;
};

/// Named plugin parameters that remember where each was written, so a plugin can
/// reject a bad value with the file, line and column of the value.
///
/// Reading a key marks it used; after a plugin is configured, the registry reports
/// every key it never read as an unknown parameter.
class CLUTTERTAMP_API Parameters {
 public:
  void set(std::string key, ParameterValue value, SourceLocation where = {});
  /// Any value, e.g. a map or a list read from YAML; its location is value.where().
  void set(std::string key, Value value);

  bool contains(const std::string& key) const;
  std::size_t size() const { return values_.size(); }
  /// Every key given, sorted; marks none read.
  std::vector<std::string> keys() const;
  /// All values as one YAML flow map, keys sorted (`{a: 1, b: [2, 3]}`); marks none read.
  std::string to_yaml() const;

  /// Each getter returns `fallback` when the key is absent and throws InputError
  /// (naming the value's location) when the value has another type. Integers are
  /// accepted where a double is asked for. `help` (units, range) is what
  /// `cluttertamp plugins -v` shows beside the key.
  double get_double(const std::string& key, double fallback, std::string_view help = {}) const;
  std::int64_t get_int(const std::string& key, std::int64_t fallback, std::string_view help = {}) const;
  bool get_bool(const std::string& key, bool fallback, std::string_view help = {}) const;
  std::string get_string(const std::string& key, const std::string& fallback, std::string_view help = {}) const;
  std::vector<double> get_vector(const std::string& key, const std::vector<double>& fallback,
                                 std::string_view help = {}) const;
  /// The value as written, of any kind (maps and lists nested freely); nullptr when
  /// absent. The plugin checks its shape and throws InputError(value->where(), ...).
  const Value* get(const std::string& key, std::string_view help = {}) const;

  /// Throws InputError naming the value when `ok` is false, e.g.
  /// `params.require(params.get_double("step", 0.02) > 0, "step", "must be positive")`.
  void require(bool ok, const std::string& key, const std::string& what) const;

  /// Keys that no getter has read.
  std::vector<std::string> unused() const;
  SourceLocation location(const std::string& key) const;

  /// What the getters were asked, in the order of first asking.
  const std::vector<ParameterDeclaration>& declarations() const { return declarations_; }
  /// The same values with nothing read or declared yet: every plugin object is
  /// configured from its own fresh copy, so one problem can create it many times.
  Parameters fresh() const;

 private:
  const Value* find(const std::string& key, const char* type, std::string fallback, std::string_view help) const;

  std::map<std::string, Value> values_;
  mutable std::set<std::string> used_;
  mutable std::vector<ParameterDeclaration> declarations_;
};

}  // namespace cluttertamp
