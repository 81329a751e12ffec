#include "cli/command_line/command.hpp"
#include "cluttertamp/io/text_file.hpp"

namespace cluttertamp::cli {

Command declare_compare(CLI::App& app, CommonOptions& common) {
  auto args = std::make_shared<CompareArgs>();
  auto* compare = app.add_subcommand(
      "compare", "Stream planning focused and not: {adaptive, incremental} x {pruned, all movable} (Tian et al., Table IV)");
  add_package_paths(*compare, common);
  compare->add_option("problems", args->problems, "Stream problem files (task: pddl); with several, --svg plots time against object count")
      ->required()
      ->check(CLI::ExistingFile);
  compare->add_option("--runs", args->runs, "Seeds per setting (seed, seed+1, ...)")->capture_default_str()->check(CLI::Range(1, 1000));
  compare->add_option("--seed", args->seed, "First seed")->capture_default_str();
  compare->add_option("--time-limit", args->time_limit, "Seconds per run (default: each problem's planner.time_limit)")
      ->check(finite_positive());
  compare->add_option("--json", args->json, "Also write the table as JSON to this file");
  compare->add_option("--csv", args->csv, "Also write every run as CSV to this file");
  compare->add_option("--svg", args->svg, "Also plot median time against object count (SVG) to this file");
  compare->add_flag("--check-goals", args->check_goals, "Exit code 1 when a run was not solved (else 0 whenever the comparison ran)");
  add_sweep_options(*compare, args->sweep, &args->ompl_log);
  add_plugin_paths(*compare, args->plugin_paths);
  add_memory_limit(*compare, common);
  add_verbosity(*compare, args->verbosity, "Same output as the default");
  return {compare, [args, &common] {
            // A sweep's results are never lost to an unwritable path found at its end.
            if (args->json) io::check_writable(*args->json, "JSON file (--json)");
            if (args->csv) io::check_writable(*args->csv, "CSV file (--csv)");
            if (args->svg) io::check_writable(*args->svg, "SVG file (--svg)");
            if (!args->sweep.records.empty()) io::check_writable(args->sweep.records, "records file (--records)");
            if (!args->ompl_log.empty()) io::check_writable(args->ompl_log, "OMPL benchmark log (--ompl-log)");
            args->sweep.package_paths = common.package_paths;
            args->sweep.memory_limit_mib = common.memory_limit_mib;
            return bench::compare(*args);
          }};
}

}  // namespace cluttertamp::cli
