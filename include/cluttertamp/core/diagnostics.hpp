#pragma once

#include <compare>
#include <cstddef>
#include <iosfwd>
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "cluttertamp/export.hpp"

namespace cluttertamp {

/// The name of an input file, shared by the copies: a parser gives every token of a
/// file a location, and copying one copies a pointer instead of the name. Reads as the
/// `const std::string&` it holds, which lives as long as some copy of the FileName does:
/// `const std::string& f = make_location().file;` would dangle (copy the string instead).
class CLUTTERTAMP_API FileName {
 public:
  FileName() = default;
  FileName(std::string name)  // NOLINT(google-explicit-constructor): a location is written {file, line, column}
      : name_(name.empty() ? nullptr : std::make_shared<const std::string>(std::move(name))) {}
  FileName(const char* name) : FileName(std::string(name)) {}  // NOLINT(google-explicit-constructor)

  const std::string& str() const { return name_ ? *name_ : empty_name(); }
  operator const std::string&() const { return str(); }  // NOLINT(google-explicit-constructor)
  const char* c_str() const { return str().c_str(); }
  bool empty() const { return !name_; }

  friend bool operator==(const FileName& a, const FileName& b) { return a.name_ == b.name_ || a.str() == b.str(); }
  friend std::strong_ordering operator<=>(const FileName& a, const FileName& b) { return a.str() <=> b.str(); }
  /// Against "s.pddl", a std::string or a std::string_view.
  template <class Text>
    requires std::is_convertible_v<const Text&, std::string_view>
  friend bool operator==(const FileName& a, const Text& b) {
    return std::string_view(a.str()) == std::string_view(b);
  }
  friend std::ostream& operator<<(std::ostream& out, const FileName& f);

 private:
  static const std::string& empty_name();
  std::shared_ptr<const std::string> name_;  // null when empty
};

/// A place in an input file. Lines and columns count from 1; 0 means "unknown"
/// (for example a whole-file problem such as a missing file).
struct SourceLocation {
  FileName file;
  std::size_t line = 0;
  std::size_t column = 0;

  /// "file:line:column", "file:line" or "file", as much as is known.
  std::string str() const;
};

/// One problem found in an input, with where it is and what is wrong.
struct Diagnostic {
  SourceLocation location;
  std::string message;
  /// Suspect but accepted (as PDDLStream or Fast Downward would accept it), not an error.
  bool warning = false;

  /// "file:line:column: error: message" ("warning:" for a warning).
  std::string str() const;
};

/// Collects every problem in an input so that all of them are reported at once.
class CLUTTERTAMP_API Diagnostics {
 public:
  void error(SourceLocation location, std::string message);
  /// Records something suspect that is accepted: kept apart from the errors, never thrown.
  void warning(SourceLocation location, std::string message);
  void append(const Diagnostics& other);
  /// The warnings, in the order recorded.
  const std::vector<Diagnostic>& warnings() const { return warnings_; }

  bool empty() const { return items_.empty(); }
  std::size_t size() const { return items_.size(); }
  const std::vector<Diagnostic>& items() const { return items_; }

  /// Items sorted by file, line and column, one per line.
  std::string str() const;

  /// Throws InputError when any problem was collected.
  void throw_if_any() const;

 private:
  std::vector<Diagnostic> items_;
  std::vector<Diagnostic> warnings_;
};

/// Bad input from a user: a file that does not parse, does not validate, a plugin
/// that does not exist or does not load. The CLI maps it to exit code 2.
class CLUTTERTAMP_API InputError : public std::runtime_error {
 public:
  explicit InputError(Diagnostics diagnostics);
  InputError(SourceLocation location, const std::string& message);
  ~InputError() override;

  const Diagnostics& diagnostics() const { return diagnostics_; }

 private:
  Diagnostics diagnostics_;
};

/// " (did you mean 'x'?)" — or " (did you mean 'x' or 'y'?)" — naming the `candidates`
/// within a few edits of `given` (at most 2, or a quarter of its length); empty when
/// none is. For the end of an error about an unknown name.
CLUTTERTAMP_API std::string did_you_mean(const std::string& given, const std::vector<std::string>& candidates);

}  // namespace cluttertamp
