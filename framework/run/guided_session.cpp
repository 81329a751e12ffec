#include "cluttertamp/run/guided_session.hpp"

#include <memory>
#include <algorithm>
#include <cmath>
#include <sstream>

#include <nlohmann/json.hpp>

#include "cluttertamp/io/guidance_io.hpp"
#include "cluttertamp/io/shape_json.hpp"
#include "cluttertamp/physics/push_planning.hpp"
#include "cluttertamp/plugin/push_sampler.hpp"
#include "cluttertamp/robot/robot_description.hpp"
#include "cluttertamp/run/runner.hpp"

namespace cluttertamp::run {

namespace {
using Clock = std::chrono::steady_clock;
using Json = nlohmann::ordered_json;

double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

std::string fixed3(double v) {
  std::ostringstream out;
  out.setf(std::ios::fixed);
  out.precision(3);
  out << v;
  return out.str();
}

Json box_json(const Eigen::AlignedBox2d& b) { return {b.min().x(), b.min().y(), b.max().x(), b.max().y()}; }

// The problem as the session plans it: a push sampler named, the default one if need be.
Problem with_push_sampler(Problem problem, const GuidedSessionOptions& options) {
  if (!problem.samplers.count(plugin::KindOf<plugin::PushSampler>::name)) {
    problem.samplers[plugin::KindOf<plugin::PushSampler>::name] = PluginChoice{options.default_push_sampler, {}, {problem.source_file.string(), 0, 0}};
  }
  return problem;
}
}  // namespace

struct GuidedSession::Impl {
  Problem problem;
  GuidedSessionOptions options;
  Plugins plugins;
  physics::KinodynamicSettings search;
  physics::ReachTolerances reach;
  physics::PushSettings push;  // the problem's physics: what pushes
  std::unique_ptr<physics::PushWorld> start_world;  // at the start: where the hand is for a pose
  Clock::time_point started = Clock::now();
  std::map<std::string, std::uint64_t> counters;
  WorldState state;
  Eigen::Vector3d gripper;
  Eigen::AlignedBox2d shelf;  // where guide regions must lie: the support
  Eigen::AlignedBox2d view;   // what the page shows: the gripper's region
  Result result;
  io::HumanGuidance record;
  Guidance guidance;  // the satisfied guides
  double planning = 0.0;       // s, every input's and the reach's
  bool finished = false;
  Clock::time_point finished_at;

  double time_left() const { return std::max(0.0, problem.time_limit - planning); }

  plugin::PlanningContext context(double seconds, std::uint64_t salt) {
    return {problem, plugin::Deadline::after(seconds), problem.seed + salt, counters, plugins.samplers, nullptr};
  }

  io::RunInfo info() const {
    io::RunInfo run{"operator (GRTC-HITL) + " + search.planner, problem.time_limit, problem.seed,
                    finished ? (result.solved ? ExitCode::solved : ExitCode::no_plan) : ExitCode::no_plan, record};
    // The operator's time ends when the robot takes over.
    const double wall = std::chrono::duration<double>((finished ? finished_at : Clock::now()) - started).count();
    run.human_guidance->interaction_time = std::max(0.0, wall - planning);
    return run;
  }
};

GuidedSession::GuidedSession(Problem problem, const plugin::Registry& registry, GuidedSessionOptions options)
    : impl_(std::make_unique<Impl>()) {
  Impl& s = *impl_;
  if (!std::holds_alternative<ReachTask>(problem.task)) {
    throw InputError({problem.source_file.string(), 0, 0}, "guided sessions need a problem with task: {reach: <target>}");
  }
  s.problem = with_push_sampler(std::move(problem), options);
  s.options = options;
  s.plugins = create_plugins(s.problem, registry);
  // The reach takes the problem planner's kinodynamic settings and tolerances.
  s.search.read(s.problem.planner.parameters);
  s.reach.read(s.problem.planner.parameters);
  s.state = WorldState::initial(s.problem.scene);
  s.state.robot_configuration = robot::initial_configuration(s.problem.robot);
  s.push = physics::push_settings(s.problem);
  s.start_world = std::make_unique<physics::PushWorld>(s.problem.scene, s.state, s.push);
  s.gripper = s.start_world->start_pose();
  s.shelf = s.start_world->support_region();
  s.view = s.start_world->gripper_region();
  s.result.reason = "the operator has not let the robot finish";
}

GuidedSession::~GuidedSession() = default;

const Problem& GuidedSession::problem() const { return impl_->problem; }
bool GuidedSession::finished() const { return impl_->finished; }
double GuidedSession::time_left() const { return impl_->time_left(); }

GuidedSession::Outcome GuidedSession::guide(const std::string& object, const Eigen::Vector2d& centre,
                                            std::optional<double> diameter) {
  Impl& s = *impl_;
  const Scene& scene = s.problem.scene;
  if (s.finished) return {false, false, "the session is finished"};
  const auto index = scene.find_object(object);
  if (!index) return {false, false, "no object '" + object + "' in the scene"};
  if (!scene.objects[*index].movable) return {false, false, "'" + object + "' is fixed: it cannot be pushed"};
  const double d = diameter.value_or(s.options.diameter);
  if (!(d > 0) || !std::isfinite(d) || !centre.allFinite()) return {false, false, "the region needs a finite centre and a positive diameter"};
  Eigen::AlignedBox2d inner = s.shelf;
  inner.min().array() += d / 2;
  inner.max().array() -= d / 2;
  if (inner.isEmpty() || !inner.contains(centre)) {
    return {false, false, "the " + fixed3(d) + " m region about (" + fixed3(centre.x()) + ", " + fixed3(centre.y()) +
                       ") does not lie on the shelf [" + fixed3(s.shelf.min().x()) + ", " + fixed3(s.shelf.max().x()) + "] x [" +
                       fixed3(s.shelf.min().y()) + ", " + fixed3(s.shelf.max().y()) + "]"};
  }
  if (s.time_left() <= 0) return {false, false, "no planning time is left (time limit " + fixed3(s.problem.time_limit) + " s)"};

  io::OperatorInput input{object, centre, d, false, 0.0, {}};
  const auto t0 = Clock::now();
  plugin::PlanningContext context = s.context(std::min(s.options.push_time, s.time_left()), s.record.inputs.size() + 1);
  plugin::PushAnswer answer = s.plugins.samplers.get<plugin::PushSampler>()->push(context, {*index, centre, d / 2, s.state, s.gripper});
  input.planning_time = seconds_since(t0);
  s.planning += input.planning_time;
  Outcome out;
  if (answer.step && answer.resulting_state) {
    const int k = static_cast<int>(s.guidance.size()) + 1;
    answer.step->values["guide"] = {double(k)};
    answer.step->values["region"] = {centre.x(), centre.y(), d};
    for (ObjectIndex i : answer.step->objects) {
      if (std::find(s.result.moved_objects.begin(), s.result.moved_objects.end(), i) == s.result.moved_objects.end()) {
        s.result.moved_objects.push_back(i);
      }
    }
    s.result.plan.push_back(std::move(*answer.step));
    s.state = std::move(*answer.resulting_state);
    s.gripper = answer.gripper_end;
    s.guidance.push_back({*index, centre, d, {}});
    input.satisfied = true;
    out = {true, true, "pushed " + object + " into its region in " + fixed3(input.planning_time) + " s"};
  } else {
    input.reason = answer.failure ? answer.failure->reason : "the push sampler gave no push and no reason";
    if (answer.failure) s.result.failures.push_back(*answer.failure);
    out = {false, true, "could not push " + object + " there (" + fixed3(input.planning_time) + " s): " + input.reason};
  }
  s.record.inputs.push_back(std::move(input));
  s.result.time.task_planning = s.planning;
  s.result.time.total = s.planning;
  return out;
}

GuidedSession::Outcome GuidedSession::finish() {
  Impl& s = *impl_;
  if (s.finished) return {false, false, "the session is finished"};
  const Scene& scene = s.problem.scene;
  const auto t0 = Clock::now();
  const physics::PushWorld world(scene, s.state, s.push);
  const physics::ReachGoal goal(world, scene.target, s.reach);
  const physics::KinodynamicOutcome out = physics::plan_pushes(world, world.state_of(s.state, s.gripper), goal, s.search,
                                                               physics::PushBudget::of(s.search, s.time_left()),
                                                               s.problem.seed + s.record.inputs.size() + 1);
  const double reach_time = seconds_since(t0);
  s.planning += reach_time;
  s.finished = true;
  s.finished_at = Clock::now();
  s.counters[counter::propagations] += out.propagations;
  s.result.counters = s.counters;
  s.result.counters[counter::guides] = s.guidance.size();
  s.result.time.motion_planning = reach_time;
  s.result.time.total = s.planning;
  if (!out.path) {
    s.result.reason = "reaching the target after " + std::to_string(s.guidance.size()) + " guides failed: " + out.reason;
    s.result.failures.push_back({"reach", s.result.reason, {}});
    return {false, true, s.result.reason};
  }
  s.result.plan.push_back(physics::push_step(world, *out.path, s.state));
  s.state = physics::world_state_of(s.state, out.path->states.back());
  s.gripper = out.path->states.back().gripper;
  s.result.solved = true;
  s.result.reason.clear();
  return {true, true, "the robot reached the target in " + fixed3(reach_time) + " s of planning"};
}

std::string GuidedSession::guidance_yaml() const { return io::guidance_to_yaml(impl_->problem.scene, impl_->guidance); }

std::string GuidedSession::result_json() const {
  return io::result_to_json(impl_->problem, impl_->result, impl_->info());
}

namespace {
// The gripper's palm and fingers from above: [x, y, depth, width] each, gripper frame, m.
Json gripper_boxes_json(const physics::PushSettings& settings) {
  Json boxes = Json::array();
  for (const physics::GripperBox& b : physics::gripper_boxes(settings)) {
    boxes.push_back({b.offset.x(), b.offset.y(), b.size.x(), b.size.y()});
  }
  return boxes;
}
}  // namespace

std::string GuidedSession::state_json() const {
  const Impl& s = *impl_;
  const Scene& scene = s.problem.scene;
  const physics::PushSettings& settings = s.push;
  Json objects = Json::array();
  for (ObjectIndex i = 0; i < scene.objects.size(); ++i) {
    const SceneObject& o = scene.objects[i];
    const Eigen::Isometry3d& pose = s.state.world_T_objects[i];
    objects.push_back({{"id", o.id}, {"shape", io::shape_json(o.shape)},
                       {"pose", {pose.translation().x(), pose.translation().y(), yaw_of(pose)}},
                       {"role", i == scene.target ? "target" : o.movable ? "movable" : "fixed"}});
  }
  // Walls and boards that meet the gripper's plane, as footprints.
  const double top = world_bounds(scene.objects[scene.target].shape, s.state.world_T_objects[scene.target]).min().z();
  Json walls = Json::array();
  for (const FixedBody& f : scene.fixed) {
    const Eigen::AlignedBox3d b = world_bounds(f.shape, f.world_T_body);
    if (b.max().z() > top + 0.005 && b.min().z() < top + settings.gripper_clearance + settings.gripper_size.z()) {
      walls.push_back({{"id", f.id}, {"box", {b.min().x(), b.min().y(), b.max().x(), b.max().y()}}});
    }
  }
  Json log = Json::array();
  for (const io::OperatorInput& in : s.record.inputs) {
    log.push_back({{"object", in.object}, {"centre", {in.centre.x(), in.centre.y()}}, {"diameter", in.diameter},
                   {"satisfied", in.satisfied}, {"planning_time", in.planning_time}, {"reason", in.reason}});
  }
  const io::RunInfo info = s.info();
  // The page draws the hand: the floating gripper, or the arm's tool drawn as one.
  const Eigen::Vector3d hand = s.start_world->hand(s.gripper);
  Json out{{"problem", s.problem.name},
           {"shelf", box_json(s.shelf)},
           {"view", box_json(s.view)},
           {"walls", walls},
           {"objects", objects},
           {"gripper", {{"pose", {hand.x(), hand.y(), hand.z()}}, {"boxes", gripper_boxes_json(settings)}}},
           {"diameter", s.options.diameter},
           {"time_limit", s.problem.time_limit},
           {"time_left", s.time_left()},
           {"planning_time", s.planning},
           {"interaction_time", info.human_guidance->interaction_time},
           {"inputs", log},
           {"finished", s.finished},
           {"solved", s.result.solved},
           {"reason", s.result.reason}};
  return out.dump(-1, ' ', false, Json::error_handler_t::replace);
}

}  // namespace cluttertamp::run
