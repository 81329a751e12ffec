#include "cli/command_line/command.hpp"

namespace cluttertamp::cli {

Command declare_plugins(CLI::App& app, CommonOptions&) {
  auto args = std::make_shared<PluginsArgs>();
  auto* plugins = app.add_subcommand("plugins", "List the plugins found, with kinds and versions, and any that failed to load");
  plugins->add_option("names", args->names, "Only these plugins (with -v: their parameters)");
  add_plugin_paths(*plugins, args->plugin_paths);
  add_verbosity(*plugins, args->verbosity,
                "Also print each plugin's library path and the parameters it reads (key, type, default, help)");
  return {plugins, [args] { return cli::plugins(*args); }};
}

}  // namespace cluttertamp::cli
