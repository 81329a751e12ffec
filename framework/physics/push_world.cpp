#include "cluttertamp/physics/push_world.hpp"

#include <algorithm>
#include <cmath>
#include <mutex>
#include <set>
#include <stdexcept>
#include <variant>

#include <btBulletDynamicsCommon.h>
#include <BulletCollision/CollisionDispatch/btManifoldResult.h>

namespace cluttertamp::physics {

namespace {

constexpr double kGravity = 9.81;  // m/s^2
// Contacts deeper than this between the gripper and fixed geometry count as a hit (m):
// grazing a wall is contact, entering it is not.
constexpr double kFixedPenetration = 0.002;
// Below these an object is at rest at the end of a control (m/s, rad/s).
constexpr double kAtRestSpeed = 0.01;
constexpr double kAtRestTurn = 0.1;

std::unique_ptr<btCollisionShape> make_shape(const Shape& shape) {
  return std::visit(
      [](const auto& s) -> std::unique_ptr<btCollisionShape> {
        using T = std::decay_t<decltype(s)>;
        if constexpr (std::is_same_v<T, Box>) {
          return std::make_unique<btBoxShape>(btVector3(btScalar(s.size.x() / 2), btScalar(s.size.y() / 2), btScalar(s.size.z() / 2)));
        } else if constexpr (std::is_same_v<T, Cylinder>) {
          return std::make_unique<btCylinderShapeZ>(btVector3(btScalar(s.radius), btScalar(s.radius), btScalar(s.height / 2)));
        } else {
          return std::make_unique<btSphereShape>(btScalar(s.radius));
        }
      },
      shape);
}

// A body that may tip stands on its whole base only if its contacts are clipped face
// against face: Bullet gives a curved shape one contact point per pair and step, which
// rocks an upright cylinder until it walks across the board. So such bodies collide as
// polyhedra: a cylinder as a prism of kPrismSides sides (its radius off by at most
// 1 - cos(pi / kPrismSides), 0.9 %), a box with its faces.
constexpr int kPrismSides = 24;
std::unique_ptr<btCollisionShape> make_polyhedron(const Shape& shape) {
  if (const auto* c = std::get_if<Cylinder>(&shape)) {
    // Bullet grows a hull by its margin: the points inset by it, the prism is the cylinder.
    constexpr double margin = 0.001;
    auto prism = std::make_unique<btConvexHullShape>();
    for (int k = 0; k < kPrismSides; ++k) {
      const double a = 2 * M_PI * k / kPrismSides, r = c->radius - margin;
      for (const double z : {-c->height / 2 + margin, c->height / 2 - margin}) {
        prism->addPoint(btVector3(btScalar(r * std::cos(a)), btScalar(r * std::sin(a)), btScalar(z)), false);
      }
    }
    prism->recalcLocalAabb();
    prism->setMargin(btScalar(margin));
    prism->initializePolyhedralFeatures();
    return prism;
  }
  std::unique_ptr<btCollisionShape> made = make_shape(shape);
  if (auto* box = dynamic_cast<btBoxShape*>(made.get())) box->initializePolyhedralFeatures();
  return made;
}

btTransform bt(const Eigen::Isometry3d& pose) {
  const Eigen::Quaterniond q(pose.rotation());
  const Eigen::Vector3d& t = pose.translation();
  return btTransform(btQuaternion(btScalar(q.x()), btScalar(q.y()), btScalar(q.z()), btScalar(q.w())),
                     btVector3(btScalar(t.x()), btScalar(t.y()), btScalar(t.z())));
}

btTransform planar(const Eigen::Vector3d& pose, double z) {
  btQuaternion q;
  q.setRotation(btVector3(0, 0, 1), btScalar(pose.z()));
  return btTransform(q, btVector3(btScalar(pose.x()), btScalar(pose.y()), btScalar(z)));
}

double yaw_of(const btTransform& t) {
  const btVector3 x = t.getBasis().getColumn(0);
  return std::atan2(double(x.y()), double(x.x()));
}

double bottom_of(const Shape& shape, const Eigen::Isometry3d& pose) { return world_bounds(shape, pose).min().z(); }

// Bodies marked so (user index 2) combine their friction coefficients by the larger
// (MuJoCo's rule); any other pair as Bullet does, by the product clamped to 10.
constexpr int kMaxFriction = 0x6d6178;
btScalar combined_friction(const btCollisionObject* a, const btCollisionObject* b) {
  const btScalar fa = a->getFriction(), fb = b->getFriction();
  if (a->getUserIndex2() == kMaxFriction && b->getUserIndex2() == kMaxFriction) return std::max(fa, fb);
  return std::clamp(fa * fb, btScalar(-10), btScalar(10));
}
// Torsional friction of an object sliding on its base: a torque up to the contact's
// friction times its normal force times the object's spin radius (its spinning
// friction; (2/3) r for a disc of radius r under even pressure). Without it Bullet spins
// a sliding cylinder up from its few contact points and leaves it drifting.
btScalar combined_spinning_friction(const btCollisionObject* a, const btCollisionObject* b) {
  return std::clamp((a->getSpinningFriction() + b->getSpinningFriction()) * combined_friction(a, b), btScalar(0), btScalar(10));
}
// Bullet's rules are globals; ours keep its results for unmarked bodies without spin radii.
void install_friction_rule() {
  static std::once_flag once;
  std::call_once(once, [] {
    gCalculateCombinedFrictionCallback = &combined_friction;
    gCalculateCombinedSpinningFrictionCallback = &combined_spinning_friction;
  });
}

// The convex hull of a part's points, or its primitive.
std::unique_ptr<btCollisionShape> make_part_shape(const PusherPart& part) {
  if (part.hull.empty()) return make_shape(part.shape);
  auto hull = std::make_unique<btConvexHullShape>();
  for (const Eigen::Vector3d& v : part.hull) hull->addPoint(btVector3(btScalar(v.x()), btScalar(v.y()), btScalar(v.z())), false);
  hull->recalcLocalAabb();
  hull->optimizeConvexHull();
  hull->setMargin(btScalar(0.001));  // Bullet's default 4 cm would inflate the hull
  return hull;
}

// The corners of a part in the pusher's frame: of its hull, or of its primitive's bounds.
std::vector<Eigen::Vector3d> part_points(const PusherPart& part) {
  std::vector<Eigen::Vector3d> points;
  if (!part.hull.empty()) {
    for (const Eigen::Vector3d& v : part.hull) points.push_back(part.frame_T_part * v);
    return points;
  }
  const Eigen::AlignedBox3d box = world_bounds(part.shape, Eigen::Isometry3d::Identity());
  for (int corner = 0; corner < 8; ++corner) {
    points.push_back(part.frame_T_part * box.corner(static_cast<Eigen::AlignedBox3d::CornerType>(corner)));
  }
  return points;
}

// The largest force (N) on one point of a contact in the step just taken: the impulses
// the solver applied, normal and along both friction directions, over the step.
double contact_force(const btPersistentManifold& contact, double dt) {
  double largest = 0;
  for (int p = 0; p < contact.getNumContacts(); ++p) {
    const btManifoldPoint& point = contact.getContactPoint(p);
    const double impulse = std::hypot(double(point.getAppliedImpulse()), double(point.m_appliedImpulseLateral1),
                                      double(point.m_appliedImpulseLateral2));
    largest = std::max(largest, impulse / dt);
  }
  return largest;
}

Eigen::Vector3d compose(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  const double c = std::cos(a.z()), s = std::sin(a.z());
  return {a.x() + c * b.x() - s * b.y(), a.y() + s * b.x() + c * b.y(), std::remainder(a.z() + b.z(), 2 * M_PI)};
}

}  // namespace

struct PushWorld::Impl {
  const Scene& scene;
  PushSettings settings;
  std::vector<bool> present = {};  // per scene object
  std::vector<Eigen::Isometry3d> initial_pose = {};  // per scene object: heights and footprints come from it
  std::vector<ObjectIndex> pushable = {};
  Eigen::AlignedBox2d support = {};
  double plane = 0;           // the gripper's bottom, m
  double frame_z = 0;         // the pusher's frame, m
  std::vector<PusherPart> parts = {};                   // in the pusher's frame
  Eigen::Vector3d frame_T_hand = Eigen::Vector3d::Zero();  // planar
  double hand_face = 0;       // m
  double hand_half_width = 0; // m
  std::vector<std::unique_ptr<btCollisionShape>> fixed_shapes = {}, object_shapes = {};
  std::vector<std::unique_ptr<btCollisionShape>> pusher_children = {};  // the parts of pusher_shape
  std::unique_ptr<btCompoundShape> pusher_shape = nullptr;
  std::vector<btVector3> inertia = {};  // per object, for its mass
  std::vector<double> mass = {}, friction = {}, spin_radius = {};  // per object
  std::vector<double> fixed_friction = {};      // per fixed body
  std::vector<bool> wall = {};                  // per fixed body: not a board the objects stand on

  // A sphere would roll, not tip: it keeps sliding as without a tip limit.
  bool may_tip(std::size_t object) const {
    return settings.tip_limit && !std::holds_alternative<Sphere>(scene.objects[object].shape);
  }

  void make_gripper(double support_top);
  void make_arm(double support_top);
  void set_friction(btCollisionObject& body, double coefficient) const {
    body.setFriction(btScalar(coefficient));
    if (settings.friction_combine == PushSettings::FrictionCombine::max) body.setUserIndex2(kMaxFriction);
  }

  // One simulation, built afresh per propagation: Bullet keeps contact caches and
  // solver warm starts between steps, so reusing a world would make the outcome depend
  // on what was simulated before.
  struct Simulation {
    // Small pools (Bullet allocates beyond them on the heap): the default 4096-entry
    // pools were cleared on every construction, 40 % of a kinodynamic planner's time.
    static btDefaultCollisionConstructionInfo small_pools() {
      btDefaultCollisionConstructionInfo info;
      info.m_defaultMaxPersistentManifoldPoolSize = 128;
      info.m_defaultMaxCollisionAlgorithmPoolSize = 128;
      return info;
    }
    btDefaultCollisionConfiguration configuration{small_pools()};
    btCollisionDispatcher dispatcher{&configuration};
    btDbvtBroadphase broadphase;
    btSequentialImpulseConstraintSolver solver;
    btDiscreteDynamicsWorld world{&dispatcher, &broadphase, &solver, &configuration};
    std::vector<std::unique_ptr<btDefaultMotionState>> states;
    std::vector<std::unique_ptr<btRigidBody>> bodies;
    std::vector<btRigidBody*> objects;  // per scene object, null when absent
    btRigidBody* gripper = nullptr;
    std::set<const btCollisionObject*> fixed;
    std::set<const btCollisionObject*> walls;  // of `fixed`

    ~Simulation() {
      for (auto it = bodies.rbegin(); it != bodies.rend(); ++it) world.removeRigidBody(it->get());
    }

    btRigidBody* add(btCollisionShape* shape, const btTransform& pose, double mass, const btVector3& inertia,
                     bool kinematic = false) {
      states.push_back(std::make_unique<btDefaultMotionState>(pose));
      btRigidBody::btRigidBodyConstructionInfo info(btScalar(mass), states.back().get(), shape, inertia);
      bodies.push_back(std::make_unique<btRigidBody>(info));
      btRigidBody* body = bodies.back().get();
      if (kinematic) {
        // Moved by us, step by step; it meets fixed geometry too (Bullet's default
        // filter keeps kinematic and static bodies apart), to tell when it enters a wall.
        body->setCollisionFlags(body->getCollisionFlags() | btCollisionObject::CF_KINEMATIC_OBJECT);
        body->setActivationState(DISABLE_DEACTIVATION);
        world.addRigidBody(body, btBroadphaseProxy::KinematicFilter, btBroadphaseProxy::AllFilter);
      } else {
        world.addRigidBody(body);
      }
      return body;
    }
  };
};

Eigen::AlignedBox2d support_region(const Scene& scene, const WorldState& state, const PushSettings& settings) {
  const ObjectIndex target = scene.target;
  const double support_top = bottom_of(scene.objects.at(target).shape, state.world_T_objects.at(target));
  const double plane = support_top + settings.gripper_clearance;
  Eigen::AlignedBox2d support;
  const Eigen::Vector2d target_xy = state.world_T_objects.at(target).translation().head<2>();
  for (const FixedBody& f : scene.fixed) {
    const Eigen::AlignedBox3d b = world_bounds(f.shape, f.world_T_body);
    const Eigen::AlignedBox2d board(b.min().head<2>(), b.max().head<2>());
    if (std::abs(b.max().z() - support_top) < 0.01 && board.contains(target_xy)) support.extend(board);
  }
  if (support.isEmpty()) support = Eigen::AlignedBox2d(scene.workspace.min().head<2>(), scene.workspace.max().head<2>());
  // Walls standing on the support cut it back: of the four ways to cut a wall's
  // footprint off, keep the one that leaves the most room about the target.
  for (const FixedBody& f : scene.fixed) {
    const Eigen::AlignedBox3d b = world_bounds(f.shape, f.world_T_body);
    const Eigen::AlignedBox2d wall(b.min().head<2>(), b.max().head<2>());
    if (b.max().z() < support_top + 0.005 || b.min().z() > plane + settings.gripper_size.z() ||
        support.intersection(wall).isEmpty() || wall.contains(target_xy)) {
      continue;
    }
    Eigen::AlignedBox2d best = support;
    double best_area = -1;
    for (int axis = 0; axis < 2; ++axis) {
      for (const bool below : {true, false}) {
        Eigen::AlignedBox2d cut = support;
        if (below) cut.max()[axis] = std::min(cut.max()[axis], wall.min()[axis]);
        else cut.min()[axis] = std::max(cut.min()[axis], wall.max()[axis]);
        if (!cut.isEmpty() && cut.contains(target_xy) && cut.volume() > best_area) {
          best = cut;
          best_area = cut.volume();
        }
      }
    }
    if (best_area >= 0) support = best;
  }
  return support;
}

std::vector<GripperBox> gripper_boxes(const PushSettings& settings) {
  const Eigen::Vector3d& palm = settings.gripper_size;
  std::vector<GripperBox> boxes{{palm, Eigen::Vector2d::Zero()}};
  if (settings.finger_length > 0) {
    const Eigen::Vector3d finger(settings.finger_length, settings.finger_width, palm.z());
    for (const double side : {1.0, -1.0}) {
      boxes.push_back({finger, {palm.x() / 2 + settings.finger_length / 2, side * (palm.y() - settings.finger_width) / 2}});
    }
  }
  return boxes;
}

void PushWorld::Impl::make_gripper(double support_top) {
  plane = support_top + settings.gripper_clearance;
  frame_z = plane + settings.gripper_size.z() / 2;
  for (const GripperBox& box : gripper_boxes(settings)) {
    parts.push_back({Box{box.size}, Eigen::Isometry3d(Eigen::Translation3d(box.offset.x(), box.offset.y(), 0)), {}});
  }
  hand_face = settings.gripper_size.x() / 2;
  hand_half_width = settings.gripper_size.y() / 2;
}

// The arm's parts in the mobile base's frame; the hand's tool centre point at
// hand_height above the support (by default its lowest point at gripper_clearance).
void PushWorld::Impl::make_arm(double support_top) {
  const ArmPusher& arm = *settings.arm;
  if (arm.parts.empty() || arm.hand.size() != arm.parts.size()) throw std::invalid_argument("PushWorld: an arm needs parts, each marked hand or not");
  const Eigen::Isometry3d base_T_arm(Eigen::Translation3d(arm.base_offset.x(), arm.base_offset.y(), 0));
  const Eigen::Isometry3d base_T_tcp = base_T_arm * arm.arm_T_tcp;
  const Eigen::Vector3d approach = base_T_tcp.linear().col(2);
  if (approach.head<2>().norm() < 0.1) throw std::invalid_argument("PushWorld: the arm's posture points its tool up or down; it cannot push in the plane");
  const Eigen::Vector2d heading = approach.head<2>().normalized();
  frame_T_hand = {base_T_tcp.translation().x(), base_T_tcp.translation().y(), std::atan2(heading.y(), heading.x())};
  double lowest = std::numeric_limits<double>::infinity();
  hand_face = 0;
  for (std::size_t i = 0; i < arm.parts.size(); ++i) {
    PusherPart part = arm.parts[i];
    part.frame_T_part = base_T_arm * part.frame_T_part;
    if (arm.hand[i]) {
      for (const Eigen::Vector3d& p : part_points(part)) {
        const Eigen::Vector2d from_tcp = p.head<2>() - base_T_tcp.translation().head<2>();
        lowest = std::min(lowest, p.z());
        hand_face = std::max(hand_face, from_tcp.dot(heading));
        hand_half_width = std::max(hand_half_width, std::abs(from_tcp.dot(Eigen::Vector2d(-heading.y(), heading.x()))));
      }
    }
    parts.push_back(std::move(part));
  }
  if (!std::isfinite(lowest)) lowest = base_T_tcp.translation().z();
  const double tcp_above_lowest = base_T_tcp.translation().z() - lowest;
  const double hand_height = settings.hand_height.value_or(settings.gripper_clearance + tcp_above_lowest);
  frame_z = support_top + hand_height - base_T_tcp.translation().z();
  plane = support_top + hand_height - tcp_above_lowest;
}

PushWorld::PushWorld(const Scene& scene, const WorldState& initial, PushSettings settings)
    : impl_(std::make_unique<Impl>(Impl{scene, settings})) {
  Impl& w = *impl_;
  if (!(settings.time_step > 0)) throw std::invalid_argument("PushWorld: time_step must be positive");
  if (settings.finger_length < 0 || !(settings.finger_width > 0) || 2 * settings.finger_width >= settings.gripper_size.y()) {
    throw std::invalid_argument("PushWorld: fingers need a length >= 0 and a width > 0 that leaves a gap between them");
  }
  if (!(settings.yaw_limits.x() <= settings.yaw_limits.y())) throw std::invalid_argument("PushWorld: yaw limits need min <= max");
  install_friction_rule();
  for (const FixedBody& f : scene.fixed) {
    w.fixed_shapes.push_back(settings.tip_limit ? make_polyhedron(f.shape) : make_shape(f.shape));
    w.fixed_friction.push_back(settings.fixed_friction.value_or(f.friction));
  }
  for (std::size_t i = 0; i < scene.objects.size(); ++i) {
    const SceneObject& o = scene.objects[i];
    w.present.push_back(!initial.removed.at(i));
    w.initial_pose.push_back(initial.world_T_objects.at(i));
    w.object_shapes.push_back(settings.tip_limit ? make_polyhedron(o.shape) : make_shape(o.shape));
    w.mass.push_back(o.movable ? settings.object_mass.value_or(o.mass) : 0.0);
    w.friction.push_back(o.movable ? settings.object_friction.value_or(o.friction) : settings.fixed_friction.value_or(o.friction));
    w.spin_radius.push_back(cluttertamp::footprint_radius(o.shape, initial.world_T_objects.at(i)));
    btVector3 inertia(0, 0, 0);
    if (o.movable) {
      if (!(w.mass.back() > 0)) throw std::invalid_argument("PushWorld: movable object '" + o.id + "' needs a positive mass");
      make_shape(o.shape)->calculateLocalInertia(btScalar(w.mass.back()), inertia);  // the primitive's, not its prism's box
    }
    w.inertia.push_back(inertia);
    if (o.movable && w.present.back()) w.pushable.push_back(i);
  }
  const ObjectIndex target = scene.target;
  const double support_top = bottom_of(scene.objects.at(target).shape, initial.world_T_objects.at(target));
  for (const FixedBody& f : scene.fixed) {
    w.wall.push_back(std::abs(world_bounds(f.shape, f.world_T_body).max().z() - support_top) >= 0.01);
  }
  w.support = physics::support_region(scene, initial, settings);
  if (settings.arm) w.make_arm(support_top);
  else w.make_gripper(support_top);
  w.pusher_shape = std::make_unique<btCompoundShape>();
  for (const PusherPart& part : w.parts) {
    w.pusher_children.push_back(make_part_shape(part));
    w.pusher_shape->addChildShape(bt(part.frame_T_part), w.pusher_children.back().get());
  }
}

PushWorld::~PushWorld() = default;

const PushSettings& PushWorld::settings() const { return impl_->settings; }
const Scene& PushWorld::scene() const { return impl_->scene; }
double PushWorld::plane_z() const { return impl_->plane; }
const std::vector<PusherPart>& PushWorld::pusher_parts() const { return impl_->parts; }
double PushWorld::pusher_z() const { return impl_->frame_z; }
double PushWorld::hand_face() const { return impl_->hand_face; }
double PushWorld::hand_half_width() const { return impl_->hand_half_width; }

Eigen::Vector3d PushWorld::hand(const Eigen::Vector3d& pose) const { return compose(pose, impl_->frame_T_hand); }

Eigen::Vector3d PushWorld::pose_for_hand(const Eigen::Vector3d& hand) const {
  const Eigen::Vector3d& h = impl_->frame_T_hand;
  double yaw = std::remainder(hand.z() - h.z(), 2 * M_PI);
  if (!yaw_allowed(yaw)) yaw = clamp_yaw(yaw);  // turned into the limits about the hand's point
  const double c = std::cos(yaw), s = std::sin(yaw);
  return {hand.x() - (c * h.x() - s * h.y()), hand.y() - (s * h.x() + c * h.y()), yaw};
}

// A heading a rounding error beyond a limit (a clamped yaw carried through the hand's
// frame and back) is still within it.
bool PushWorld::yaw_allowed(double yaw) const { return std::abs(clamp_yaw(yaw) - yaw) <= 1e-9; }

bool PushWorld::hand_heading_allowed(double hand_yaw) const {
  return yaw_allowed(std::remainder(hand_yaw - impl_->frame_T_hand.z(), 2 * M_PI));
}

double PushWorld::clamp_yaw(double yaw) const {
  const Eigen::Vector2d& limits = impl_->settings.yaw_limits;
  if (!std::isfinite(limits.x()) || !std::isfinite(limits.y())) return yaw;
  // The turn nearest the limits' middle, then into them.
  const double middle = (limits.x() + limits.y()) / 2;
  const double near = middle + std::remainder(yaw - middle, 2 * M_PI);
  const double clamped = std::clamp(near, limits.x(), limits.y());
  return clamped == near ? yaw : clamped;
}

Eigen::Vector3d PushWorld::start_pose() const {
  return pose_for_hand(impl_->settings.start_hand.value_or(gripper_at_exit(impl_->scene)));
}
const std::vector<ObjectIndex>& PushWorld::pushable() const { return impl_->pushable; }
const Eigen::AlignedBox2d& PushWorld::support_region() const { return impl_->support; }

Eigen::AlignedBox2d PushWorld::gripper_region() const {
  const Scene& scene = impl_->scene;
  const Eigen::AlignedBox2d& support = impl_->support;
  const double exit_x = scene.world_T_exit.translation().x();
  Eigen::AlignedBox2d region(Eigen::Vector2d(std::min(exit_x, support.min().x()) - 0.05, support.min().y()),
                             support.max());
  const Eigen::AlignedBox2d workspace(scene.workspace.min().head<2>(), scene.workspace.max().head<2>());
  return region.intersection(workspace);
}

double PushWorld::footprint_radius(ObjectIndex object) const {
  return cluttertamp::footprint_radius(impl_->scene.objects.at(object).shape, impl_->initial_pose.at(object));
}

Eigen::Vector3d gripper_at_exit(const Scene& scene) {
  return {scene.world_T_exit.translation().x(), scene.world_T_exit.translation().y(), 0.0};
}

PushState PushWorld::state_of(const WorldState& initial, const Eigen::Vector3d& gripper) const {
  PushState s;
  s.gripper = gripper;
  for (const Eigen::Isometry3d& pose : initial.world_T_objects) {
    PlanarBody b;
    b.pose = {pose.translation().x(), pose.translation().y(), cluttertamp::yaw_of(pose)};
    s.objects.push_back(b);
  }
  return s;
}

PushOutcome PushWorld::propagate(const PushState& from, const PushControl& control) const {
  const Impl& w = *impl_;
  const Scene& scene = w.scene;
  if (from.objects.size() != scene.objects.size()) throw std::invalid_argument("PushWorld::propagate: one body per scene object");
  Impl::Simulation sim;
  sim.world.setGravity(btVector3(0, 0, btScalar(-kGravity)));
  for (std::size_t i = 0; i < scene.fixed.size(); ++i) {
    btRigidBody* b = sim.add(w.fixed_shapes[i].get(), bt(scene.fixed[i].world_T_body), 0.0, btVector3(0, 0, 0));
    w.set_friction(*b, w.fixed_friction[i]);
    sim.fixed.insert(b);
    if (w.wall[i]) sim.walls.insert(b);
  }
  sim.objects.assign(scene.objects.size(), nullptr);
  for (std::size_t i = 0; i < scene.objects.size(); ++i) {
    if (!w.present[i]) continue;
    const SceneObject& o = scene.objects[i];
    const double z = w.initial_pose[i].translation().z();
    const PlanarBody& body = from.objects[i];
    btRigidBody* b = sim.add(w.object_shapes[i].get(), planar(body.pose, z), w.mass[i], w.inertia[i]);
    w.set_friction(*b, w.friction[i]);
    if (o.movable) {
      b->setSpinningFriction(btScalar(2.0 / 3.0 * w.spin_radius[i]));
      // Bullet's rigid-body solver adds torsional friction only beside rolling friction;
      // a trace of it, too little to hold an object that tips.
      b->setRollingFriction(btScalar(1e-6));
      const bool tips = w.may_tip(i);
      b->setAngularFactor(btVector3(tips ? 1 : 0, tips ? 1 : 0, 1));  // slides and turns; tips only when allowed to
      b->setLinearVelocity(btVector3(btScalar(body.velocity.x()), btScalar(body.velocity.y()), 0));
      b->setAngularVelocity(btVector3(0, 0, btScalar(body.velocity.z())));
      if (tips && body.velocity.isZero()) {
        // Asleep until something touches it: Bullet's contacts of a polyhedron at rest on
        // a board are never quite still, and an object left to them creeps (mm/s).
        b->setActivationState(ISLAND_SLEEPING);
      } else {
        b->setActivationState(DISABLE_DEACTIVATION);
      }
    } else {
      sim.fixed.insert(b);
    }
    sim.objects[i] = b;
  }
  sim.gripper = sim.add(w.pusher_shape.get(), planar(from.gripper, w.frame_z), 0.0, btVector3(0, 0, 0), true);
  w.set_friction(*sim.gripper, w.settings.pusher_friction);

  PushOutcome out;
  std::set<ObjectIndex> touched;
  const int steps = std::max(1, static_cast<int>(std::ceil(control.duration / w.settings.time_step - 1e-9)));
  const double dt = control.duration > 0 ? control.duration / steps : 0.0;
  Eigen::Vector3d gripper = from.gripper;
  const double force_limit = w.settings.wall_force_limit.value_or(std::numeric_limits<double>::infinity());
  for (int k = 0; k < steps && dt > 0 && out.wall_force <= force_limit; ++k) {
    gripper += control.velocity * dt;
    sim.gripper->getMotionState()->setWorldTransform(planar(gripper, w.frame_z));  // the kinematic body follows
    sim.world.stepSimulation(btScalar(dt), 0);
    const int manifolds = sim.dispatcher.getNumManifolds();
    for (int m = 0; m < manifolds; ++m) {
      const btPersistentManifold* c = sim.dispatcher.getManifoldByIndexInternal(m);
      const btCollisionObject* a = c->getBody0();
      const btCollisionObject* b = c->getBody1();
      if (sim.walls.count(a) || sim.walls.count(b)) out.wall_force = std::max(out.wall_force, contact_force(*c, dt));
      if (a != sim.gripper && b != sim.gripper) continue;
      const btCollisionObject* other = a == sim.gripper ? b : a;
      for (int p = 0; p < c->getNumContacts(); ++p) {
        const double distance = c->getContactPoint(p).getDistance();
        if (sim.fixed.count(other)) {
          out.gripper_hit_fixed = out.gripper_hit_fixed || distance < -kFixedPenetration;
        } else if (distance < 1e-4) {
          const auto it = std::find(sim.objects.begin(), sim.objects.end(), other);
          if (it != sim.objects.end()) touched.insert(static_cast<ObjectIndex>(it - sim.objects.begin()));
        }
      }
    }
  }
  out.state.gripper = gripper;
  out.state.objects = from.objects;
  for (std::size_t i = 0; i < scene.objects.size(); ++i) {
    const btRigidBody* b = sim.objects[i];
    if (!b || !scene.objects[i].movable) continue;
    const btTransform& t = b->getWorldTransform();
    PlanarBody& body = out.state.objects[i];
    body.pose = {double(t.getOrigin().x()), double(t.getOrigin().y()), yaw_of(t)};
    body.velocity = {double(b->getLinearVelocity().x()), double(b->getLinearVelocity().y()),
                     double(b->getAngularVelocity().z())};
    // An object that may tip and is all but still is at rest (it would stop within
    // microns), so that the next propagation starts it asleep.
    if (w.settings.tip_limit && body.velocity.head<2>().norm() < kAtRestSpeed && std::abs(body.velocity.z()) < kAtRestTurn) {
      body.velocity.setZero();
    }
    if (double(t.getOrigin().z()) < w.initial_pose[i].translation().z() - w.settings.fall_drop) {
      out.fallen.push_back(static_cast<ObjectIndex>(i));
    }
    const double tilt = std::acos(std::clamp(double(t.getBasis()[2][2]), -1.0, 1.0));
    if (w.may_tip(i) && tilt > *w.settings.tip_limit) out.tipped.push_back(static_cast<ObjectIndex>(i));
  }
  out.touched.assign(touched.begin(), touched.end());
  return out;
}

}  // namespace cluttertamp::physics
