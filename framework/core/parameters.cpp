#include "cluttertamp/core/parameters.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace cluttertamp {

namespace {

Value to_value(ParameterValue value, SourceLocation where) {
  return std::visit(
      [&](auto&& v) -> Value {
        using T = std::decay_t<decltype(v)>;
        if constexpr (std::is_same_v<T, std::vector<double>>) {
          Value::List list;
          for (double x : v) list.emplace_back(x, where);
          return Value(std::move(list), where);
        } else {
          return Value(std::move(v), where);
        }
      },
      std::move(value));
}

std::string yaml_of(const std::vector<double>& numbers) {
  Value::List list;
  for (double x : numbers) list.emplace_back(x);
  return Value(std::move(list)).to_yaml();
}

std::string wrong_type(const std::string& key, const Value& got, const char* wanted) {
  return "parameter '" + key + "' must be " + wanted + ", not " + got.kind_name();
}

std::string number_text(double x) {
  std::ostringstream out;
  out << x;
  return out.str();
}

}  // namespace

bool Range::contains(double x) const {
  if (std::isnan(x)) return false;
  if (low && (low_open ? x <= *low : x < *low)) return false;
  if (high && (high_open ? x >= *high : x > *high)) return false;
  return true;
}

std::string Range::str() const {
  if (low && high) {
    return std::string(low_open ? "(" : "[") + number_text(*low) + ", " + number_text(*high) + (high_open ? ")" : "]");
  }
  if (low) return (low_open ? "above " : "at least ") + number_text(*low);
  if (high) return (high_open ? "below " : "at most ") + number_text(*high);
  return "";
}

void Parameters::fail(SourceLocation where, std::string message) const {
  if (!collect_) throw InputError(std::move(where), message);
  errors_.error(std::move(where), std::move(message));
}

bool Parameters::in_range(const std::string& key, const Value& value, double x, const Range& range) const {
  if (range.contains(x)) return true;
  const std::string allowed = range.low && range.high ? "in " + range.str() : range.str();
  fail(value.where(), "parameter '" + key + "' must be " + allowed + ", not " + number_text(x));
  return false;
}

void Parameters::set(std::string key, ParameterValue value, SourceLocation where) {
  set(std::move(key), to_value(std::move(value), std::move(where)));
}

void Parameters::set(std::string key, Value value) { values_[std::move(key)] = std::move(value); }

bool Parameters::contains(const std::string& key) const { return values_.count(key) > 0; }

std::vector<std::string> Parameters::keys() const {
  std::vector<std::string> out;
  for (const auto& [key, value] : values_) out.push_back(key);
  return out;
}

std::string Parameters::to_yaml() const {
  Value::Map map;
  for (const auto& [key, value] : values_) map.emplace_back(key, value);
  return Value(std::move(map)).to_yaml();
}

const Value* Parameters::find(const std::string& key, const char* type, std::string fallback,
                              std::string_view help, const Range& range) const {
  const bool declared = std::any_of(declarations_.begin(), declarations_.end(),
                                    [&](const ParameterDeclaration& d) { return d.key == key; });
  if (!declared) declarations_.push_back({key, type, std::move(fallback), std::string(help), range.str()});
  auto it = values_.find(key);
  if (it == values_.end()) return nullptr;
  used_.insert(key);
  return &it->second;
}

double Parameters::get_double(const std::string& key, double fallback, std::string_view help,
                              const Range& range) const {
  const Value* v = find(key, "number", Value(fallback).to_yaml(), help, range);
  if (!v) return fallback;
  if (const auto x = v->number()) return in_range(key, *v, *x, range) ? *x : fallback;
  fail(v->where(), wrong_type(key, *v, "a number"));
  return fallback;
}

std::int64_t Parameters::get_int(const std::string& key, std::int64_t fallback, std::string_view help,
                                 const Range& range) const {
  const Value* v = find(key, "integer", std::to_string(fallback), help, range);
  if (!v) return fallback;
  if (const std::int64_t* i = v->integer()) return in_range(key, *v, static_cast<double>(*i), range) ? *i : fallback;
  fail(v->where(), wrong_type(key, *v, "an integer"));
  return fallback;
}

bool Parameters::get_bool(const std::string& key, bool fallback, std::string_view help) const {
  const Value* v = find(key, "boolean", fallback ? "true" : "false", help);
  if (!v) return fallback;
  if (const bool* b = v->boolean()) return *b;
  fail(v->where(), wrong_type(key, *v, "a boolean"));
  return fallback;
}

std::string Parameters::get_string(const std::string& key, const std::string& fallback, std::string_view help) const {
  const Value* v = find(key, "string", Value(fallback).to_yaml(), help);
  if (!v) return fallback;
  if (const std::string* s = v->string()) return *s;
  fail(v->where(), wrong_type(key, *v, "a string"));
  return fallback;
}

std::vector<double> Parameters::get_vector(const std::string& key, const std::vector<double>& fallback,
                                           std::string_view help, const Range& range) const {
  const Value* v = find(key, "list of numbers", yaml_of(fallback), help, range);
  if (!v) return fallback;
  const auto numbers = v->numbers();
  if (!numbers) {
    fail(v->where(), wrong_type(key, *v, "a list of numbers"));
    return fallback;
  }
  for (double x : *numbers) {
    if (!in_range(key, *v, x, range)) return fallback;
  }
  return *numbers;
}

const Value* Parameters::get(const std::string& key, std::string_view help) const {
  return find(key, "any", "", help);
}

void Parameters::require(bool ok, const std::string& key, const std::string& what) const {
  if (!ok) fail(location(key), "parameter '" + key + "' " + what);
}

std::vector<std::string> Parameters::unused() const {
  std::vector<std::string> keys;
  for (const auto& [key, value] : values_) {
    if (!used_.count(key)) keys.push_back(key);
  }
  return keys;
}

SourceLocation Parameters::location(const std::string& key) const {
  auto it = values_.find(key);
  return it == values_.end() ? SourceLocation{} : it->second.where();
}

Parameters Parameters::fresh(bool collect) const {
  Parameters copy;
  copy.values_ = values_;
  copy.collect_ = collect;
  return copy;
}

}  // namespace cluttertamp
