#include "cli/command_line/command.hpp"
#include "cluttertamp/search/planner.hpp"

namespace cluttertamp::cli {

Command declare_pddl(CLI::App& app, CommonOptions& common) {
  auto args = std::make_shared<PddlArgs>();
  auto* pddl = app.add_subcommand("pddl", "Plan a PDDL domain and problem; print the plan in IPC format");
  pddl->add_option("domain", args->domain, "PDDL domain file")->required();
  pddl->add_option("problem", args->problem, "PDDL problem file")->required();
  pddl->add_option("--search", args->search, "Search algorithm")
      ->capture_default_str()
      ->check(CLI::IsMember(search::search_names()));
  pddl->add_option("--landmarks", args->landmarks,
                   "Landmarks of lama-first and --anytime: rhw (Richter, Helmert & Westphal, as LAMA: back-chaining "
                   "with finite-domain variables from mutex groups) or zhu-givan (label propagation)")
      ->capture_default_str()
      ->check(CLI::IsMember({"rhw", "zhu-givan"}));
  pddl->add_option("--time-limit", args->time_limit, "Seconds")->capture_default_str()->check(seconds_validator());
  pddl->add_option("--max-expansions", args->max_expansions, "Stop after this many expansions")->check(count_validator());
  pddl->add_option("--weight", args->weight, "Weight of h in wastar-ff")->capture_default_str()->check(finite_range(1.0, 1000.0));
  pddl->add_option("--plan", args->plan_file, "Also write the plan to this file (replaced whole; with --anytime, by each better plan)");
  pddl->add_flag("--anytime", args->anytime,
                 "After the first plan, search on for cheaper ones as LAMA does (weighted A* with weights 5, 3, 2, 1, "
                 "each under the best cost so far) until --time-limit, --max-expansions (counted over all searches), "
                 "or until no cheaper plan exists; each better plan is printed to stderr as found");
  add_memory_limit(*pddl, common);
  add_verbosity(*pddl, args->verbosity, "Same output as the default");
  return {pddl, [args] { return cli::pddl(*args); }};
}

}  // namespace cluttertamp::cli
