#include "cluttertamp/core/value.hpp"

#include <charconv>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <sstream>

namespace cluttertamp {

Value::Value(Data data, SourceLocation where) : data_(std::move(data)), where_(std::move(where)) {}

std::optional<double> Value::number() const {
  if (const auto* d = std::get_if<double>(&data_)) return *d;
  if (const auto* i = std::get_if<std::int64_t>(&data_)) return static_cast<double>(*i);
  return std::nullopt;
}

std::optional<std::vector<double>> Value::numbers() const {
  const List* entries = list();
  if (!entries) return std::nullopt;
  std::vector<double> out;
  out.reserve(entries->size());
  for (const Value& v : *entries) {
    const auto x = v.number();
    if (!x) return std::nullopt;
    out.push_back(*x);
  }
  return out;
}

const Value* Value::find(std::string_view key) const {
  if (const Map* entries = map()) {
    for (const auto& [k, v] : *entries) {
      if (k == key) return &v;
    }
  }
  return nullptr;
}

const char* Value::kind_name() const {
  switch (data_.index()) {
    case 0: return "null";
    case 1: return "a boolean";
    case 2: return "an integer";
    case 3: return "a number";
    case 4: return "a string";
    case 5: return "a list";
    default: return "a map";
  }
}

namespace {

// Plain scalars that YAML would read back as something other than this string.
bool needs_quotes(const std::string& s) {
  if (s.empty()) return true;
  // Words YAML reads as booleans or null (the problem reader takes YAML 1.1's yes/no/on/off
  // too), in any of their spellings.
  std::string lower;
  for (char c : s) lower += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  for (const char* word : {"true", "false", "null", "~", "yes", "no", "on", "off", "y", "n", ".inf", "+.inf", "-.inf", ".nan"}) {
    if (lower == word) return true;
  }
  char* end = nullptr;
  std::strtod(s.c_str(), &end);
  if (end && *end == '\0') return true;
  for (char c : s) {
    if (std::string_view(":{}[],#&*!|>'\"%@`\n\t").find(c) != std::string_view::npos) return true;
  }
  return s.front() == ' ' || s.back() == ' ' || s.front() == '-' || s.front() == '?';
}

void write(std::ostream& out, const Value& v) {
  if (v.is_null()) out << "null";
  else if (const bool* b = v.boolean()) out << (*b ? "true" : "false");
  else if (const std::int64_t* i = v.integer()) out << *i;
  else if (const std::string* s = v.string()) {
    if (!needs_quotes(*s)) {
      out << *s;
      return;
    }
    out << '"';
    for (char c : *s) {
      if (c == '"' || c == '\\') out << '\\' << c;
      else if (c == '\n') out << "\\n";
      else out << c;
    }
    out << '"';
  } else if (const Value::List* list = v.list()) {
    out << '[';
    for (std::size_t k = 0; k < list->size(); ++k) {
      if (k) out << ", ";
      write(out, (*list)[k]);
    }
    out << ']';
  } else if (const Value::Map* map = v.map()) {
    out << '{';
    for (std::size_t k = 0; k < map->size(); ++k) {
      if (k) out << ", ";
      write(out, Value((*map)[k].first));
      out << ": ";
      write(out, (*map)[k].second);
    }
    out << '}';
  } else {
    const double d = *v.number();
    char text[64];
    const auto written = std::to_chars(text, text + sizeof text, d);  // the shortest text that reads back as d
    std::string t(text, written.ptr);
    // A number that prints like an integer would read back as one.
    if (std::isfinite(d) && t.find_first_of(".eE") == std::string::npos) t += ".0";
    out << t;
  }
}

}  // namespace

std::string Value::to_yaml() const {
  std::ostringstream out;
  write(out, *this);
  return out.str();
}

}  // namespace cluttertamp
