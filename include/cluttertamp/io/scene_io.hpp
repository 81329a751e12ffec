#pragma once

#include <filesystem>
#include <string>

#include "cluttertamp/core/scene.hpp"
#include "cluttertamp/export.hpp"

namespace cluttertamp::io {

/// The scene and problem file format versions this library reads.
inline constexpr int kSceneFormatVersion = 1;

/// Reads and validates a scene file (format: docs/file-formats.md, "Scene files").
/// Throws InputError listing every problem found, each with file:line:column.
CLUTTERTAMP_API Scene load_scene(const std::filesystem::path& file);

/// The scene as a scene file (format version 1) that load_scene reads back to the
/// same scene (lengths and angles to 10 significant digits).
CLUTTERTAMP_API std::string scene_to_yaml(const Scene& scene);

/// Writes scene_to_yaml to `file`. Throws InputError when it cannot be written.
CLUTTERTAMP_API void write_scene(const std::filesystem::path& file, const Scene& scene);

}  // namespace cluttertamp::io
