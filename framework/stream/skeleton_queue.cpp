#include "stream/skeleton_queue.hpp"

#include <algorithm>
#include <functional>
#include <limits>
#include <sstream>
#include <utility>

namespace cluttertamp::stream::detail {

SkeletonQueue::SkeletonQueue(SearchCore& core)
    : core_(core), base_(core.facts()), evaluator_(core.evaluator()), context_(core.context()),
      options_(core.options()) {}

bool SkeletonQueue::add(Skeleton skeleton) {
  if (!queued_.insert(skeleton.key).second) return false;
  queue_.push_back(std::move(skeleton));
  return true;
}

std::optional<Skeleton> SkeletonQueue::skeleton_of(const std::vector<Step>& steps) {
  Uses uses;
  const auto support = core_.plan_support(steps, true, &uses);
  if (!support) return std::nullopt;
  Skeleton sk;
  sk.actions = steps;
  auto optimistic_certifiers = [&](const Instance& inst) {
    std::vector<int> out;
    const Env env = base_.env_of(inst);
    for (const pddl::Atom& a : base_.decl(inst.stream).domain) {
      const auto fact = base_.ground(a, env);
      const FactInfo* info = fact ? base_.fact(*fact) : nullptr;
      if (info && info->optimistic && info->certifier >= 0) out.push_back(info->certifier);
    }
    return out;
  };
  // The steps at which each needed instance's facts are used.
  std::map<int, std::set<int>> needed;
  std::function<void(int, int)> need = [&](int id, int step) {
    if (!needed[id].insert(step).second) return;
    for (int d : optimistic_certifiers(base_.instance_at(id))) need(d, step);
  };
  for (const FactKey& f : support->facts) {
    const FactInfo* info = base_.fact(f);
    if (!info || !info->optimistic) continue;
    for (int step : uses.steps[f]) need(info->certifier, step);
  }
  auto entries = [&](int id, bool negated) {
    const StreamDecl& d = base_.decl(base_.instance_at(id).stream);
    const std::set<int>& at = needed[id];
    if (d.fluents.empty() || at.empty()) return std::vector<PlannedInstance>{{id, negated, -1}};
    if (!d.outputs.empty()) return std::vector<PlannedInstance>{{id, negated, *at.begin()}};
    std::vector<PlannedInstance> out;
    for (int step : at) out.push_back({id, negated, step});
    return out;
  };
  std::set<PlannedInstance> placed;
  std::function<void(const PlannedInstance&)> place = [&](const PlannedInstance& p) {
    if (!placed.insert(p).second) return;
    for (int d : optimistic_certifiers(base_.instance_at(p.instance))) {
      for (const PlannedInstance& e : entries(d, false)) place(e);
    }
    if (p.step >= 0) {  // the makers of the optimistic objects in its state come first
      for (const FactKey& f : base_.fluent_state(uses.states[static_cast<std::size_t>(p.step)], base_.instance_at(p.instance).stream)) {
        for (std::size_t i = 1; i < f.size(); ++i) {
          const ObjectRecord& o = base_.object(f[i]);
          if (!o.optimistic || o.maker < 0) continue;
          if (needed[o.maker].empty()) need(o.maker, p.step);  // once: a maker placed stays put
          for (const PlannedInstance& e : entries(o.maker, false)) place(e);
        }
      }
    }
    sk.stream_plan.push_back(p);
  };
  // Deferred streams (expensive ones, e.g. motion planning) after the others, unless
  // another needs their outputs first: a skeleton that fails in a cheap stream then
  // never pays for them.
  // Negated tests come after the streams of their pass.
  // Within each, cheap streams likely to fail first (PDDLStream's p_success and
  // overhead: the expected cost of a sequence of independent tests is least in
  // increasing overhead / (1 - p_success)); a stream's inputs are placed before it.
  std::vector<int> ordered;
  for (const auto& [id, at] : needed) ordered.push_back(id);
  auto failure_cost = [&](int id) {
    const StreamOptions& o = evaluator_.options_of(base_.decl(base_.instance_at(id).stream));
    return o.p_success < 1.0 ? o.overhead / (1.0 - o.p_success) : std::numeric_limits<double>::infinity();
  };
  std::stable_sort(ordered.begin(), ordered.end(), [&](int a, int b) { return failure_cost(a) < failure_cost(b); });
  auto deferred_stream = [&](int id) { return evaluator_.options_of(base_.decl(base_.instance_at(id).stream)).defer; };
  for (const bool deferred : {false, true}) {
    for (const int id : ordered) {
      if (deferred_stream(id) != deferred) continue;
      for (const PlannedInstance& e : entries(id, false)) place(e);
    }
    for (const FactKey& f : support->negated) {
      const auto id = core_.test_instance(f);
      if (id && deferred_stream(*id) == deferred) place({*id, true, -1});
    }
  }
  std::ostringstream key;
  for (const Step& s : steps) {
    key << s.action->name;
    for (ObjectId o : s.args) key << ' ' << o;
    key << ';';
  }
  sk.key = key.str();
  sk.stack.push_back({});
  return sk;
}

ObjectId SkeletonQueue::bound(const Binding& b, ObjectId o) {
  const auto it = b.mapping.find(o);
  return it == b.mapping.end() ? o : it->second;
}

std::vector<Step> SkeletonQueue::bound_steps(std::vector<Step> steps, const Binding& b) {
  for (Step& s : steps) {
    for (ObjectId& o : s.args) o = bound(b, o);
  }
  return steps;
}

// An instance whose next call would exceed the level's complexity waits, at the bottom
// of the stack, for the level to rise.
std::optional<std::vector<Step>> SkeletonQueue::advance(Skeleton& sk, Move& move, int level) {
  move = Move::moved;
  Binding& b = sk.stack.back();
  if (b.index == sk.stream_plan.size()) {
    std::vector<Step> steps = bound_steps(sk.actions, b);
    sk.stack.pop_back();
    if (core_.verify(steps)) return steps;
    return std::nullopt;
  }
  const PlannedInstance planned = sk.stream_plan[b.index];
  const Instance& optimistic = base_.instance_at(planned.instance);
  std::vector<ObjectId> inputs;
  for (ObjectId o : optimistic.inputs) inputs.push_back(bound(b, o));
  std::optional<std::vector<FactKey>> fluent_state;
  if (planned.step < 0 && !base_.decl(optimistic.stream).fluents.empty()) {
    sk.stack.pop_back();  // no step needs it directly (only a negated test's domain): no state to run it in
    return std::nullopt;
  }
  if (planned.step >= 0) {
    const State state = core_.state_before(bound_steps(sk.actions, b), static_cast<std::size_t>(planned.step));
    fluent_state = base_.fluent_state(state, optimistic.stream);
    for (const FactKey& f : *fluent_state) {
      if (std::any_of(f.begin() + 1, f.end(), [&](ObjectId o) { return base_.object(o).optimistic; })) {
        sk.stack.pop_back();  // its state is not known yet (makers ordered in a cycle)
        return std::nullopt;
      }
    }
  }
  const int id = base_.instance(optimistic.stream, inputs, fluent_state);
  Instance& inst = base_.instance_at(id);
  const std::optional<int> domain = inst.real ? evaluator_.real_domain(inst) : std::nullopt;
  if (!domain) {  // an earlier value broke this branch
    sk.stack.pop_back();
    return std::nullopt;
  }
  if (planned.negated) {
    if (inst.calls == 0 && !inst.exhausted) {
      evaluator_.call(id);
      move = Move::called;
    }
    if (!inst.results.empty()) sk.stack.pop_back();  // the test holds: this branch fails
    else ++b.index;
    return std::nullopt;
  }
  if (b.consumed < inst.results.size()) {
    Binding child = b;
    child.index = b.index + 1;
    child.consumed = 0;
    const std::vector<ObjectId>& values = inst.results[b.consumed++];
    for (std::size_t i = 0; i < values.size() && i < optimistic.optimistic_outputs.size(); ++i) {
      child.mapping[optimistic.optimistic_outputs[i]] = values[i];
    }
    sk.stack.push_back(std::move(child));
    return std::nullopt;
  }
  if (inst.exhausted) {
    sk.stack.pop_back();
  } else if (*domain + inst.calls > level) {
    std::rotate(sk.stack.begin(), sk.stack.end() - 1, sk.stack.end());
    move = Move::waiting;
  } else {
    evaluator_.call(id);
    inst.disabled = true;
    move = Move::called;
  }
  return std::nullopt;
}

std::optional<std::vector<Step>> SkeletonQueue::refine(double budget, int level, bool& progress) {
  progress = false;
  for (Skeleton& sk : queue_) sk.waiting = false;
  std::size_t waits = 0;  // bindings in a row of the current skeleton that wait
  double spent = 0;
  while (spent < budget && !context_.deadline.expired()) {
    const std::uint64_t checks_before = context_.checks_done();
    const auto it = std::min_element(queue_.begin(), queue_.end(), [](const Skeleton& a, const Skeleton& b) {
      return std::make_pair(a.waiting, a.actions.size()) < std::make_pair(b.waiting, b.actions.size());
    });
    if (it == queue_.end() || it->waiting) break;
    Move move = Move::moved;
    if (auto steps = advance(*it, move, level)) return steps;
    progress |= move == Move::called;
    const double work = 1.0 + (move == Move::called ? options_.call_cost : 0.0) +
                        static_cast<double>(context_.checks_done() - checks_before);
    spent += work;
    core_.work() += work;
    if (it->stack.empty()) {
      queue_.erase(it);
      waits = 0;
    } else if (move != Move::waiting) {
      waits = 0;
    } else if (++waits >= it->stack.size()) {
      it->waiting = true;
      waits = 0;
    }
  }
  return std::nullopt;
}

}  // namespace cluttertamp::stream::detail
