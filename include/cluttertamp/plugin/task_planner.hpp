#pragma once

#include <string>
#include <vector>

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

  /// The plugin kinds this planner, as configured, cannot plan without (e.g.
  /// "grasp_sampler"; "push_sampler" only when configured to push). Called after
  /// configure(). `plan` and `validate` refuse a problem whose plugins block fills none
  /// of a kind as bad input, before planning. The default: none.
  virtual std::vector<std::string> required_kinds() const;

  /// Checks the inputs this planner reads beside its parameters — files its parameters
  /// name, the scene objects those files name — against `problem`, before planning.
  /// Called after configure(), by `plan` and by `validate` alike, so that what planning
  /// would refuse as bad input `validate` reports first. Throws InputError with every
  /// error located (file:line:column). The default checks nothing.
  virtual void check_inputs(const Problem& problem) const;
};

}  // namespace cluttertamp::plugin

CLUTTERTAMP_PLUGIN_KIND(::cluttertamp::plugin::TaskPlanner, task_planner)

/// Exports CLASS as the task_planner NAME (see CLUTTERTAMP_EXPORT_PLUGIN in export.hpp).
#define CLUTTERTAMP_EXPORT_TASK_PLANNER(CLASS, NAME, DESCRIPTION, VERSION) \
  CLUTTERTAMP_EXPORT_PLUGIN(task_planner, CLASS, NAME, DESCRIPTION, VERSION)
