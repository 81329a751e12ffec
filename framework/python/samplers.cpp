// Grasp, placement, motion and push samplers written in Python, as plugins of this
// process (plugin::provide_plugin): a problem file names them like a library's. The
// run calls them with the GIL held; what they propose is checked as the framework
// checks its own samplers' (manipulation::GraspChecker, PlacementChecker, dense motion
// checks, the push physics), so a Python sampler cannot hand the planner a grasp that
// collides. A Python exception is the sampler's failure, with its traceback.
#include "python/samplers.hpp"

#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "cluttertamp/collision/shared_world.hpp"
#include "cluttertamp/core/diagnostics.hpp"
#include "cluttertamp/core/parameters.hpp"
#include "cluttertamp/manipulation/actions.hpp"
#include "cluttertamp/manipulation/grasp_check.hpp"
#include "cluttertamp/manipulation/placement_check.hpp"
#include "cluttertamp/physics/push_planning.hpp"
#include "cluttertamp/physics/push_world.hpp"
#include "cluttertamp/plugin/grasp_sampler.hpp"
#include "cluttertamp/plugin/motion_sampler.hpp"
#include "cluttertamp/plugin/placement_sampler.hpp"
#include "cluttertamp/plugin/push_sampler.hpp"
#include "cluttertamp/plugin/registry.hpp"
#include "cluttertamp/robot/robot_description.hpp"
#include "cluttertamp/robot/robot_model.hpp"
#include "python/gil.hpp"

namespace py = pybind11;

namespace cluttertamp::python {
namespace {

// rad between the checks of a Python motion's straight segments: pick's dense check.
constexpr double kMotionResolution = 0.01;

// ---------------------------------------------------------------- values crossing

Eigen::Isometry3d isometry_from(const Eigen::Matrix4d& m, const char* what) {
  const Eigen::Matrix3d r = m.topLeftCorner<3, 3>();
  if (!m.allFinite() || !(r.transpose() * r).isApprox(Eigen::Matrix3d::Identity(), 1e-6) || r.determinant() < 0 ||
      !m.row(3).isApprox(Eigen::RowVector4d(0, 0, 0, 1))) {
    throw py::value_error(std::string(what) + " is not a rigid transform (a 4 x 4 matrix, rotation and translation)");
  }
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = r;
  pose.translation() = m.topRightCorner<3, 1>();
  return pose;
}

py::dict shape_dict(const Shape& shape) {
  py::dict d;
  if (const auto* c = std::get_if<Cylinder>(&shape)) {
    d["type"] = "cylinder";
    d["radius"] = c->radius;
    d["height"] = c->height;
  } else if (const auto* b = std::get_if<Box>(&shape)) {
    d["type"] = "box";
    d["size"] = Eigen::Vector3d(b->size);
  } else {
    d["type"] = "sphere";
    d["radius"] = std::get<Sphere>(shape).radius;
  }
  return d;
}

// Objects handed to Python that point into a sampler call's arguments answer only while
// the call lasts: Python may keep them, but not use them afterwards.
class CallScope {
 public:
  CallScope() : alive_(std::make_shared<bool>(true)) {}
  ~CallScope() { *alive_ = false; }
  CallScope(const CallScope&) = delete;
  CallScope& operator=(const CallScope&) = delete;
  const std::shared_ptr<bool>& alive() const { return alive_; }

 private:
  std::shared_ptr<bool> alive_;
};

void check_alive(const std::shared_ptr<bool>& alive, const char* what) {
  if (alive && !*alive) {
    throw std::runtime_error(std::string("this ") + what +
                             " belonged to a sampler call that is over: keep the values you need, not the " + what);
  }
}

// ---------------------------------------------------------------- World

// The scene and robot at one state, for Python: a sampler's view during its call, or a
// view that owns its collision world (Problem.world()). Configurations are 1-D arrays
// in the robot's joint order (rad, m); poses 4 x 4 matrices in the world frame.
struct World {
  std::shared_ptr<bool> alive;  // null: owns what it points to (`owner`)
  std::shared_ptr<void> owner;
  const plugin::WorldView* view = nullptr;
  const Scene* scene = nullptr;
  const robot::RobotDescription* robot = nullptr;

  const plugin::WorldView& get() const {
    check_alive(alive, "world");
    return *view;
  }
  void check(const Eigen::VectorXd& q) const {
    if (static_cast<std::size_t>(q.size()) != robot->model()->variable_count()) {
      throw py::value_error("a configuration of '" + robot->name() + "' has " +
                            std::to_string(robot->model()->variable_count()) + " values, not " + std::to_string(q.size()));
    }
  }
  std::vector<ObjectIndex> indices(const std::vector<std::string>& ids) const {
    std::vector<ObjectIndex> out;
    for (const std::string& id : ids) {
      const auto it = std::find_if(scene->objects.begin(), scene->objects.end(),
                                   [&](const SceneObject& o) { return o.id == id; });
      if (it == scene->objects.end()) throw py::value_error("the scene has no object '" + id + "'");
      out.push_back(static_cast<ObjectIndex>(it - scene->objects.begin()));
    }
    return out;
  }
  py::dict contacts_dict(const plugin::Contacts& c) const {
    py::dict d;
    d["self"] = c.self;
    d["fixed"] = c.fixed;
    py::list objects;
    for (ObjectIndex i : c.objects) objects.append(scene->objects.at(i).id);
    d["objects"] = objects;
    d["valid"] = c.valid();
    return d;
  }
  bool is_valid(const Eigen::VectorXd& q, const std::vector<std::string>& ignored) const {
    const auto& v = get();
    check(q);
    return v.is_valid(q, indices(ignored));
  }
  py::dict contacts(const Eigen::VectorXd& q, const std::vector<std::string>& ignored) const {
    const auto& v = get();
    check(q);
    return contacts_dict(v.contacts(q, indices(ignored)));
  }
  double min_distance(const Eigen::VectorXd& q, const std::vector<std::string>& ignored) const {
    const auto& v = get();
    check(q);
    return v.min_distance(q, indices(ignored));
  }
  Eigen::Matrix4d tool_pose(const Eigen::VectorXd& q) const {
    const auto& v = get();
    check(q);
    return v.tool_pose(q).matrix();
  }
  std::vector<Eigen::VectorXd> ik(const Eigen::Matrix4d& world_T_tool, std::optional<Eigen::VectorXd> seed) const {
    const auto& v = get();
    const Eigen::VectorXd start = seed.value_or(v.state().robot_configuration.size() ? v.state().robot_configuration
                                                                                       : robot->home());
    check(start);
    return v.inverse_kinematics(isometry_from(world_T_tool, "world_T_tool"), start);
  }
  py::dict object_contacts(const std::string& id, const Eigen::Matrix4d& world_T_object,
                           const std::vector<std::string>& ignored) const {
    const auto& v = get();
    std::vector<ObjectIndex> skip = indices(ignored);
    const ObjectIndex object = indices({id}).front();
    skip.push_back(object);
    return contacts_dict(v.shape_contacts(scene->objects.at(object).shape, isometry_from(world_T_object, "world_T_object"), skip));
  }
  std::map<std::string, Eigen::Matrix4d> object_poses() const {
    const WorldState& s = get().state();
    std::map<std::string, Eigen::Matrix4d> out;
    for (std::size_t i = 0; i < scene->objects.size(); ++i) {
      if (!s.removed.at(i)) out[scene->objects[i].id] = s.world_T_objects.at(i).matrix();
    }
    return out;
  }
};

// A view that owns its collision world: the SharedWorld must outlive the view.
struct OwnedWorld {
  std::shared_ptr<const Problem> problem;
  std::unique_ptr<collision::SharedWorld> shared;
  std::unique_ptr<plugin::WorldView> view;
  ~OwnedWorld() { view.reset(); }
};

// ---------------------------------------------------------------- Parameters

// A plugin's Parameters for its Python configure(): the same checks, locations and
// declarations as a C++ plugin's. Usable only during configure().
struct PythonParameters {
  std::shared_ptr<bool> alive;
  const Parameters* parameters = nullptr;

  const Parameters& get() const {
    check_alive(alive, "parameters object");
    return *parameters;
  }
  static Range range(std::optional<double> low, std::optional<double> high) {
    Range r;
    r.low = low;
    r.high = high;
    return r;
  }
};

// ---------------------------------------------------------------- queries

// What every query shows Python besides its own fields.
struct QueryBase {
  std::shared_ptr<bool> alive;
  plugin::PlanningContext* context = nullptr;
  World world;
  std::uint64_t seed = 0;

  plugin::PlanningContext& get() const {
    check_alive(alive, "query");
    return *context;
  }
  Eigen::VectorXd configuration() const {
    get();
    const WorldState& s = world.get().state();
    return s.robot_configuration.size() ? s.robot_configuration : world.robot->home();
  }
  double remaining_time() const { return get().deadline.remaining(); }
  std::vector<std::string> joint_names() const {
    get();
    return world.robot->model()->variable_names();
  }
};

struct PythonGraspQuery : QueryBase {
  ObjectIndex object = 0;
  const SceneObject& scene_object() const {
    get();
    return world.scene->objects.at(object);
  }
  Eigen::Matrix4d world_T_object() const { return world.get().state().world_T_objects.at(object).matrix(); }
  plugin::Grasp grasp(const Eigen::Matrix4d& world_T_gripper, double approach, double lift, double clearance) const {
    const SceneObject& o = scene_object();
    return manipulation::grasp_at(o, world.get().state().world_T_objects.at(object),
                                  isometry_from(world_T_gripper, "world_T_gripper"), world.robot->gripper().stroke,
                                  approach, lift, clearance);
  }
};

struct PythonPlacementQuery : QueryBase {
  ObjectIndex object = 0;
  const Region* region = nullptr;
  std::optional<Eigen::Isometry3d> gripper_T_object;
  std::size_t max_placements = 1;
};

struct PythonMotionQuery : QueryBase {
  Eigen::VectorXd start, goal;
};

// A push is planar physics: the query has no world view (the robot may be a floating gripper).
struct PythonPushQuery : QueryBase {
  const WorldState* state = nullptr;
  ObjectIndex object = 0;
  Eigen::Vector2d goal_xy = Eigen::Vector2d::Zero();
  double goal_radius = 0.0;
  Eigen::Vector3d gripper = Eigen::Vector3d::Zero();
  Eigen::AlignedBox2d support;
  double footprint_radius = 0.0;
  physics::PushSettings settings;
};

// ---------------------------------------------------------------- the adapters

// What every Python sampler's adapter shares: the instance, its configure() and how a
// call into Python is made and its exception turned into a failure.
class PythonSampler {
 public:
  PythonSampler(std::string kind, std::string name, py::object instance)
      : kind_(std::move(kind)), name_(std::move(name)), instance_(std::move(instance)) {}
  ~PythonSampler() { release(instance_); }
  PythonSampler(const PythonSampler&) = delete;
  PythonSampler& operator=(const PythonSampler&) = delete;

  void configure_python(const Parameters& parameters) {
    const py::gil_scoped_acquire gil;
    const HoldingGil held(true);
    const CallScope scope;
    try {
      if (py::hasattr(instance_, "configure")) {
        instance_.attr("configure")(PythonParameters{scope.alive(), &parameters});
      }
    } catch (py::error_already_set& e) {
      throw std::runtime_error("its Python configure() raised:\n" + traceback_of(e));
    }
  }

  // An integer attribute of the instance (a class attribute the base classes set).
  std::int64_t attribute(const char* key, std::int64_t fallback) const {
    const py::gil_scoped_acquire gil;
    const HoldingGil held(true);
    try {
      if (!py::hasattr(instance_, key)) return fallback;
      return instance_.attr(key).cast<std::int64_t>();
    } catch (const std::exception&) {
      throw std::runtime_error("its attribute '" + std::string(key) + "' is not an integer");
    }
  }

  // Calls `body` with the GIL held; an exception is the sampler's failure `stage`.
  template <class Body>
  std::optional<Failure> call(const std::string& stage, Body&& body) {
    const py::gil_scoped_acquire gil;
    const HoldingGil held(true);
    drop_pending_references();
    try {
      body();
    } catch (py::error_already_set& e) {
      return Failure{stage, "the Python " + kind_ + " '" + name_ + "' raised:\n" + traceback_of(e), {}};
    } catch (const std::exception& e) {
      return Failure{stage, "the Python " + kind_ + " '" + name_ + "' answered what is not allowed: " + e.what(), {}};
    }
    return std::nullopt;
  }

  const py::object& instance() const { return instance_; }
  const std::string& name() const { return name_; }

 private:
  std::string kind_;
  std::string name_;
  py::object instance_;
};

// Runs `work` (C++ only) without the GIL, so that other Python threads go on.
template <class Work>
void without_gil(Work&& work) {
  const py::gil_scoped_release unlocked;
  const HoldingGil released(false);
  work();
}

World view_world(const CallScope& scope, const plugin::PlanningContext& context, const plugin::WorldView& view) {
  return World{scope.alive(), nullptr, &view, &context.scene(), &context.robot()};
}

std::uint64_t mixed_seed(std::uint64_t seed, std::uint64_t salt) {
  std::uint64_t z = seed + 0x9e3779b97f4a7c15ull * (salt + 1);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  return z ^ (z >> 31);
}

class PythonGraspSampler final : public plugin::GraspSampler {
 public:
  PythonGraspSampler(std::string name, py::object instance) : python_("grasp_sampler", std::move(name), std::move(instance)) {}

  void configure(const Parameters& parameters) override {
    python_.configure_python(parameters);
    max_usable_ = std::max<std::int64_t>(1, python_.attribute("max_usable", max_usable_));
  }

  plugin::GraspAnswer sample(plugin::PlanningContext& context, const plugin::GraspQuery& query) override {
    plugin::GraspAnswer answer;
    WorldState empty_handed = query.state;
    empty_handed.held.reset();
    const std::unique_ptr<plugin::WorldView> world = context.world_at(empty_handed);
    if (!world || !context.problem.robot.loaded) {
      answer.failure = Failure{"grasp", "the problem has no robot to grasp with", {}};
      return answer;
    }
    const std::string& id = context.scene().objects.at(query.object).id;
    const Eigen::VectorXd seed =
        query.state.robot_configuration.size() ? query.state.robot_configuration : context.robot().home();
    const manipulation::GraspChecker checker(context, *world, query.object, seed);
    std::size_t proposed = 0;
    const auto failure = python_.call("grasp", [&] {
      const CallScope scope;
      PythonGraspQuery q;
      static_cast<QueryBase&>(q) = {scope.alive(), &context, view_world(scope, context, *world),
                                    mixed_seed(context.seed, query.object)};
      q.object = query.object;
      const py::object proposals = python_.instance().attr("sample")(q);
      if (proposals.is_none()) return;
      for (const py::handle item : py::iter(proposals)) {
        if (context.deadline.expired()) break;
        plugin::Grasp grasp = py::isinstance<plugin::Grasp>(item)
                                  ? item.cast<plugin::Grasp>()
                                  : q.grasp(item.cast<Eigen::Matrix4d>(), 0.10, 0.03, 0.008);
        ++proposed;
        context.count(counter::samples);
        without_gil([&] { checker.check(std::move(grasp), answer); });
        if (static_cast<std::int64_t>(answer.usable.size()) >= max_usable_) break;
      }
    });
    if (failure) {
      answer.usable.clear();
      answer.failure = failure;
    } else if (answer.usable.empty()) {
      answer.failure = proposed == 0 ? Failure{"grasp", "the Python grasp_sampler '" + python_.name() +
                                                            "' proposed no grasp of '" + id + "'",
                                               {}}
                                     : manipulation::GraspChecker::no_usable_grasp(id, answer);
    }
    return answer;
  }

 private:
  PythonSampler python_;
  std::int64_t max_usable_ = 3;
};

class PythonPlacementSampler final : public plugin::PlacementSampler {
 public:
  PythonPlacementSampler(std::string name, py::object instance)
      : python_("placement_sampler", std::move(name), std::move(instance)) {}

  void configure(const Parameters& parameters) override {
    python_.configure_python(parameters);
    max_attempts_ = std::max<std::int64_t>(1, python_.attribute("max_attempts", max_attempts_));
  }

  plugin::PlacementAnswer sample(plugin::PlanningContext& context, const plugin::PlacementQuery& query) override {
    plugin::PlacementAnswer answer;
    const Scene& scene = context.scene();
    const SceneObject& object = scene.objects.at(query.object);
    const Region* region = scene.find_region(query.region);
    if (!region) {
      answer.failure = Failure{"placement", "the scene has no region '" + query.region + "'", {}};
      return answer;
    }
    WorldState empty_handed = query.state;
    empty_handed.held.reset();
    const std::unique_ptr<plugin::WorldView> world = context.world_at(empty_handed);
    if (!world) {
      answer.failure = Failure{"placement", "the problem has no robot", {}};
      return answer;
    }
    const Eigen::VectorXd seed =
        query.state.robot_configuration.size() ? query.state.robot_configuration : context.robot().home();
    const manipulation::PlacementChecker checker(context, *world, query.object, seed);
    std::size_t proposed = 0, touching = 0, unreachable = 0;
    const auto failure = python_.call("placement", [&] {
      const CallScope scope;
      PythonPlacementQuery q;
      static_cast<QueryBase&>(q) = {scope.alive(), &context, view_world(scope, context, *world),
                                    mixed_seed(context.seed, query.object)};
      q.object = query.object;
      q.region = region;
      q.gripper_T_object = query.gripper_T_object;
      q.max_placements = query.max_placements;
      const py::object proposals = python_.instance().attr("sample")(q);
      if (proposals.is_none()) return;
      for (const py::handle item : py::iter(proposals)) {
        if (context.deadline.expired() || static_cast<std::int64_t>(proposed) >= max_attempts_) break;
        const Eigen::Isometry3d pose = isometry_from(item.cast<Eigen::Matrix4d>(), "a proposed world_T_object");
        ++proposed;
        context.count(counter::samples);
        const Eigen::Isometry3d grip =
            query.gripper_T_object ? *query.gripper_T_object : manipulation::PlacementChecker::facing_grip(scene, pose);
        manipulation::PlacementCheck checked;
        without_gil([&] { checked = checker.check(pose, grip); });
        if (checked.verdict == manipulation::PlacementCheck::Verdict::ok) {
          answer.world_T_object.push_back(pose);
          answer.configurations.push_back(checked.configuration);
          if (answer.world_T_object.size() >= query.max_placements) break;
        } else {
          ++(checked.verdict == manipulation::PlacementCheck::Verdict::touches ? touching : unreachable);
        }
      }
    });
    if (failure) {
      answer.world_T_object.clear();
      answer.configurations.clear();
      answer.failure = failure;
    } else if (answer.world_T_object.empty()) {
      answer.failure = Failure{"placement", "no placement of '" + object.id + "' in '" + region->id + "': the Python " +
                                                "placement_sampler '" + python_.name() + "' proposed " +
                                                std::to_string(proposed) + ", " + std::to_string(touching) +
                                                " touched something, " + std::to_string(unreachable) + " were out of reach",
                               {}};
    }
    return answer;
  }

 private:
  PythonSampler python_;
  std::int64_t max_attempts_ = 200;
};

class PythonMotionSampler final : public plugin::MotionSampler {
 public:
  PythonMotionSampler(std::string name, py::object instance)
      : python_("motion_sampler", std::move(name), std::move(instance)) {}

  void configure(const Parameters& parameters) override { python_.configure_python(parameters); }

  plugin::MotionAnswer plan(plugin::PlanningContext& context, const plugin::MotionQuery& query) override {
    plugin::MotionAnswer answer;
    const std::unique_ptr<plugin::WorldView> world = context.world_at(query.state);
    if (!world) {
      answer.failure = Failure{"motion", "the problem has no robot", {}};
      return answer;
    }
    const std::size_t dof = context.robot().model()->variable_count();
    std::vector<Eigen::VectorXd> waypoints;
    bool answered = false;
    auto failure = python_.call("motion", [&] {
      const CallScope scope;
      PythonMotionQuery q;
      static_cast<QueryBase&>(q) = {scope.alive(), &context, view_world(scope, context, *world),
                                    mixed_seed(context.seed, context.counters[counter::samples])};
      q.start = query.start;
      q.goal = query.goal;
      context.count(counter::samples);
      const py::object path = python_.instance().attr("plan")(q);
      if (path.is_none()) return;
      answered = true;
      for (const py::handle row : py::iter(path)) {
        Eigen::VectorXd waypoint = row.cast<Eigen::VectorXd>();
        if (static_cast<std::size_t>(waypoint.size()) != dof || !waypoint.allFinite()) {
          throw std::runtime_error("waypoint " + std::to_string(waypoints.size()) + " has " +
                                   std::to_string(waypoint.size()) + " values (the robot has " + std::to_string(dof) +
                                   " joints), or one is not finite");
        }
        waypoints.push_back(std::move(waypoint));
      }
    });
    if (!failure && !answered) {
      failure = Failure{"motion", "the Python motion_sampler '" + python_.name() + "' found no motion", {}};
    }
    if (!failure) failure = checked(context, *world, query, waypoints);
    if (failure) {
      answer.failure = failure;
      return answer;
    }
    answer.trajectory = manipulation::timed(context.robot(), waypoints);
    return answer;
  }

 private:
  // The motion from the start through `waypoints` to the goal (added where missing),
  // every straight segment free at kMotionResolution; else why not, with what is in the way.
  std::optional<Failure> checked(plugin::PlanningContext& context, const plugin::WorldView& world,
                                 const plugin::MotionQuery& query, std::vector<Eigen::VectorXd>& waypoints) const {
    if (waypoints.empty() || !waypoints.front().isApprox(query.start, 1e-9)) waypoints.insert(waypoints.begin(), query.start);
    if (!waypoints.back().isApprox(query.goal, 1e-9)) waypoints.push_back(query.goal);
    const Eigen::VectorXd lower = context.robot().model()->lower_limits(), upper = context.robot().model()->upper_limits();
    for (std::size_t k = 0; k < waypoints.size(); ++k) {
      if ((waypoints[k].array() < lower.array() - 1e-9).any() || (waypoints[k].array() > upper.array() + 1e-9).any()) {
        return Failure{"motion", "the Python motion_sampler '" + python_.name() + "': waypoint " + std::to_string(k) +
                                     " is outside the joint limits",
                       {}};
      }
    }
    for (std::size_t k = 0; k + 1 < waypoints.size(); ++k) {
      const Eigen::VectorXd& a = waypoints[k];
      const Eigen::VectorXd& b = waypoints[k + 1];
      const int n = std::max(1, static_cast<int>(std::ceil((b - a).cwiseAbs().maxCoeff() / kMotionResolution)));
      for (int s = 0; s <= n; ++s) {
        const Eigen::VectorXd q = a + (b - a) * (double(s) / n);
        context.count(counter::collision_checks);
        if (world.is_valid(q)) continue;
        const plugin::Contacts contacts = world.contacts(q);
        std::string what = contacts.fixed ? "fixed geometry (" + world.describe_fixed_contacts(q) + ")"
                           : contacts.self ? "the robot itself"
                                           : std::to_string(contacts.objects.size()) + " movable object(s)";
        return Failure{"motion", "the Python motion_sampler '" + python_.name() + "': the segment from waypoint " +
                                     std::to_string(k) + " to " + std::to_string(k + 1) + " touches " + what,
                       contacts.fixed || contacts.self ? std::vector<ObjectIndex>{} : contacts.objects};
      }
    }
    return std::nullopt;
  }

  PythonSampler python_;
};

class PythonPushSampler final : public plugin::PushSampler {
 public:
  PythonPushSampler(std::string name, py::object instance)
      : python_("push_sampler", std::move(name), std::move(instance)) {}

  void configure(const Parameters& parameters) override { python_.configure_python(parameters); }

  plugin::PushAnswer push(plugin::PlanningContext& context, const plugin::PushQuery& query) override {
    plugin::PushAnswer answer;
    const Scene& scene = context.scene();
    const physics::PushWorld physics(scene, query.state, physics::push_settings(context.problem));
    const std::string& id = scene.objects.at(query.object).id;
    auto fail = [&](const std::string& reason) {
      answer.failure = Failure{"push", "the Python push_sampler '" + python_.name() + "': " + reason, {}};
      return answer;
    };
    if (!std::binary_search(physics.pushable().begin(), physics.pushable().end(), query.object)) {
      return fail("'" + id + "' cannot be pushed: it is fixed or no longer in the scene");
    }
    std::vector<Eigen::Vector3d> waypoints;
    bool answered = false;
    const auto failure = python_.call("push", [&] {
      const CallScope scope;
      PythonPushQuery q;
      static_cast<QueryBase&>(q) = {scope.alive(), &context, World{scope.alive(), nullptr, nullptr, &scene, nullptr},
                                    mixed_seed(context.seed, query.object)};
      q.state = &query.state;
      q.object = query.object;
      q.goal_xy = query.goal_xy;
      q.goal_radius = query.goal_radius;
      q.gripper = query.gripper;
      q.support = physics.support_region();
      q.footprint_radius = physics.footprint_radius(query.object);
      q.settings = physics.settings();
      const py::object path = python_.instance().attr("push")(q);
      if (path.is_none()) return;
      answered = true;
      for (const py::handle row : py::iter(path)) {
        const Eigen::VectorXd w = row.cast<Eigen::VectorXd>();
        if (w.size() != 3 || !w.allFinite()) {
          throw std::runtime_error("waypoint " + std::to_string(waypoints.size()) + " is not three finite numbers (x, y, yaw)");
        }
        waypoints.emplace_back(w);
      }
    });
    if (failure) {
      answer.failure = failure;
      return answer;
    }
    if (!answered) return fail("found no push of '" + id + "'");
    const physics::KinodynamicSettings settings;
    physics::PushPath path{{physics.state_of(query.state, query.gripper)}, {}, settings.step};
    for (std::size_t k = 0; k < waypoints.size(); ++k) {
      const auto controls = physics::straight_controls(path.states.back().gripper, waypoints[k], settings);
      for (const physics::PushControl& c : controls) {
        context.count(counter::propagations, static_cast<std::uint64_t>(std::lround(c.duration / settings.step)));
      }
      if (!physics::simulate(physics, path, controls)) {
        return fail("on the way to waypoint " + std::to_string(k) +
                    " an object fell or left the support, or the gripper hit fixed geometry or left its region");
      }
    }
    const double off = (path.states.back().objects.at(query.object).pose.head<2>() - query.goal_xy).norm();
    if (off > query.goal_radius) {
      std::ostringstream why;
      why << "'" << id << "' ends " << off << " m from the goal (allowed " << query.goal_radius << " m)";
      return fail(why.str());
    }
    answer.step = physics::push_step(physics, path, query.state);
    answer.resulting_state = physics::world_state_of(query.state, path.states.back());
    answer.gripper_end = path.states.back().gripper;
    return answer;
  }

 private:
  PythonSampler python_;
};

// Makes the adapter of `kind` around a new instance of the Python class `cls`.
std::shared_ptr<plugin::Plugin> make_adapter(const std::string& kind, const std::string& name, const py::object& cls) {
  const py::gil_scoped_acquire gil;
  const HoldingGil held(true);
  py::object instance;
  try {
    instance = cls();
  } catch (py::error_already_set& e) {
    throw std::runtime_error("creating the Python object raised:\n" + traceback_of(e));
  }
  if (kind == "grasp_sampler") return std::make_shared<PythonGraspSampler>(name, std::move(instance));
  if (kind == "placement_sampler") return std::make_shared<PythonPlacementSampler>(name, std::move(instance));
  if (kind == "motion_sampler") return std::make_shared<PythonMotionSampler>(name, std::move(instance));
  return std::make_shared<PythonPushSampler>(name, std::move(instance));
}

const std::vector<std::string>& sampler_kinds() {
  static const std::vector<std::string> kinds{"grasp_sampler", "placement_sampler", "motion_sampler", "push_sampler"};
  return kinds;
}

void provide_sampler(const std::string& kind, const std::string& name, const py::object& cls,
                     const std::string& description, const std::string& origin) {
  const auto& kinds = sampler_kinds();
  if (std::find(kinds.begin(), kinds.end(), kind) == kinds.end()) {
    throw py::value_error("a Python sampler's kind is one of grasp_sampler, placement_sampler, motion_sampler, "
                          "push_sampler, not '" + kind + "'");
  }
  if (!PyCallable_Check(cls.ptr())) throw py::type_error("the sampler must be a class (or a callable making one)");
  // The class is kept until the process ends (the registry keeps every factory): its
  // reference is never dropped, so no thread needs the GIL to forget it.
  auto* kept = new py::object(cls);
  try {
    plugin::provide_plugin({kind, name, description, "", origin,
                            [kind, name, kept] { return make_adapter(kind, name, *kept); }});
  } catch (const std::invalid_argument& e) {
    throw py::value_error(e.what());
  }
}

template <class Query>
void bind_query_base(py::class_<Query>& c) {
  c.def_property_readonly("world", [](const Query& q) { return q.world; })
      .def_property_readonly("seed", [](const Query& q) { return q.seed; })
      .def_property_readonly("configuration", &Query::configuration)
      .def_property_readonly("joint_names", &Query::joint_names)
      .def_property_readonly("remaining_time", &Query::remaining_time)
      .def_property_readonly("world_T_robot_base",
                             [](const Query& q) {
                               q.get();
                               return Eigen::Matrix4d(q.world.scene->world_T_robot_base.matrix());
                             });
}

}  // namespace

py::object world_of(std::shared_ptr<const Problem> problem, const WorldState& state) {
  if (!problem->robot.loaded) throw InputError(problem->robot.where, "the problem has no robot");
  auto owned = std::make_shared<OwnedWorld>();
  owned->problem = problem;
  owned->shared = std::make_unique<collision::SharedWorld>(problem->scene, problem->robot.loaded);
  owned->view = owned->shared->at(state);
  World w{nullptr, owned, owned->view.get(), &problem->scene, problem->robot.loaded.get()};
  return py::cast(w);
}

void bind_samplers(py::module_& m) {
  py::class_<World>(m, "World")
      .def("is_valid", &World::is_valid, py::arg("q"), py::arg("ignored") = std::vector<std::string>{})
      .def("contacts", &World::contacts, py::arg("q"), py::arg("ignored") = std::vector<std::string>{})
      .def("min_distance", &World::min_distance, py::arg("q"), py::arg("ignored") = std::vector<std::string>{})
      .def("tool_pose", &World::tool_pose, py::arg("q"))
      .def("ik", &World::ik, py::arg("world_T_tool"), py::arg("seed") = py::none())
      .def("object_contacts", &World::object_contacts, py::arg("object"), py::arg("world_T_object"),
           py::arg("ignored") = std::vector<std::string>{})
      .def_property_readonly("object_poses", &World::object_poses)
      .def_property_readonly("held", [](const World& w) -> std::optional<std::string> {
        const auto& held = w.get().state().held;
        if (!held) return std::nullopt;
        return w.scene->objects.at(*held).id;
      });

  py::class_<plugin::Grasp>(m, "Grasp")
      .def(py::init<>())
      .def_property(
          "world_T_gripper", [](const plugin::Grasp& g) { return Eigen::Matrix4d(g.world_T_gripper.matrix()); },
          [](plugin::Grasp& g, const Eigen::Matrix4d& m) { g.world_T_gripper = isometry_from(m, "world_T_gripper"); })
      .def_property(
          "world_T_pregrasp", [](const plugin::Grasp& g) { return Eigen::Matrix4d(g.world_T_pregrasp.matrix()); },
          [](plugin::Grasp& g, const Eigen::Matrix4d& m) { g.world_T_pregrasp = isometry_from(m, "world_T_pregrasp"); })
      .def_property(
          "world_T_lift", [](const plugin::Grasp& g) { return Eigen::Matrix4d(g.world_T_lift.matrix()); },
          [](plugin::Grasp& g, const Eigen::Matrix4d& m) { g.world_T_lift = isometry_from(m, "world_T_lift"); })
      .def_property(
          "gripper_T_object", [](const plugin::Grasp& g) { return Eigen::Matrix4d(g.gripper_T_object.matrix()); },
          [](plugin::Grasp& g, const Eigen::Matrix4d& m) { g.gripper_T_object = isometry_from(m, "gripper_T_object"); })
      .def_readwrite("finger_open", &plugin::Grasp::finger_open)
      .def_readwrite("finger_closed", &plugin::Grasp::finger_closed)
      .def("__repr__", [](const plugin::Grasp& g) {
        std::ostringstream out;
        const Eigen::Vector3d p = g.world_T_gripper.translation();
        out << "Grasp(at (" << p.x() << ", " << p.y() << ", " << p.z() << "), fingers " << g.finger_open << " -> "
            << g.finger_closed << " m)";
        return out.str();
      });

  py::class_<PythonParameters>(m, "Parameters")
      .def(
          "number",
          [](const PythonParameters& p, const std::string& key, double fallback, const std::string& help,
             std::optional<double> low, std::optional<double> high) {
            return p.get().get_double(key, fallback, help, PythonParameters::range(low, high));
          },
          py::arg("key"), py::arg("default"), py::arg("help") = "", py::arg("low") = py::none(),
          py::arg("high") = py::none())
      .def(
          "integer",
          [](const PythonParameters& p, const std::string& key, std::int64_t fallback, const std::string& help,
             std::optional<double> low, std::optional<double> high) {
            return p.get().get_int(key, fallback, help, PythonParameters::range(low, high));
          },
          py::arg("key"), py::arg("default"), py::arg("help") = "", py::arg("low") = py::none(),
          py::arg("high") = py::none())
      .def(
          "boolean",
          [](const PythonParameters& p, const std::string& key, bool fallback, const std::string& help) {
            return p.get().get_bool(key, fallback, help);
          },
          py::arg("key"), py::arg("default"), py::arg("help") = "")
      .def(
          "string",
          [](const PythonParameters& p, const std::string& key, const std::string& fallback, const std::string& help) {
            return p.get().get_string(key, fallback, help);
          },
          py::arg("key"), py::arg("default"), py::arg("help") = "")
      .def(
          "numbers",
          [](const PythonParameters& p, const std::string& key, const std::vector<double>& fallback,
             const std::string& help, std::optional<double> low, std::optional<double> high) {
            return p.get().get_vector(key, fallback, help, PythonParameters::range(low, high));
          },
          py::arg("key"), py::arg("default"), py::arg("help") = "", py::arg("low") = py::none(),
          py::arg("high") = py::none())
      .def(
          "require",
          [](const PythonParameters& p, bool ok, const std::string& key, const std::string& what) {
            p.get().require(ok, key, what);
          },
          py::arg("ok"), py::arg("key"), py::arg("what"));

  py::class_<PythonGraspQuery> grasp(m, "GraspQuery");
  bind_query_base(grasp);
  grasp.def_property_readonly("object", [](const PythonGraspQuery& q) { return q.scene_object().id; })
      .def_property_readonly("shape", [](const PythonGraspQuery& q) { return shape_dict(q.scene_object().shape); })
      .def_property_readonly("world_T_object", &PythonGraspQuery::world_T_object)
      .def_property_readonly("gripper_stroke",
                             [](const PythonGraspQuery& q) {
                               q.get();
                               return q.world.robot->gripper().stroke;
                             })
      .def("grasp", &PythonGraspQuery::grasp, py::arg("world_T_gripper"), py::arg("approach") = 0.10,
           py::arg("lift") = 0.03, py::arg("clearance") = 0.008);

  py::class_<PythonPlacementQuery> placement(m, "PlacementQuery");
  bind_query_base(placement);
  placement
      .def_property_readonly("object", [](const PythonPlacementQuery& q) {
        q.get();
        return q.world.scene->objects.at(q.object).id;
      })
      .def_property_readonly("shape", [](const PythonPlacementQuery& q) {
        q.get();
        return shape_dict(q.world.scene->objects.at(q.object).shape);
      })
      .def_property_readonly("region", [](const PythonPlacementQuery& q) {
        q.get();
        return q.region->id;
      })
      .def_property_readonly("world_T_region", [](const PythonPlacementQuery& q) {
        q.get();
        return Eigen::Matrix4d(q.region->world_T_region.matrix());
      })
      .def_property_readonly("region_size", [](const PythonPlacementQuery& q) {
        q.get();
        return Eigen::Vector3d(q.region->size);
      })
      .def_property_readonly("gripper_T_object", [](const PythonPlacementQuery& q) -> std::optional<Eigen::Matrix4d> {
        q.get();
        if (!q.gripper_T_object) return std::nullopt;
        return Eigen::Matrix4d(q.gripper_T_object->matrix());
      })
      .def_property_readonly("max_placements", [](const PythonPlacementQuery& q) { return q.max_placements; });

  py::class_<PythonMotionQuery> motion(m, "MotionQuery");
  bind_query_base(motion);
  motion.def_property_readonly("start", [](const PythonMotionQuery& q) {
          q.get();
          return q.start;
        })
      .def_property_readonly("goal", [](const PythonMotionQuery& q) {
        q.get();
        return q.goal;
      })
      .def_property_readonly("lower_limits",
                             [](const PythonMotionQuery& q) {
                               q.get();
                               return q.world.robot->model()->lower_limits();
                             })
      .def_property_readonly("upper_limits", [](const PythonMotionQuery& q) {
        q.get();
        return q.world.robot->model()->upper_limits();
      });

  py::class_<PythonPushQuery> push(m, "PushQuery");
  push.def_property_readonly("seed", [](const PythonPushQuery& q) { return q.seed; })
      .def_property_readonly("remaining_time", &PythonPushQuery::remaining_time)
      .def_property_readonly("object", [](const PythonPushQuery& q) {
        q.get();
        return q.world.scene->objects.at(q.object).id;
      })
      .def_property_readonly("goal_xy", [](const PythonPushQuery& q) {
        q.get();
        return q.goal_xy;
      })
      .def_property_readonly("goal_radius", [](const PythonPushQuery& q) { return q.goal_radius; })
      .def_property_readonly("footprint_radius", [](const PythonPushQuery& q) { return q.footprint_radius; })
      .def_property_readonly("palm_size", [](const PythonPushQuery& q) { return Eigen::Vector3d(q.settings.gripper_size); })
      .def_property_readonly("finger_length", [](const PythonPushQuery& q) { return q.settings.finger_length; })
      .def_property_readonly("finger_width", [](const PythonPushQuery& q) { return q.settings.finger_width; })
      .def_property_readonly("gripper", [](const PythonPushQuery& q) {
        q.get();
        return q.gripper;
      })
      .def_property_readonly("support", [](const PythonPushQuery& q) {
        q.get();
        return std::pair<Eigen::Vector2d, Eigen::Vector2d>(q.support.min(), q.support.max());
      })
      .def_property_readonly("object_poses", [](const PythonPushQuery& q) {
        q.get();
        std::map<std::string, Eigen::Matrix4d> out;
        for (std::size_t i = 0; i < q.world.scene->objects.size(); ++i) {
          if (!q.state->removed.at(i)) out[q.world.scene->objects[i].id] = q.state->world_T_objects.at(i).matrix();
        }
        return out;
      });

  m.def("provide_sampler", &provide_sampler, py::arg("kind"), py::arg("name"), py::arg("cls"),
        py::arg("description") = "", py::arg("origin") = "python");
  m.def(
      "withdraw_sampler", [](const std::string& kind, const std::string& name) { return plugin::withdraw_plugin(kind, name); },
      py::arg("kind"), py::arg("name"));
  m.def("sampler_kinds", [] { return sampler_kinds(); });
}

}  // namespace cluttertamp::python
