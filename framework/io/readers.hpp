#pragma once
// Internal: the file readers, reporting into a caller's Diagnostics so that a problem
// file and its scene are validated together.

#include <filesystem>

#include "cluttertamp/core/diagnostics.hpp"
#include "cluttertamp/core/scene.hpp"

namespace cluttertamp::io::detail {

Scene read_scene(const std::filesystem::path& file, Diagnostics& diagnostics);

}  // namespace cluttertamp::io::detail
