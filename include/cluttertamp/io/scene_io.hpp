#pragma once

#include <filesystem>

#include "cluttertamp/core/scene.hpp"
#include "cluttertamp/export.hpp"

namespace cluttertamp::io {

/// The scene and problem file format versions this library reads.
inline constexpr int kSceneFormatVersion = 1;

/// Reads and validates a scene file (format: README, "Scene files").
/// Throws InputError listing every problem found, each with file:line:column.
CLUTTERTAMP_API Scene load_scene(const std::filesystem::path& file);

}  // namespace cluttertamp::io
