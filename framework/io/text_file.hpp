#pragma once
// Internal: whole text files in and out, failures as InputError naming the file.

#include <filesystem>
#include <string>

namespace cluttertamp::io::detail {

/// The file's bytes. Throws InputError naming the file and `what` when it cannot be read.
std::string read_text_file(const std::filesystem::path& file, const std::string& what = "file");

/// Writes `text` to `file`, creating its directory. Throws InputError naming the file
/// and `what` when it cannot be written.
void write_text_file(const std::filesystem::path& file, const std::string& text, const std::string& what = "file");

}  // namespace cluttertamp::io::detail
