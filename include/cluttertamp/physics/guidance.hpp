#pragma once
// Automatic guidance for reaching through clutter (Papallas & Dogar 2020, Section II-B);
// the data types are in core/guidance.hpp.

#include <vector>

#include <Eigen/Core>

#include "cluttertamp/core/guidance.hpp"
#include "cluttertamp/physics/push_world.hpp"

namespace cluttertamp::physics {

using cluttertamp::Guide;     // the data live in core, so that io reads them without physics
using cluttertamp::Guidance;

/// An automatic guidance: the objects whose footprint meets the gripper's straight way
/// from `from` (world x, y, m) to where it touches the target in `state` (as wide as the
/// gripper plus 4 cm), nearest `from` first, at most `max_guides`; each pushed square to
/// the way, to the side where its push is cheaper, its centre 1 cm clear of the way
/// (anywhere in its region it may reach into the way by up to diameter / 2). Cost: the
/// push's length plus 0.15 m per object in its path. A side is out when the region,
/// `diameter` wide, would leave the support; an object with neither side gets no guide.
/// Deterministic.
CLUTTERTAMP_API Guidance generate_guidance(const PushWorld& world, const PushState& state, const Eigen::Vector2d& from,
                                           int max_guides, double diameter);
}  // namespace cluttertamp::physics
