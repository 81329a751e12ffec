#include "cluttertamp/io/text_file.hpp"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include "cluttertamp/core/diagnostics.hpp"

namespace cluttertamp::io {

namespace fs = std::filesystem;

WriteError::WriteError(const std::string& message) : std::runtime_error(message) {}
WriteError::~WriteError() = default;

std::string read_text_file(const fs::path& file, const std::string& what) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError({file.string(), 0, 0}, "cannot read the " + what);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

namespace {

// Writes all of `text` to `fd` and makes it durable; false with errno set otherwise.
bool write_all(int fd, const std::string& text) {
  std::size_t done = 0;
  while (done < text.size()) {
    const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    done += static_cast<std::size_t>(n);
  }
  return true;
}

// mkstemp makes files 0600; an output gets the mode any new file of the user would.
mode_t process_umask() {
  static const mode_t mask = [] {
    const mode_t m = ::umask(022);
    ::umask(m);
    return m;
  }();
  return mask;
}

std::string cause(int error) { return error == 0 ? "unknown cause" : std::strerror(error); }

// A probe file in `directory`, created and removed: true when the directory takes files.
int probe_directory(const fs::path& directory) {
  std::string name = (directory.empty() ? fs::path(".") : directory) / ".cluttertamp-probe-XXXXXX";
  const int fd = ::mkstemp(name.data());
  if (fd < 0) return errno;
  ::close(fd);
  ::unlink(name.c_str());
  return 0;
}

}  // namespace

void check_writable_directory(const fs::path& directory, const std::string& what) {
  std::error_code ec;
  if (fs::exists(directory, ec) && !fs::is_directory(directory, ec)) {
    throw InputError({directory.string(), 0, 0}, "the " + what + " is a file, not a directory");
  }
  fs::create_directories(directory, ec);
  if (ec) throw InputError({directory.string(), 0, 0}, "cannot create the " + what + ": " + ec.message());
  if (const int error = probe_directory(directory)) {
    throw InputError({directory.string(), 0, 0}, "cannot write into the " + what + ": " + cause(error));
  }
}

void check_writable(const fs::path& file, const std::string& what) {
  std::error_code ec;
  if (fs::is_directory(file, ec)) throw InputError({file.string(), 0, 0}, "the " + what + " is a directory");
  if (fs::exists(file, ec) && !fs::is_regular_file(file, ec)) {
    // A device or pipe: opening it for writing (without truncating) is the check.
    const int fd = ::open(file.c_str(), O_WRONLY | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0 && errno != ENXIO) throw InputError({file.string(), 0, 0}, "cannot write the " + what + ": " + cause(errno));
    if (fd >= 0) ::close(fd);
    return;
  }
  const fs::path parent = file.parent_path();
  if (!parent.empty()) {
    if (fs::exists(parent, ec) && !fs::is_directory(parent, ec)) {
      throw InputError({file.string(), 0, 0}, "cannot write the " + what + ": " + parent.string() + " is not a directory");
    }
    fs::create_directories(parent, ec);
    if (ec) throw InputError({file.string(), 0, 0}, "cannot write the " + what + ": " + ec.message());
  }
  if (const int error = probe_directory(parent)) {
    throw InputError({file.string(), 0, 0}, "cannot write the " + what + ": " + cause(error));
  }
}

void write_text_file(const fs::path& file, const std::string& text, const std::string& what) {
  std::error_code ec;
  if (file.has_parent_path()) fs::create_directories(file.parent_path(), ec);
  const auto fail = [&](int error) {
    throw WriteError(file.string() + ": error: cannot write the " + what + ": " + cause(error));
  };
  // A device or pipe (/dev/stdout) is written as it is; a file is replaced whole, by
  // renaming a complete, synced copy over it, so that a full disk or a kill never
  // leaves half of one.
  if (fs::exists(file, ec) && !fs::is_regular_file(file, ec)) {
    const int fd = ::open(file.c_str(), O_WRONLY | O_CLOEXEC);
    if (fd < 0) fail(errno);
    const bool ok = write_all(fd, text);
    const int error = errno;
    ::close(fd);
    if (!ok) fail(error);
    return;
  }
  std::string hidden = ".";  // appended: g++ 12 warns falsely (-Wrestrict) on "." + std::string
  hidden += file.filename().string();
  hidden += ".partial-XXXXXX";
  std::string written = (file.parent_path().empty() ? fs::path(".") : file.parent_path()) / hidden;
  const int fd = ::mkstemp(written.data());
  if (fd < 0) fail(errno);
  bool ok = write_all(fd, text) && ::fsync(fd) == 0 && ::fchmod(fd, 0666 & ~process_umask()) == 0;
  int error = errno;
  if (::close(fd) != 0 && ok) {
    ok = false;
    error = errno;
  }
  if (ok && ::rename(written.c_str(), file.c_str()) != 0) {
    ok = false;
    error = errno;
  }
  if (!ok) {
    ::unlink(written.c_str());
    fail(error);
  }
}

}  // namespace cluttertamp::io
