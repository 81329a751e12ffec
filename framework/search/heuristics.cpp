#include "search/heuristics.hpp"

#include <algorithm>
#include <cstdint>
#include <queue>
#include <tuple>
#include <type_traits>

#include "cluttertamp/search/grounding.hpp"  // TimeLimit
#include "search/small_sort.hpp"

namespace cluttertamp::search::detail {

namespace {

double relaxed_cost(double cost, RelaxedTask::Costs costs) {
  switch (costs) {
    case RelaxedTask::Costs::normal: return cost;
    case RelaxedTask::Costs::one: return 1.0;
    case RelaxedTask::Costs::plus_one: return cost + 1.0;
  }
  return cost;
}

constexpr std::size_t kMaxBucket = 1 << 16;
struct BucketOverflow {};

// The exploration's queue where costs are whole numbers (as in every IPC task): one
// bucket per cost, each taken from its back, so that of facts of equal cost the one
// reached last comes first (Fast Downward's bucket queue). Costs are held as `Cost`;
// past kMaxBucket it gives up (throws BucketOverflow).
template <class Cost>
class BucketQueue {
 public:
  explicit BucketQueue(std::vector<std::vector<FactId>>& buckets) : buckets_(buckets) {}
  ~BucketQueue() {
    for (std::size_t k = current_; k <= highest_ && k < buckets_.size(); ++k) buckets_[k].clear();
  }
  void push(Cost cost, FactId f) {
    const auto k = static_cast<std::size_t>(cost);
    if (k >= kMaxBucket) throw BucketOverflow{};
    if (k >= buckets_.size()) buckets_.resize(k + 1);
    current_ = std::min(current_, k);
    highest_ = std::max(highest_, k);
    buckets_[k].push_back(f);
    ++size_;
  }
  bool empty() const { return size_ == 0; }
  std::pair<Cost, FactId> pop() {
    while (buckets_[current_].empty()) ++current_;
    const FactId f = buckets_[current_].back();
    buckets_[current_].pop_back();
    --size_;
    return {static_cast<Cost>(current_), f};
  }

 private:
  std::vector<std::vector<FactId>>& buckets_;  // empty between explorations
  std::size_t current_ = ~std::size_t{0} >> 1, highest_ = 0, size_ = 0;
};

// Any costs: a heap ordered by cost, then latest push first (the same order).
class HeapQueue {
 public:
  void push(double cost, FactId f) { heap_.push({cost, -(++pushed_), f}); }
  bool empty() const { return heap_.empty(); }
  std::pair<double, FactId> pop() {
    const auto [cost, order, f] = heap_.top();
    (void)order;
    heap_.pop();
    return {cost, f};
  }

 private:
  using Entry = std::tuple<double, std::int64_t, FactId>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> heap_;
  std::int64_t pushed_ = 0;
};

bool whole_numbers(const std::vector<double>& costs) {
  return std::all_of(costs.begin(), costs.end(), [](double c) {
    return c >= 0.0 && c < static_cast<double>(kMaxBucket) && c == static_cast<double>(static_cast<std::int64_t>(c));
  });
}

}  // namespace

RelaxedTask::RelaxedTask(const Task& task, Costs costs, const std::vector<char>& left_out)
    : left_out_(left_out), task_facts_(static_cast<FactId>(task.fact_count())), origin_count_(task.operators.size()) {
  origin_reduced_.assign(origin_count_, 0);
  // A fluent fact some condition needs false gets a complement fact, added by the
  // operators that delete the fact, as Fast Downward's translation gives it a value of
  // its own: negative preconditions and goals then count. Derived facts do not (no
  // operator deletes one); conditions on their falsity are ignored, which only relaxes.
  complement_.assign(task.fact_count(), -1);
  auto note = [&](const Condition& c) {
    for (FactId f : c.negative) {
      if (!task.derived[f]) complement_[f] = 0;
    }
  };
  for (OperatorId o = 0; o < static_cast<OperatorId>(task.operators.size()); ++o) {
    if (this->left_out(o)) continue;
    note(task.operators[o].precondition);
    for (const ConditionalEffect& c : task.operators[o].conditional) note(c.condition);
  }
  for (const Axiom& a : task.axioms) note(a.body);
  for (const Condition& c : task.goal) note(c);
  FactId next = task_facts_;
  for (FactId f = 0; f < task_facts_; ++f) {
    if (complement_[f] < 0) continue;
    complement_[f] = next++;
    complemented_.push_back(f);
  }
  goal_ = next;
  facts_ = static_cast<std::size_t>(next) + 1;
  build_operators(task, costs, left_out);
  index_operators();
  base_cost_.resize(ops_.size());
  for (std::size_t i = 0; i < ops_.size(); ++i) base_cost_[i] = ops_[i].cost;
  whole_costs_ = whole_numbers(base_cost_);
  // Sums of whole costs below kMaxBucket stay within 32 bits while no operator has 2^15
  // preconditions or more: h_add then explores in 32-bit integers.
  if (whole_costs_ && std::all_of(pre_count_.begin(), pre_count_.end(), [](int n) { return n < (1 << 15); })) {
    whole_base_cost_.assign(base_cost_.begin(), base_cost_.end());
  }
  initial_order_.resize(static_cast<std::size_t>(goal_));
  for (FactId f = 0; f < goal_; ++f) initial_order_[f] = f;
}

namespace {

// Per key, the operators `keys_of` gives it, in operator order: a counting sort into
// `items`, which `start` (per key, and one past the last) indexes.
template <class KeysOf>
void group_by(std::size_t keys, std::size_t ops, const KeysOf& keys_of, std::vector<std::uint32_t>& start,
              std::vector<int>& items) {
  start.assign(keys + 1, 0);
  for (std::size_t i = 0; i < ops; ++i) {
    for (FactId k : keys_of(i)) ++start[static_cast<std::size_t>(k) + 1];
  }
  for (std::size_t k = 0; k < keys; ++k) start[k + 1] += start[k];
  items.resize(start[keys]);
  std::vector<std::uint32_t> next(start.begin(), start.end() - 1);
  for (std::size_t i = 0; i < ops; ++i) {
    for (FactId k : keys_of(i)) items[next[static_cast<std::size_t>(k)]++] = static_cast<int>(i);
  }
}

}  // namespace

// The relaxed operators, their facts appended to op_facts_ and viewed once it is whole.
void RelaxedTask::build_operators(const Task& task, Costs costs, const std::vector<char>& left_out) {
  struct Range {
    std::size_t pre_begin, pre_end, eff_begin, eff_end;
  };
  std::vector<Range> ranges;
  {  // room for the operators and their facts, conditional effects aside
    std::size_t facts = 0;
    for (const Operator& op : task.operators) facts += op.precondition.positive.size() + op.precondition.negative.size() + op.add.size() + op.del.size();
    op_facts_.reserve(facts);
    ops_.reserve(task.operators.size() + task.axioms.size() + task.goal.size());
    ranges.reserve(ops_.capacity());
  }
  auto condition = [&](const Condition& c, const std::vector<FactId>* also) {
    const std::size_t begin = op_facts_.size();
    if (also) op_facts_.insert(op_facts_.end(), also->begin(), also->end());
    op_facts_.insert(op_facts_.end(), c.positive.begin(), c.positive.end());
    for (FactId f : c.negative) {
      if (complement_[f] >= 0) op_facts_.push_back(complement_[f]);
    }
    std::sort(op_facts_.begin() + static_cast<std::ptrdiff_t>(begin), op_facts_.end());
    op_facts_.erase(std::unique(op_facts_.begin() + static_cast<std::ptrdiff_t>(begin), op_facts_.end()), op_facts_.end());
    return begin;
  };
  auto effects = [&](const std::vector<FactId>& add, const std::vector<FactId>& del) {
    const std::size_t begin = op_facts_.size();
    op_facts_.insert(op_facts_.end(), add.begin(), add.end());
    for (FactId f : del) {
      if (complement_[f] >= 0) op_facts_.push_back(complement_[f]);
    }
    return begin;
  };
  auto add_op = [&](std::size_t pre_begin, std::size_t pre_end, std::size_t eff_begin, double cost, OperatorId origin,
                    bool conditional) {
    if (eff_begin == op_facts_.size()) {  // no effect: no operator
      op_facts_.resize(pre_begin);
      return;
    }
    ranges.push_back({pre_begin, pre_end, eff_begin, op_facts_.size()});
    ops_.push_back({{}, {}, cost, origin, conditional});
  };
  std::vector<FactId> pre;
  for (OperatorId id = 0; id < static_cast<OperatorId>(task.operators.size()); ++id) {
    if (!left_out.empty() && left_out[id]) continue;
    const Operator& op = task.operators[id];
    const double cost = relaxed_cost(op.cost, costs);
    const std::size_t pre_begin = condition(op.precondition, nullptr), pre_end = op_facts_.size();
    pre.assign(op_facts_.begin() + static_cast<std::ptrdiff_t>(pre_begin), op_facts_.end());
    add_op(pre_begin, pre_end, effects(op.add, op.del), cost, id, false);
    for (const ConditionalEffect& c : op.conditional) {
      const std::size_t c_begin = condition(c.condition, &pre), c_end = op_facts_.size();
      add_op(c_begin, c_end, effects(c.add, c.del), cost, id, true);
    }
  }
  for (const Axiom& a : task.axioms) {
    const std::size_t begin = condition(a.body, nullptr), end = op_facts_.size();
    op_facts_.push_back(a.head);
    add_op(begin, end, end, 0.0, -1, false);
  }
  for (const Condition& c : task.goal) {
    const std::size_t begin = condition(c, nullptr), end = op_facts_.size();
    op_facts_.push_back(goal_);
    add_op(begin, end, end, 0.0, -1, false);
  }
  for (std::size_t i = 0; i < ops_.size(); ++i) {
    const Range& r = ranges[i];
    ops_[i].pre = {op_facts_.data() + r.pre_begin, op_facts_.data() + r.pre_end};
    ops_[i].eff = {op_facts_.data() + r.eff_begin, op_facts_.data() + r.eff_end};
  }
}

// The flat arrays the explorations and LM-cut read: triggers, achievers, effects and
// each task operator's relaxed operators.
void RelaxedTask::index_operators() {
  for (std::size_t i = 0; i < ops_.size(); ++i) {
    if (ops_[i].pre.empty()) no_precondition_.push_back(static_cast<int>(i));
  }
  group_by(facts_, ops_.size(), [&](std::size_t i) { return ops_[i].pre; }, trigger_start_, triggers_);
  group_by(facts_, ops_.size(), [&](std::size_t i) { return ops_[i].eff; }, achiever_start_, achievers_);
  in_cut_.resize(ops_.size());
  in_goal_zone_.resize(facts_);
  reached_.resize(facts_);
  fact_cost_.resize(facts_);
  supporter_.resize(facts_);
  // The exploration's hot loop reads flat arrays of its own: effects_ is reordered by
  // follow(), while each operator's `eff` keeps the task's order.
  pre_count_.resize(ops_.size());
  effect_start_.reserve(ops_.size() + 1);
  for (std::size_t i = 0; i < ops_.size(); ++i) {
    pre_count_[i] = static_cast<int>(ops_[i].pre.size());
    effect_start_.push_back(static_cast<std::uint32_t>(effects_.size()));
    effects_.insert(effects_.end(), ops_[i].eff.begin(), ops_[i].eff.end());
  }
  effect_start_.push_back(static_cast<std::uint32_t>(effects_.size()));
  std::vector<FactId> origin(ops_.size());
  for (std::size_t i = 0; i < ops_.size(); ++i) origin[i] = ops_[i].origin;
  group_by(origin_count_, ops_.size(),
           [&](std::size_t i) { return std::span<const FactId>(origin.data() + i, origin[i] >= 0 ? 1 : 0); },
           relaxed_start_, relaxed_of_);
}

void RelaxedTask::follow(const TieOrder& order) {
  const auto task_fact = [&](FactId f) { return f < task_facts_ ? f : complemented(f); };
  if (!order.initial_rank.empty()) {
    std::stable_sort(initial_order_.begin(), initial_order_.end(), [&](FactId a, FactId b) {
      return order.initial_rank[task_fact(a)] < order.initial_rank[task_fact(b)];
    });
  }
  if (order.effect_rank.empty()) return;
  const auto rank = [&](FactId f) { return f == goal_ ? ~std::uint32_t{0} : order.effect_rank[task_fact(f)]; };
  for (std::size_t i = 0; i < ops_.size(); ++i) {
    stable_sort_short(effects_.begin() + effect_start_[i], effects_.begin() + effect_start_[i + 1],
                     [&](FactId a, FactId b) { return rank(a) < rank(b); });
  }
}

// Generalized Dijkstra: an operator fires when its last precondition is reached; its
// value is the max (h_max) or sum (h_add) of its preconditions' costs. Among facts of
// equal cost the one reached last comes first (LIFO, as Fast Downward's bucket queue):
// the supporters, and so relaxed plans and preferred operators, follow the same order.
double RelaxedTask::exploration(const State& s, bool max, const std::vector<double>& op_cost, bool stop_at_goal) {
  // Each kind of exploration sizes its records when first used: a search uses one kind,
  // and records never used cost no memory.
  const auto sized = [&](auto& records) {
    if (records.size() != ops_.size()) records.resize(ops_.size());
    return records.data();
  };
  const auto with = [&](auto& queue) {
    if (max) explore<true>(queue, s, op_cost.data(), fact_cost_.data(), sized(op_state_), stop_at_goal);
    else explore<false>(queue, s, op_cost.data(), fact_cost_.data(), sized(add_state_), stop_at_goal);
    return fact_cost_[goal_];
  };
  if (whole_costs_) {
    try {
      // h_add of the task's own costs in 32-bit integers: half the memory per operator
      // and fact that the hot loop reads in doubles.
      if (!max && &op_cost == &base_cost_ && !whole_base_cost_.empty()) {
        BucketQueue<std::int32_t> queue(buckets_);
        whole_fact_cost_.resize(facts_);
        explore<false>(queue, s, whole_base_cost_.data(), whole_fact_cost_.data(), sized(whole_add_state_), stop_at_goal);
        const std::int32_t goal_cost = whole_fact_cost_[goal_];
        return goal_cost == std::numeric_limits<std::int32_t>::max() ? kInfinity : goal_cost;
      }
      BucketQueue<double> queue(buckets_);
      return with(queue);
    } catch (const BucketOverflow&) {
    }
  }
  HeapQueue queue;
  return with(queue);
}

// The hot loop of every FF, h_add and h_max evaluation: it reads the arrays through
// local pointers, which the compiler keeps in registers (through the members it reloads
// them after every store, as a store might change them).
template <bool Max, class Queue, class Value, class Record>
void RelaxedTask::explore(Queue& queue, const State& s, const Value* cost_of, Value* fact_cost, Record* op_state,
                          bool stop_at_goal) {
  static_assert(!Max || std::is_same_v<Record, OpState>, "h_max keeps a costliest precondition");
  constexpr Value kUnreached =
      std::numeric_limits<Value>::has_infinity ? std::numeric_limits<Value>::infinity() : std::numeric_limits<Value>::max();
  int* const supporter = supporter_.data();
  const std::uint32_t* const effect_start = effect_start_.data();
  const FactId* const effects = effects_.data();
  const std::uint32_t* const trigger_start = trigger_start_.data();
  const int* const triggers = triggers_.data();
  const FactId goal = goal_;
  std::fill(fact_cost, fact_cost + facts_, kUnreached);
  std::fill(supporter_.begin(), supporter_.end(), -1);
  const int* const pre_count = pre_count_.data();
  for (std::size_t i = 0, n = ops_.size(); i < n; ++i) {
    if constexpr (Max) op_state[i] = {pre_count[i], -1, 0.0};
    else op_state[i] = {pre_count[i], 0};
  }
  for (FactId f : initial_order_) {
    if (holds_in(s, f)) {
      fact_cost[f] = 0;
      queue.push(0, f);
    }
  }
  const auto fire = [&](int i) {
    const Value value = op_state[i].value + cost_of[i];
    for (std::uint32_t k = effect_start[i], end = effect_start[i + 1]; k < end; ++k) {
      const FactId e = effects[k];
      if (value < fact_cost[e]) {
        fact_cost[e] = value;
        supporter[e] = i;
        queue.push(value, e);
      }
    }
  };
  for (int i : no_precondition_) fire(i);
  while (!queue.empty()) {
    const auto [cost, f] = queue.pop();
    if (cost > fact_cost[f]) continue;
    if (f == goal && stop_at_goal) break;
    for (std::uint32_t k = trigger_start[f], end = trigger_start[f + 1]; k < end; ++k) {
      const int i = triggers[k];
      Record& o = op_state[i];
      if constexpr (!Max) {
        o.value += cost;
      } else if (cost >= o.value) {  // facts come in cost order: the last is a costliest
        o.value = cost;
        o.costliest = f;
      }
      if (--o.unsatisfied == 0) fire(i);
    }
  }
}

double RelaxedTask::cost_to_goal(const State& s, bool max) { return exploration(s, max, base_cost_, true); }

double RelaxedTask::ff(const State& s, const StateSpace& space, std::vector<OperatorId>* preferred) {
  if (exploration(s, false, base_cost_, true) == kInfinity) return kInfinity;
  std::vector<char>& marked_fact = marked_fact_;
  std::vector<char>& used_origin = used_origin_;
  marked_fact.assign(facts_, 0);
  used_origin.assign(space.task().operators.size(), 0);
  std::vector<FactId>& open = open_;
  open.assign(1, goal_);
  marked_fact[goal_] = 1;
  double h = 0.0;
  while (!open.empty()) {
    const FactId f = open.back();
    open.pop_back();
    const int op = supporter_[f];
    if (op < 0) continue;  // true in s
    const Op& o = ops_[op];
    if (o.origin >= 0 && !used_origin[o.origin]) {
      used_origin[o.origin] = 1;
      h += o.cost;
      if (preferred && space.applicable(s, o.origin)) preferred->push_back(o.origin);
    }
    for (FactId p : o.pre) {
      if (!marked_fact[p]) {
        marked_fact[p] = 1;
        open.push_back(p);
      }
    }
  }
  return h;
}

double RelaxedTask::lmcut(const State& s) {
  // Costs belong to task operators: the relaxed operators of one operator's
  // conditional effects share it, and a cut reduces each operator once.
  remaining_.assign(origin_count_, 0.0);
  for (const Op& o : ops_) {
    if (o.origin >= 0) remaining_[o.origin] = o.cost;
  }
  std::vector<double>& cost = lmcut_cost_;
  cost = base_cost_;
  double h = 0.0;
  constexpr FactId none = -1;
  // Every operator's h_max once; after each cut only what the cheaper operators change.
  exploration(s, true, cost, false);
  for (int round = 0; round < 100000; ++round) {
    if (std::chrono::steady_clock::now() >= deadline_) throw TimeLimit("time limit");
    if (fact_cost_[goal_] == kInfinity) return kInfinity;
    if (fact_cost_[goal_] <= 0.0) return h;
    // Precondition choice function: a precondition with the largest h_max, which the
    // explorations keep as each operator's costliest.
    // Goal zone: facts from which the goal is reached through zero-cost operators.
    std::fill(in_goal_zone_.begin(), in_goal_zone_.end(), 0);
    in_goal_zone_[goal_] = 1;
    open_.assign(1, goal_);
    while (!open_.empty()) {
      const FactId f = open_.back();
      open_.pop_back();
      for (int i : achievers(f)) {
        const FactId pcf = op_state_[i].costliest;
        if (op_state_[i].unsatisfied > 0 || cost[i] != 0.0 || pcf == none || in_goal_zone_[pcf]) continue;
        in_goal_zone_[pcf] = 1;
        open_.push_back(pcf);
      }
    }
    // Forward from the state through the justification graph, stopping at the zone;
    // operators crossing into the zone form the cut.
    std::fill(reached_.begin(), reached_.end(), 0);
    open_.clear();
    for (FactId f = 0; f < goal_; ++f) {
      if (holds_in(s, f) && !in_goal_zone_[f]) {
        reached_[f] = 1;
        open_.push_back(f);
      }
    }
    cut_.clear();
    auto visit = [&](int i) {
      if (op_state_[i].unsatisfied > 0) return;
      bool crosses = false;
      for (std::uint32_t k = effect_start_[i]; k < effect_start_[i + 1]; ++k) crosses = crosses || in_goal_zone_[effects_[k]];
      if (crosses) {
        if (!in_cut_[i]) {
          in_cut_[i] = 1;
          cut_.push_back(i);
        }
        return;
      }
      for (std::uint32_t k = effect_start_[i]; k < effect_start_[i + 1]; ++k) {
        const FactId e = effects_[k];
        if (!reached_[e]) {
          reached_[e] = 1;
          open_.push_back(e);
        }
      }
    };
    for (int i : no_precondition_) visit(i);
    while (!open_.empty()) {
      const FactId f = open_.back();
      open_.pop_back();
      for (int i : precondition_of(f)) {
        if (op_state_[i].costliest == f) visit(i);
      }
    }
    if (cut_.empty()) return h;  // cannot happen with finite h_max > 0; stay safe
    double m = kInfinity;
    for (int i : cut_) m = std::min(m, cost[i]);
    h += m;
    cheaper_.clear();
    for (int i : cut_) {
      in_cut_[i] = 0;
      const OperatorId origin = ops_[i].origin;
      if (origin < 0 || origin_reduced_[origin]) continue;
      origin_reduced_[origin] = 1;
      remaining_[origin] -= m;
      for (std::uint32_t k = relaxed_start_[origin]; k < relaxed_start_[origin + 1]; ++k) {
        cost[relaxed_of_[k]] = remaining_[origin];
        cheaper_.push_back(relaxed_of_[k]);
      }
    }
    for (int i : cut_) {
      if (ops_[i].origin >= 0) origin_reduced_[ops_[i].origin] = 0;
    }
    lower_hmax(cheaper_, cost);
  }
  return h;
}

// Operator costs only fall between LM-cut's rounds, so h_max only falls: from the
// cheaper operators' effects, a Dijkstra over the facts whose cost falls, each
// operator's value (its most costly precondition) taken again where one of its
// preconditions fell. Reachability does not change.
void RelaxedTask::lower_hmax(const std::vector<int>& cheaper, const std::vector<double>& op_cost) {
  using Entry = std::pair<double, FactId>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> queue;
  auto offer = [&](int i) {
    const double value = op_state_[i].value + op_cost[i];
    for (std::uint32_t k = effect_start_[i]; k < effect_start_[i + 1]; ++k) {
      const FactId e = effects_[k];
      if (value < fact_cost_[e]) {
        fact_cost_[e] = value;
        queue.push({value, e});
      }
    }
  };
  for (int i : cheaper) {
    if (op_state_[i].unsatisfied == 0) offer(i);
  }
  while (!queue.empty()) {
    const auto [c, f] = queue.top();
    queue.pop();
    if (c > fact_cost_[f]) continue;
    for (std::uint32_t k = trigger_start_[f]; k < trigger_start_[f + 1]; ++k) {
      const int i = triggers_[k];
      OpState& o = op_state_[i];
      if (o.unsatisfied > 0) continue;
      double value = -1.0;
      for (FactId p : ops_[i].pre) {
        if (fact_cost_[p] > value) {
          value = fact_cost_[p];
          o.costliest = p;  // even at an equal value: the one before may have fallen
        }
      }
      if (value < o.value) {
        o.value = value;
        offer(i);
      }
    }
  }
}

}  // namespace cluttertamp::search::detail
