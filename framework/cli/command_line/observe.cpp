#include "cli/command_line/command.hpp"

namespace cluttertamp::cli {

Command declare_observe(CLI::App& app, CommonOptions& common) {
  auto args = std::make_shared<ObserveArgs>();
  auto* observe = app.add_subcommand(
      "observe", "What the scene's camera sees: each object observed or hidden, how much of it is in view and "
                 "what hides it (ray casting; Tian et al., Section V-A)");
  add_package_paths(*observe, common);
  observe->add_option("file", args->file, "Scene or problem file")->required()->check(CLI::ExistingFile);
  observe->add_option("--remove", args->remove, "Take these objects away first (ids, repeatable or comma-separated)")
      ->delimiter(',');
  observe->add_option("--min-visible", args->min_visible_fraction,
                      "Observed when at least this fraction of the surface facing the camera is in view")
      ->capture_default_str()
      ->check(finite_range(0.001, 1.0));
  observe->add_flag("--json", args->json, "Print JSON: [{object, observed, visible_fraction, occluders}]");
  return {observe, [args] { return cli::observe(*args); }};
}

}  // namespace cluttertamp::cli
