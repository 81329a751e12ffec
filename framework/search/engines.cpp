#include <algorithm>
#include <chrono>
#include <cstdint>
#include <memory>
#include <queue>
#include <stdexcept>
#include <tuple>

#include "cluttertamp/search/planner.hpp"
#include "cluttertamp/core/free_beside.hpp"
#include "cluttertamp/search/grounding.hpp"  // TimeLimit
#include "search/heuristics.hpp"
#include "search/landmarks.hpp"
#include "search/mutex_groups.hpp"
#include "search/state_space.hpp"
#include "search/successor_order.hpp"
#include "search/tuple_index.hpp"

namespace cluttertamp::search {

namespace {

using detail::kInfinity;
using detail::LandmarkCount;
using detail::Landmarks;
using detail::RelaxedTask;
using detail::State;
using detail::StateSpace;
using Clock = std::chrono::steady_clock;

enum class Heuristic { blind, hmax, hadd, hff, lmcut };

struct Node {
  int parent;
  OperatorId op;
  double g;
  double h;
  bool closed;
};

// States seen so far, each with the best path to it: a state's id is its place in
// the TupleIndex of their words.
class Registry {
 public:
  explicit Registry(std::size_t words) : states_(words) {}
  std::pair<int, bool> insert(const State& s) {
    const auto [id, added] = states_.insert(s);
    if (added) nodes_.push_back({-1, -1, kInfinity, kInfinity, false});
    return {static_cast<int>(id), added};
  }
  /// Copies state `id` into `out`.
  void load(int id, State& out) const {
    const std::span<const std::uint64_t> words = states_[static_cast<std::size_t>(id)];
    out.assign(words.begin(), words.end());
  }
  Node& node(int id) { return nodes_[id]; }
  std::vector<OperatorId> path(int id) const {
    std::vector<OperatorId> plan;
    for (int n = id; nodes_[n].parent >= 0; n = nodes_[n].parent) plan.push_back(nodes_[n].op);
    return {plan.rbegin(), plan.rend()};
  }

 private:
  detail::TupleIndex<std::uint64_t> states_;
  std::vector<Node> nodes_;  // per state id
};

class Evaluator {
 public:
  Evaluator(Heuristic kind, const Task& task, const StateSpace& space, Clock::time_point deadline,
            RelaxedTask::Costs costs = RelaxedTask::Costs::normal)
      : kind_(kind), relaxed_(task, costs, space.left_out()), space_(space) {
    relaxed_.follow(space.tie_order());
    relaxed_.set_deadline(deadline);
  }
  double operator()(const State& s, std::vector<OperatorId>* preferred) {
    switch (kind_) {
      case Heuristic::blind: return space_.is_goal(s) ? 0.0 : min_cost_;
      case Heuristic::hmax: return relaxed_.cost_to_goal(s, true);
      case Heuristic::hadd: return relaxed_.cost_to_goal(s, false);
      case Heuristic::hff: return relaxed_.ff(s, space_, preferred);
      case Heuristic::lmcut: return relaxed_.lmcut(s);
    }
    return 0.0;
  }
  void set_min_cost(double c) { min_cost_ = c; }
  const char* name() const {
    switch (kind_) {
      case Heuristic::blind: return "blind";
      case Heuristic::hmax: return "hmax";
      case Heuristic::hadd: return "add";
      case Heuristic::hff: return "ff";
      case Heuristic::lmcut: return "lmcut";
    }
    return "";
  }
  const RelaxedTask& relaxed() const { return relaxed_; }

 private:
  Heuristic kind_;
  RelaxedTask relaxed_;
  const StateSpace& space_;
  double min_cost_ = 0.0;
};

// One heuristic of the lazy search. It is told every transition the search takes,
// for heuristics whose value depends on the path (landmark count).
class LazyHeuristic {
 public:
  virtual ~LazyHeuristic() = default;
  virtual void start(int /*id*/, const State& /*s*/) {}
  virtual void reach(int /*parent*/, int /*child*/, const State& /*parent_state*/, const State& /*s*/, bool /*is_new*/) {}
  virtual double value(int id, const State& s, std::vector<OperatorId>* preferred) = 0;
  virtual const char* name() const = 0;
};

class StateHeuristic final : public LazyHeuristic {
 public:
  explicit StateHeuristic(Evaluator& h) : h_(h) {}
  double value(int, const State& s, std::vector<OperatorId>* preferred) override { return h_(s, preferred); }
  const char* name() const override { return "ff"; }

 private:
  Evaluator& h_;
};

class LandmarkHeuristic final : public LazyHeuristic {
 public:
  explicit LandmarkHeuristic(const Landmarks& landmarks) : count_(landmarks) {}
  void start(int id, const State& s) override { count_.start(id, s); }
  void reach(int parent, int child, const State& parent_state, const State& s, bool is_new) override {
    count_.reach(parent, child, parent_state, s, is_new);
  }
  double value(int id, const State& s, std::vector<OperatorId>*) override { return count_.value(id, s); }
  const char* name() const override { return "landmark count"; }

 private:
  LandmarkCount count_;
};

struct Limits {
  Clock::time_point deadline;
  std::uint64_t max_expansions;
  double cost_bound;  // a path of this cost or more is not followed
  std::function<void(const SearchProgress&)> progress;  // may be empty
  void report(const char* heuristic, double value, const SearchStatistics& stats) const {
    if (progress) progress({heuristic, value, stats.expanded, stats.evaluated});
  }
  bool exceeded(const SearchStatistics& stats, std::string& reason) const {
    if (stats.expanded >= max_expansions) {
      reason = "expansion limit";
      return true;
    }
    if (Clock::now() >= deadline) {  // every expansion: one LM-cut evaluation can take milliseconds
      reason = "time limit";
      return true;
    }
    return false;
  }
  bool time_up(std::string& reason) const {
    if (Clock::now() < deadline) return false;
    reason = "time limit";
    return true;
  }
};

// Open lists taken in turn, as Fast Downward's alternation: per heuristic one list of
// all successors and one of preferred successors. The list taken least often comes
// first (on a tie, the earlier list); progress (a better h) boosts the preferred
// lists, which are then taken 1000 times before the others again.
template <class Entry, class Queue = std::priority_queue<Entry, std::vector<Entry>, std::greater<>>>
class AlternationQueue {
 public:
  explicit AlternationQueue(std::size_t heuristics) : lists_(2 * heuristics), taken_(2 * heuristics, 0) {}
  void push(std::size_t heuristic, const Entry& e, bool preferred) {
    lists_[2 * heuristic].push(e);
    if (preferred) lists_[2 * heuristic + 1].push(e);
  }
  bool empty() const {
    return std::all_of(lists_.begin(), lists_.end(), [](const Queue& q) { return q.empty(); });
  }
  Entry pop() {
    std::size_t best = lists_.size();
    for (std::size_t i = 0; i < lists_.size(); ++i) {
      if (!lists_[i].empty() && (best == lists_.size() || taken_[i] < taken_[best])) best = i;
    }
    ++taken_[best];
    Entry e = lists_[best].top();
    lists_[best].pop();
    return e;
  }
  void boost() {
    for (std::size_t i = 1; i < taken_.size(); i += 2) taken_[i] -= 1000;
  }

 private:
  std::vector<Queue> lists_;
  std::vector<long> taken_;
};

SearchResult finish(const StateSpace& space, Registry& registry, int goal, SearchResult result) {
  result.plan = registry.path(goal);
  // Check the plan once more by simulation.
  State s = space.initial();
  double cost = 0;
  for (OperatorId op : result.plan) {
    if (!space.applicable(s, op)) throw std::logic_error("search produced an inapplicable plan");
    s = space.apply(s, op);
    cost += space.cost(op);
  }
  if (!space.is_goal(s)) throw std::logic_error("search produced a plan that does not reach the goal");
  result.solved = true;
  result.cost = cost;
  return result;
}

// A search stopped by a limit: what it built is freed beside the caller, whose time is up.
template <class Open>
SearchResult stopped(Registry&& registry, Open&& open, SearchResult& result) {
  free_beside(std::move(registry));
  free_beside(std::move(open));
  return result;
}

// Eager best-first search on key (w_g * g + w_h * h, h).
SearchResult eager(const StateSpace& space, Evaluator& h, double w_g, double w_h, bool use_preferred, bool reopen,
                   const Limits& limits) {
  SearchResult result;
  State state = space.initial(), child_state;
  Registry registry(state.size());
  using Entry = std::tuple<double, double, std::uint64_t, int>;  // key, h, insertion order, state
  AlternationQueue<Entry> open(1);
  std::uint64_t order = 0;
  const auto [start, inserted] = registry.insert(state);
  (void)inserted;
  std::vector<OperatorId> preferred;
  double best_h = h(state, &preferred);
  ++result.statistics.evaluated;
  limits.report(h.name(), best_h, result.statistics);
  if (best_h == kInfinity) {
    result.reason = "no plan exists (the initial state is a dead end)";
    return result;
  }
  registry.node(start) = {-1, -1, 0.0, best_h, false};
  open.push(0, {w_h * best_h, best_h, order++, start}, false);
  std::vector<OperatorId> successors;
  // A time limit inside one evaluation (LM-cut between its rounds) stops it like any other.
  try {
    while (!open.empty()) {
      const auto [key, h_value, unused, id] = open.pop();
      (void)unused;
      Node& node = registry.node(id);
      if (node.closed || w_g * node.g + w_h * node.h < key - 1e-9) continue;  // stale entry
      registry.load(id, state);
      if (space.is_goal(state)) return finish(space, registry, id, result);
      if (limits.exceeded(result.statistics, result.reason)) return stopped(std::move(registry), std::move(open), result);
      node.closed = true;
      ++result.statistics.expanded;
      const double g = node.g;
      preferred.clear();
      if (use_preferred) h(state, &preferred);
      space.applicable_operators(state, successors);
      for (OperatorId op : successors) {
        ++result.statistics.generated;
        const double child_g = g + space.cost(op);
        if (child_g >= limits.cost_bound) continue;
        space.apply(state, op, child_state);
        const auto [child, is_new] = registry.insert(child_state);
        Node& c = registry.node(child);
        if (!is_new && (child_g >= c.g || (c.closed && !reopen) || c.h == kInfinity)) continue;  // dead ends stay closed
        if (is_new) {
          // Evaluating every successor of one state can take seconds (LM-cut on hundreds
          // of blocks): the time limit is looked at before each evaluation.
          if (limits.time_up(result.reason)) return stopped(std::move(registry), std::move(open), result);
          c.h = h(child_state, nullptr);
          ++result.statistics.evaluated;
          if (c.h == kInfinity) {
            c.closed = true;
            continue;
          }
        }
        c.parent = id;
        c.op = op;
        c.g = child_g;
        c.closed = false;
        const bool is_preferred = std::find(preferred.begin(), preferred.end(), op) != preferred.end();
        if (c.h < best_h) {
          best_h = c.h;
          limits.report(h.name(), best_h, result.statistics);
          if (use_preferred) open.boost();
        }
        open.push(0, {w_g * child_g + w_h * c.h, c.h, order++, child}, is_preferred);
      }
    }
  } catch (const TimeLimit&) {
    result.reason = "time limit";
    return stopped(std::move(registry), std::move(open), result);
  }
  result.reason = limits.cost_bound < kInfinity ? "no plan found below the cost bound" : "no plan exists (every reachable state was expanded)";
  return result;
}

// Keys of the lazy search's open lists: w_g * g + w_h * h (greedy: 0 and 1).
struct LazyKeys {
  double w_g = 0.0;
  double w_h = 1.0;
  bool reopen = false;  // a cheaper path to a state seen before opens it again
};

// One open list of the lazy search: entries (key, order, parent, op) taken by least key,
// then least order (first in, first out). Whole keys go to a bucket each, as in Fast
// Downward's open lists, which spares a heap's sifting on every push; a bucket holds
// only (parent, op), 8 bytes where a heap entry takes 24: its key is its index and its
// entries are in order. The first other key moves the list to a heap for good (the
// same order).
class BucketList {
 public:
  using Entry = std::tuple<double, std::uint64_t, int, OperatorId>;
  void push(const Entry& e) {
    const double key = std::get<0>(e);
    if (!heap_.empty() || !whole(key)) {
      to_heap();
      heap_.push(e);
      return;
    }
    const auto k = static_cast<std::size_t>(key);
    if (k >= buckets_.size()) buckets_.resize(k + 1);
    buckets_[k].items.push_back({std::get<2>(e), std::get<3>(e)});
    lowest_ = std::min(lowest_, k);
    ++size_;
  }
  bool empty() const { return size_ == 0 && heap_.empty(); }
  /// The first entry; from a bucket its order is left 0 (the search does not read it).
  Entry top() const {
    if (!heap_.empty()) return heap_.top();
    const std::size_t k = first();
    const Bucket& b = buckets_[k];
    return {static_cast<double>(k), 0, b.items[b.head].parent, b.items[b.head].op};
  }
  void pop() {
    if (!heap_.empty()) {
      heap_.pop();
      return;
    }
    Bucket& b = buckets_[first()];
    if (++b.head == b.items.size()) {
      b.items.clear();
      b.head = 0;
    }
    --size_;
  }

 private:
  static constexpr std::size_t kMaxBucket = 1 << 18;
  struct Item {
    int parent;
    OperatorId op;
  };
  struct Bucket {
    std::vector<Item> items;
    std::size_t head = 0;  // items before it are taken
  };
  static bool whole(double key) {
    return key >= 0.0 && key < static_cast<double>(kMaxBucket) && key == static_cast<double>(static_cast<std::int64_t>(key));
  }
  std::size_t first() const {
    while (buckets_[lowest_].head == buckets_[lowest_].items.size()) ++lowest_;
    return lowest_;
  }
  // Entries of one bucket share their key and lie in push order, so numbering them in
  // that order keeps the order among them; every later push has a larger order (one
  // number per successor, at most one push per list each).
  void to_heap() {
    if (size_ == 0) return;
    std::uint64_t order = 0;
    for (std::size_t k = 0; k < buckets_.size(); ++k) {
      Bucket& b = buckets_[k];
      for (std::size_t i = b.head; i < b.items.size(); ++i) heap_.push({static_cast<double>(k), order++, b.items[i].parent, b.items[i].op});
      b.items.clear();
      b.head = 0;
    }
    size_ = 0;
  }
  std::vector<Bucket> buckets_;
  mutable std::size_t lowest_ = 0;
  std::size_t size_ = 0;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> heap_;
};

// Lazy best-first search: a successor enters the open lists with its parent's values
// and is evaluated when taken out. The first heuristic gives the preferred operators.
SearchResult lazy(const StateSpace& space, const std::vector<LazyHeuristic*>& heuristics, const LazyKeys& keys,
                  const Limits& limits) {
  SearchResult result;
  State parent_state = space.initial(), state;
  Registry registry(parent_state.size());
  const std::size_t k = heuristics.size();
  using Entry = BucketList::Entry;  // key, order, parent, op
  AlternationQueue<Entry, BucketList> open(k);
  std::uint64_t order = 0;
  std::vector<double> values;  // per state: its k heuristic values
  std::vector<double> best(k, kInfinity);
  std::vector<OperatorId> preferred, successors;
  // False: a dead end. The initial state's values are the first best ones, not progress
  // (as in Fast Downward: no boost before the first expansion).
  auto evaluate = [&](int id, const State& state, bool initial) -> bool {
    preferred.clear();
    ++result.statistics.evaluated;
    values.resize(std::max(values.size(), (static_cast<std::size_t>(id) + 1) * k));
    bool progress = false;
    for (std::size_t i = 0; i < k; ++i) {
      const double v = heuristics[i]->value(id, state, i == 0 ? &preferred : nullptr);
      if (v == kInfinity) return false;
      values[id * k + i] = v;
      if (v < best[i]) {
        best[i] = v;
        progress = true;
        limits.report(heuristics[i]->name(), v, result.statistics);
      }
    }
    if (progress && !initial) open.boost();
    return true;
  };
  auto expand = [&](int id, const State& state) {
    ++result.statistics.expanded;
    const double g = registry.node(id).g;
    space.applicable_operators(state, successors);
    for (OperatorId op : successors) {
      ++result.statistics.generated;
      const double child_g = g + space.cost(op);
      if (child_g >= limits.cost_bound) continue;
      const bool is_preferred = std::find(preferred.begin(), preferred.end(), op) != preferred.end();
      for (std::size_t i = 0; i < k; ++i) open.push(i, {keys.w_g * child_g + keys.w_h * values[id * k + i], order, id, op}, is_preferred);
      ++order;
    }
  };
  const int start = registry.insert(parent_state).first;
  registry.node(start) = {-1, -1, 0.0, 0.0, true};
  for (LazyHeuristic* h : heuristics) h->start(start, parent_state);
  if (space.is_goal(parent_state)) return finish(space, registry, start, result);
  if (!evaluate(start, parent_state, true)) {
    result.reason = "no plan exists (the initial state is a dead end)";
    return result;
  }
  expand(start, parent_state);
  while (!open.empty()) {
    if (limits.exceeded(result.statistics, result.reason)) return stopped(std::move(registry), std::move(open), result);
    const auto [key, unused, parent, op] = open.pop();
    (void)key;
    (void)unused;
    const double child_g = registry.node(parent).g + space.cost(op);
    if (child_g >= limits.cost_bound) continue;
    registry.load(parent, parent_state);
    space.apply(parent_state, op, state);
    const auto [child, is_new] = registry.insert(state);
    Node& c = registry.node(child);
    if (!is_new && (!keys.reopen || c.h == kInfinity || child_g >= c.g)) continue;  // dead ends stay closed
    // Only a state evaluated now learns from this path (as in Fast Downward's lazy search):
    // a closed state's data stays what its children were queued with.
    for (LazyHeuristic* h : heuristics) h->reach(parent, child, parent_state, state, is_new);
    c.parent = parent;
    c.op = op;
    c.g = child_g;
    c.closed = true;
    if (space.is_goal(state)) return finish(space, registry, child, result);
    if (!evaluate(child, state, false)) {
      registry.node(child).h = kInfinity;
      continue;
    }
    registry.node(child).h = values[child * k];
    expand(child, state);
  }
  result.reason = limits.cost_bound < kInfinity ? "no plan found below the cost bound" : "no plan exists (every reachable state was expanded)";
  return result;
}

// Label operations allowed to find landmarks (a few tenths of a second): beyond, the
// goal facts are the landmarks.
constexpr std::uint64_t kLandmarkWork = 100'000'000;

// The heuristics of one lazy search: h_FF first (it gives the preferred operators),
// then the landmark count when asked for.
enum class LandmarkKind { none, zhu_givan, rhw };

LandmarkKind landmark_kind(const std::string& name) {
  if (name == "rhw") return LandmarkKind::rhw;
  if (name == "zhu-givan") return LandmarkKind::zhu_givan;
  throw std::invalid_argument("unknown landmarks '" + name + "'; known: rhw, zhu-givan");
}

class LazyHeuristics {
 public:
  LazyHeuristics(const Task& task, const StateSpace& space, const Limits& limits, RelaxedTask::Costs costs,
                 LandmarkKind landmarks, const detail::MutexGroups* mutexes = nullptr)
      : ff_(Heuristic::hff, task, space, limits.deadline, costs), ff_adapter_(ff_) {
    if (landmarks == LandmarkKind::zhu_givan) {
      landmarks_ = std::make_unique<Landmarks>(ff_.relaxed(), space.initial(), kLandmarkWork);
    } else if (landmarks == LandmarkKind::rhw) {
      landmarks_ = std::make_unique<Landmarks>(Landmarks::rhw(ff_.relaxed(), task, space.initial(), kLandmarkWork, limits.deadline, mutexes));
    }
  }
  void describe(SearchStatistics& s) const {
    if (!landmarks_) return;
    s.landmarks = landmarks_->size();
    s.disjunctive_landmarks = landmarks_->disjunctive_count();
    s.landmark_orders = landmarks_->order_count();
    s.variables = landmarks_->variable_count();
  }
  // Fresh per search: the landmark count keeps per-state data.
  std::vector<LazyHeuristic*> fresh() {
    std::vector<LazyHeuristic*> out{&ff_adapter_};
    if (landmarks_) {
      count_ = std::make_unique<LandmarkHeuristic>(*landmarks_);
      out.push_back(count_.get());
    }
    return out;
  }

 private:
  Evaluator ff_;
  StateHeuristic ff_adapter_;
  std::unique_ptr<Landmarks> landmarks_;
  std::unique_ptr<LandmarkHeuristic> count_;
};

SearchResult run_search(const Task& task, const StateSpace& space, const std::string& a, double weight,
                        LandmarkKind landmarks, const detail::MutexGroups& mutexes, const Limits& limits) {
  SearchResult result;
  if (task.goal.empty()) {
    result.reason = "no plan exists (the goal is unsatisfiable in every reachable state)";
    return result;
  }
  if (limits.cost_bound <= 0) {  // not even the empty plan (costs are not negative)
    result.reason = "no plan found below the cost bound";
    return result;
  }
  std::unique_ptr<Evaluator> h;
  std::unique_ptr<LazyHeuristics> lazy_h;
  auto with = [&](Heuristic kind) -> Evaluator& {
    h = std::make_unique<Evaluator>(kind, task, space, limits.deadline);
    return *h;
  };
  try {
    if (a == "lama-first") {  // LAMA's first iteration: plan length, not cost, guides it
      lazy_h = std::make_unique<LazyHeuristics>(task, space, limits, RelaxedTask::Costs::one, landmarks, &mutexes);
      result = lazy(space, lazy_h->fresh(), LazyKeys{}, limits);
      lazy_h->describe(result.statistics);
    } else if (a == "lazy-gbfs-ff") {
      lazy_h = std::make_unique<LazyHeuristics>(task, space, limits, RelaxedTask::Costs::normal, LandmarkKind::none);
      result = lazy(space, lazy_h->fresh(), LazyKeys{}, limits);
    } else if (a == "eager-gbfs-ff") {
      result = eager(space, with(Heuristic::hff), 0.0, 1.0, true, false, limits);
    } else if (a == "gbfs-add") {
      result = eager(space, with(Heuristic::hadd), 0.0, 1.0, false, false, limits);
    } else if (a == "wastar-ff") {
      result = eager(space, with(Heuristic::hff), 1.0, weight, false, true, limits);
    } else if (a == "astar-hmax" || a == "astar-lmcut" || a == "astar-blind") {
      const Heuristic kind = a == "astar-hmax" ? Heuristic::hmax : a == "astar-lmcut" ? Heuristic::lmcut : Heuristic::blind;
      result = eager(space, with(kind), 1.0, 1.0, false, true, limits);
    } else {
      std::string known;
      for (const auto& n : search_names()) known += (known.empty() ? "" : ", ") + n;
      throw std::invalid_argument("unknown search '" + a + "'; known: " + known);
    }
  } catch (const TimeLimit&) {  // inside one evaluation (LM-cut)
    result = SearchResult{};
    result.reason = "time limit";
  }
  if (result.reason == "time limit") {  // a relaxed task of every operator
    free_beside(std::move(h));
    free_beside(std::move(lazy_h));
  }
  return result;
}

void add(SearchStatistics& total, const SearchStatistics& more) {
  total.expanded += more.expanded;
  total.generated += more.generated;
  total.evaluated += more.evaluated;
}

// After the first plan, LAMA's restarts: lazy weighted A* with h_FF and the landmark
// count (costs plus one, so that zero-cost operators count), weights 5, 3, 2, 1 and
// then 1 again, each under the best cost so far, until a search exhausts the states
// below it (the last plan is optimal) or a limit is reached.
void improve(const Task& task, const StateSpace& space, const SearchOptions& options, const detail::MutexGroups& mutexes,
             const Limits& limits, SearchResult& best) {
  const RelaxedTask::Costs costs = task.unit_cost ? RelaxedTask::Costs::one : RelaxedTask::Costs::plus_one;
  LazyHeuristics heuristics(task, space, limits, costs, landmark_kind(options.landmarks), &mutexes);
  const double weights[] = {5.0, 3.0, 2.0, 1.0};
  for (int iteration = 0;; ++iteration) {
    Limits bounded = limits;
    bounded.cost_bound = std::min(limits.cost_bound, best.cost);
    bounded.max_expansions = limits.max_expansions - std::min(limits.max_expansions, best.statistics.expanded);
    bounded.progress = nullptr;  // on_plan says what each restart found
    const LazyKeys keys{1.0, weights[std::min(iteration, 3)], true};
    SearchResult next = lazy(space, heuristics.fresh(), keys, bounded);
    add(best.statistics, next.statistics);
    if (!next.solved) {
      best.anytime_end = next.reason == "no plan found below the cost bound" ? "no cheaper plan exists" : next.reason;
      return;
    }
    next.statistics = best.statistics;
    next.plans_found = best.plans_found + 1;
    best = std::move(next);
    if (options.on_plan) options.on_plan(best);
  }
}

// The task the searches run on, as Fast Downward's translator and search see it:
// operators whose preconditions are mutex or that change nothing the goal depends on
// are left out, the rest are numbered by name, and successors are listed in its
// successor generator's order. Ties in every heuristic follow operator order and greedy
// searches follow successor order, so the same orders keep our searches close to its.
// The grounder gives its operators in name order: then the grounded task is searched
// with the operators left out marked (`left_out`). Otherwise a copy in name order is,
// without the operators left out and without names, which no search reads; `original`
// maps its operators back to the grounded task, which names them.
struct SearchTask {
  detail::MutexGroups mutexes;
  bool as_grounded = false;  // the grounded task is searched, else `reduced`
  std::vector<char> left_out;  // per grounded operator, when some are left out of it
  Task reduced;
  std::vector<OperatorId> original;  // per operator of `reduced`: its id in the grounded task
  detail::TieOrder order;  // per operator and fact searched
  std::size_t never_applicable = 0, irrelevant = 0;
};

SearchTask search_task(const Task& grounded) {
  SearchTask out;
  out.mutexes = detail::find_mutex_groups(grounded, kLandmarkWork / 4);
  const std::vector<char> never = detail::never_applicable(grounded, out.mutexes);
  detail::SuccessorOrder order = detail::successor_order(grounded, out.mutexes, never);
  for (OperatorId o = 0; o < static_cast<OperatorId>(grounded.operators.size()); ++o) {
    if (never[o]) ++out.never_applicable;
    else if (!order.relevant[o]) ++out.irrelevant;
    else out.original.push_back(o);
  }
  const auto by_name = [&](OperatorId a, OperatorId b) { return grounded.operators[a].name < grounded.operators[b].name; };
  out.order.initial_rank = std::move(order.search_variable);
  out.order.effect_rank = std::move(order.translator_variable);
  if (std::is_sorted(out.original.begin(), out.original.end(), by_name)) {
    out.as_grounded = true;
    if (out.original.size() < grounded.operators.size()) {
      out.left_out.assign(grounded.operators.size(), 1);
      for (OperatorId o : out.original) out.left_out[o] = 0;
    }
    out.original.clear();
    out.order.successor_rank = std::move(order.rank);
    return out;
  }
  std::stable_sort(out.original.begin(), out.original.end(), by_name);
  Task& task = out.reduced;
  task.fact_names = grounded.fact_names;
  task.derived = grounded.derived;
  task.initial = grounded.initial;
  task.axioms = grounded.axioms;
  task.goal = grounded.goal;
  task.unit_cost = grounded.unit_cost;
  task.operators.reserve(out.original.size());
  out.order.successor_rank.reserve(out.original.size());
  for (OperatorId o : out.original) {
    const Operator& op = grounded.operators[o];
    task.operators.push_back({{}, op.precondition, op.add, op.del, op.conditional, op.cost});
    out.order.successor_rank.push_back(order.rank[o]);
  }
  return out;
}

}  // namespace

const std::vector<std::string>& search_names() {
  static const std::vector<std::string> names{"lama-first", "lazy-gbfs-ff", "eager-gbfs-ff", "gbfs-add",
                                              "wastar-ff",  "astar-hmax",   "astar-lmcut",   "astar-blind"};
  return names;
}

SearchResult plan(const Task& grounded, const SearchOptions& options) {
  const auto start = Clock::now();
  auto prepared = std::make_unique<const SearchTask>(search_task(grounded));
  const Task& task = prepared->as_grounded ? grounded : prepared->reduced;
  const detail::MutexGroups& mutexes = prepared->mutexes;
  const auto to_grounded = [&](SearchResult& r) {
    if (prepared->as_grounded) return;
    for (OperatorId& op : r.plan) op = prepared->original[op];
  };
  SearchOptions inner = options;
  if (options.on_plan) {
    inner.on_plan = [&](const SearchResult& r) {
      SearchResult said = r;
      to_grounded(said);
      options.on_plan(said);
    };
  }
  auto space = std::make_unique<const StateSpace>(task, prepared->order, prepared->left_out);
  const Limits limits{start + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(
                                  std::min(options.time_limit, 1e9))),
                      options.max_expansions, options.cost_bound, options.on_progress};
  const LandmarkKind landmarks = landmark_kind(options.landmarks);
  SearchResult result = run_search(task, *space, options.algorithm, options.weight, landmarks, mutexes, limits);
  if (result.solved) {
    result.plans_found = 1;
    if (options.anytime) {
      if (inner.on_plan) inner.on_plan(result);
      try {
        improve(task, *space, inner, mutexes, limits, result);
      } catch (const TimeLimit&) {
        result.anytime_end = "time limit";
      }
    }
  }
  to_grounded(result);
  result.statistics.never_applicable = prepared->never_applicable;
  result.statistics.irrelevant = prepared->irrelevant;
  if (result.reason == "time limit") {  // a reduced copy of the grounded task and its successor index
    free_beside(std::move(space));
    free_beside(std::move(prepared));
  }
  result.statistics.seconds = std::chrono::duration<double>(Clock::now() - start).count();
  return result;
}

double initial_heuristic(const Task& task, const std::string& heuristic) {
  const StateSpace space(task);
  RelaxedTask relaxed(task);
  const State s = space.initial();
  if (heuristic == "hmax") return relaxed.cost_to_goal(s, true);
  if (heuristic == "hadd") return relaxed.cost_to_goal(s, false);
  if (heuristic == "hff") return relaxed.ff(s, space, nullptr);
  if (heuristic == "lmcut") return relaxed.lmcut(s);
  throw std::invalid_argument("unknown heuristic '" + heuristic + "'");
}

}  // namespace cluttertamp::search
