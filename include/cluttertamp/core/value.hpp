#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <variant>
#include <vector>

#include "cluttertamp/core/diagnostics.hpp"
#include "cluttertamp/export.hpp"

namespace cluttertamp {

/// A value written in a YAML file (a plugin parameter, an object's value in a stream
/// problem): null, a boolean, an integer, a number, a string, a list or a map, nested
/// freely, each part remembering where it was written so that a plugin can reject it
/// with file, line and column (`throw InputError(value.where(), "...")`).
///
/// Scalars are typed as the problem reader reads them: `3` an integer, `3.0` a number,
/// `true`, `false` (and YAML 1.1's `yes`, `no`, `on`, `off`) a boolean, `~` or nothing
/// null, `"3"` (quoted) and anything else a string.
class CLUTTERTAMP_API Value {
 public:
  using List = std::vector<Value>;
  /// Keys in the order written; unique (the reader refuses duplicates).
  using Map = std::vector<std::pair<std::string, Value>>;
  using Data = std::variant<std::monostate, bool, std::int64_t, double, std::string, List, Map>;

  Value() = default;
  Value(Data data, SourceLocation where = {});

  const Data& data() const { return data_; }
  const SourceLocation& where() const { return where_; }

  bool is_null() const { return std::holds_alternative<std::monostate>(data_); }
  const bool* boolean() const { return std::get_if<bool>(&data_); }
  const std::int64_t* integer() const { return std::get_if<std::int64_t>(&data_); }
  const std::string* string() const { return std::get_if<std::string>(&data_); }
  const List* list() const { return std::get_if<List>(&data_); }
  const Map* map() const { return std::get_if<Map>(&data_); }
  /// An integer or a number, as a double; nullopt for anything else.
  std::optional<double> number() const;
  /// A list whose entries are all integers or numbers; nullopt for anything else.
  std::optional<std::vector<double>> numbers() const;
  /// The entry `key` of a map; nullptr when absent or when this is not a map.
  const Value* find(std::string_view key) const;

  /// "a boolean", "an integer", "a number", "a string", "a list", "a map" or "null".
  const char* kind_name() const;
  /// The value in YAML flow style, e.g. `{x: [0, 1.5], name: "a b"}`.
  std::string to_yaml() const;

 private:
  Data data_;
  SourceLocation where_;
};

}  // namespace cluttertamp
