#pragma once
// Where the bench and compare commands write their --json file: one way, with the same
// error for a path that cannot be written (bad input, exit code 2).
#include <filesystem>

#include "cluttertamp/io/text_file.hpp"

namespace cluttertamp::bench {

/// Writes `json` (any nlohmann JSON type) indented to `path`, replacing it whole. Throws
/// InputError naming the file when it cannot be written.
template <class Json>
void write_json_file(const std::filesystem::path& path, const Json& json) {
  io::write_text_file(path, json.dump(2) + "\n", "JSON file");
}

}  // namespace cluttertamp::bench
