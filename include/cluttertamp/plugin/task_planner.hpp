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

}  // namespace cluttertamp::plugin

CLUTTERTAMP_PLUGIN_KIND(::cluttertamp::plugin::TaskPlanner, task_planner)

/// Exports CLASS as the task_planner NAME (see CLUTTERTAMP_EXPORT_PLUGIN in export.hpp).
#define CLUTTERTAMP_EXPORT_TASK_PLANNER(CLASS, NAME, DESCRIPTION, VERSION) \
  CLUTTERTAMP_EXPORT_PLUGIN(task_planner, CLASS, NAME, DESCRIPTION, VERSION)
