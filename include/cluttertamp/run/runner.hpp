#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "cluttertamp/core/problem.hpp"
#include "cluttertamp/core/result.hpp"
#include "cluttertamp/export.hpp"
#include "cluttertamp/io/result_json.hpp"
#include "cluttertamp/plugin/context.hpp"
#include "cluttertamp/plugin/registry.hpp"

namespace cluttertamp::plugin {
class TaskPlanner;
}

namespace cluttertamp::run {

/// Process exit codes of `cluttertamp` (docs/commands.md, "Exit codes").
enum ExitCode : int { solved = 0, no_plan = 1, bad_input = 2, internal_error = 3 };

/// "memory limit reached (N MiB)": the reason of a run an allocation beyond the memory
/// limit (core/memory_limit.hpp) ended.
CLUTTERTAMP_API std::string memory_limit_reason();

/// Overrides of what a problem file says, e.g. from the command line.
struct RunOptions {
  std::optional<std::uint64_t> seed;
  std::optional<double> time_limit;  ///< seconds
  std::vector<std::filesystem::path> plugin_paths;  ///< searched before the problem's own
};

struct RunOutcome {
  Result result;
  io::RunInfo info;
};

/// The plugin directories a run of `problem` searches, in order: `options`' paths,
/// the problem file's `plugins: paths:`, then Registry::default_search_paths().
CLUTTERTAMP_API std::vector<std::filesystem::path> plugin_search_paths(const Problem& problem,
                                                                       const RunOptions& options);

/// The plugins a problem names, created and configured.
struct Plugins {
  std::shared_ptr<plugin::TaskPlanner> planner;
  plugin::Samplers samplers;
};

/// Creates and configures every plugin the problem names. Throws InputError listing
/// every one that is missing (with the near names that exist) or rejects its parameters.
CLUTTERTAMP_API Plugins create_plugins(const Problem& problem, const plugin::Registry& registry);

/// How much of a problem the plugin checks may judge.
enum class ProblemPart {
  /// The whole problem read without error: every check runs.
  whole,
  /// Only its `planner` and `plugins` blocks read without error: each named plugin is
  /// created and configured, and the planner says which kinds it needs, but it is not
  /// asked to check the problem's other inputs (they did not read).
  plugins,
  /// Some plugin choices did not read: the ones that did are created and configured.
  some_plugins,
};

/// create_plugins that adds every error to `errors` instead of throwing; `read` says
/// how much of the problem read (io::ProblemReading), and so which checks can run.
CLUTTERTAMP_API Plugins create_plugins(const Problem& problem, const plugin::Registry& registry, Diagnostics& errors,
                                       ProblemPart read);

/// Throws InputError, one error per contact, when a retrieval problem's robot starts in
/// collision: its initial configuration touching a movable object (located at the
/// object), a fixed body (at the body, naming the links) or itself (at the robot). No
/// plan can leave such a start; `plan` and `validate` refuse it before planning.
CLUTTERTAMP_API void check_start_configuration(const Problem& problem);

/// Creates the problem's plugins from `registry` and runs its task planner within the
/// time limit. Throws InputError when a plugin is missing or rejects its parameters, or
/// when the robot starts in collision (check_start_configuration).
/// Planning failure is an unsolved Result with a reason (exit code 1); an exception
/// escaping a plugin is caught and reported as an internal error (exit code 3).
CLUTTERTAMP_API RunOutcome plan(const Problem& problem, const plugin::Registry& registry, const RunOptions& options);

}  // namespace cluttertamp::run
