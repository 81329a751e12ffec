#pragma once
// The subcommands of the `cluttertamp` program. Each returns a process exit code
// (run::ExitCode) and lets InputError escape for main() to report with exit code 2.

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace cluttertamp::cli {

enum class Verbosity { quiet, normal, verbose };

struct PlanArgs {
  std::filesystem::path problem;
  std::optional<std::int64_t> seed;  ///< validated >= 0 by the parser
  std::optional<double> time_limit;
  std::filesystem::path output = "cluttertamp-out";
  std::vector<std::filesystem::path> plugin_paths;
  Verbosity verbosity = Verbosity::normal;
};
int plan(const PlanArgs& args);

struct ValidateArgs {
  std::vector<std::filesystem::path> files;
  bool skip_plugins = false;
  std::vector<std::filesystem::path> plugin_paths;
  Verbosity verbosity = Verbosity::normal;
};
int validate(const ValidateArgs& args);

struct PluginsArgs {
  std::vector<std::filesystem::path> plugin_paths;
  Verbosity verbosity = Verbosity::normal;
};
int plugins(const PluginsArgs& args);

}  // namespace cluttertamp::cli
