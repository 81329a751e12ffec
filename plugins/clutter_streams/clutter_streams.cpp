// clutter_streams: the streams of domains/pddl/clutter-streams/stream.pddl over the
// run's grasp, placement and motion samplers.
//  - plan-pick (?o ?p) -> (?g ?t): a grasp of o standing at p and a trajectory from
//    the robot's home through pre-grasp, approach, grasp, lift and retreat back home.
//  - plan-place (?o ?g ?r) -> (?p ?t): a stable pose in region r and a trajectory from
//    home, holding o with g, down to it, releasing it and back home.
//  - test-cfree-traj-pose (?t ?o2 ?p2): t (robot and held object) misses o2 at p2.
//  - test-cfree-pose-pose (?o ?p ?o2 ?p2): o at p and o2 at p2 do not overlap.
// A pick is planned among the other objects where the scene file has them, ignoring
// those that blocked the tries before (so a trajectory passes through as few of them as
// it can), at last among the fixed geometry alone; a placement among the fixed geometry
// alone. Objects that are not movable (a pruner's obstacles, which stay where they
// stand) count as fixed geometry: every motion and placement avoids them, and no test
// is asked about them. The tests then say which movable objects are in the way where
// they actually stand, so the symbolic search can move them.
// Successive calls of a generator draw afresh (seeds derived from the run's) and try
// the grasps in another order.

#include <algorithm>
#include <cmath>
#include <functional>
#include <random>
#include <set>
#include <string>

#include "cluttertamp/core/geometry.hpp"
#include "cluttertamp/core/problem.hpp"
#include "cluttertamp/manipulation/actions.hpp"
#include "cluttertamp/pddl/sexpr.hpp"
#include "cluttertamp/plugin/export.hpp"
#include "cluttertamp/plugin/grasp_sampler.hpp"
#include "cluttertamp/plugin/motion_sampler.hpp"
#include "cluttertamp/plugin/placement_sampler.hpp"
#include "cluttertamp/plugin/stream_sampler.hpp"
#include "cluttertamp/robot/robot_description.hpp"

namespace {

using namespace cluttertamp;
using plugin::StreamBatch;
using plugin::StreamValue;

/// How an object is held: its pose in the tool frame.
class GraspValue final : public plugin::StreamPayload {
 public:
  explicit GraspValue(const Eigen::Isometry3d& gripper_T_object) : gripper_T_object_(gripper_T_object) {}
  std::vector<double> numbers() const override { return pose_values(gripper_T_object_); }
  const Eigen::Isometry3d& gripper_T_object() const { return gripper_T_object_; }

 private:
  Eigen::Isometry3d gripper_T_object_;
};

/// A home-to-home manipulation: its segments, which of them carry the object, and the
/// whole as one trajectory for the plan.
class MotionValue final : public plugin::StreamPayload {
 public:
  struct Part {
    manipulation::Segment segment;
    bool held = false;
  };
  MotionValue(ObjectIndex object, const Eigen::Isometry3d& gripper_T_object, std::vector<Part> parts)
      : object_(object), gripper_T_object_(gripper_T_object), parts_(std::move(parts)) {
    double offset = 0;
    for (const Part& p : parts_) {
      const Trajectory& t = p.segment.trajectory;
      whole_.joint_names = t.joint_names;
      for (std::size_t i = 0; i < t.positions.size(); ++i) {
        if (!whole_.positions.empty() && i == 0 && (t.positions[0] - whole_.positions.back()).norm() < 1e-12) continue;
        whole_.times.push_back(offset + t.times[i]);
        whole_.positions.push_back(t.positions[i]);
      }
      if (!t.times.empty()) offset += t.times.back();
    }
  }
  const Trajectory* trajectory() const override { return &whole_; }
  ObjectIndex object() const { return object_; }
  const Eigen::Isometry3d& gripper_T_object() const { return gripper_T_object_; }
  const std::vector<Part>& parts() const { return parts_; }

 private:
  ObjectIndex object_;
  Eigen::Isometry3d gripper_T_object_;
  std::vector<Part> parts_;
  Trajectory whole_;
};

/// The grasp sampler's usable grasps, shuffled for every call of a pick generator but
/// the first (which keeps the sampler's order, best first): the k-th call tries the
/// grasps in another order, so its trajectory comes from another direction.
class ShuffledGrasps final : public plugin::GraspSampler {
 public:
  ShuffledGrasps(std::shared_ptr<plugin::GraspSampler> inner, std::size_t call, std::uint64_t seed)
      : inner_(std::move(inner)), call_(call), seed_(seed) {}
  plugin::GraspAnswer sample(plugin::PlanningContext& context, const plugin::GraspQuery& query) override {
    plugin::GraspAnswer a = inner_->sample(context, query);
    if (call_ > 0) {
      std::mt19937_64 rng(seed_);
      std::shuffle(a.usable.begin(), a.usable.end(), rng);
    }
    return a;
  }

 private:
  std::shared_ptr<plugin::GraspSampler> inner_;
  std::size_t call_;
  std::uint64_t seed_;
};

std::uint64_t mix(std::uint64_t a, std::uint64_t b) {
  a ^= b + 0x9e3779b97f4a7c15ull + (a << 6) + (a >> 2);
  return a;
}

std::uint64_t pose_hash(const Eigen::Isometry3d& p) {
  std::uint64_t h = 0;
  for (double v : pose_values(p)) h = mix(h, std::hash<long long>{}(std::llround(v * 1e6)));
  return h;
}

struct Settings {
  double resolution = 0.02;  // rad between collision checks along a trajectory
  std::int64_t call_max_checks = 1500000;  // collision checks a generator's call may make at most
};

/// What every generator needs: the scene objects by name, the empty world, home.
class Streams {
 public:
  Streams(plugin::PlanningContext& context, const Settings& settings) : settings_(settings) {
    const Scene& scene = context.scene();
    home_ = robot::initial_configuration(context.problem.robot);
    empty_ = WorldState::initial(scene);
    empty_.robot_configuration = home_;
    std::fill(empty_.removed.begin(), empty_.removed.end(), true);
    fixed_ = empty_;
    for (ObjectIndex o = 0; o < scene.objects.size(); ++o) fixed_.removed[o] = scene.objects[o].movable;
  }

  ObjectIndex object(const plugin::PlanningContext& context, const StreamValue& v) const {
    const std::string& name = std::get<std::string>(v);
    for (ObjectIndex i = 0; i < context.scene().objects.size(); ++i) {
      if (pddl::lower_name(context.scene().objects[i].id) == name) return i;
    }
    throw std::invalid_argument("clutter_streams: '" + name + "' is no object of the scene");
  }

  /// Only `object` in the world, at `pose`; the robot at home (what a test checks against).
  WorldState alone(ObjectIndex object, const Eigen::Isometry3d& pose) const { return with(empty_, object, pose); }

  /// `object` at `pose` among the objects that never move; the robot at home (where a
  /// motion is planned when no movable object counts).
  WorldState among_fixed(ObjectIndex object, const Eigen::Isometry3d& pose) const { return with(fixed_, object, pose); }

  /// `object` at `pose`, the others where the scene has them unless `ignored` or resting,
  /// directly or through others, on `object` or an ignored object: the domain lets
  /// nothing be picked before what rests on it (Clear), so those are gone by then.
  WorldState among(const Scene& scene, ObjectIndex object, const Eigen::Isometry3d& pose,
                   const std::set<ObjectIndex>& ignored) const {
    std::vector<bool> gone(scene.objects.size(), false);
    gone[object] = true;
    for (ObjectIndex o : ignored) gone[o] = true;
    scene.mark_what_rests_on(gone);
    WorldState s = among_fixed(object, pose);
    for (ObjectIndex o = 0; o < scene.objects.size(); ++o) {
      if (!gone[o]) s.removed[o] = false;
    }
    return s;
  }

  /// A context for one call: its own seed and samplers, a work budget of at most
  /// call_max_checks collision checks (work, not time: a call's values do not depend on
  /// the machine).
  plugin::PlanningContext call_context(plugin::PlanningContext& context, plugin::Samplers& samplers, std::uint64_t seed) const {
    plugin::PlanningContext c{context.problem, context.deadline, seed, context.counters, samplers, context.worlds,
                              context.checks_until};
    return c.with_checks(static_cast<std::uint64_t>(settings_.call_max_checks));
  }

  /// Plans from the end of `outcome` back home, appending a "return" segment. A pick
  /// carries its object out backwards along the approach first (manipulation::move_out:
  /// the planner's trees alone took up to 0.6 s to leave the shelf, and their random
  /// ways out hit neighbours the search then had to move). After a placement the open
  /// fingers may still touch the object they let go of (when no retreat was
  /// possible): that object is left out of the return's planning.
  bool return_home(plugin::PlanningContext& context, manipulation::ActionOutcome& outcome, std::optional<Failure>& why,
                   std::optional<ObjectIndex> released = std::nullopt) const {
    WorldState from = outcome.after;
    std::optional<Trajectory> back;
    if (released) {
      from.removed[*released] = true;
      plugin::MotionAnswer a = context.samplers.get<plugin::MotionSampler>()->plan(context, plugin::MotionQuery{from.robot_configuration, home_, from});
      back = std::move(a.trajectory);
      why = a.failure;
    } else {
      back = manipulation::move_out(context, from, home_, why);
    }
    if (!back) {
      if (!why) why = Failure{"motion", "no way back home", {}};
      return false;
    }
    outcome.segments.push_back({"return", std::move(*back)});
    return true;
  }

  const Eigen::VectorXd& home() const { return home_; }
  const Settings& settings() const { return settings_; }

 private:
  static WorldState with(WorldState s, ObjectIndex object, const Eigen::Isometry3d& pose) {
    s.removed[object] = false;
    s.world_T_objects[object] = pose;
    return s;
  }

  const Settings& settings_;
  Eigen::VectorXd home_;
  WorldState empty_;  // no object
  WorldState fixed_;  // the objects that are not movable, where they stand
};

std::optional<Failure> failure_of(const manipulation::ActionOutcome& o, const std::string& fallback) {
  return o.failure ? o.failure : Failure{"stream", fallback, {}};
}

class PlanPick final : public plugin::StreamGenerator {
 public:
  PlanPick(std::shared_ptr<const Streams> streams, ObjectIndex object, Eigen::Isometry3d pose, std::uint64_t seed)
      : streams_(std::move(streams)), object_(object), pose_(pose), seed_(seed) {}

  StreamBatch next(plugin::PlanningContext& context) override {
    StreamBatch batch;
    plugin::Samplers samplers = context.samplers;
    const std::uint64_t seed = mix(seed_, calls_);
    samplers.set<plugin::GraspSampler>(std::make_shared<ShuffledGrasps>(context.samplers.get<plugin::GraspSampler>(), calls_++, seed));
    plugin::PlanningContext c = streams_->call_context(context, samplers, seed);
    // Among the other objects where the scene has them, ignoring those that blocked the
    // tries before (so that a trajectory passes through as few objects as it can), and
    // at last among the fixed geometry alone.
    manipulation::ActionOutcome picked;
    std::set<ObjectIndex> ignored;
    for (int attempt = 0; attempt < 4 && !c.stopped(); ++attempt) {
      picked = manipulation::pick(c, streams_->among(context.scene(), object_, pose_, ignored), object_);
      if (picked.ok) break;
      const std::size_t before = ignored.size();
      if (picked.failure) ignored.insert(picked.failure->blocking_objects.begin(), picked.failure->blocking_objects.end());
      if (ignored.size() == before) break;
    }
    if (!picked.ok && !c.stopped()) picked = manipulation::pick(c, streams_->among_fixed(object_, pose_), object_);
    std::optional<Failure> why;
    if (!picked.ok || !picked.grasp || !streams_->return_home(c, picked, why)) {
      batch.failure = picked.ok ? why : failure_of(picked, "no pick");
      return batch;
    }
    const Eigen::Isometry3d gripper_T_object = picked.grasp->gripper_T_object;
    std::vector<MotionValue::Part> parts;
    bool held = false;
    for (manipulation::Segment& s : picked.segments) {
      held = held || s.name == "lift";
      parts.push_back({std::move(s), held});
    }
    batch.outputs.push_back({std::make_shared<const GraspValue>(gripper_T_object),
                             std::make_shared<const MotionValue>(object_, gripper_T_object, std::move(parts))});
    return batch;
  }

 private:
  std::shared_ptr<const Streams> streams_;
  ObjectIndex object_;
  Eigen::Isometry3d pose_;
  std::uint64_t seed_;
  std::size_t calls_ = 0;
};

class PlanPlace final : public plugin::StreamGenerator {
 public:
  PlanPlace(std::shared_ptr<const Streams> streams, ObjectIndex object, std::shared_ptr<const GraspValue> grasp,
            std::string region, std::uint64_t seed)
      : streams_(std::move(streams)), object_(object), grasp_(std::move(grasp)), region_(std::move(region)), seed_(seed) {}

  StreamBatch next(plugin::PlanningContext& context) override {
    StreamBatch batch;
    plugin::Samplers samplers = context.samplers;
    plugin::PlanningContext c = streams_->call_context(context, samplers, mix(seed_, calls_++));
    WorldState state = streams_->among_fixed(object_, Eigen::Isometry3d::Identity());
    state.world_T_objects[object_] = c.world_at(state)->tool_pose(streams_->home()) * grasp_->gripper_T_object();
    state.held = object_;
    manipulation::ActionOutcome placed = manipulation::place(c, state, region_);
    std::optional<Failure> why;
    if (!placed.ok || !streams_->return_home(c, placed, why, object_)) {
      batch.failure = placed.ok ? why : failure_of(placed, "no placement");
      return batch;
    }
    const Eigen::Isometry3d pose = placed.after.world_T_objects[object_];
    std::vector<MotionValue::Part> parts;
    for (manipulation::Segment& s : placed.segments) {
      const bool held = s.name == "transfer" || s.name == "place";
      parts.push_back({std::move(s), held});
    }
    batch.outputs.push_back({pose, std::make_shared<const MotionValue>(object_, grasp_->gripper_T_object(), std::move(parts))});
    return batch;
  }

 private:
  std::shared_ptr<const Streams> streams_;
  ObjectIndex object_;
  std::shared_ptr<const GraspValue> grasp_;
  std::string region_;
  std::uint64_t seed_;
  std::size_t calls_ = 0;
};

/// A test: computed once, on the first call.
class Test final : public plugin::StreamGenerator {
 public:
  explicit Test(std::function<std::optional<Failure>(plugin::PlanningContext&)> check) : check_(std::move(check)) {}
  StreamBatch next(plugin::PlanningContext& context) override {
    StreamBatch batch;
    batch.exhausted = true;
    if (auto failure = check_(context)) batch.failure = failure;
    else batch.outputs.push_back({});
    return batch;
  }

 private:
  std::function<std::optional<Failure>(plugin::PlanningContext&)> check_;
};

// Does `motion` (robot, and the object while held) touch `other` standing at `pose`?
std::optional<Failure> trajectory_hits(plugin::PlanningContext& context, const Streams& streams, const MotionValue& motion,
                                       ObjectIndex other, const Eigen::Isometry3d& pose) {
  if (other == motion.object()) return std::nullopt;  // the object it moves
  WorldState state = streams.alone(other, pose);
  const std::unique_ptr<plugin::WorldView> robot_only = context.world_at(state);  // the tool's poses
  const auto& supports = context.scene().objects[motion.object()].supports;
  const bool supported_by_other = std::find(supports.begin(), supports.end(), other) != supports.end();
  for (const MotionValue::Part& part : motion.parts()) {
    const auto& q = part.segment.trajectory.positions;
    if (q.empty()) continue;
    state.held.reset();
    state.removed[motion.object()] = true;
    if (part.held) {
      state.held = motion.object();
      state.removed[motion.object()] = false;
      state.robot_configuration = q.front();
      state.world_T_objects[motion.object()] = robot_only->tool_pose(q.front()) * motion.gripper_T_object();
    }
    const std::unique_ptr<plugin::WorldView> world = context.world_at(state);
    // Lifting off a support starts in contact with it: that touch is no collision.
    const std::size_t skip = part.held && supported_by_other && part.segment.name == "lift" ? 2 : 0;
    std::size_t step = 0;
    for (std::size_t i = 0; i < q.size(); ++i) {
      const std::size_t n = i == 0 ? 1 : std::max<std::size_t>(1, static_cast<std::size_t>(std::ceil(
                                                                      (q[i] - q[i - 1]).cwiseAbs().maxCoeff() / streams.settings().resolution)));
      for (std::size_t k = 1; k <= n; ++k, ++step) {
        const Eigen::VectorXd at = i == 0 ? q[0] : Eigen::VectorXd(q[i - 1] + (q[i] - q[i - 1]) * (double(k) / double(n)));
        if (step < skip) continue;
        context.count(counter::collision_checks);
        if (world->touches_object(at)) {  // `other` is the only object present
          return Failure{"test-cfree-traj-pose", "the " + part.segment.name + " motion of '" +
                                                     context.scene().objects[motion.object()].id + "' hits '" +
                                                     context.scene().objects[other].id + "'",
                         {other}};
        }
      }
    }
  }
  return std::nullopt;
}

class ClutterStreams final : public plugin::StreamSampler {
 public:
  void configure(const Parameters& p) override {
    settings_.resolution = p.get_double("resolution", settings_.resolution,
                                        "rad between collision checks along a trajectory", Range::open(0, 1));
    p.require(!p.contains("call_time"), "call_time",
              "is no longer read: a call's budget is work, so that a seed gives the same values on any machine; "
              "set call_max_checks (collision checks per call, default 1500000)");
    settings_.call_max_checks = p.get_int("call_max_checks", settings_.call_max_checks,
                                          "collision checks per generator call (the work budget)", Range::above(0));
  }

  std::unique_ptr<plugin::StreamGenerator> instantiate(plugin::PlanningContext& context, std::string_view stream,
                                                       const std::vector<StreamValue>& in,
                                                       const std::vector<plugin::StreamFact>&) override {
    if (!context.worlds || !context.problem.robot.loaded || !context.samplers.get<plugin::GraspSampler>() || !context.samplers.get<plugin::PlacementSampler>() ||
        !context.samplers.get<plugin::MotionSampler>()) {
      throw std::invalid_argument("clutter_streams needs a robot and grasp, placement and motion samplers");
    }
    if (!streams_ || &context.problem != problem_) {
      streams_ = std::make_shared<const Streams>(context, settings_);
      problem_ = &context.problem;
    }
    const std::uint64_t seed = mix(context.seed, std::hash<std::string_view>{}(stream));
    if (stream == "plan-pick") {
      const Eigen::Isometry3d pose = std::get<Eigen::Isometry3d>(in.at(1));
      const ObjectIndex o = streams_->object(context, in.at(0));
      return std::make_unique<PlanPick>(streams_, o, pose, mix(mix(seed, o), pose_hash(pose)));
    }
    if (stream == "plan-place") {
      const ObjectIndex o = streams_->object(context, in.at(0));
      auto grasp = std::dynamic_pointer_cast<const GraspValue>(std::get<std::shared_ptr<const plugin::StreamPayload>>(in.at(1)));
      const std::string region = std::get<std::string>(in.at(2));
      return std::make_unique<PlanPlace>(streams_, o, grasp, region_id(context, region),
                                         mix(mix(seed, o), pose_hash(grasp->gripper_T_object())));
    }
    if (stream == "test-cfree-traj-pose") {
      auto motion = std::dynamic_pointer_cast<const MotionValue>(std::get<std::shared_ptr<const plugin::StreamPayload>>(in.at(0)));
      const ObjectIndex other = streams_->object(context, in.at(1));
      const Eigen::Isometry3d pose = std::get<Eigen::Isometry3d>(in.at(2));
      auto streams = streams_;
      return std::make_unique<Test>([=](plugin::PlanningContext& c) { return trajectory_hits(c, *streams, *motion, other, pose); });
    }
    if (stream == "test-cfree-pose-pose") {
      const ObjectIndex a = streams_->object(context, in.at(0)), b = streams_->object(context, in.at(2));
      const Eigen::Isometry3d pa = std::get<Eigen::Isometry3d>(in.at(1)), pb = std::get<Eigen::Isometry3d>(in.at(3));
      auto streams = streams_;
      return std::make_unique<Test>([=](plugin::PlanningContext& c) -> std::optional<Failure> {
        if (a == b) return std::nullopt;
        const ObjectIndex ignore[] = {a};
        const plugin::Contacts r = c.world_at(streams->alone(b, pb))->shape_contacts(c.scene().objects[a].shape, pa, ignore);
        if (std::find(r.objects.begin(), r.objects.end(), b) == r.objects.end()) return std::nullopt;
        return Failure{"test-cfree-pose-pose", "'" + c.scene().objects[a].id + "' would overlap '" + c.scene().objects[b].id + "'", {b}};
      });
    }
    throw std::invalid_argument("clutter_streams has no stream '" + std::string(stream) +
                                "' (it has plan-pick, plan-place, test-cfree-traj-pose, test-cfree-pose-pose)");
  }

 private:
  static std::string region_id(const plugin::PlanningContext& context, const std::string& lowered) {
    for (const Region& r : context.scene().regions) {
      if (pddl::lower_name(r.id) == lowered) return r.id;
    }
    throw std::invalid_argument("clutter_streams: '" + lowered + "' is no region of the scene");
  }

  Settings settings_;
  std::shared_ptr<const Streams> streams_;
  const Problem* problem_ = nullptr;
};

}  // namespace

CLUTTERTAMP_EXPORT_STREAM_SAMPLER(ClutterStreams, clutter_streams,
                                  "Pick, place and collision-test streams for domains/pddl/clutter-streams", "1.0.0")
