#pragma once
// Shared helpers for the tests: paths of the test data and fixtures.

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "cluttertamp/core/diagnostics.hpp"

namespace cluttertamp::test {

/// A pose at (x, y, z), not rotated.
inline Eigen::Isometry3d at(double x, double y, double z) {
  Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
  p.translation() << x, y, z;
  return p;
}

/// What a command printed (stdout and stderr together) and its exit code.
struct CliRun {
  int exit_code;
  std::string output;
};

/// A shell command's exit code (-1 when it did not exit) and output.
inline CliRun run_command(const std::string& command) {
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return {-1, "popen failed"};
  std::string output;
  std::array<char, 4096> buffer{};
  while (std::size_t n = std::fread(buffer.data(), 1, buffer.size(), pipe)) output.append(buffer.data(), n);
  const int status = pclose(pipe);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, output};
}

#ifdef CLUTTERTAMP_CLI
/// `cluttertamp ARGUMENTS`, stderr with stdout.
inline CliRun run_cli(const std::string& arguments) { return run_command(std::string(CLUTTERTAMP_CLI) + " " + arguments + " 2>&1"); }
#endif

inline std::filesystem::path data(const std::string& relative) {
  return std::filesystem::path(CLUTTERTAMP_TEST_DATA) / relative;
}

inline std::filesystem::path plugin_dir(const std::string& name) {
  return std::filesystem::path(CLUTTERTAMP_TEST_PLUGINS) / name;
}

/// The whole text of a file.
inline std::string read_text(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

/// `text` with the first `from` replaced by `to`; a failure when `from` is missing.
inline std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const std::size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return at == std::string::npos ? text : text.replace(at, from.size(), to);
}

/// Runs `load`, expects InputError, and returns its diagnostics.
template <class F>
Diagnostics expect_input_error(F&& load) {
  try {
    load();
  } catch (const InputError& e) {
    return e.diagnostics();
  }
  ADD_FAILURE() << "expected an InputError";
  return {};
}

/// True when some diagnostic is at `line`:`column` (0: any column) and contains `text`.
inline ::testing::AssertionResult has_error(const Diagnostics& d, std::size_t line, std::size_t column,
                                            const std::string& text) {
  for (const Diagnostic& item : d.items()) {
    if (item.location.line == line && (column == 0 || item.location.column == column) &&
        item.message.find(text) != std::string::npos) {
      return ::testing::AssertionSuccess();
    }
  }
  return ::testing::AssertionFailure() << "no error at " << line << ":" << column << " containing '" << text
                                       << "'; got:\n"
                                       << d.str();
}

}  // namespace cluttertamp::test
