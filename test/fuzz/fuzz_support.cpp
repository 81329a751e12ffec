#include "fuzz_support.hpp"

#include <unistd.h>

#include <fstream>

namespace cluttertamp::fuzz {

namespace fs = std::filesystem;

const fs::path& workspace() {
  static const fs::path dir = [] {
    const fs::path d = fs::temp_directory_path() / ("cluttertamp-fuzz-" + std::to_string(::getpid()));
    fs::create_directories(d);
    const fs::path source(CLUTTERTAMP_SOURCE_DIR);
    std::error_code ec;
    fs::create_directory_symlink(source / "test" / "data", d / "data", ec);
    fs::create_directory_symlink(source / "domains", d / "domains", ec);
    fs::create_directory_symlink(source / "problems", d / "problems", ec);
    return d;
  }();
  return dir;
}

fs::path input_file(const std::uint8_t* data, std::size_t size, const std::string& name) {
  const fs::path file = workspace() / name;
  std::ofstream(file, std::ios::binary | std::ios::trunc).write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  return file;
}

}  // namespace cluttertamp::fuzz
