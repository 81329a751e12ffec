#include "cli/command_line/command.hpp"

namespace cluttertamp::cli {

Command declare_validate(CLI::App& app, CommonOptions& common) {
  auto args = std::make_shared<ValidateArgs>();
  auto* validate = app.add_subcommand("validate", "Check problem and scene files; print every error with its location");
  add_package_paths(*validate, common);
  validate->add_option("files", args->files, "Problem or scene files (YAML)")->required();
  validate->add_flag("--no-plugins", args->skip_plugins,
                     "Do not check that the plugins a problem names exist and accept their parameters");
  add_plugin_paths(*validate, args->plugin_paths);
  add_verbosity(*validate, args->verbosity, "Also list every object of each valid scene");
  return {validate, [args] { return cli::validate(*args); }};
}

}  // namespace cluttertamp::cli
