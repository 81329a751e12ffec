#pragma once
// The retrieval planner's last step before a plan: a removal order that works, made
// shorter where the robot can do without some of its removals.

#include <cstdint>
#include <functional>
#include <set>
#include <vector>

#include "cluttertamp/core/result.hpp"
#include "cluttertamp/core/world_state.hpp"
#include "cluttertamp/plugin/context.hpp"
#include "cluttertamp/retrieval/removal_checker.hpp"
#include "cluttertamp/retrieval/retrieval_graph.hpp"

namespace cluttertamp::retrieval_graph_plugin {

/// Drops removals from an order the robot checked (each try checked again with the
/// robot from the initial state, within its own work budget), first in the order's
/// own order, then — when one went — nearest the exit x_s first; optionally replaces
/// the order by the blockers of one of the target's own grasps when they alone let it
/// out. Deterministic: tries and budgets are counted in collision checks.
class Shortener {
 public:
  /// The distinct sets of removable objects blocking the target's freeable grasps in
  /// the initial state, fewest objects first.
  using GraspBlockers = std::function<std::vector<retrieval::ObjectSet>()>;

  /// `max_checks`: collision checks per try (per object and one more for a grasp's
  /// set); `grasp_orders`: at most this many grasp sets tried (0: none). Every
  /// reference must outlive the shortener.
  Shortener(plugin::PlanningContext& context, retrieval::RemovalChecker& checker, const WorldState& initial,
            std::int64_t max_checks, int grasp_orders);

  /// The shortest order found from `order`; `reseeds` seeds the checks as the
  /// planner's own. Counts `removals_dropped` and `grasp_orders_taken` into `result`.
  /// The context's work budget is the same afterwards as before.
  retrieval::ObjectSet shortened(retrieval::ObjectSet order, std::uint64_t reseeds, const GraspBlockers& grasp_blockers,
                                 Result& result);

 private:
  bool grasp_order(retrieval::ObjectSet& order, std::set<retrieval::ObjectSet>& tried, std::uint64_t reseeds,
                   const GraspBlockers& grasp_blockers, const plugin::PlanningContext& run);
  void nearest_exit_first(retrieval::ObjectSet& objects) const;
  std::uint64_t per_try() const;

  plugin::PlanningContext& context_;
  retrieval::RemovalChecker& checker_;
  const WorldState& initial_;
  std::int64_t max_checks_;
  int grasp_orders_;
};

}  // namespace cluttertamp::retrieval_graph_plugin
