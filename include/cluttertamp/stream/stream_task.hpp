#pragma once

#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cluttertamp/core/diagnostics.hpp"
#include "cluttertamp/core/problem.hpp"
#include "cluttertamp/export.hpp"
#include "cluttertamp/pddl/ast.hpp"
#include "cluttertamp/stream/stream_file.hpp"

namespace cluttertamp::stream {

/// The files of a `task: pddl` problem, parsed once when the problem is loaded
/// (io::load_problem fills PddlTask::parsed with it).
struct ParsedTask {
  pddl::Domain domain;
  std::optional<pddl::Problem> problem;  ///< absent: the facts come from the scene
  std::optional<StreamFile> streams;
  /// What the files hold that is suspect but accepted, in the order read.
  std::vector<Diagnostic> warnings;
};

/// Parses the domain, the problem (against the domain) and the stream file (against
/// the domain) of `task`. Throws InputError with every error of the first file that
/// has any (a problem cannot be read against a domain that does not parse).
CLUTTERTAMP_API std::shared_ptr<const ParsedTask> parse_task(const PddlTask& task);

/// The files of `task` as parsed at load, or parsed now when the task was built in code.
CLUTTERTAMP_API std::shared_ptr<const ParsedTask> parsed_task(const PddlTask& task);

/// Adds an error for every stream of `streams` that has no code (rules need none),
/// located at its declaration. `is_bound(name)`: whether the stream (its name lower
/// case, as the stream file declares it) is bound to a stream_sampler.
CLUTTERTAMP_API void check_streams_bound(const StreamFile& streams, const std::function<bool(const std::string&)>& is_bound,
                                         Diagnostics& diagnostics);

/// Adds an error for every binding of a problem file (`plugins: streams:`, by name as
/// written) that names no stream of `streams`, located at the binding.
CLUTTERTAMP_API void check_bindings_declared(const StreamFile& streams,
                                             const std::map<std::string, PluginChoice>& bindings,
                                             Diagnostics& diagnostics);

}  // namespace cluttertamp::stream
