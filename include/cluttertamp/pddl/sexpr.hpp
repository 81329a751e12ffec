#pragma once

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "cluttertamp/core/diagnostics.hpp"
#include "cluttertamp/export.hpp"

namespace cluttertamp::pddl {

/// One node of an s-expression: an atom (a symbol, ?variable, :keyword or number) or a
/// parenthesised list. Symbols are lower-cased (PDDL is case-insensitive).
struct SExpr {
  bool is_list = false;
  std::string text;  ///< the atom's text; empty for lists
  std::vector<SExpr> items;
  SourceLocation where;

  bool is_atom() const { return !is_list; }
  bool is(std::string_view symbol) const { return !is_list && text == symbol; }
  /// A list whose first item is the atom `head`.
  bool is_form(std::string_view head) const { return is_list && !items.empty() && items[0].is(head); }
};

/// The text of a file, kept to quote lines in error messages.
struct SourceText {
  FileName file;  ///< shared by the locations read_sexprs gives
  std::string text;

  /// "  <line>\n  <spaces>^" for a location in this text; empty when out of range.
  std::string excerpt(const SourceLocation& where) const;
  /// InputError at `where` whose message ends with the excerpt.
  [[noreturn]] void fail(const SourceLocation& where, const std::string& message) const;
  /// "message" followed by the excerpt, for Diagnostics that collect several errors.
  std::string with_excerpt(const SourceLocation& where, const std::string& message) const;
};

/// Reads every top-level expression of a PDDL file. Throws InputError (file, line,
/// column and an excerpt with a caret) for unbalanced parentheses, stray characters
/// or nesting deeper than 200 levels. Never recurses deeper than that.
CLUTTERTAMP_API std::vector<SExpr> read_sexprs(const SourceText& source);

/// `name` as PDDL reads it: lower-cased (PDDL ignores case), e.g. a scene id or a
/// stream name from a problem file that must match a PDDL symbol.
CLUTTERTAMP_API std::string lower_name(std::string name);

/// The whole text of a PDDL or stream file. Throws InputError naming the file when it
/// does not exist, is not a regular file or is larger than 64 MiB.
CLUTTERTAMP_API std::string read_text_file(const std::filesystem::path& file);

}  // namespace cluttertamp::pddl
