#pragma once
// Guidance files (Papallas & Dogar 2020, Section II-B): Guidance in YAML.

#include <filesystem>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "cluttertamp/core/guidance.hpp"
#include "cluttertamp/core/scene.hpp"
#include "cluttertamp/export.hpp"

namespace cluttertamp::io {

/// Reads a guidance file (format: docs/plugins.md, "Guidance files"):
///   version: 1
///   guides:
///     - {object: o3, centre: [0.85, 0.3], diameter: 0.1}
/// Every guide names a movable object of `scene`, and its whole region lies inside
/// `shelf` (world x, y, m: where pushed objects must stay). Throws InputError listing
/// every problem with file:line:column.
CLUTTERTAMP_API Guidance load_guidance(const std::filesystem::path& file, const Scene& scene,
                                       const Eigen::AlignedBox2d& shelf);

/// The guidance as a file that load_guidance reads back (lengths to 10 significant digits).
CLUTTERTAMP_API std::string guidance_to_yaml(const Scene& scene, const Guidance& guidance);

}  // namespace cluttertamp::io
