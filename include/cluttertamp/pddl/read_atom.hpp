#pragma once
// Reading (predicate term...) from an s-expression, shared by the PDDL and stream-file
// readers, which word their own messages.

#include <optional>

#include "cluttertamp/pddl/ast.hpp"
#include "cluttertamp/pddl/sexpr.hpp"
#include "cluttertamp/export.hpp"

namespace cluttertamp::pddl {

/// Why an expression is no atom.
enum class NotAnAtom { head, argument };

/// The atom `e` spells, or nothing with what is wrong and where (`e` itself, or the
/// nested argument).
CLUTTERTAMP_API std::optional<Atom> read_atom(const SExpr& e, NotAnAtom& why, SourceLocation& where);

}  // namespace cluttertamp::pddl
