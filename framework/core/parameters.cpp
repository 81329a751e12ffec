#include "cluttertamp/core/parameters.hpp"

namespace cluttertamp {

namespace {
const char* type_name(const ParameterValue& value) {
  switch (value.index()) {
    case 0: return "a boolean";
    case 1: return "an integer";
    case 2: return "a number";
    case 3: return "a string";
    default: return "a list of numbers";
  }
}
}  // namespace

void Parameters::set(std::string key, ParameterValue value, SourceLocation where) {
  values_[std::move(key)] = Entry{std::move(value), std::move(where)};
}

bool Parameters::contains(const std::string& key) const { return values_.count(key) > 0; }

const Parameters::Entry* Parameters::find(const std::string& key) const {
  auto it = values_.find(key);
  if (it == values_.end()) return nullptr;
  used_.insert(key);
  return &it->second;
}

namespace {
[[noreturn]] void wrong_type(const std::string& key, const SourceLocation& where, const char* wanted,
                             const ParameterValue& got) {
  throw InputError(where, "parameter '" + key + "' must be " + wanted + ", not " + type_name(got));
}
}  // namespace

double Parameters::get_double(const std::string& key, double fallback) const {
  const Entry* e = find(key);
  if (!e) return fallback;
  if (const auto* d = std::get_if<double>(&e->value)) return *d;
  if (const auto* i = std::get_if<std::int64_t>(&e->value)) return static_cast<double>(*i);
  wrong_type(key, e->where, "a number", e->value);
}

std::int64_t Parameters::get_int(const std::string& key, std::int64_t fallback) const {
  const Entry* e = find(key);
  if (!e) return fallback;
  if (const auto* i = std::get_if<std::int64_t>(&e->value)) return *i;
  wrong_type(key, e->where, "an integer", e->value);
}

bool Parameters::get_bool(const std::string& key, bool fallback) const {
  const Entry* e = find(key);
  if (!e) return fallback;
  if (const auto* b = std::get_if<bool>(&e->value)) return *b;
  wrong_type(key, e->where, "a boolean", e->value);
}

std::string Parameters::get_string(const std::string& key, const std::string& fallback) const {
  const Entry* e = find(key);
  if (!e) return fallback;
  if (const auto* s = std::get_if<std::string>(&e->value)) return *s;
  wrong_type(key, e->where, "a string", e->value);
}

std::vector<double> Parameters::get_vector(const std::string& key, const std::vector<double>& fallback) const {
  const Entry* e = find(key);
  if (!e) return fallback;
  if (const auto* v = std::get_if<std::vector<double>>(&e->value)) return *v;
  wrong_type(key, e->where, "a list of numbers", e->value);
}

void Parameters::require(bool ok, const std::string& key, const std::string& what) const {
  if (!ok) throw InputError(location(key), "parameter '" + key + "' " + what);
}

std::vector<std::string> Parameters::unused() const {
  std::vector<std::string> keys;
  for (const auto& [key, entry] : values_) {
    if (!used_.count(key)) keys.push_back(key);
  }
  return keys;
}

SourceLocation Parameters::location(const std::string& key) const {
  auto it = values_.find(key);
  return it == values_.end() ? SourceLocation{} : it->second.where;
}

}  // namespace cluttertamp
