#pragma once
// Guidance for reaching through clutter (Papallas & Dogar 2020, Section II-B): an
// ordered list of guides, each an object to push and a disc in the shelf plane that its
// centre should end in. Plain data: read by io, generated and followed by physics.

#include <vector>

#include <Eigen/Core>

#include "cluttertamp/core/diagnostics.hpp"
#include "cluttertamp/core/scene.hpp"

namespace cluttertamp {

/// Push `object` until its centre is within diameter / 2 of `centre` (world x, y, m).
struct Guide {
  ObjectIndex object = 0;
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
  double diameter = 0.0;  ///< m
  SourceLocation where;   ///< the guide in its file (empty when generated)
};

/// The guides, in the order they are to be satisfied.
using Guidance = std::vector<Guide>;

}  // namespace cluttertamp
