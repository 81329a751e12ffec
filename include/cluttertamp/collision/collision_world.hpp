#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "cluttertamp/core/scene.hpp"
#include "cluttertamp/core/world_state.hpp"
#include "cluttertamp/export.hpp"
#include "cluttertamp/plugin/world_view.hpp"
#include "cluttertamp/robot/robot_description.hpp"

namespace cluttertamp::collision {

/// Movable objects, sorted by index, without repeats.
using ObjectSet = std::vector<ObjectIndex>;

/// What a robot configuration collides with (the SDK's type, so that a view answers
/// with what the world computes).
using CollisionReport = plugin::Contacts;

/// A robot link (or the held object) touching a fixed body: what "fixed geometry is in
/// the way" means, for messages and diagnosis.
struct FixedContact {
  std::optional<robot::LinkIndex> link;  ///< the robot's link; none: the held object
  std::size_t fixed_body = 0;            ///< index into Scene::fixed
  bool operator==(const FixedContact&) const = default;
};

/// A disc footprint in the shelf plane and the height band it occupies: the target
/// object plus gripper as it moves (Tian et al.: radius r_b). World frame, metres.
struct Footprint {
  double radius = 0.0;
  double z_min = 0.0;
  double z_max = 0.0;
};

/// The robot and the scene's geometry over FCL: fixed bodies and movable objects in
/// separate broadphase managers, robot links with adjacent pairs disabled, and an
/// optionally held object that moves with the tool.
///
/// Changing the world (object poses, removal, attaching) is cheap — no geometry is
/// rebuilt — but must not overlap with queries. Queries are const and may run from
/// several threads at once, each with its own Context.
///
/// Robot configurations are full joint vectors of the robot description's model;
/// the robot's root link stands at Scene::world_T_robot_base.
class CLUTTERTAMP_API CollisionWorld {
 public:
  /// Builds all geometry once. `robot` may be null for a world without a robot
  /// (footprint queries only).
  CollisionWorld(const Scene& scene, std::shared_ptr<const robot::RobotDescription> robot);
  ~CollisionWorld();
  CollisionWorld(const CollisionWorld&) = delete;
  CollisionWorld& operator=(const CollisionWorld&) = delete;

  const Scene& scene() const;
  /// The robot the world was built with; null for a world without a robot.
  const robot::RobotDescription* robot() const;

  // ---- changing the world ---------------------------------------------------------
  void set_object_pose(ObjectIndex object, const Eigen::Isometry3d& world_T_object);
  const Eigen::Isometry3d& object_pose(ObjectIndex object) const;
  /// Takes an object out of the world (e.g. carried away); restore_object puts it back.
  void remove_object(ObjectIndex object);
  void restore_object(ObjectIndex object);
  bool present(ObjectIndex object) const;
  /// The held object travels with the tool link at `tool_T_object`; it no longer
  /// blocks the robot and is checked against everything except the gripper's links.
  void attach(ObjectIndex object, const Eigen::Isometry3d& tool_T_object);
  /// Puts the held object back into the world at `world_T_object`.
  void detach(const Eigen::Isometry3d& world_T_object);
  std::optional<ObjectIndex> held() const;
  /// Poses, removed objects and the held object of `state`; the held object's grip
  /// is taken from its pose relative to the tool at state.robot_configuration.
  void sync(const WorldState& state);
  /// Changes with every call that changes the world (the calls above): a view that
  /// synced at one value knows the world is still at its state while it holds.
  std::uint64_t generation() const;

  // ---- robot queries ----------------------------------------------------------------
  /// Per-thread scratch space: link poses and the robot's FCL objects. Made by
  /// make_context(); usable with the world that made it only.
  class CLUTTERTAMP_API Context {
   public:
    ~Context();
    Context(const Context&) = delete;
    Context& operator=(const Context&) = delete;

   private:
    friend class CollisionWorld;
    Context();
    struct State;
    std::unique_ptr<State> state_;
  };
  std::unique_ptr<Context> make_context() const;

  /// True when the configuration touches nothing: no self collision, fixed body or
  /// movable object (objects in `ignored` excepted). Stops at the first contact.
  bool is_valid(const Eigen::VectorXd& q, Context& context, std::span<const ObjectIndex> ignored = {}) const;
  /// Everything the configuration collides with — the full set of movable objects,
  /// not the first one hit: the robot-obstacle feedback of the retrieval graph.
  CollisionReport check(const Eigen::VectorXd& q, Context& context, std::span<const ObjectIndex> ignored = {}) const;
  /// True when the robot or held object at q touches a present movable object (those
  /// in `ignored` excepted); self and fixed contacts are not looked at. Stops at the
  /// first contact: a cheap test of a known-free path against one more object.
  bool touches_object(const Eigen::VectorXd& q, Context& context, std::span<const ObjectIndex> ignored = {}) const;
  /// The pairs of robot links (lower index first, sorted) in contact at q, among the
  /// pairs the description does not disable: what `cluttertamp self-collisions` counts.
  std::vector<std::pair<std::size_t, std::size_t>> self_contacts(const Eigen::VectorXd& q, Context& context) const;
  /// Every (link, fixed body) pair in contact at q, sorted by link then body (the held
  /// object last), without repeats: which part of the robot is in the way, for messages
  /// and for placing a mobile base. Checks every shape against every fixed body, with
  /// no early exit: cheap for the few fixed bodies of a scene.
  std::vector<FixedContact> fixed_contacts(const Eigen::VectorXd& q, Context& context) const;
  /// "base_link on table, torso_lift_link on table": fixed_contacts in words, or ""
  /// when there are none.
  std::string describe_fixed_contacts(const Eigen::VectorXd& q, Context& context) const;
  /// Smallest distance (m) from the robot and held object to fixed bodies and movable
  /// objects; 0 when touching or overlapping (penetration depth is not computed).
  double min_distance(const Eigen::VectorXd& q, Context& context, std::span<const ObjectIndex> ignored = {}) const;
  /// World pose of the tool link (the description's tip) at q.
  Eigen::Isometry3d tool_pose(const Eigen::VectorXd& q, Context& context) const;

  /// What a shape placed at `world_T_shape` would touch, without changing the world:
  /// fixed geometry, and the full set of present movable objects (a placement check).
  /// Thread-safe.
  CollisionReport shape_contacts(const Shape& shape, const Eigen::Isometry3d& world_T_shape,
                                 std::span<const ObjectIndex> ignored = {}) const;

  // ---- footprint queries (analytic, in the shelf plane) --------------------------------
  /// Col(x): movable objects a footprint centred at `centre` overlaps.
  ObjectSet footprint_objects(const Eigen::Vector2d& centre, const Footprint& footprint,
                              std::span<const ObjectIndex> ignored = {}) const;
  /// EdgeCol(x, x'): movable objects the footprint sweeps through moving in a straight
  /// line from `from` to `to`. Exact for upright cylinders, spheres and boxes rotated
  /// about z; other objects count by their axis-aligned bounding rectangle.
  ObjectSet swept_objects(const Eigen::Vector2d& from, const Eigen::Vector2d& to, const Footprint& footprint,
                          std::span<const ObjectIndex> ignored = {}) const;
  /// True when the swept footprint touches fixed geometry in its height band.
  bool sweep_hits_fixed(const Eigen::Vector2d& from, const Eigen::Vector2d& to, const Footprint& footprint) const;
  /// Distance (m) in the plane from `centre` to the nearest fixed geometry in the
  /// footprint's height band (its radius is not subtracted); infinity when there is none.
  double fixed_clearance(const Eigen::Vector2d& centre, const Footprint& footprint) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace cluttertamp::collision
