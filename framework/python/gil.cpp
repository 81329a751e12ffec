#include "python/gil.hpp"

#include <mutex>
#include <vector>

namespace py = pybind11;

namespace cluttertamp::python {
namespace {

std::mutex& pending_mutex() {
  static std::mutex mutex;
  return mutex;
}
std::vector<PyObject*>& pending_references() {
  static auto* pending = new std::vector<PyObject*>();  // leaked: outlives every thread
  return *pending;
}

thread_local bool holding_gil = false;

}  // namespace

HoldingGil::HoldingGil(bool held) : before_(holding_gil) { holding_gil = held; }
HoldingGil::~HoldingGil() { holding_gil = before_; }

void release(py::object& object) {
  if (!object) return;
  if (holding_gil) {
    object = py::object();
    return;
  }
  const std::lock_guard<std::mutex> lock(pending_mutex());
  pending_references().push_back(object.release().ptr());
}

void drop_pending_references() {
  std::vector<PyObject*> drop;
  {
    const std::lock_guard<std::mutex> lock(pending_mutex());
    drop.swap(pending_references());
  }
  for (PyObject* o : drop) Py_DECREF(o);
}

std::string traceback_of(py::error_already_set& e) {
  std::string text = e.what();
  try {
    py::object format = py::module_::import("traceback").attr("format_exception");
    // An error raised in C (a wrong number of arguments, say) has no traceback.
    py::object trace = e.trace() ? py::reinterpret_borrow<py::object>(e.trace()) : py::none();
    py::list lines = format(e.type(), e.value(), trace);
    text.clear();
    for (py::handle line : lines) text += line.cast<std::string>();
  } catch (...) {  // keep what() when even the traceback cannot be written
    PyErr_Clear();
  }
  while (!text.empty() && text.back() == '\n') text.pop_back();
  return text;
}

}  // namespace cluttertamp::python
