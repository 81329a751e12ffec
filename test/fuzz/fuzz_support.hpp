#pragma once
// What the fuzz targets share: the input written as a file beside links to the
// project's data, and the one way an input may be refused.

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>

#include "cluttertamp/core/diagnostics.hpp"

namespace cluttertamp::fuzz {

/// A directory of this process (made on first use) with links to the project's data —
/// data/ (test/data), domains/ and problems/ — so that an input may name them by
/// relative paths ("domains/robots/ur10_ag95.yaml").
const std::filesystem::path& workspace();

/// Writes the input to workspace()/name; its path.
std::filesystem::path input_file(const std::uint8_t* data, std::size_t size, const std::string& name);

/// The input as text.
inline std::string text(const std::uint8_t* data, std::size_t size) {
  return std::string(reinterpret_cast<const char*>(data), size);
}

/// Runs `read`. InputError is bad input, reported: the expected refusal. Any other
/// exception escapes to the fuzzing engine, which reports it as a finding.
template <class F>
void refusing_bad_input(F&& read) {
  try {
    read();
  } catch (const InputError&) {
  }
}

}  // namespace cluttertamp::fuzz
