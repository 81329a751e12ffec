// Views of the run's one CollisionWorld: each syncs the world to its own state
// whenever something else changed it since, so no caller depends on where another
// left it.
#include "cluttertamp/collision/shared_world.hpp"

#include <optional>
#include <stdexcept>
#include <string>
#include <utility>

#include "cluttertamp/robot/robot_description.hpp"

namespace cluttertamp::collision {
namespace {

class SyncedView final : public plugin::WorldView {
 public:
  struct Grip {
    ObjectIndex object;
    Eigen::Isometry3d gripper_T_object;
  };

  SyncedView(CollisionWorld& world, WorldState state, std::optional<Grip> grip,
             std::shared_ptr<CollisionWorld::Context> checker)
      : world_(world), state_(std::move(state)), grip_(std::move(grip)), checker_(std::move(checker)) {}
  // A view that queried the world leaves it at its state (one only asked for tool
  // poses never touched it). A sync that fails here (it failed for the view's queries
  // too, and that error is already on its way) is not thrown twice.
  ~SyncedView() override {
    if (!synced_at_) return;
    try {
      ensure();
    } catch (...) {
    }
  }

  const WorldState& state() const override { return state_; }

  Eigen::Isometry3d tool_pose(const Eigen::VectorXd& q) const override { return world_.tool_pose(q, *checker_); }
  std::vector<Eigen::VectorXd> inverse_kinematics(const Eigen::Isometry3d& world_T_tool,
                                                  const Eigen::VectorXd& seed) const override {
    return robot().ik().solve(robot().world_T_ik_base(world_.scene().world_T_robot_base).inverse() * world_T_tool, seed);
  }
  bool is_valid(const Eigen::VectorXd& q, std::span<const ObjectIndex> ignored) const override {
    ensure();
    return world_.is_valid(q, *checker_, ignored);
  }
  plugin::Contacts contacts(const Eigen::VectorXd& q, std::span<const ObjectIndex> ignored) const override {
    ensure();
    return world_.check(q, *checker_, ignored);
  }
  bool touches_object(const Eigen::VectorXd& q, std::span<const ObjectIndex> ignored) const override {
    ensure();
    return world_.touches_object(q, *checker_, ignored);
  }
  double min_distance(const Eigen::VectorXd& q, std::span<const ObjectIndex> ignored) const override {
    ensure();
    return world_.min_distance(q, *checker_, ignored);
  }
  std::string describe_fixed_contacts(const Eigen::VectorXd& q) const override {
    ensure();
    return world_.describe_fixed_contacts(q, *checker_);
  }
  plugin::Contacts shape_contacts(const Shape& shape, const Eigen::Isometry3d& world_T_shape,
                                  std::span<const ObjectIndex> ignored) const override {
    ensure();
    return world_.shape_contacts(shape, world_T_shape, ignored);
  }
  std::unique_ptr<plugin::WorldView> holding(ObjectIndex object, const Eigen::Isometry3d& gripper_T_object) const override {
    return std::make_unique<SyncedView>(world_, state_, Grip{object, gripper_T_object}, checker_);
  }

  const CollisionWorld& synced() const {
    ensure();
    return world_;
  }
  CollisionWorld::Context& checker() const { return *checker_; }

 private:
  const robot::RobotDescription& robot() const { return *world_.robot(); }

  // Syncs the world to this view's state unless nothing changed it since this view did.
  void ensure() const {
    if (synced_at_ && *synced_at_ == world_.generation()) return;
    world_.sync(state_);
    if (grip_) {
      if (world_.held()) world_.detach(state_.world_T_objects.at(*world_.held()));
      world_.attach(grip_->object, grip_->gripper_T_object);
    }
    synced_at_ = world_.generation();
  }

  CollisionWorld& world_;
  WorldState state_;
  std::optional<Grip> grip_;
  std::shared_ptr<CollisionWorld::Context> checker_;
  mutable std::optional<std::uint64_t> synced_at_;
};

const SyncedView& as_synced(const plugin::WorldView& view) {
  const auto* synced = dynamic_cast<const SyncedView*>(&view);
  if (!synced) throw std::logic_error("this WorldView does not come from a collision::SharedWorld");
  return *synced;
}

}  // namespace

SharedWorld::SharedWorld(const Scene& scene, std::shared_ptr<const robot::RobotDescription> robot)
    : world_(std::make_unique<CollisionWorld>(scene, std::move(robot))) {}
SharedWorld::~SharedWorld() = default;

std::unique_ptr<plugin::WorldView> SharedWorld::at(const WorldState& state) {
  const std::size_t objects = world_->scene().objects.size();
  if (state.world_T_objects.size() != objects || state.removed.size() != objects) {
    throw std::invalid_argument("a WorldState of " + std::to_string(state.world_T_objects.size()) + " poses and " +
                                std::to_string(state.removed.size()) + " removed flags for a scene of " +
                                std::to_string(objects) + " objects");
  }
  return std::make_unique<SyncedView>(*world_, state, std::nullopt, checker());
}

std::shared_ptr<CollisionWorld::Context> SharedWorld::checker() {
  std::unique_ptr<CollisionWorld::Context> spare;
  if (spare_checkers_.empty()) {
    spare = world_->make_context();
  } else {
    spare = std::move(spare_checkers_.back());
    spare_checkers_.pop_back();
  }
  return {spare.release(), [this](CollisionWorld::Context* c) { spare_checkers_.emplace_back(c); }};
}

CollisionWorld* shared_world(const plugin::PlanningContext& context) {
  auto* shared = dynamic_cast<SharedWorld*>(context.worlds);
  return shared ? &shared->world() : nullptr;
}

const CollisionWorld& synced_world(const plugin::WorldView& view) { return as_synced(view).synced(); }
CollisionWorld::Context& view_checker(const plugin::WorldView& view) { return as_synced(view).checker(); }

}  // namespace cluttertamp::collision
