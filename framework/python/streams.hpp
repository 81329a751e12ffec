#pragma once
// Python streams behind the stream searches (module.cpp adds them to the module).

#include <pybind11/pybind11.h>

namespace cluttertamp::python {

/// Adds solve_python_streams to `m`: a domain, stream file and problem solved with
/// streams that are Python callables.
void bind_streams(pybind11::module_& m);

}  // namespace cluttertamp::python
