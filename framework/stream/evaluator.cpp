// Calling the user's streams: generators made through the bound samplers, their
// values turned into objects and certified facts, their failures filed.
#include "stream/evaluator.hpp"

#include <algorithm>
#include <chrono>

namespace cluttertamp::stream::detail {
namespace {

using Clock = std::chrono::steady_clock;

double since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

}  // namespace

StreamEvaluator::StreamEvaluator(const StreamProblem& problem, FactBase& base, plugin::PlanningContext& context,
                                 const StreamSearchOptions& options, StreamSolution& out)
    : problem_(problem), base_(base), context_(context), options_(options), out_(out) {}

const StreamOptions& StreamEvaluator::options_of(const StreamDecl& d) const {
  static const StreamOptions defaults;
  const auto it = options_.streams.find(d.name);
  return it == options_.streams.end() ? defaults : it->second;
}

void StreamEvaluator::release_generators() {
  for (std::size_t i = 0; i < base_.instance_count(); ++i) base_.instance_at(static_cast<int>(i)).generator.reset();
}

std::optional<int> StreamEvaluator::real_domain(const Instance& inst) {
  int c = 0;
  const Env env = base_.env_of(inst);
  for (const pddl::Atom& a : base_.decl(inst.stream).domain) {
    const auto fact = base_.ground(a, env);
    const FactInfo* info = fact ? base_.real_fact(*fact) : nullptr;
    if (!info) return std::nullopt;
    c = std::max(c, info->complexity);
  }
  return c;
}

plugin::StreamValue StreamEvaluator::value_of(ObjectId id) const {
  const ObjectRecord& o = base_.object(id);
  return o.value ? *o.value : plugin::StreamValue(o.name);
}

bool StreamEvaluator::call(int id) {
  Instance& inst = base_.instance_at(id);
  const StreamDecl& d = base_.decl(inst.stream);
  if (inst.exhausted) return false;
  // As for optimistic facts, the number of calls does not count: the k-th value of a
  // stream is as usable as its first (advance() bounds the calls per level).
  const int complexity = real_domain(inst).value_or(0) + 1;
  if (d.kind == StreamDecl::Kind::rule) {
    inst.exhausted = true;
    inst.results.push_back({});
    certify(id, {}, complexity);
    return true;
  }
  const auto start = Clock::now();
  if (!inst.generator) {
    std::vector<plugin::StreamValue> inputs;
    for (ObjectId o : inst.inputs) inputs.push_back(value_of(o));
    std::vector<plugin::StreamFact> fluents;
    for (const FactKey& f : inst.fluent_state.value_or(std::vector<FactKey>{})) {
      plugin::StreamFact fact{base_.predicate_name(f[0]), {}};
      for (std::size_t i = 1; i < f.size(); ++i) fact.args.push_back(value_of(f[i]));
      fluents.push_back(std::move(fact));
    }
    inst.generator = problem_.bindings.at(d.name)->instantiate(context_, d.name, inputs, fluents);
    ++out_.statistics.stream_instances;
    if (!inst.generator) {
      inst.exhausted = true;
      fail(d, "its sampler made no generator for these inputs");
      return false;
    }
  }
  const plugin::StreamBatch batch = inst.generator->next(context_);
  ++inst.calls;
  ++out_.statistics.stream_calls;
  ++out_.statistics.calls_per_stream[d.name];
  out_.statistics.stream_seconds += since(start);
  bool produced = false;
  for (const auto& values : batch.outputs) {
    if (d.kind == StreamDecl::Kind::function) {
      if (values.size() != 1 || !std::holds_alternative<double>(values[0])) {
        fail(d, "a function must yield one number");
        continue;
      }
      inst.value = std::get<double>(values[0]);
      inst.exhausted = produced = true;
      break;
    }
    if (values.size() != d.outputs.size()) {
      fail(d, "yielded " + std::to_string(values.size()) + " value(s) for " + std::to_string(d.outputs.size()) +
                  " output(s)");
      continue;
    }
    std::vector<ObjectId> ids;
    for (std::size_t i = 0; i < values.size(); ++i) ids.push_back(object_for(values[i], d.outputs[i].name));
    inst.results.push_back(ids);
    certify(id, ids, complexity);
    produced = true;
  }
  if (d.is_test() || batch.exhausted) inst.exhausted = true;
  if (batch.failure) fail(d, batch.failure->reason, batch.failure->blocking_objects);
  return produced;
}

ObjectId StreamEvaluator::object_for(const plugin::StreamValue& value, const std::string& variable) {
  // A stream may answer with an existing object's name (a discrete value).
  if (const auto* name = std::get_if<std::string>(&value)) {
    if (const auto id = base_.find(*name)) return *id;
  }
  ++out_.statistics.values;
  ObjectRecord r;
  r.name = variable;  // "?p" -> "#p3"
  r.name[0] = '#';
  r.name += std::to_string(++generated_);
  r.value = value;
  return base_.add_object(std::move(r));
}

void StreamEvaluator::certify(int id, const std::vector<ObjectId>& outputs, int complexity) {
  const Instance& inst = base_.instance_at(id);
  const Env env = base_.env_of(inst, &outputs);
  for (const pddl::Atom& a : base_.decl(inst.stream).certified) {
    const auto fact = base_.ground(a, env);
    if (!fact) continue;
    if (inst.fluent_state) base_.add_state_fact(*fact, FactInfo{false, complexity, id});
    else base_.add_fact(*fact, FactInfo{false, complexity, id});
  }
}

void StreamEvaluator::fail(const StreamDecl& d, const std::string& reason, std::vector<ObjectIndex> blocking) {
  Failure f{"stream " + d.name, reason, std::move(blocking)};
  const bool seen = std::any_of(out_.failures.begin(), out_.failures.end(), [&](const Failure& g) {
    return g.stage == f.stage && g.reason == f.reason && g.blocking_objects == f.blocking_objects;
  });
  if (!seen && out_.failures.size() < 100) out_.failures.push_back(std::move(f));
}

void StreamEvaluator::close_real() {
  for (bool changed = true; changed && !context_.deadline.expired();) {
    changed = false;
    for (int s = 0; s < static_cast<int>(problem_.streams->streams.size()); ++s) {
      const StreamDecl& d = base_.decl(s);
      const bool eager = options_of(d).eager;
      if (d.kind != StreamDecl::Kind::rule && d.kind != StreamDecl::Kind::function && !eager) continue;
      for (int id : real_instances(s)) {
        const Instance& inst = base_.instance_at(id);
        if (inst.exhausted || (eager && inst.calls > 0)) continue;  // an eager stream: once each
        changed |= call(id) && (d.kind == StreamDecl::Kind::rule || (eager && !d.is_test()));
      }
    }
  }
}

std::vector<int> StreamEvaluator::real_instances(int stream) {
  std::vector<std::vector<ObjectId>> found;
  const StreamDecl& d = base_.decl(stream);
  base_.bindings(d.inputs, d.domain, false, [&](const std::vector<ObjectId>& inputs, int) { found.push_back(inputs); });
  std::vector<int> ids;
  for (const auto& inputs : found) ids.push_back(base_.instance(stream, inputs));
  return ids;
}

}  // namespace cluttertamp::stream::detail
