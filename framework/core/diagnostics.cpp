#include "cluttertamp/core/diagnostics.hpp"

#include <algorithm>
#include <tuple>

namespace cluttertamp {

std::string SourceLocation::str() const {
  std::string out = file.empty() ? std::string("<input>") : file;
  if (line > 0) {
    out += ":" + std::to_string(line);
    if (column > 0) out += ":" + std::to_string(column);
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

}  // namespace cluttertamp
