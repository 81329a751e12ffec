#include "cli/command_line/command.hpp"

namespace cluttertamp::cli {

Command declare_validate_plan(CLI::App& app, CommonOptions&) {
  auto args = std::make_shared<ValidatePlanArgs>();
  auto* validate_plan = app.add_subcommand("validate-plan", "Check a plan against a PDDL domain and problem");
  validate_plan->add_option("domain", args->domain, "PDDL domain file")->required();
  validate_plan->add_option("problem", args->problem, "PDDL problem file")->required();
  validate_plan->add_option("plan", args->plan, "Plan file: (action arg ...) per line")->required();
  add_verbosity(*validate_plan, args->verbosity, "Same output as the default");
  return {validate_plan, [args] { return cli::validate_plan(*args); }};
}

}  // namespace cluttertamp::cli
