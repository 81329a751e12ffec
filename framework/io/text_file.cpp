#include "cluttertamp/io/text_file.hpp"

#include <fstream>
#include <sstream>

#include <unistd.h>

#include "cluttertamp/core/diagnostics.hpp"

namespace cluttertamp::io {

std::string read_text_file(const std::filesystem::path& file, const std::string& what) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError({file.string(), 0, 0}, "cannot read the " + what);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

void write_text_file(const std::filesystem::path& file, const std::string& text, const std::string& what) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (file.has_parent_path()) fs::create_directories(file.parent_path(), ec);
  const std::string failed = "cannot write the " + what + " (is the directory writable, the disk not full?)";
  // A device or pipe (/dev/stdout) is written as it is; a file is replaced whole, by
  // renaming a complete copy over it, so that a full disk or a kill never leaves half of one.
  const bool special = fs::exists(file, ec) && !fs::is_regular_file(file, ec);
  const fs::path written = special ? file : fs::path(file.string() + ".partial-" + std::to_string(::getpid()));
  std::ofstream out(written, std::ios::binary);
  out << text;
  out.close();
  if (!out) {
    if (!special) fs::remove(written, ec);
    throw InputError({file.string(), 0, 0}, failed);
  }
  if (special) return;
  fs::rename(written, file, ec);
  if (ec) {
    fs::remove(written, ec);
    throw InputError({file.string(), 0, 0}, failed);
  }
}

}  // namespace cluttertamp::io
