#pragma once
// One subcommand of the `cluttertamp` program on the command line: each file of this
// folder declares one command's options (bound to its own arguments) and what runs it,
// so main() only lists the commands and maps outcomes to exit codes.

#include <cstddef>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "cli/commands.hpp"

namespace cluttertamp::cli {

/// A subcommand as declared: its CLI11 app and what runs it once parsed (an exit code).
struct Command {
  CLI::App* app = nullptr;
  std::function<int()> run;
};

/// What every command may set beside its own arguments.
struct CommonOptions {
  std::size_t memory_limit_mib = 0;  ///< 0: the default
};

/// Declares one subcommand on `app`, its arguments owned by the returned Command.
using CommandDeclaration = Command (*)(CLI::App& app, CommonOptions& common);

Command declare_plan(CLI::App& app, CommonOptions& common);
Command declare_observe(CLI::App& app, CommonOptions& common);
Command declare_view(CLI::App& app, CommonOptions& common);
Command declare_validate(CLI::App& app, CommonOptions& common);
Command declare_plugins(CLI::App& app, CommonOptions& common);
Command declare_pddl(CLI::App& app, CommonOptions& common);
Command declare_validate_plan(CLI::App& app, CommonOptions& common);
Command declare_generate(CLI::App& app, CommonOptions& common);
Command declare_guide(CLI::App& app, CommonOptions& common);
Command declare_self_collisions(CLI::App& app, CommonOptions& common);
Command declare_bench(CLI::App& app, CommonOptions& common);
Command declare_compare(CLI::App& app, CommonOptions& common);

// Options several commands share, worded the same everywhere.
void add_verbosity(CLI::App& app, Verbosity& verbosity, const std::string& verbose_help);
/// --memory-limit MiB on the commands that plan or search.
void add_memory_limit(CLI::App& app, CommonOptions& common);
/// --plugin-path DIR, repeatable.
void add_plugin_paths(CLI::App& app, std::vector<std::filesystem::path>& paths);
/// A whole number from 0 to 2^63 - 1.
CLI::Validator seed_validator();
/// A finite number of seconds greater than 0.
CLI::Validator seconds_validator();
/// A bundled file of the source tree (the default of some options).
std::filesystem::path source_file(const std::string& relative);

}  // namespace cluttertamp::cli
