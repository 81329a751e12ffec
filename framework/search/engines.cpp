#include <chrono>
#include <memory>
#include <queue>
#include <stdexcept>
#include <unordered_map>

#include "cluttertamp/search/planner.hpp"
#include "cluttertamp/core/free_beside.hpp"
#include "cluttertamp/search/grounding.hpp"  // TimeLimit
#include "search/heuristics.hpp"
#include "search/state_space.hpp"

namespace cluttertamp::search {

namespace {

using detail::kInfinity;
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

// States seen so far, each with the best path to it.
class Registry {
 public:
  std::pair<int, bool> insert(const State& s) {
    auto [it, inserted] = index_.emplace(s, static_cast<int>(states_.size()));
    if (inserted) {
      states_.push_back(&it->first);
      nodes_.push_back({-1, -1, kInfinity, kInfinity, false});
    }
    return {it->second, inserted};
  }
  const State& state(int id) const { return *states_[id]; }
  Node& node(int id) { return nodes_[id]; }
  std::vector<OperatorId> path(int id) const {
    std::vector<OperatorId> plan;
    for (int n = id; nodes_[n].parent >= 0; n = nodes_[n].parent) plan.push_back(nodes_[n].op);
    return {plan.rbegin(), plan.rend()};
  }

 private:
  std::unordered_map<State, int, detail::StateHash> index_;
  std::vector<const State*> states_;
  std::vector<Node> nodes_;
};

class Evaluator {
 public:
  Evaluator(Heuristic kind, const Task& task, const StateSpace& space, Clock::time_point deadline)
      : kind_(kind), relaxed_(task), space_(space) {
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

 private:
  Heuristic kind_;
  RelaxedTask relaxed_;
  const StateSpace& space_;
  double min_cost_ = 0.0;
};

struct Limits {
  Clock::time_point deadline;
  std::uint64_t max_expansions;
  double cost_bound;  // a path of this cost or more is not followed
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

// Two open lists, all successors and preferred successors, taken in turn; a list
// that led to progress (a better h) is boosted, as in Fast Downward.
template <class Entry>
class DualQueue {
 public:
  using Queue = std::priority_queue<Entry, std::vector<Entry>, std::greater<>>;
  void push(const Entry& e, bool preferred) {
    all_.push(e);
    if (preferred) preferred_.push(e);
  }
  bool empty() const { return all_.empty() && preferred_.empty(); }
  Entry pop() {
    const bool use_preferred = !preferred_.empty() && (all_.empty() || priority_preferred_ >= priority_all_);
    Queue& q = use_preferred ? preferred_ : all_;
    (use_preferred ? priority_preferred_ : priority_all_) -= 1;
    Entry e = q.top();
    q.pop();
    return e;
  }
  void boost() { priority_preferred_ += 1000; }

 private:
  Queue all_, preferred_;
  long priority_all_ = 0, priority_preferred_ = 0;
};

SearchResult finish(const StateSpace& space, Registry& registry, int goal, SearchResult result) {
  result.plan = registry.path(goal);
  // Check the plan once more by simulation.
  State s = space.initial();
  double cost = 0;
  for (OperatorId op : result.plan) {
    if (!space.applicable(s, op)) throw std::logic_error("search produced an inapplicable plan");
    s = space.apply(s, op);
    cost += space.task().operators[op].cost;
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
  Registry registry;
  using Entry = std::tuple<double, double, std::uint64_t, int>;  // key, h, insertion order, state
  DualQueue<Entry> open;
  std::uint64_t order = 0;
  const auto [start, inserted] = registry.insert(space.initial());
  (void)inserted;
  std::vector<OperatorId> preferred;
  double best_h = h(registry.state(start), &preferred);
  ++result.statistics.evaluated;
  if (best_h == kInfinity) {
    result.reason = "no plan exists (the initial state is a dead end)";
    return result;
  }
  registry.node(start) = {-1, -1, 0.0, best_h, false};
  open.push({w_h * best_h, best_h, order++, start}, false);
  std::vector<OperatorId> successors;
  // A time limit inside one evaluation (LM-cut between its rounds) stops it like any other.
  try {
    while (!open.empty()) {
      const auto [key, h_value, unused, id] = open.pop();
      (void)unused;
      Node& node = registry.node(id);
      if (node.closed || w_g * node.g + w_h * node.h < key - 1e-9) continue;  // stale entry
      if (space.is_goal(registry.state(id))) return finish(space, registry, id, result);
      if (limits.exceeded(result.statistics, result.reason)) return stopped(std::move(registry), std::move(open), result);
      node.closed = true;
      ++result.statistics.expanded;
      const State state = registry.state(id);
      const double g = node.g;
      preferred.clear();
      if (use_preferred) h(state, &preferred);
      successors.clear();
      space.applicable_operators(state, [&](OperatorId op) { successors.push_back(op); });
      for (OperatorId op : successors) {
        ++result.statistics.generated;
        const double child_g = g + space.task().operators[op].cost;
        if (child_g >= limits.cost_bound) continue;
        const auto [child, is_new] = registry.insert(space.apply(state, op));
        Node& c = registry.node(child);
        if (!is_new && (child_g >= c.g || (c.closed && !reopen) || c.h == kInfinity)) continue;  // dead ends stay closed
        if (is_new) {
          // Evaluating every successor of one state can take seconds (LM-cut on hundreds
          // of blocks): the time limit is looked at before each evaluation.
          if (limits.time_up(result.reason)) return stopped(std::move(registry), std::move(open), result);
          c.h = h(registry.state(child), nullptr);
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
          if (use_preferred) open.boost();
        }
        open.push({w_g * child_g + w_h * c.h, c.h, order++, child}, is_preferred);
      }
    }
  } catch (const TimeLimit&) {
    result.reason = "time limit";
    return stopped(std::move(registry), std::move(open), result);
  }
  result.reason = limits.cost_bound < kInfinity ? "no plan found below the cost bound" : "no plan exists (every reachable state was expanded)";
  return result;
}

// Lazy greedy best-first search: successors inherit their parent's h and are evaluated
// when taken from the open list.
SearchResult lazy(const StateSpace& space, Evaluator& h, const Limits& limits) {
  SearchResult result;
  Registry registry;
  using Entry = std::tuple<double, std::uint64_t, int, OperatorId>;  // parent h, order, parent, op
  DualQueue<Entry> open;
  std::uint64_t order = 0;
  const int start = registry.insert(space.initial()).first;
  registry.node(start).g = 0.0;
  double best_h = kInfinity;
  std::vector<OperatorId> preferred, successors;
  auto expand = [&](int id) -> bool {  // false: dead end
    const State state = registry.state(id);
    preferred.clear();
    const double value = h(state, &preferred);
    ++result.statistics.evaluated;
    registry.node(id).h = value;
    if (value == kInfinity) return false;
    if (value < best_h) {
      best_h = value;
      open.boost();
    }
    ++result.statistics.expanded;
    successors.clear();
    space.applicable_operators(state, [&](OperatorId op) { successors.push_back(op); });
    for (OperatorId op : successors) {
      ++result.statistics.generated;
      const bool is_preferred = std::find(preferred.begin(), preferred.end(), op) != preferred.end();
      open.push({value, order++, id, op}, is_preferred);
    }
    return true;
  };
  registry.node(start).closed = true;
  if (space.is_goal(registry.state(start))) return finish(space, registry, start, result);
  if (!expand(start)) {
    result.reason = "no plan exists (the initial state is a dead end)";
    return result;
  }
  while (!open.empty()) {
    if (limits.exceeded(result.statistics, result.reason)) return stopped(std::move(registry), std::move(open), result);
    const auto [parent_h, unused, parent, op] = open.pop();
    (void)parent_h;
    (void)unused;
    const double child_g = registry.node(parent).g + space.task().operators[op].cost;
    if (child_g >= limits.cost_bound) continue;
    const auto [child, is_new] = registry.insert(space.apply(registry.state(parent), op));
    if (!is_new) continue;
    Node& c = registry.node(child);
    c.parent = parent;
    c.op = op;
    c.g = child_g;
    c.closed = true;
    if (space.is_goal(registry.state(child))) return finish(space, registry, child, result);
    expand(child);
  }
  result.reason = limits.cost_bound < kInfinity ? "no plan found below the cost bound" : "no plan exists (every reachable state was expanded)";
  return result;
}

SearchResult run_search(const Task& task, const StateSpace& space, const std::string& a, double weight,
                        const Limits& limits) {
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
  auto with = [&](Heuristic kind) -> Evaluator& {
    h = std::make_unique<Evaluator>(kind, task, space, limits.deadline);
    return *h;
  };
  try {
    if (a == "lazy-gbfs-ff") {
      result = lazy(space, with(Heuristic::hff), limits);
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
  if (result.reason == "time limit") free_beside(std::move(h));  // a relaxed task of every operator
  return result;
}

}  // namespace

const std::vector<std::string>& search_names() {
  static const std::vector<std::string> names{"lazy-gbfs-ff", "eager-gbfs-ff", "gbfs-add", "wastar-ff",
                                              "astar-hmax",   "astar-lmcut",   "astar-blind"};
  return names;
}

SearchResult plan(const Task& task, const SearchOptions& options) {
  const auto start = Clock::now();
  auto space = std::make_unique<const StateSpace>(task);
  const Limits limits{start + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(
                                  std::min(options.time_limit, 1e9))),
                      options.max_expansions, options.cost_bound};
  SearchResult result = run_search(task, *space, options.algorithm, options.weight, limits);
  if (result.reason == "time limit") free_beside(std::move(space));
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
