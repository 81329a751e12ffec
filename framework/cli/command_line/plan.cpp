#include "cli/command_line/command.hpp"

namespace cluttertamp::cli {

Command declare_plan(CLI::App& app, CommonOptions& common) {
  auto args = std::make_shared<PlanArgs>();
  auto* plan = app.add_subcommand("plan", "Plan a problem file; write OUTPUT/result.json");
  add_package_paths(*plan, common);
  plan->add_option("problem", args->problem, "Problem file (YAML)")->required()->check(CLI::ExistingFile);
  plan->add_option("--seed", args->seed, "Random seed, 0 to 2^63-1 (overrides the problem file's planner.seed)")
      ->check(seed_validator());
  plan->add_option("--time-limit", args->time_limit, "Wall-clock limit in seconds, > 0 (overrides planner.time_limit)")
      ->check(seconds_validator());
  plan->add_option("--planner", args->planner,
                   "Task planner plugin to run instead of the problem file's planner.plugin (its parameters are "
                   "dropped), e.g. exhaustive or traversability_graph to compare with retrieval_graph");
  plan->add_option("-o,--output", args->output, "Directory for result.json")->capture_default_str();
  add_plugin_paths(*plan, args->plugin_paths);
  plan->add_flag("--html", args->html, "Also write OUTPUT/plan.html, a page that replays the plan (see view)");
  plan->add_option("--repeat", args->repeat,
                   "Plan N times and check that every result equals the first apart from time fields (exit code 3 "
                   "when one differs, naming the first difference); OUTPUT/result.json is the first run's")
      ->check(CLI::Range(1, 1000));
  plan->add_option("--load", args->load,
                   "Run N busy threads on the planner's CPU while it plans (the planner then gets a fraction of one "
                   "core, as on a loaded machine): with --repeat or --expect, shows that load changes nothing")
      ->check(CLI::Range(0, 16));
  plan->add_option("--expect", args->expect,
                   "Compare the result with this earlier result.json apart from time fields and the problem and scene "
                   "paths (exit code 3 when they differ, naming the first difference)")
      ->check(CLI::ExistingFile);
  add_memory_limit(*plan, common);
  add_verbosity(*plan, args->verbosity, "Also print the plugin search (directories, plugins, failures)");
  return {plan, [args] { return cli::plan(*args); }};
}

}  // namespace cluttertamp::cli
