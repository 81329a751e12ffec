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
  std::vector<std::filesystem::path> package_paths;  ///< --package-path, for package:// meshes
};

/// Declares one subcommand on `app`, its arguments owned by the returned Command.
using CommandDeclaration = Command (*)(CLI::App& app, CommonOptions& common);

// The subcommands, in the order `--help` lists them: X(name) for each, the command
// declared by declare_name() in command_line/name.cpp.
#define CLUTTERTAMP_CLI_COMMANDS(X) \
  X(plan) X(observe) X(view) X(validate) X(plugins) X(pddl) X(validate_plan) X(generate) X(guide) \
  X(self_collisions) X(bench) X(compare)

#define CLUTTERTAMP_CLI_DECLARE(name) Command declare_##name(CLI::App& app, CommonOptions& common);
CLUTTERTAMP_CLI_COMMANDS(CLUTTERTAMP_CLI_DECLARE)
#undef CLUTTERTAMP_CLI_DECLARE

// Options several commands share, worded the same everywhere.
void add_verbosity(CLI::App& app, Verbosity& verbosity, const std::string& verbose_help);
/// --memory-limit MiB on the commands that plan or search.
void add_memory_limit(CLI::App& app, CommonOptions& common);
/// --plugin-path DIR, repeatable.
void add_plugin_paths(CLI::App& app, std::vector<std::filesystem::path>& paths);
/// --package-path DIR (repeatable): where a robot's package:// meshes are looked for.
void add_package_paths(CLI::App& app, CommonOptions& common);
/// A whole number from 0 to 2^63 - 1.
CLI::Validator seed_validator();
/// A finite number of seconds greater than 0.
CLI::Validator seconds_validator();
/// A finite number greater than 0 (CLI11's PositiveNumber lets NaN through).
CLI::Validator finite_positive();
/// A finite number of at least 0.
CLI::Validator finite_non_negative();
/// A finite number from `low` to `high` (CLI11's Range lets NaN through).
CLI::Validator finite_range(double low, double high);
/// A whole number from 0 to 2^64 - 1, without a sign (CLI11 reads "-1" as 2^64 - 1).
CLI::Validator count_validator();
/// "K/N" with 0 <= K < N (bench::parse_shard).
CLI::Validator shard_validator();
/// --shard K/N, -j N, --records FILE and --ompl-log FILE: a command that runs as a
/// sweep (docs/commands.md, "Sweeps"). Without `ompl_log` no --ompl-log: a speed bench,
/// whose runs are timed batches and not planning runs. `jobs_help` replaces -j's help.
void add_sweep_options(CLI::App& app, bench::SweepOptions& sweep, std::filesystem::path* ompl_log,
                       const std::string& jobs_help = "");
/// A bundled file of the source tree (the default of some options).
std::filesystem::path source_file(const std::string& relative);

}  // namespace cluttertamp::cli
