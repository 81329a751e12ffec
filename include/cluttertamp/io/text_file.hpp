#pragma once
// Whole text files in and out, failures as InputError naming the file.

#include <filesystem>
#include <string>

#include "cluttertamp/export.hpp"

namespace cluttertamp::io {

/// The file's bytes. Throws InputError naming the file and `what` when it cannot be read.
CLUTTERTAMP_API std::string read_text_file(const std::filesystem::path& file, const std::string& what = "file");

/// Writes `text` to `file`, creating its directory. A regular file is replaced
/// atomically (a complete copy renamed over it): readers see the old or the new file,
/// never part of one. Throws InputError naming the file and `what` when it cannot be
/// written (the old file is then left as it was).
CLUTTERTAMP_API void write_text_file(const std::filesystem::path& file, const std::string& text, const std::string& what = "file");

}  // namespace cluttertamp::io
