#pragma once

#include <cstdint>
#include <map>
#include <optional>
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

/// The numbers a parameter may take: an interval, either end closed, open or absent.
/// A NaN is in no range.
struct CLUTTERTAMP_API Range {
  std::optional<double> low, high;
  bool low_open = false, high_open = false;

  static Range closed(double low, double high) { return {low, high, false, false}; }              ///< [low, high]
  static Range open(double low, double high) { return {low, high, true, true}; }                  ///< (low, high)
  static Range closed_open(double low, double high) { return {low, high, false, true}; }         ///< [low, high)
  static Range open_closed(double low, double high) { return {low, high, true, false}; }         ///< (low, high]
  static Range at_least(double low) { return {low, std::nullopt, false, false}; }                 ///< [low, inf)
  static Range above(double low) { return {low, std::nullopt, true, false}; }                     ///< (low, inf)

  bool any() const { return !low && !high; }
  bool contains(double x) const;
  /// "(0, 1)", "[1, 64]", "at least 0", "above 0"; "" for any number.
  std::string str() const;
};

/// A parameter a plugin reads in configure(): its key, type, value when absent, range
/// and help. `cluttertamp plugins -v` lists them, configuring each plugin with nothing set.
struct ParameterDeclaration {
  std::string key;
  std::string type;      ///< "number", "integer", "boolean", "string", "list of numbers", "any"
  std::string fallback;  ///< the default, in YAML ("" for get())
  std::string help;
  std::string range;     ///< Range::str() of the values allowed ("" for any)
};

/// Named plugin parameters that remember where each was written, so a plugin can
/// reject a bad value with the file, line and column of the value.
///
/// Reading a key marks it used; after a plugin is configured, the registry reports
/// every key it never read as an unknown parameter. A value of the wrong type, outside
/// its range or failing require() throws InputError at once, except on the copies the
/// registry configures plugins with (collecting()): there each such error is recorded,
/// the getter returns the default, and the registry reports them all together.
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
  /// With a `range`, a value outside it is an error too (every element, for a list).
  double get_double(const std::string& key, double fallback, std::string_view help = {}, const Range& range = {}) const;
  std::int64_t get_int(const std::string& key, std::int64_t fallback, std::string_view help = {},
                       const Range& range = {}) const;
  bool get_bool(const std::string& key, bool fallback, std::string_view help = {}) const;
  std::string get_string(const std::string& key, const std::string& fallback, std::string_view help = {}) const;
  std::vector<double> get_vector(const std::string& key, const std::vector<double>& fallback,
                                 std::string_view help = {}, const Range& range = {}) const;
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
  /// With `collect`, the copy records bad values instead of throwing (see errors()).
  Parameters fresh(bool collect = false) const;
  /// The bad values recorded by a collecting copy, in the order met.
  const Diagnostics& errors() const { return errors_; }

 private:
  const Value* find(const std::string& key, const char* type, std::string fallback, std::string_view help,
                    const Range& range = {}) const;
  void fail(SourceLocation where, std::string message) const;
  bool in_range(const std::string& key, const Value& value, double x, const Range& range) const;

  std::map<std::string, Value> values_;
  mutable std::set<std::string> used_;
  mutable std::vector<ParameterDeclaration> declarations_;
  bool collect_ = false;
  mutable Diagnostics errors_;
};

}  // namespace cluttertamp
