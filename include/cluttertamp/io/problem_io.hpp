#pragma once

#include <filesystem>

#include "cluttertamp/core/problem.hpp"
#include "cluttertamp/export.hpp"

namespace cluttertamp::io {

inline constexpr int kProblemFormatVersion = 1;

/// Reads and validates a problem file and the scene it names (format: docs/file-formats.md,
/// "Problem files"). Relative paths in the file are taken relative to the file.
/// Throws InputError listing every problem found in both files.
CLUTTERTAMP_API Problem load_problem(const std::filesystem::path& file);

/// What read_problem made of a problem file: the problem as far as it could be read (a
/// part with an error is left as its default) and which parts read without error.
struct ProblemReading {
  Problem problem;
  /// No error in the problem file nor in any file it names (load_problem would return it).
  bool whole = false;
  /// No error in the `planner` and `plugins` blocks: the plugin choices are the file's.
  bool plugins_whole = false;
  /// No error in `plugins: paths:` (or none given): every directory the file names for
  /// plugins is known, so a plugin not found is not found.
  bool plugin_paths_whole = true;
};

/// load_problem that collects every error into `errors` instead of throwing, so that a
/// caller can go on to check what did read (`validate` checks the plugins of a problem
/// whose scene has errors). Throws only what load_problem throws beyond InputError.
CLUTTERTAMP_API ProblemReading read_problem(const std::filesystem::path& file, Diagnostics& errors);

/// What a YAML file is, judged by its top-level keys: a problem names a `task`.
enum class FileKind { problem, scene };
/// Throws InputError when the file cannot be read or parsed.
CLUTTERTAMP_API FileKind detect_file_kind(const std::filesystem::path& file);

}  // namespace cluttertamp::io
