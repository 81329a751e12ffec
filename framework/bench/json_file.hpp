#pragma once
// Where the bench and compare commands write their --json file: one way, with the same
// error for a path that cannot be written (bad input, exit code 2).
#include <filesystem>
#include <fstream>

#include "cluttertamp/core/diagnostics.hpp"

namespace cluttertamp::bench {

/// Writes `json` (any nlohmann JSON type) indented to `path`. Throws InputError naming
/// the file when it cannot be written.
template <class Json>
void write_json_file(const std::filesystem::path& path, const Json& json) {
  std::ofstream out(path);
  out << json.dump(2) << "\n";
  if (!out) throw InputError({path.string(), 0, 0}, "cannot write the JSON file");
}

}  // namespace cluttertamp::bench
