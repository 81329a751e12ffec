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

/// What a YAML file is, judged by its top-level keys: a problem names a `task`.
enum class FileKind { problem, scene };
/// Throws InputError when the file cannot be read or parsed.
CLUTTERTAMP_API FileKind detect_file_kind(const std::filesystem::path& file);

}  // namespace cluttertamp::io
