#pragma once

#include <memory>
#include <vector>

#include "cluttertamp/collision/collision_world.hpp"
#include "cluttertamp/export.hpp"
#include "cluttertamp/plugin/context.hpp"
#include "cluttertamp/plugin/world_view.hpp"

namespace cluttertamp::collision {

/// The one CollisionWorld of a run, handed to plugins as views at a state
/// (plugin::WorldView). Each view remembers the world's generation after it synced it
/// and syncs again before a query whenever anything changed the world since, so views
/// of different states may be used in turn. A view that queried the world leaves it at
/// the view's state when it is destroyed.
class CLUTTERTAMP_API SharedWorld final : public plugin::WorldSource {
 public:
  /// Builds the world once (see CollisionWorld). `robot` must not be null. Every view
  /// must be gone before the SharedWorld is.
  SharedWorld(const Scene& scene, std::shared_ptr<const robot::RobotDescription> robot);
  ~SharedWorld() override;

  /// Throws std::invalid_argument for a state whose poses or removed flags do not
  /// match the scene's objects.
  std::unique_ptr<plugin::WorldView> at(const WorldState& state) override;

  /// The world itself, for planners above the SDK that move objects about on their
  /// own (they sync it before use: a sampler's view may have changed it).
  CollisionWorld& world() { return *world_; }

 private:
  std::shared_ptr<CollisionWorld::Context> checker();

  std::unique_ptr<CollisionWorld> world_;
  // Scratch spaces of views gone, for the next views: each holds a copy of every robot
  // shape, too costly to make for every query.
  std::vector<std::unique_ptr<CollisionWorld::Context>> spare_checkers_;
};

/// The run's CollisionWorld behind `context.worlds`, or null when the run has none
/// (no robot) or its views come from another source. The caller syncs it before use.
CLUTTERTAMP_API CollisionWorld* shared_world(const plugin::PlanningContext& context);

/// The CollisionWorld behind a view of a SharedWorld, synced to the view's state, and
/// the view's scratch space for queries: for code that needs more than the view offers
/// (fixed and self contacts, footprints). Valid until another view is queried or the
/// world is changed. Throws std::logic_error for a view of another source.
CLUTTERTAMP_API const CollisionWorld& synced_world(const plugin::WorldView& view);
CLUTTERTAMP_API CollisionWorld::Context& view_checker(const plugin::WorldView& view);

}  // namespace cluttertamp::collision
