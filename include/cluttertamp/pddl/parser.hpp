#pragma once

#include <filesystem>
#include <string>

#include "cluttertamp/export.hpp"
#include "cluttertamp/pddl/ast.hpp"

namespace cluttertamp::pddl {

/// Requirements this parser supports; any other is refused with its name.
/// :strips :typing :negative-preconditions :disjunctive-preconditions :equality
/// :existential-preconditions :universal-preconditions :quantified-preconditions
/// :conditional-effects :derived-predicates :action-costs :adl
CLUTTERTAMP_API const std::set<std::string>& supported_requirements();

/// Parses and checks a domain. `file` names the text in errors. Throws InputError
/// listing every problem found (file:line:column, message, excerpt with a caret):
/// syntax errors, undeclared predicates, types, constants or variables, wrong arity,
/// type mismatches, duplicate names, unsupported requirements or constructs.
CLUTTERTAMP_API Domain parse_domain(const std::string& text, const std::string& file);
CLUTTERTAMP_API Domain load_domain(const std::filesystem::path& file);

/// Parses a problem and checks it against its domain (same errors as above, plus a
/// domain name that does not match).
CLUTTERTAMP_API Problem parse_problem(const std::string& text, const std::string& file, const Domain& domain);
CLUTTERTAMP_API Problem load_problem(const std::filesystem::path& file, const Domain& domain);

/// "(name arg ...)" of an atom, for messages and plans.
CLUTTERTAMP_API std::string to_string(const Atom& atom);

}  // namespace cluttertamp::pddl
