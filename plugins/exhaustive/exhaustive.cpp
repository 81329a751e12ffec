// exhaustive: the brute-force retrieval baseline of Tian et al. (T-RO 2023, Section
// VI-F, Table VI) — every removal set and order, smallest sets first, with the same
// feasibility checks as retrieval_graph. The first set whose removal lets the target
// out is a minimum one.
//
// Orders are enumerated by dynamic programming over sets: a set of k + 1 objects is
// removable when some removable set of k objects, then one more object, works. Every
// last object after every removable set is tried, so every order is reached unless two
// orders of the same set leave the world in different states (only the buffer
// placements differ; the first order found stands for its set).
#include <chrono>
#include <map>
#include <string>
#include <vector>

#include "cluttertamp/plugin/export.hpp"
#include "cluttertamp/plugin/task_planner.hpp"
#include "cluttertamp/retrieval/removal_checker.hpp"

namespace {

using namespace cluttertamp;
using Clock = std::chrono::steady_clock;
using Order = std::vector<ObjectIndex>;
using Set = std::vector<bool>;

class Exhaustive final : public plugin::TaskPlanner {
 public:
  void configure(const Parameters& p) override {
    region_ = p.get_string("region", region_);
    max_removals_ = static_cast<int>(p.get_int("max_removals", max_removals_));
    p.require(max_removals_ >= 0, "max_removals", "must be at least 0");
  }

  Result solve(plugin::PlanningContext& context, const WorldState& initial) override {
    Result result;
    if (auto why = retrieval::retrieval_inputs_missing(context, "exhaustive")) {
      result.reason = *why;
      return result;
    }
    const auto start = Clock::now();
    const ObjectIndex target = context.scene().target;
    const int objects = static_cast<int>(context.scene().objects.size());
    retrieval::RemovalChecker checker(context, initial, region_);
    std::uint64_t sets_checked = 0;

    // Level k: every removable set of k objects with one order that removes it.
    std::map<Set, Order> level{{Set(objects, false), Order{}}};
    int k = 0;
    bool solved = false;
    for (; !level.empty() && !context.deadline.expired(); ++k) {
      for (const auto& [set, order] : level) {
        if (context.deadline.expired()) break;
        ++sets_checked;
        if (checker.retrieve(order).ok) {
          checker.write_plan(order, 0, result);
          solved = true;
          break;
        }
      }
      if (solved || k >= max_removals_) break;
      level = next_level(context, checker, level, target);
    }

    checker.record_times(result, start);
    result.counters["removal_sets_checked"] = sets_checked;
    result.solved = solved;
    if (!solved) {
      const std::string size = std::to_string(k);
      result.reason = context.deadline.expired() ? "time limit reached while checking removal sets of " + size + " objects"
                      : level.empty()            ? "no removal set lets the target out; every removable set was checked"
                                                 : "no removal set of at most " + size + " objects lets the target out";
    }
    return result;
  }

 private:
  // Every removable set one object larger than those of `level`.
  static std::map<Set, Order> next_level(plugin::PlanningContext& context, retrieval::RemovalChecker& checker,
                                         const std::map<Set, Order>& level, ObjectIndex target) {
    std::map<Set, Order> next;
    for (const auto& [set, order] : level) {
      for (ObjectIndex o = 0; o < set.size(); ++o) {
        if (context.deadline.expired()) return next;
        if (o == target || set[o]) continue;
        Set bigger = set;
        bigger[o] = true;
        if (next.count(bigger)) continue;  // already removable in another order
        Order longer = order;
        longer.push_back(o);
        if (checker.remove(longer).ok) next.emplace(std::move(bigger), std::move(longer));
      }
    }
    return next;
  }

  std::string region_ = "buffer";
  int max_removals_ = 1 << 20;
};

}  // namespace

CLUTTERTAMP_EXPORT_TASK_PLANNER(Exhaustive, exhaustive,
                                "Brute force over removal sets and orders, smallest first: the optimal baseline", "0.1.0")
