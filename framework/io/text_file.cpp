#include "cluttertamp/io/text_file.hpp"

#include <fstream>
#include <sstream>

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
  std::error_code ec;
  if (file.has_parent_path()) std::filesystem::create_directories(file.parent_path(), ec);
  std::ofstream out(file, std::ios::binary);
  out << text;
  out.close();
  if (!out) throw InputError({file.string(), 0, 0}, "cannot write the " + what + " (is the directory writable?)");
}

}  // namespace cluttertamp::io
