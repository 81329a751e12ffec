#pragma once

#include <vector>

#include "cluttertamp/core/result.hpp"
#include "cluttertamp/plugin/context.hpp"
#include "cluttertamp/plugin/plugin.hpp"

namespace cluttertamp::plugin {

/// The objects a symbolic search should treat as movable; all others become fixed.
struct PruneAnswer {
  /// Candidate removal orders, best first. Empty with a failure when none was found.
  std::vector<std::vector<ObjectIndex>> removal_sequences;
  std::optional<Failure> failure;

  /// Every object in any sequence, sorted and without repeats.
  std::vector<ObjectIndex> movable_objects() const;
};

/// Narrows the objects a task planner must consider (focused planning).
class CLUTTERTAMP_API ObjectPruner : public Plugin {
 public:
  ~ObjectPruner() override;
  virtual PruneAnswer prune(PlanningContext& context, const WorldState& state) = 0;
};

}  // namespace cluttertamp::plugin

CLUTTERTAMP_PLUGIN_KIND(::cluttertamp::plugin::ObjectPruner, object_pruner)

/// Exports CLASS as the object_pruner NAME (see CLUTTERTAMP_EXPORT_PLUGIN in export.hpp).
#define CLUTTERTAMP_EXPORT_OBJECT_PRUNER(CLASS, NAME, DESCRIPTION, VERSION) \
  CLUTTERTAMP_EXPORT_PLUGIN(object_pruner, CLASS, NAME, DESCRIPTION, VERSION)
