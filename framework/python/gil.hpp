#pragma once
// Holding Python objects in C++ objects that may die on any thread, and Python errors
// as text: shared by the Python streams and samplers.

#include <pybind11/pybind11.h>

#include <string>

namespace cluttertamp::python {

/// Marks, for this thread, whether it holds the GIL by our own doing (PyGILState_Check
/// answers 1 on any thread once finalization has begun): set where we take it, cleared
/// where we release it.
class HoldingGil {
 public:
  explicit HoldingGil(bool held);
  ~HoldingGil();
  HoldingGil(const HoldingGil&) = delete;
  HoldingGil& operator=(const HoldingGil&) = delete;

 private:
  bool before_;
};

/// Drops `object`'s reference now when this thread holds the GIL (HoldingGil), else
/// later, in drop_pending_references. A search or sampler freed on a background thread
/// (after a time limit, core/free_beside.hpp) must not take the GIL: the interpreter
/// may be finalizing, and a thread taking its GIL then is ended, mid destructor.
void release(pybind11::object& object);

/// Drops the references left for later. Precondition: the GIL is held.
void drop_pending_references();

/// The Python exception's traceback as text (what() when it cannot be formatted).
/// Precondition: the GIL is held.
std::string traceback_of(pybind11::error_already_set& e);

}  // namespace cluttertamp::python
