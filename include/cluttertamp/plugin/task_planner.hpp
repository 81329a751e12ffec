#pragma once

#include "cluttertamp/core/result.hpp"
#include "cluttertamp/plugin/context.hpp"
#include "cluttertamp/plugin/plugin.hpp"

namespace cluttertamp::plugin {

/// Solves a whole task (e.g. a retrieval) and returns the plan with every motion.
class CLUTTERTAMP_API TaskPlanner : public Plugin {
 public:
  ~TaskPlanner() override;

  /// Plans from `initial` until solved or `context.deadline` expires. Failure to
  /// find a plan is a Result with solved = false and a reason, not an exception.
  virtual Result solve(PlanningContext& context, const WorldState& initial) = 0;
};

template <>
struct KindOf<TaskPlanner> {
  static constexpr Kind value = Kind::task_planner;
};

}  // namespace cluttertamp::plugin
