#include "cluttertamp/collision/collision_world.hpp"

#include <algorithm>
#include <cstdint>
#include <limits>
#include <stdexcept>

#include <fcl/broadphase/broadphase_dynamic_AABB_tree.h>
#include <fcl/geometry/bvh/BVH_model.h>
#include <fcl/geometry/shape/box.h>
#include <fcl/geometry/shape/convex.h>
#include <fcl/geometry/shape/cylinder.h>
#include <fcl/geometry/shape/sphere.h>
#include <fcl/narrowphase/collision.h>
#include <fcl/narrowphase/distance.h>

#include "collision/footprint.hpp"
#include "collision/separation.hpp"

namespace cluttertamp::collision {

namespace {

using Geometry = std::shared_ptr<fcl::CollisionGeometryd>;
using Object = fcl::CollisionObjectd;
using Manager = fcl::DynamicAABBTreeCollisionManagerd;

// A held object is shrunk by this much on every side, so that the contact it starts
// with (resting on a board, between the fingers) is not a collision.
constexpr double kHeldShrink = 1e-3;  // m

Geometry make_geometry(const Shape& shape, double shrink = 0.0) {
  if (const auto* box = std::get_if<Box>(&shape)) {
    return std::make_shared<fcl::Boxd>((box->size.array() - 2 * shrink).max(1e-4).matrix());
  }
  if (const auto* sphere = std::get_if<Sphere>(&shape)) {
    return std::make_shared<fcl::Sphered>(std::max(sphere->radius - shrink, 1e-4));
  }
  const auto& cylinder = std::get<Cylinder>(shape);
  return std::make_shared<fcl::Cylinderd>(std::max(cylinder.radius - shrink, 1e-4),
                                          std::max(cylinder.height - 2 * shrink, 1e-4));
}

// A link mesh as FCL geometry: its convex hull as a convex polytope (GJK on its
// vertices), or its triangles in a bounding volume hierarchy of oriented boxes.
Geometry make_geometry(const robot::TriangleMesh& mesh, bool convex) {
  if (convex) {
    auto vertices = std::make_shared<std::vector<fcl::Vector3d>>(mesh.vertices.begin(), mesh.vertices.end());
    auto faces = std::make_shared<std::vector<int>>();
    faces->reserve(mesh.triangles.size() * 4);
    for (const auto& t : mesh.triangles) faces->insert(faces->end(), {3, static_cast<int>(t[0]), static_cast<int>(t[1]), static_cast<int>(t[2])});
    auto hull = std::make_shared<fcl::Convexd>(vertices, static_cast<int>(mesh.triangles.size()), faces);
    hull->computeLocalAABB();  // the box narrow_collide tests first
    return hull;
  }
  auto model = std::make_shared<fcl::BVHModel<fcl::OBBRSSd>>();
  std::vector<fcl::Vector3d> vertices(mesh.vertices.begin(), mesh.vertices.end());
  std::vector<fcl::Triangle> triangles;
  triangles.reserve(mesh.triangles.size());
  for (const auto& t : mesh.triangles) triangles.emplace_back(t[0], t[1], t[2]);
  model->beginModel(static_cast<int>(triangles.size()), static_cast<int>(vertices.size()));
  model->addSubModel(vertices, triangles);
  model->endModel();
  model->computeLocalAABB();
  return model;
}

fcl::Transform3d to_fcl(const Eigen::Isometry3d& pose) { return fcl::Transform3d(pose.matrix()); }

// User data of movable objects: their index plus one (0 marks robot and fixed objects).
void* tag(ObjectIndex index) { return reinterpret_cast<void*>(static_cast<std::uintptr_t>(index) + 1); }
std::optional<ObjectIndex> untag(const Object* object) {
  const auto value = reinterpret_cast<std::uintptr_t>(object->getUserData());
  if (value == 0) return std::nullopt;
  return static_cast<ObjectIndex>(value - 1);
}

fcl::CollisionRequestd collision_request() {
  fcl::CollisionRequestd request;
  // libccd answers boolean queries with MPR; FCL 0.7 own GJK also runs EPA whenever the
  // shapes overlap, even when no contact is asked for, which costs more.
  request.gjk_solver_type = fcl::GST_LIBCCD;
  return request;
}

// A solid that holds the geometry, centred at `centre` in the geometry's frame: the
// primitive itself, or for meshes and convex hulls the box of their local bounds.
struct Bound {
  detail::Solid solid;
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
};

std::optional<Bound> bound(const fcl::CollisionGeometryd& g) {
  switch (g.getNodeType()) {
    case fcl::GEOM_BOX: return Bound{{detail::Solid::Kind::box, static_cast<const fcl::Boxd&>(g).side / 2}};
    case fcl::GEOM_SPHERE:
      return Bound{{detail::Solid::Kind::sphere, Eigen::Vector3d::Constant(static_cast<const fcl::Sphered&>(g).radius)}};
    case fcl::GEOM_CYLINDER: {
      const auto& c = static_cast<const fcl::Cylinderd&>(g);
      return Bound{{detail::Solid::Kind::cylinder, Eigen::Vector3d(c.radius, c.radius, c.lz / 2)}};
    }
    case fcl::GEOM_CONVEX:
    case fcl::BV_OBBRSS: {
      // GJK on a hull of a few hundred vertices costs several times a box test, and most
      // pairs the broadphase passes on are apart by more than their boxes.
      const fcl::AABBd& box = g.aabb_local;
      if (!(box.min_.array() <= box.max_.array()).all()) return std::nullopt;
      return Bound{{detail::Solid::Kind::box, (box.max_ - box.min_) / 2}, (box.max_ + box.min_) / 2};
    }
    default: return std::nullopt;
  }
}

// The cheap separation tests first; FCL only for the pairs they cannot decide.
bool narrow_collide(const Object* a, const Object* b) {
  const auto ba = bound(*a->collisionGeometry()), bb = bound(*b->collisionGeometry());
  if (ba && bb) {
    Eigen::Isometry3d world_T_a(a->getTransform().matrix()), world_T_b(b->getTransform().matrix());
    world_T_a.translation() += world_T_a.linear() * ba->centre;
    world_T_b.translation() += world_T_b.linear() * bb->centre;
    if (detail::separated(ba->solid, world_T_a, bb->solid, world_T_b)) return false;
  }
  static const fcl::CollisionRequestd request = collision_request();
  fcl::CollisionResultd result;
  return fcl::collide(a, b, request, result) > 0;
}

// Broadphase callback data for one query object against one manager.
struct CollideData {
  std::span<const ObjectIndex> ignored;
  bool stop_at_first = true;
  bool hit = false;
  ObjectSet* hits = nullptr;  // movable manager: every object touched
};

bool on_pair(Object* o1, Object* o2, void* raw) {
  auto* data = static_cast<CollideData*>(raw);
  const std::optional<ObjectIndex> index = untag(o1) ? untag(o1) : untag(o2);
  if (index) {
    if (std::find(data->ignored.begin(), data->ignored.end(), *index) != data->ignored.end()) return false;
    if (data->hits && std::find(data->hits->begin(), data->hits->end(), *index) != data->hits->end()) return false;
  }
  if (!narrow_collide(o1, o2)) return false;
  data->hit = true;
  if (data->hits && index) data->hits->push_back(*index);
  return data->stop_at_first;
}

struct DistanceData {
  std::span<const ObjectIndex> ignored;
  double min = std::numeric_limits<double>::infinity();
};

bool on_distance(Object* o1, Object* o2, void* raw, double& current) {
  auto* data = static_cast<DistanceData*>(raw);
  const std::optional<ObjectIndex> index = untag(o1) ? untag(o1) : untag(o2);
  if (index && std::find(data->ignored.begin(), data->ignored.end(), *index) != data->ignored.end()) return false;
  // Boolean test first: FCL's signed distance (libccd EPA) can abort on touching
  // shapes, so overlap is reported as 0 rather than as a depth.
  if (narrow_collide(o1, o2)) {
    data->min = 0.0;
    current = 0.0;
    return true;
  }
  fcl::DistanceRequestd request;
  request.gjk_solver_type = fcl::GST_INDEP;
  fcl::DistanceResultd result;
  fcl::distance(o1, o2, request, result);
  data->min = std::min(data->min, result.min_distance);
  current = std::min(current, result.min_distance);
  return false;
}

}  // namespace

// Every context owns its FCL objects *and* their geometry: FCL writes to a geometry
// (its local AABB) when an object is made from it, so sharing one between threads races.
struct CollisionWorld::Context::State {
  std::vector<Eigen::Isometry3d> root_T_links;
  std::vector<std::unique_ptr<Object>> shapes;  // one per robot shape
  std::unique_ptr<Object> held;
  std::uint64_t held_generation = 0;  // which attach() `held` was made for
};

CollisionWorld::Context::Context() : state_(std::make_unique<State>()) {}
CollisionWorld::Context::~Context() = default;

struct CollisionWorld::Impl {
  struct RobotShape {
    robot::LinkIndex link;
    Shape shape;
    Eigen::Isometry3d link_T_shape;  // of the mesh, for a mesh
    bool gripper;  // part of the hand (below the tool's rigid body): may touch the held object
    std::shared_ptr<const robot::TriangleMesh> mesh;  // null for a primitive
    bool convex = false;
    // A mesh's FCL geometry, built once: each context gets a copy, which costs a
    // fraction of building it (a polytope's adjacency, a hierarchy's boxes).
    std::shared_ptr<const fcl::CollisionGeometryd> prototype;

    Geometry geometry() const {
      if (!prototype) return make_geometry(shape);
      if (convex) return std::make_shared<fcl::Convexd>(static_cast<const fcl::Convexd&>(*prototype));
      return std::make_shared<fcl::BVHModel<fcl::OBBRSSd>>(static_cast<const fcl::BVHModel<fcl::OBBRSSd>&>(*prototype));
    }
  };
  struct MovableObject {
    Geometry geometry;
    std::unique_ptr<Object> object;
    bool present = true;
    detail::Outline outline;
  };

  Scene scene;
  std::shared_ptr<const robot::RobotDescription> robot;
  std::vector<std::unique_ptr<Object>> fixed_objects;
  std::vector<detail::Outline> fixed_outlines;
  std::vector<MovableObject> movable;
  Manager fixed_manager;
  Manager movable_manager;
  std::vector<RobotShape> robot_shapes;
  std::vector<std::pair<std::size_t, std::size_t>> self_pairs;  // robot shape indices to check
  std::optional<ObjectIndex> held;
  Eigen::Isometry3d tool_T_held = Eigen::Isometry3d::Identity();
  std::uint64_t held_generation = 0;  // counts attach() calls
  std::uint64_t generation = 0;       // counts the calls that change the world

  using State = Context::State;
  void pose_robot(const Eigen::VectorXd& q, State& c) const;
  bool self_collides(const State& c) const;
  /// Poses a movable object without touching the broadphase; true when the pose
  /// changed and the object is in the broadphase (so the caller must update it).
  bool move_object(ObjectIndex object, const Eigen::Isometry3d& world_T_object);
  /// Collides the posed robot shapes and held object with a manager's objects.
  bool hits(const Manager& manager, State& c, CollideData& data) const;
};

CollisionWorld::CollisionWorld(const Scene& scene, std::shared_ptr<const robot::RobotDescription> robot)
    : impl_(std::make_unique<Impl>()) {
  Impl& w = *impl_;
  w.scene = scene;
  w.robot = std::move(robot);
  for (const FixedBody& body : scene.fixed) {
    auto object = std::make_unique<Object>(make_geometry(body.shape), to_fcl(body.world_T_body));
    object->setUserData(nullptr);  // FCL leaves it uninitialised; null: not a movable object
    object->computeAABB();
    w.fixed_manager.registerObject(object.get());
    w.fixed_objects.push_back(std::move(object));
    w.fixed_outlines.push_back(detail::outline(body.shape, body.world_T_body));
  }
  w.fixed_manager.setup();
  w.movable.resize(scene.objects.size());
  for (ObjectIndex i = 0; i < scene.objects.size(); ++i) {
    Impl::MovableObject& m = w.movable[i];
    m.geometry = make_geometry(scene.objects[i].shape);
    m.object = std::make_unique<Object>(m.geometry, to_fcl(scene.objects[i].world_T_object));
    m.object->setUserData(tag(i));
    m.object->computeAABB();
    m.outline = detail::outline(scene.objects[i].shape, scene.objects[i].world_T_object);
    w.movable_manager.registerObject(m.object.get());
  }
  w.movable_manager.setup();
  if (!w.robot) return;

  const robot::RobotModel& model = *w.robot->model();
  // The hand: the tool's rigid body and everything below it (fingers).
  const robot::LinkIndex tool_root = model.rigid_root(w.robot->tip_link());
  for (std::size_t l = 0; l < model.links().size(); ++l) {
    const auto link = static_cast<robot::LinkIndex>(l);
    for (const robot::CollisionShape& c : model.links()[l].collision) {
      const bool gripper = model.descends_from(link, tool_root);
      if (c.mesh) w.robot_shapes.push_back({link, c.shape, c.link_T_mesh, gripper, c.mesh, c.convex, make_geometry(*c.mesh, c.convex)});
      else w.robot_shapes.push_back({link, c.shape, c.link_T_shape, gripper, nullptr, false, nullptr});
    }
  }
  const auto& adjacent = w.robot->disabled_collisions();
  for (std::size_t a = 0; a < w.robot_shapes.size(); ++a) {
    for (std::size_t b = a + 1; b < w.robot_shapes.size(); ++b) {
      const auto la = w.robot_shapes[a].link, lb = w.robot_shapes[b].link;
      if (la == lb) continue;
      const std::pair<robot::LinkIndex, robot::LinkIndex> pair{std::min(la, lb), std::max(la, lb)};
      if (std::binary_search(adjacent.begin(), adjacent.end(), pair)) continue;
      w.self_pairs.emplace_back(a, b);
    }
  }
}

CollisionWorld::~CollisionWorld() = default;

const Scene& CollisionWorld::scene() const { return impl_->scene; }
const robot::RobotDescription* CollisionWorld::robot() const { return impl_->robot.get(); }

bool CollisionWorld::Impl::move_object(ObjectIndex object, const Eigen::Isometry3d& world_T_object) {
  Eigen::Isometry3d& pose = scene.objects.at(object).world_T_object;
  if (pose.matrix() == world_T_object.matrix()) return false;
  MovableObject& m = movable[object];
  pose = world_T_object;
  m.object->setTransform(to_fcl(world_T_object));
  m.object->computeAABB();
  m.outline = detail::outline(scene.objects[object].shape, world_T_object);
  return m.present;
}

std::uint64_t CollisionWorld::generation() const { return impl_->generation; }

void CollisionWorld::set_object_pose(ObjectIndex object, const Eigen::Isometry3d& world_T_object) {
  ++impl_->generation;
  if (impl_->move_object(object, world_T_object)) impl_->movable_manager.update(impl_->movable[object].object.get());
}

const Eigen::Isometry3d& CollisionWorld::object_pose(ObjectIndex object) const {
  return impl_->scene.objects.at(object).world_T_object;
}

void CollisionWorld::remove_object(ObjectIndex object) {
  ++impl_->generation;
  Impl::MovableObject& m = impl_->movable.at(object);
  if (!m.present) return;
  impl_->movable_manager.unregisterObject(m.object.get());
  m.present = false;
}

void CollisionWorld::restore_object(ObjectIndex object) {
  ++impl_->generation;
  Impl::MovableObject& m = impl_->movable.at(object);
  if (m.present || impl_->held == object) return;
  impl_->movable_manager.registerObject(m.object.get());
  m.present = true;
}

bool CollisionWorld::present(ObjectIndex object) const { return impl_->movable.at(object).present; }

void CollisionWorld::attach(ObjectIndex object, const Eigen::Isometry3d& tool_T_object) {
  ++impl_->generation;
  if (!impl_->robot) throw std::logic_error("CollisionWorld::attach: the world has no robot");
  if (impl_->held) throw std::logic_error("CollisionWorld::attach: already holding an object");
  remove_object(object);
  impl_->held = object;
  impl_->tool_T_held = tool_T_object;
  ++impl_->held_generation;
}

void CollisionWorld::detach(const Eigen::Isometry3d& world_T_object) {
  ++impl_->generation;
  if (!impl_->held) return;
  const ObjectIndex object = *impl_->held;
  impl_->held.reset();
  set_object_pose(object, world_T_object);
  restore_object(object);
}

std::optional<ObjectIndex> CollisionWorld::held() const { return impl_->held; }

void CollisionWorld::sync(const WorldState& state) {
  ++impl_->generation;
  if (impl_->held) detach(object_pose(*impl_->held));
  // One rebalancing of the broadphase tree for all moved objects: FCL rebalances on
  // every single update, which made syncing 100 objects cost more than planning.
  std::vector<Object*> moved;
  for (ObjectIndex i = 0; i < impl_->movable.size(); ++i) {
    if (impl_->move_object(i, state.world_T_objects.at(i))) moved.push_back(impl_->movable[i].object.get());
    if (state.removed.at(i)) remove_object(i); else restore_object(i);
  }
  if (!moved.empty()) impl_->movable_manager.update(moved);
  if (state.held && impl_->robot) {
    auto context = make_context();
    const Eigen::Isometry3d world_T_tool = tool_pose(state.robot_configuration, *context);
    attach(*state.held, world_T_tool.inverse() * state.world_T_objects.at(*state.held));
  }
}

std::unique_ptr<CollisionWorld::Context> CollisionWorld::make_context() const {
  std::unique_ptr<Context> context(new Context());
  for (const Impl::RobotShape& shape : impl_->robot_shapes) {
    context->state_->shapes.push_back(std::make_unique<Object>(shape.geometry()));
    context->state_->shapes.back()->setUserData(nullptr);  // FCL leaves it uninitialised
  }
  return context;
}

Eigen::Isometry3d CollisionWorld::tool_pose(const Eigen::VectorXd& q, Context& context) const {
  impl_->robot->model()->link_poses(q, context.state_->root_T_links);
  return impl_->scene.world_T_robot_base * context.state_->root_T_links[impl_->robot->tip_link()];
}

void CollisionWorld::Impl::pose_robot(const Eigen::VectorXd& q, State& c) const {
  if (!robot) throw std::logic_error("CollisionWorld: the world has no robot");
  const robot::RobotModel& model = *robot->model();
  if (static_cast<std::size_t>(q.size()) != model.variable_count()) {
    throw std::invalid_argument("CollisionWorld: configuration has " + std::to_string(q.size()) + " values, the robot " +
                                std::to_string(model.variable_count()));
  }
  model.link_poses(q, c.root_T_links);
  for (std::size_t i = 0; i < robot_shapes.size(); ++i) {
    const RobotShape& shape = robot_shapes[i];
    c.shapes[i]->setTransform(to_fcl(scene.world_T_robot_base * c.root_T_links[shape.link] * shape.link_T_shape));
    c.shapes[i]->computeAABB();
  }
  if (held) {
    if (!c.held || c.held_generation != held_generation) {
      c.held = std::make_unique<Object>(make_geometry(scene.objects[*held].shape, kHeldShrink));
      c.held->setUserData(nullptr);  // the query object, not one of the managers'
      c.held_generation = held_generation;
    }
    c.held->setTransform(to_fcl(scene.world_T_robot_base * c.root_T_links[robot->tip_link()] * tool_T_held));
    c.held->computeAABB();
  }
}

bool CollisionWorld::Impl::self_collides(const State& c) const {
  for (const auto& [a, b] : self_pairs) {
    if (c.shapes[a]->getAABB().overlap(c.shapes[b]->getAABB()) && narrow_collide(c.shapes[a].get(), c.shapes[b].get())) {
      return true;
    }
  }
  if (!held) return false;
  for (std::size_t i = 0; i < robot_shapes.size(); ++i) {
    if (!robot_shapes[i].gripper && c.held->getAABB().overlap(c.shapes[i]->getAABB()) &&
        narrow_collide(c.held.get(), c.shapes[i].get())) {
      return true;
    }
  }
  return false;
}

// The robot's shapes and the held object, posed in the context.
bool CollisionWorld::Impl::hits(const Manager& manager, State& c, CollideData& data) const {
  for (auto& shape : c.shapes) {
    manager.collide(shape.get(), &data, on_pair);
    if (data.hit && data.stop_at_first) return true;
  }
  if (held) manager.collide(c.held.get(), &data, on_pair);
  return data.hit;
}

bool CollisionWorld::is_valid(const Eigen::VectorXd& q, Context& context, std::span<const ObjectIndex> ignored) const {
  const Impl& w = *impl_;
  Context::State& c = *context.state_;
  w.pose_robot(q, c);
  // Cheapest and most likely contacts first: in clutter, objects; then boards; then self.
  CollideData movable{ignored, true};
  if (w.hits(w.movable_manager, c, movable)) return false;
  CollideData fixed{ignored, true};
  if (w.hits(w.fixed_manager, c, fixed)) return false;
  return !w.self_collides(c);
}

CollisionReport CollisionWorld::check(const Eigen::VectorXd& q, Context& context,
                                      std::span<const ObjectIndex> ignored) const {
  const Impl& w = *impl_;
  Context::State& c = *context.state_;
  w.pose_robot(q, c);
  CollisionReport report;
  report.self = w.self_collides(c);
  CollideData fixed{ignored, true};
  report.fixed = w.hits(w.fixed_manager, c, fixed);
  CollideData movable{ignored, false, false, &report.objects};
  w.hits(w.movable_manager, c, movable);
  std::sort(report.objects.begin(), report.objects.end());
  return report;
}

bool CollisionWorld::touches_object(const Eigen::VectorXd& q, Context& context, std::span<const ObjectIndex> ignored) const {
  const Impl& w = *impl_;
  Context::State& c = *context.state_;
  w.pose_robot(q, c);
  CollideData movable{ignored, true};
  return w.hits(w.movable_manager, c, movable);
}

std::vector<std::pair<std::size_t, std::size_t>> CollisionWorld::self_contacts(const Eigen::VectorXd& q,
                                                                               Context& context) const {
  const Impl& w = *impl_;
  Context::State& c = *context.state_;
  w.pose_robot(q, c);
  std::vector<std::pair<std::size_t, std::size_t>> out;
  for (const auto& [a, b] : w.self_pairs) {
    if (c.shapes[a]->getAABB().overlap(c.shapes[b]->getAABB()) && narrow_collide(c.shapes[a].get(), c.shapes[b].get())) {
      const std::size_t la = w.robot_shapes[a].link, lb = w.robot_shapes[b].link;
      out.emplace_back(std::min(la, lb), std::max(la, lb));
    }
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

std::vector<FixedContact> CollisionWorld::fixed_contacts(const Eigen::VectorXd& q, Context& context) const {
  const Impl& w = *impl_;
  Context::State& c = *context.state_;
  w.pose_robot(q, c);
  std::vector<FixedContact> out;
  auto touching = [](const Object* a, const Object* b) { return a->getAABB().overlap(b->getAABB()) && narrow_collide(a, b); };
  for (std::size_t body = 0; body < w.fixed_objects.size(); ++body) {
    const Object* fixed = w.fixed_objects[body].get();
    for (std::size_t s = 0; s < c.shapes.size(); ++s) {
      if (touching(c.shapes[s].get(), fixed)) out.push_back({w.robot_shapes[s].link, body});
    }
    if (w.held && touching(c.held.get(), fixed)) out.push_back({std::nullopt, body});
  }
  auto key = [](const FixedContact& f) { return std::pair(f.link.value_or(std::numeric_limits<robot::LinkIndex>::max()), f.fixed_body); };
  std::sort(out.begin(), out.end(), [&](const FixedContact& a, const FixedContact& b) { return key(a) < key(b); });
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

std::string CollisionWorld::describe_fixed_contacts(const Eigen::VectorXd& q, Context& context) const {
  std::string out;
  for (const FixedContact& f : fixed_contacts(q, context)) {
    if (!out.empty()) out += ", ";
    out += f.link ? impl_->robot->model()->links()[static_cast<std::size_t>(*f.link)].name : std::string("the held object");
    out += " on " + impl_->scene.fixed[f.fixed_body].id;
  }
  return out;
}

double CollisionWorld::min_distance(const Eigen::VectorXd& q, Context& context,
                                    std::span<const ObjectIndex> ignored) const {
  const Impl& w = *impl_;
  Context::State& c = *context.state_;
  w.pose_robot(q, c);
  DistanceData data{ignored};
  auto measure = [&](Object* object) {
    w.fixed_manager.distance(object, &data, on_distance);
    if (data.min > 0) w.movable_manager.distance(object, &data, on_distance);
  };
  for (auto& shape : c.shapes) {
    measure(shape.get());
    if (data.min <= 0) return data.min;
  }
  if (w.held) measure(c.held.get());
  return data.min;
}

CollisionReport CollisionWorld::shape_contacts(const Shape& shape, const Eigen::Isometry3d& world_T_shape,
                                              std::span<const ObjectIndex> ignored) const {
  Object probe(make_geometry(shape), to_fcl(world_T_shape));  // its own geometry: thread-safe
  probe.computeAABB();
  CollisionReport report;
  CollideData fixed{ignored, true};
  impl_->fixed_manager.collide(&probe, &fixed, on_pair);
  report.fixed = fixed.hit;
  CollideData movable{ignored, false, false, &report.objects};
  impl_->movable_manager.collide(&probe, &movable, on_pair);
  std::sort(report.objects.begin(), report.objects.end());
  return report;
}

ObjectSet CollisionWorld::footprint_objects(const Eigen::Vector2d& centre, const Footprint& footprint,
                                            std::span<const ObjectIndex> ignored) const {
  return swept_objects(centre, centre, footprint, ignored);
}

ObjectSet CollisionWorld::swept_objects(const Eigen::Vector2d& from, const Eigen::Vector2d& to,
                                        const Footprint& footprint, std::span<const ObjectIndex> ignored) const {
  ObjectSet objects;
  const auto& movable = impl_->movable;
  for (ObjectIndex i = 0; i < movable.size(); ++i) {
    const Impl::MovableObject& m = movable[i];
    if (!m.present || !detail::maybe_within(from, to, m.outline, footprint.radius)) continue;
    if (!detail::bands_overlap(m.outline, footprint.z_min, footprint.z_max)) continue;
    if (std::find(ignored.begin(), ignored.end(), i) != ignored.end()) continue;
    if (detail::segment_distance(from, to, m.outline) < footprint.radius) objects.push_back(i);
  }
  return objects;
}

bool CollisionWorld::sweep_hits_fixed(const Eigen::Vector2d& from, const Eigen::Vector2d& to,
                                      const Footprint& footprint) const {
  for (const detail::Outline& o : impl_->fixed_outlines) {
    if (detail::maybe_within(from, to, o, footprint.radius) && detail::bands_overlap(o, footprint.z_min, footprint.z_max) &&
        detail::segment_distance(from, to, o) < footprint.radius) {
      return true;
    }
  }
  return false;
}

double CollisionWorld::fixed_clearance(const Eigen::Vector2d& centre, const Footprint& footprint) const {
  double clearance = std::numeric_limits<double>::infinity();
  for (const detail::Outline& o : impl_->fixed_outlines) {
    if (detail::bands_overlap(o, footprint.z_min, footprint.z_max)) {
      clearance = std::min(clearance, detail::segment_distance(centre, centre, o));
    }
  }
  return clearance;
}

}  // namespace cluttertamp::collision
