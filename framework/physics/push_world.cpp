#include "cluttertamp/physics/push_world.hpp"

#include <algorithm>
#include <cmath>
#include <set>
#include <stdexcept>
#include <variant>

#include <btBulletDynamicsCommon.h>

namespace cluttertamp::physics {

namespace {

constexpr double kGravity = 9.81;  // m/s^2
// Contacts deeper than this between the gripper and fixed geometry count as a hit (m):
// grazing a wall is contact, entering it is not.
constexpr double kFixedPenetration = 0.002;

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

}  // namespace

struct PushWorld::Impl {
  const Scene& scene;
  PushSettings settings;
  std::vector<bool> present = {};  // per scene object
  std::vector<Eigen::Isometry3d> initial_pose = {};  // per scene object: heights and footprints come from it
  std::vector<ObjectIndex> pushable = {};
  Eigen::AlignedBox2d support = {};
  double plane = 0;           // the gripper's bottom, m
  double gripper_z = 0;       // the gripper's centre, m
  std::vector<std::unique_ptr<btCollisionShape>> fixed_shapes = {}, object_shapes = {};
  std::vector<std::unique_ptr<btCollisionShape>> gripper_parts = {};  // the boxes of gripper_shape
  std::unique_ptr<btCompoundShape> gripper_shape = nullptr;
  std::vector<btVector3> inertia = {};  // per object, for its mass

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

PushWorld::PushWorld(const Scene& scene, const WorldState& initial, PushSettings settings)
    : impl_(std::make_unique<Impl>(Impl{scene, settings})) {
  Impl& w = *impl_;
  if (!(settings.time_step > 0)) throw std::invalid_argument("PushWorld: time_step must be positive");
  if (settings.finger_length < 0 || !(settings.finger_width > 0) || 2 * settings.finger_width >= settings.gripper_size.y()) {
    throw std::invalid_argument("PushWorld: fingers need a length >= 0 and a width > 0 that leaves a gap between them");
  }
  for (const FixedBody& f : scene.fixed) w.fixed_shapes.push_back(make_shape(f.shape));
  for (std::size_t i = 0; i < scene.objects.size(); ++i) {
    const SceneObject& o = scene.objects[i];
    w.present.push_back(!initial.removed.at(i));
    w.initial_pose.push_back(initial.world_T_objects.at(i));
    w.object_shapes.push_back(make_shape(o.shape));
    btVector3 inertia(0, 0, 0);
    if (o.movable) {
      if (!(o.mass > 0)) throw std::invalid_argument("PushWorld: movable object '" + o.id + "' needs a positive mass");
      w.object_shapes.back()->calculateLocalInertia(btScalar(o.mass), inertia);
    }
    w.inertia.push_back(inertia);
    if (o.movable && w.present.back()) w.pushable.push_back(i);
  }
  const ObjectIndex target = scene.target;
  const double support_top = bottom_of(scene.objects.at(target).shape, initial.world_T_objects.at(target));
  w.plane = support_top + settings.gripper_clearance;
  w.support = physics::support_region(scene, initial, settings);
  w.gripper_z = w.plane + settings.gripper_size.z() / 2;
  w.gripper_shape = std::make_unique<btCompoundShape>();
  for (const GripperBox& box : gripper_boxes(settings)) {
    w.gripper_parts.push_back(make_shape(Box{box.size}));
    const btVector3 at(btScalar(box.offset.x()), btScalar(box.offset.y()), 0);
    w.gripper_shape->addChildShape(btTransform(btQuaternion::getIdentity(), at), w.gripper_parts.back().get());
  }
}

PushWorld::~PushWorld() = default;

const PushSettings& PushWorld::settings() const { return impl_->settings; }
const Scene& PushWorld::scene() const { return impl_->scene; }
double PushWorld::plane_z() const { return impl_->plane; }
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
    b->setFriction(1.0);
    sim.fixed.insert(b);
  }
  sim.objects.assign(scene.objects.size(), nullptr);
  for (std::size_t i = 0; i < scene.objects.size(); ++i) {
    if (!w.present[i]) continue;
    const SceneObject& o = scene.objects[i];
    const double z = w.initial_pose[i].translation().z();
    const PlanarBody& body = from.objects[i];
    btRigidBody* b = sim.add(w.object_shapes[i].get(), planar(body.pose, z), o.movable ? o.mass : 0.0, w.inertia[i]);
    // The support's friction: Bullet multiplies the two bodies' coefficients.
    b->setFriction(btScalar(o.friction));
    if (o.movable) {
      b->setAngularFactor(btVector3(0, 0, 1));  // slides and turns; never tips
      b->setLinearVelocity(btVector3(btScalar(body.velocity.x()), btScalar(body.velocity.y()), 0));
      b->setAngularVelocity(btVector3(0, 0, btScalar(body.velocity.z())));
      b->setActivationState(DISABLE_DEACTIVATION);
    } else {
      sim.fixed.insert(b);
    }
    sim.objects[i] = b;
  }
  sim.gripper = sim.add(w.gripper_shape.get(), planar(from.gripper, w.gripper_z), 0.0, btVector3(0, 0, 0), true);
  sim.gripper->setFriction(0.5);

  PushOutcome out;
  std::set<ObjectIndex> touched;
  const int steps = std::max(1, static_cast<int>(std::ceil(control.duration / w.settings.time_step - 1e-9)));
  const double dt = control.duration > 0 ? control.duration / steps : 0.0;
  Eigen::Vector3d gripper = from.gripper;
  for (int k = 0; k < steps && dt > 0; ++k) {
    gripper += control.velocity * dt;
    sim.gripper->getMotionState()->setWorldTransform(planar(gripper, w.gripper_z));  // the kinematic body follows
    sim.world.stepSimulation(btScalar(dt), 0);
    const int manifolds = sim.dispatcher.getNumManifolds();
    for (int m = 0; m < manifolds; ++m) {
      const btPersistentManifold* c = sim.dispatcher.getManifoldByIndexInternal(m);
      const btCollisionObject* a = c->getBody0();
      const btCollisionObject* b = c->getBody1();
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
    if (double(t.getOrigin().z()) < w.initial_pose[i].translation().z() - w.settings.fall_drop) {
      out.fallen.push_back(static_cast<ObjectIndex>(i));
    }
  }
  out.touched.assign(touched.begin(), touched.end());
  return out;
}

}  // namespace cluttertamp::physics
