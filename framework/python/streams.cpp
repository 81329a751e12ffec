// Streams written in Python (PDDLStream's from_gen_fn, from_fn, from_test and plain
// functions) behind the C++ stream searches. Every call into Python holds the GIL;
// a Python exception becomes the stream's failure, with its traceback, not a crash.
#include "python/streams.hpp"

#include "python/gil.hpp"

#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "cluttertamp/core/diagnostics.hpp"
#include "cluttertamp/core/problem.hpp"
#include "cluttertamp/pddl/parser.hpp"
#include "cluttertamp/plugin/context.hpp"
#include "cluttertamp/plugin/stream_sampler.hpp"
#include "cluttertamp/stream/stream_file.hpp"
#include "cluttertamp/stream/stream_search.hpp"

namespace py = pybind11;

namespace cluttertamp::python {
namespace {

// A Python object flowing through the searches as a stream value.
class PythonValue final : public plugin::StreamPayload {
 public:
  explicit PythonValue(py::object object) : object_(std::move(object)) {}
  ~PythonValue() override { release(object_); }
  const py::object& object() const { return object_; }

 private:
  py::object object_;
};

py::object to_python(const plugin::StreamValue& value) {
  if (const auto* name = std::get_if<std::string>(&value)) return py::str(*name);
  if (const auto* number = std::get_if<double>(&value)) return py::float_(*number);
  if (const auto* vector = std::get_if<Eigen::VectorXd>(&value)) return py::cast(*vector);
  if (const auto* pose = std::get_if<Eigen::Isometry3d>(&value)) return py::cast(Eigen::Matrix4d(pose->matrix()));
  const auto& payload = std::get<std::shared_ptr<const plugin::StreamPayload>>(value);
  if (const auto* python = dynamic_cast<const PythonValue*>(payload.get())) return python->object();
  return py::cast(payload->numbers());
}

// What the Python package passes per stream: how to call it and the callable.
enum class CallKind { generator, list_generator, function, test, value };

struct PythonStream {
  CallKind kind = CallKind::generator;
  py::object callable;
};

// Python values equal to a problem object's value answer as that object, as PDDLStream
// makes one object per value.
struct KnownValues {
  py::object names = py::dict();  // hashable value -> object name
  ~KnownValues() { release(names); }
};

class PythonGenerator final : public plugin::StreamGenerator {
 public:
  PythonGenerator(std::string name, const PythonStream& stream, py::tuple inputs, py::object fluents,
                  std::shared_ptr<KnownValues> known)
      : name_(std::move(name)), stream_(stream), inputs_(std::move(inputs)), fluents_(std::move(fluents)),
        known_(std::move(known)) {}
  ~PythonGenerator() override {
    release(iterator_);
    release(inputs_);
    release(fluents_);
    release(stream_.callable);
  }

  plugin::StreamBatch next(plugin::PlanningContext&) override {
    const py::gil_scoped_acquire gil;
    const HoldingGil held(true);
    drop_pending_references();
    plugin::StreamBatch batch;
    auto failed = [&](const std::string& why) {
      batch.outputs.clear();
      batch.exhausted = true;
      batch.failure = Failure{"stream " + name_, why, {}};
    };
    try {
      call(batch);
    } catch (py::error_already_set& e) {
      failed("the Python stream raised:\n" + traceback_of(e));
    } catch (const std::exception& e) {  // what it returned is not what the stream declares
      failed(e.what());
    }
    return batch;
  }

 private:
  py::object invoke() const {
    if (fluents_ && !fluents_.is_none()) return stream_.callable(*inputs_, py::arg("fluents") = fluents_);
    return stream_.callable(*inputs_);
  }

  void call(plugin::StreamBatch& batch) {
    switch (stream_.kind) {
      case CallKind::generator:
      case CallKind::list_generator: {
        if (!iterator_) iterator_ = py::iter(invoke());
        PyObject* item = PyIter_Next(iterator_.ptr());
        if (!item) {
          if (PyErr_Occurred()) throw py::error_already_set();
          batch.exhausted = true;
          return;
        }
        const py::object produced = py::reinterpret_steal<py::object>(item);
        if (produced.is_none()) return;  // nothing this call; ask again
        if (stream_.kind == CallKind::list_generator) {
          for (py::handle outputs : produced) batch.outputs.push_back(values_of(outputs));
        } else {
          batch.outputs.push_back(values_of(produced));
        }
        return;
      }
      case CallKind::function: {
        batch.exhausted = true;
        const py::object produced = invoke();
        if (!produced.is_none()) batch.outputs.push_back(values_of(produced));
        return;
      }
      case CallKind::test:
        batch.exhausted = true;
        if (py::bool_(invoke())) batch.outputs.emplace_back();
        return;
      case CallKind::value: {
        batch.exhausted = true;
        py::object produced = invoke();
        if (py::isinstance<py::tuple>(produced) && py::len(produced) == 1) produced = produced[py::int_(0)];  // from_fn's (x,)
        if (!PyNumber_Check(produced.ptr()) || PyBool_Check(produced.ptr())) {
          throw py::type_error("function '" + name_ + "' returned " + py::repr(produced).cast<std::string>() +
                               ", not a number");
        }
        batch.outputs.push_back({produced.cast<double>()});
        return;
      }
    }
  }

  // One output tuple: each value a problem object's name when it equals that object's
  // value, else the Python object itself.
  std::vector<plugin::StreamValue> values_of(py::handle outputs) const {
    if (!py::isinstance<py::tuple>(outputs) && !py::isinstance<py::list>(outputs)) {
      throw py::type_error("stream '" + name_ + "' produced " + py::repr(outputs).cast<std::string>() +
                           ", not a tuple of outputs");
    }
    std::vector<plugin::StreamValue> values;
    for (py::handle value : outputs) {
      if (PyObject_Hash(value.ptr()) != -1) {
        const py::dict names = known_->names;
        if (names.contains(value)) {
          values.emplace_back(names[value].cast<std::string>());
          continue;
        }
      } else {
        PyErr_Clear();  // unhashable: never a problem object's value
      }
      values.emplace_back(std::make_shared<const PythonValue>(py::reinterpret_borrow<py::object>(value)));
    }
    return values;
  }

  std::string name_;
  PythonStream stream_;
  py::tuple inputs_;
  py::object fluents_;
  std::shared_ptr<KnownValues> known_;
  py::object iterator_;
};

class PythonStreamSampler final : public plugin::StreamSampler {
 public:
  PythonStreamSampler(std::map<std::string, PythonStream> streams, std::shared_ptr<KnownValues> known)
      : streams_(std::move(streams)), known_(std::move(known)) {}
  ~PythonStreamSampler() override {
    for (auto& [name, stream] : streams_) release(stream.callable);
  }
  std::unique_ptr<plugin::StreamGenerator> instantiate(plugin::PlanningContext&, std::string_view stream,
                                                       const std::vector<plugin::StreamValue>& inputs,
                                                       const std::vector<plugin::StreamFact>& fluents) override {
    const py::gil_scoped_acquire gil;
    const HoldingGil held(true);
    const PythonStream& code = streams_.at(std::string(stream));
    py::tuple args(inputs.size());
    for (std::size_t i = 0; i < inputs.size(); ++i) args[i] = to_python(inputs[i]);
    py::object facts = py::none();
    if (!fluents.empty()) {
      py::list list;
      for (const plugin::StreamFact& f : fluents) {
        py::list fact;
        fact.append(py::str(f.predicate));
        for (const auto& a : f.args) fact.append(to_python(a));
        list.append(py::tuple(fact));
      }
      facts = list;
    }
    return std::make_unique<PythonGenerator>(std::string(stream), code, std::move(args), std::move(facts), known_);
  }

 private:
  std::map<std::string, PythonStream> streams_;
  std::shared_ptr<KnownValues> known_;
};

CallKind call_kind(const std::string& kind, const std::string& stream) {
  if (kind == "gen") return CallKind::generator;
  if (kind == "list_gen") return CallKind::list_generator;
  if (kind == "fn") return CallKind::function;
  if (kind == "test") return CallKind::test;
  if (kind == "value") return CallKind::value;
  throw py::value_error("stream '" + stream + "': unknown call kind '" + kind + "'");
}

// A plain callable, as PDDLStream takes one for predicates and functions: a test of
// what the declaration certifies, or the function's value.
CallKind plain_call_kind(const stream::StreamDecl& d) {
  if (d.kind == stream::StreamDecl::Kind::function) return CallKind::value;
  if (d.is_test()) return CallKind::test;
  throw py::type_error("stream '" + d.name + "' has outputs: wrap its callable with from_gen_fn, from_list_gen_fn or from_fn");
}

// Solves a domain, stream file and problem (as PDDL text) whose streams are Python
// callables. `values`: problem object name -> its Python value; `streams`: stream,
// predicate or function name -> (call kind, callable). Returns the plan with its
// arguments as Python values.
py::dict solve_python_streams(const std::string& domain_text, const std::string& domain_name,
                              const std::string& stream_text, const std::string& stream_name,
                              const std::string& problem_text, const py::dict& values, const py::dict& streams,
                              const std::string& algorithm, const std::string& search, std::uint64_t seed,
                              double time_limit) {
  const HoldingGil held(true);
  struct DropPending {  // also when the search throws
    DropPending() { drop_pending_references(); }
    ~DropPending() { drop_pending_references(); }
  } drop_pending;
  const pddl::Domain domain = pddl::parse_domain(domain_text, domain_name);
  const pddl::Problem problem = pddl::parse_problem(problem_text, "problem", domain);
  const stream::StreamFile stream_file = stream::parse_stream_file(stream_text, stream_name, &domain);

  auto known = std::make_shared<KnownValues>();
  stream::StreamProblem task{&domain, &problem, &stream_file, {}, {}};
  for (const auto& [name, value] : values) {
    const std::string object = name.cast<std::string>();
    task.values[object] = std::make_shared<const PythonValue>(py::reinterpret_borrow<py::object>(value));
    if (PyObject_Hash(value.ptr()) != -1) known->names[value] = py::str(object);  // names is a dict
    else PyErr_Clear();
  }
  std::map<std::string, PythonStream> code;
  for (const auto& [name, entry] : streams) {
    const std::string stream = py::str(name).cast<std::string>();
    const stream::StreamDecl* decl = stream_file.find(stream);
    if (!decl || decl->kind == stream::StreamDecl::Kind::rule) {
      throw py::value_error("the stream map names '" + stream + "', which the stream file " + stream_name +
                            " does not declare");
    }
    const py::tuple pair = entry.cast<py::tuple>();
    const std::string kind = pair[0].cast<std::string>();
    // A :function's value is a number however it is wrapped.
    const bool plain = kind == "auto" || decl->kind == stream::StreamDecl::Kind::function;
    code[stream] = PythonStream{plain ? plain_call_kind(*decl) : call_kind(kind, stream), pair[1]};
  }
  PythonStreamSampler sampler(std::move(code), known);
  Diagnostics unbound;
  for (const stream::StreamDecl& d : stream_file.streams) {
    if (d.kind == stream::StreamDecl::Kind::rule) continue;
    if (streams.contains(py::str(d.name))) task.bindings[d.name] = &sampler;
    else unbound.error(d.where, "stream '" + d.name + "' has no entry in the stream map");
  }
  unbound.throw_if_any();

  const auto chosen = stream::algorithm_from_name(algorithm);
  if (!chosen) throw py::value_error("algorithm must be 'adaptive' or 'incremental', not '" + algorithm + "'");
  stream::StreamSearchOptions options;
  options.algorithm = *chosen;
  options.search = search;
  Problem none;
  std::map<std::string, std::uint64_t> counters;
  const plugin::Samplers samplers;
  plugin::PlanningContext context{none, plugin::Deadline::after(time_limit), seed, counters, samplers, nullptr};
  stream::StreamSolution solution;
  {
    const py::gil_scoped_release unlocked;  // taken again by each stream call
    const HoldingGil released(false);
    solution = stream::solve(task, context, options);
  }
  drop_pending_references();  // what the search dropped while it ran without the GIL

  py::dict out;
  out["solved"] = solution.solved;
  out["reason"] = solution.solved ? py::object(py::none()) : py::object(py::str(solution.reason));
  py::list plan;
  for (const stream::StreamPlanStep& step : solution.plan) {
    py::list arguments;
    for (const std::string& a : step.arguments) {
      if (const auto it = solution.values.find(a); it != solution.values.end()) arguments.append(to_python(it->second));
      else if (values.contains(py::str(a))) arguments.append(values[py::str(a)]);
      else arguments.append(py::str(a));
    }
    plan.append(py::make_tuple(step.action, py::tuple(arguments)));
  }
  out["plan"] = plan;
  out["cost"] = solution.cost ? py::object(py::float_(*solution.cost)) : py::object(py::none());
  py::list failures;
  for (const Failure& f : solution.failures) failures.append(py::make_tuple(f.stage, f.reason));
  out["failures"] = failures;
  py::dict statistics;
  statistics["stream_calls"] = solution.statistics.stream_calls;
  statistics["stream_instances"] = solution.statistics.stream_instances;
  statistics["searches"] = solution.statistics.searches;
  statistics["skeletons"] = solution.statistics.skeletons;
  statistics["level"] = solution.statistics.level;
  statistics["values"] = solution.statistics.values;
  statistics["search_seconds"] = solution.statistics.search_seconds;
  statistics["stream_seconds"] = solution.statistics.stream_seconds;
  statistics["calls_per_stream"] = solution.statistics.calls_per_stream;
  out["statistics"] = statistics;
  return out;
}

}  // namespace

void bind_streams(py::module_& m) {
  m.def("solve_python_streams", &solve_python_streams, py::arg("domain"), py::arg("domain_name"), py::arg("streams"),
        py::arg("streams_name"), py::arg("problem"), py::arg("values"), py::arg("stream_map"), py::arg("algorithm"),
        py::arg("search"), py::arg("seed"), py::arg("time_limit"));
}

}  // namespace cluttertamp::python
