#include "cli/command_line/command.hpp"

namespace cluttertamp::cli {

Command declare_guide(CLI::App& app, CommonOptions& common) {
  auto args = std::make_shared<GuideArgs>();
  auto* guide = app.add_subcommand(
      "guide", "Guide a reach problem from a browser (Papallas & Dogar's GRTC-HITL): serves a page on localhost where "
               "you click an object, then where it should go; the push is planned, and \"let the robot finish\" "
               "reaches the target in the time left. With --auto, write the automatic guidance to a file instead");
  add_package_paths(*guide, common);
  guide->add_option("problem", args->problem, "Problem file with task: {reach: <target>}")->required()->check(CLI::ExistingFile);
  guide->add_flag("--auto", args->automatic,
                  "Write the automatic guidance (the objects on the straight way from the exit to the target, each "
                  "pushed sideways off it) to --output and exit");
  guide->add_option("-o,--output", args->output,
                    "With --auto: the guidance file to write (required). Serving: the directory the session is saved in "
                    "after every input: guidance.yaml, result.json, and plan.html once finished (default: out/guide)");
  guide->add_option("--port", args->port, "Port to serve on (0: any free port; the address is printed)")
      ->capture_default_str()
      ->check(CLI::Range(0, 65535));
  guide->add_option("--host", args->host, "Address to serve on (127.0.0.1: this machine only)")->capture_default_str();
  guide->add_option("--push-time", args->push_time, "Planning seconds per guide at most (never beyond the time left)")
      ->capture_default_str()
      ->check(finite_positive());
  guide->add_option("--time-limit", args->time_limit,
                    "Planning seconds for the whole session, pushes and reach (overrides planner.time_limit)")
      ->check(finite_positive());
  guide->add_option("--seed", args->seed, "Random seed (overrides planner.seed)");
  guide->add_option("--max-guides", args->max_guides, "With --auto: at most this many guides")
      ->capture_default_str()
      ->check(CLI::Range(0, 100));
  guide->add_option("--diameter", args->diameter, "Diameter of every guide's region, m")
      ->capture_default_str()
      ->check(finite_range(0.01, 1.0));
  add_memory_limit(*guide, common);
  add_verbosity(*guide, args->verbosity, "Same output as the default");
  return {guide, [args] { return cli::guide(*args); }};
}

}  // namespace cluttertamp::cli
