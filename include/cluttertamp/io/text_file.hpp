#pragma once
// Whole text files in and out. Reading failures are InputError naming the file; an
// output path is checked before the work that fills it (check_writable), so that a
// write failing afterwards is a fault of the run (WriteError), not bad input.

#include <filesystem>
#include <stdexcept>
#include <string>

#include "cluttertamp/export.hpp"

namespace cluttertamp::io {

/// The file's bytes. Throws InputError naming the file and `what` when it cannot be read.
CLUTTERTAMP_API std::string read_text_file(const std::filesystem::path& file, const std::string& what = "file");

/// A file could not be written although its path was usable (full disk, removed
/// directory, I/O error): `what()` names the file and the cause. The command line maps
/// it to exit code 3, a fault during the run.
class CLUTTERTAMP_API WriteError : public std::runtime_error {
 public:
  explicit WriteError(const std::string& message);
  ~WriteError() override;
};

/// Checks, before any work, that `file` can be written: its directory exists or can be
/// created and accepts a new file, and `file` is not a directory. Creates the directory;
/// writes nothing else. Throws InputError naming `file` and `what` (exit code 2).
CLUTTERTAMP_API void check_writable(const std::filesystem::path& file, const std::string& what = "file");

/// As check_writable, for a directory that will receive files: created when missing.
CLUTTERTAMP_API void check_writable_directory(const std::filesystem::path& directory, const std::string& what = "directory");

/// Writes `text` to `file`, creating its directory. A regular file is replaced
/// atomically (a complete copy in the same directory, flushed, then renamed over it):
/// readers see the old or the new file, never part of one. A device or pipe
/// (/dev/stdout) is written as it is. Throws WriteError naming the file and `what` when
/// it cannot be written; the old file is then left as it was.
CLUTTERTAMP_API void write_text_file(const std::filesystem::path& file, const std::string& text, const std::string& what = "file");

}  // namespace cluttertamp::io
