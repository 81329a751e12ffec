#include "cluttertamp/core/diagnostics.hpp"

#include <algorithm>
#include <ostream>
#include <tuple>

namespace cluttertamp {

const std::string& FileName::empty_name() {
  static const std::string empty;
  return empty;
}

std::ostream& operator<<(std::ostream& out, const FileName& f) { return out << f.str(); }

std::string SourceLocation::str() const {
  std::string out = file.empty() ? std::string("<input>") : file.str();
  if (line > 0) {
    // Appended piece by piece: g++ 12 warns falsely (-Wrestrict) on ":" + std::string.
    out += ':';
    out += std::to_string(line);
    if (column > 0) {
      out += ':';
      out += std::to_string(column);
    }
  }
  return out;
}

std::string Diagnostic::str() const { return location.str() + (warning ? ": warning: " : ": error: ") + message; }

void Diagnostics::error(SourceLocation location, std::string message) {
  items_.push_back({std::move(location), std::move(message)});
}

void Diagnostics::warning(SourceLocation location, std::string message) {
  warnings_.push_back({std::move(location), std::move(message), true});
}

void Diagnostics::append(const Diagnostics& other) {
  items_.insert(items_.end(), other.items_.begin(), other.items_.end());
  warnings_.insert(warnings_.end(), other.warnings_.begin(), other.warnings_.end());
}

std::string Diagnostics::str() const {
  std::vector<Diagnostic> sorted = items_;
  std::stable_sort(sorted.begin(), sorted.end(), [](const Diagnostic& a, const Diagnostic& b) {
    return std::tie(a.location.file, a.location.line, a.location.column) <
           std::tie(b.location.file, b.location.line, b.location.column);
  });
  std::string out;
  for (const Diagnostic& d : sorted) out += d.str() + "\n";
  return out;
}

void Diagnostics::throw_if_any() const {
  if (!items_.empty()) throw InputError(*this);
}

namespace {
std::string summary(const Diagnostics& diagnostics) {
  std::string text = diagnostics.str();
  if (!text.empty() && text.back() == '\n') text.pop_back();
  return text;
}
Diagnostics single(SourceLocation location, const std::string& message) {
  Diagnostics d;
  d.error(std::move(location), message);
  return d;
}
}  // namespace

InputError::InputError(Diagnostics diagnostics)
    : std::runtime_error(summary(diagnostics)), diagnostics_(std::move(diagnostics)) {}

InputError::InputError(SourceLocation location, const std::string& message)
    : InputError(single(std::move(location), message)) {}

InputError::~InputError() = default;

namespace {
// Levenshtein distance.
std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t above = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = above;
    }
  }
  return row[b.size()];
}
}  // namespace

std::string did_you_mean(const std::string& given, const std::vector<std::string>& candidates) {
  std::string hint;
  for (const std::string& near : candidates) {
    if (near != given && edit_distance(near, given) <= std::max<std::size_t>(2, given.size() / 4)) {
      hint += (hint.empty() ? " (did you mean '" : " or '") + near + "'";
    }
  }
  return hint.empty() ? hint : hint + "?)";
}

}  // namespace cluttertamp
