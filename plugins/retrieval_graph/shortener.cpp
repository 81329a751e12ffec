#include "shortener.hpp"

#include <algorithm>

namespace cluttertamp::retrieval_graph_plugin {

using retrieval::ObjectSet;

Shortener::Shortener(plugin::PlanningContext& context, retrieval::RemovalChecker& checker, const WorldState& initial,
                     std::int64_t max_checks, int grasp_orders)
    : context_(context), checker_(checker), initial_(initial), max_checks_(max_checks), grasp_orders_(grasp_orders) {}

std::uint64_t Shortener::per_try() const { return static_cast<std::uint64_t>(std::max<std::int64_t>(max_checks_, 0)); }

// A working removal order with every object dropped that the target comes out
// without (last first; each try reuses the checked prefix): the graph's sequence
// can hold objects only an earlier, failed way needed. Each try gets at most
// `shorten_max_checks` collision checks: dropping is an improvement, not worth a long
// motion search.
// When that dropped something, the order mixed two ways out, and what is left of one
// may work only in another order: a second pass tries each drop with the rest
// ordered nearest the exit first (on Table VI's min4 shelf a run moved o5 and o15 of
// one way out and then o1, o9, o10 of the other, which works only front first).
// Then, with `grasp_orders`, grasp_order.
ObjectSet Shortener::shortened(ObjectSet order, std::uint64_t reseeds, const GraspBlockers& grasp_blockers,
                               Result& result) {
  struct Restore {  // the run's own budget back, however this returns
    plugin::PlanningContext& context;
    std::uint64_t checks_until;
    ~Restore() { context.checks_until = checks_until; }
  } restore{context_, context_.checks_until};
  const plugin::PlanningContext run = context_;
  std::uint64_t dropped = 0;
  std::set<ObjectSet> tried;
  auto drop_pass = [&](bool exit_first) {
    for (std::size_t i = order.size(); i-- > 0 && !run.stopped();) {
      ObjectSet shorter = order;
      shorter.erase(shorter.begin() + static_cast<std::ptrdiff_t>(i));
      if (exit_first) nearest_exit_first(shorter);
      if (!tried.insert(shorter).second) continue;
      context_.checks_until = run.with_checks(per_try()).checks_until;
      if (checker_.retrieve(shorter, reseeds).ok) {
        order = std::move(shorter);
        ++dropped;
        if (exit_first) i = order.size();  // a new order: every object may go now
      }
    }
  };
  drop_pass(false);
  if (dropped > 0) drop_pass(true);
  result.counters[counter::removals_dropped] = dropped;
  if (grasp_orders_ > 0) {
    result.counters[counter::grasp_orders_taken] = grasp_order(order, tried, reseeds, grasp_blockers, run) ? 1 : 0;
  }
  return order;
}

// Replaces `order` by the blockers of one of the target's own freeable grasps in the
// initial state when they alone let the target out: true when it did. The graph's
// footprint path counts objects a carry may lift the target over (a table has no
// board above), so one grasp's blockers can be fewer than the graph's way (on bench
// mobile tables, one object where the way had two). At most `grasp_orders` distinct
// sets not `tried` yet, each smaller than `order`, fewest objects first (the
// sampler's order among equals), each set nearest x_s first, each within
// `shorten_max_checks` per object plus one. Off by default: in shelves the carry
// cannot lift the target over anything, and the failed tries cost Table I's shelf20
// a median of 1.3 s instead of 0.2 s. `run`: the run's context, with its own budget.
bool Shortener::grasp_order(ObjectSet& order, std::set<ObjectSet>& tried, std::uint64_t reseeds,
                            const GraspBlockers& grasp_blockers, const plugin::PlanningContext& run) {
  if (order.size() < 2 || run.stopped()) return false;  // no smaller set would remove anything
  int tries = 0;
  for (ObjectSet set : grasp_blockers()) {
    if (set.size() >= order.size() || tries >= grasp_orders_ || run.stopped()) break;
    nearest_exit_first(set);
    if (!tried.insert(set).second) continue;
    ++tries;
    const std::uint64_t per_object = per_try(), objects = set.size() + 1;
    const std::uint64_t budget = per_object > ~std::uint64_t{0} / objects ? ~std::uint64_t{0} : per_object * objects;
    context_.checks_until = run.with_checks(budget).checks_until;
    if (checker_.retrieve(set, reseeds).ok) {
      order = std::move(set);
      return true;
    }
  }
  return false;
}

// Sorts `objects` by the distance of their initial positions from the exit x_s (in
// the shelf's plane), nearest first; ties keep their order.
void Shortener::nearest_exit_first(ObjectSet& objects) const {
  const Eigen::Vector2d exit = context_.scene().world_T_exit.translation().head<2>();
  auto distance = [&](ObjectIndex o) { return (initial_.world_T_objects[o].translation().head<2>() - exit).norm(); };
  std::stable_sort(objects.begin(), objects.end(), [&](ObjectIndex a, ObjectIndex b) { return distance(a) < distance(b); });
}

}  // namespace cluttertamp::retrieval_graph_plugin
