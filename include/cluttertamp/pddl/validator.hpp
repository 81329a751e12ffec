#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "cluttertamp/export.hpp"
#include "cluttertamp/pddl/ast.hpp"

namespace cluttertamp::pddl {

/// One line of a plan in IPC format: (action arg ...).
struct PlanStep {
  std::string action;
  std::vector<std::string> args;
  SourceLocation where;
};

/// Reads a plan: one (action arg ...) per line; ';' starts a comment. Throws
/// InputError (file:line:column) for syntax errors, unknown actions or objects, wrong
/// arity and arguments of the wrong type.
CLUTTERTAMP_API std::vector<PlanStep> parse_plan(const std::string& text, const std::string& file,
                                                 const Domain& domain, const Problem& problem);
CLUTTERTAMP_API std::vector<PlanStep> load_plan(const std::filesystem::path& file, const Domain& domain,
                                                const Problem& problem);

struct PlanValidation {
  bool valid = false;
  std::string reason;      ///< why not valid
  std::size_t step = 0;    ///< 1-based step that failed; 0 when the goal failed or valid
  double cost = 0;         ///< total cost (steps when the problem has no cost metric)
};

/// Simulates the plan on the lifted domain, independently of grounding and search:
/// each step's precondition in the state before it (derived predicates evaluated to
/// a fixpoint per stratum), conditional effects read in that state, deletes before
/// adds; then the goal. Derived predicates are evaluated over every typed binding of
/// their parameters, which is fine for the small problems plans are checked on.
CLUTTERTAMP_API PlanValidation validate_plan(const Domain& domain, const Problem& problem,
                                             const std::vector<PlanStep>& plan);

}  // namespace cluttertamp::pddl
