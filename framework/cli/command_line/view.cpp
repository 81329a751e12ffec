#include "cli/command_line/command.hpp"

namespace cluttertamp::cli {

Command declare_view(CLI::App& app, CommonOptions& common) {
  auto args = std::make_shared<ViewArgs>();
  auto* view = app.add_subcommand(
      "view", "Write one self-contained HTML page replaying a result.json in 3-D (opens from disk, no server, no network)");
  add_package_paths(*view, common);
  view->add_option("result", args->result, "A result.json written by plan")->required()->check(CLI::ExistingFile);
  view->add_option("--problem", args->problem, "The problem file (default: the one result.json names)")->check(CLI::ExistingFile);
  view->add_option("-o,--output", args->output, "Page to write (default: plan.html beside the result)");
  add_verbosity(*view, args->verbosity, "Same output as the default");
  return {view, [args] { return cli::view(*args); }};
}

}  // namespace cluttertamp::cli
