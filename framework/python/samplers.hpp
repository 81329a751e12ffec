#pragma once
// Samplers written in Python as plugins of this process, and views of the collision
// world for Python (module.cpp adds them to the module).

#include <pybind11/pybind11.h>

#include <memory>

#include "cluttertamp/core/problem.hpp"
#include "cluttertamp/core/world_state.hpp"

namespace cluttertamp::python {

/// Adds to `m`: provide_sampler / withdraw_sampler, the query types the samplers are
/// called with (GraspQuery, PlacementQuery, MotionQuery, PushQuery), Grasp, Parameters
/// and World.
void bind_samplers(pybind11::module_& m);

/// A World (the class bind_samplers adds) of `problem` at `state`, owning its collision
/// world. Throws InputError when the problem has no robot.
pybind11::object world_of(std::shared_ptr<const Problem> problem, const WorldState& state);

}  // namespace cluttertamp::python
