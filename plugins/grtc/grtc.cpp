// grtc: guided reaching through clutter (Papallas & Dogar, ICRA 2020, Algorithm 1).
// A guidance is an ordered list of guides (object, region); each is satisfied with the
// run's push sampler, from wherever the gripper stopped, and then the remaining
// reaching problem is solved by kinodynamic planning in the time that is left. The
// guidance comes from a file or from physics::generate_guidance.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <sstream>

#include "cluttertamp/io/guidance_io.hpp"
#include "cluttertamp/physics/guidance.hpp"
#include "cluttertamp/physics/push_planning.hpp"
#include "cluttertamp/plugin/export.hpp"
#include "cluttertamp/plugin/push_sampler.hpp"
#include "cluttertamp/plugin/task_planner.hpp"

namespace {

using namespace cluttertamp;
using Clock = std::chrono::steady_clock;

std::string describe(const Scene& scene, const physics::Guide& g) {
  std::ostringstream out;
  out.precision(3);
  out << "push '" << scene.objects.at(g.object).id << "' into the " << g.diameter << " m disc about (" << g.centre.x()
      << ", " << g.centre.y() << ")";
  return out.str();
}

class GrtcPlanner final : public plugin::TaskPlanner {
 public:
  void configure(const Parameters& p) override {
    search_.read(p);
    guidance_ = p.get_string("guidance", guidance_, "guidance file, relative to the problem file, or auto");
    guidance_where_ = p.location("guidance");
    max_guides_ = static_cast<int>(
        p.get_int("max_guides", max_guides_, "guides generated at most (guidance auto)", Range::at_least(0)));
    diameter_ = p.get_double("guide_diameter", diameter_, "m across each generated guide's region", Range::above(0));
    unsatisfied_ = p.get_string("unsatisfied_guides", unsatisfied_,
                                "a guide that cannot be satisfied: skip (pass it over) or stop (end the run)");
    reach_.read(p);
    p.require(unsatisfied_ == "skip" || unsatisfied_ == "stop", "unsatisfied_guides", "must be skip or stop");
    p.require(!guidance_.empty(), "guidance", "must be a guidance file or 'auto'");
  }

  std::vector<std::string> required_kinds() const override { return {plugin::KindOf<plugin::PushSampler>::name}; }

  // The task and the guidance file, read against the scene as solve() would read them.
  void check_inputs(const Problem& problem) const override {
    if (!std::get_if<ReachTask>(&problem.task)) {
      throw InputError(problem.planner.where, "grtc plans reach tasks only (task: {reach: <target>})");
    }
    if (guidance_ == "auto") return;
    const Scene& scene = problem.scene;
    io::load_guidance(guidance_file(problem), scene, physics::support_region(scene, WorldState::initial(scene)));
  }

  Result solve(plugin::PlanningContext& context, const WorldState& initial) override {
    const auto started = Clock::now();
    Result result;
    const Scene& scene = context.scene();
    if (!std::get_if<ReachTask>(&context.problem.task)) {
      result.reason = "grtc plans reach tasks only (task: {reach: <target>})";
      return result;
    }
    if (!context.samplers.get<plugin::PushSampler>()) {
      result.reason = "grtc satisfies its guides with a push sampler: name one in the problem file "
                      "(plugins: {push_sampler: push_ompl})";
      return result;
    }
    const physics::PushSettings settings = physics::push_settings(context.problem);
    const physics::PushWorld initial_world(scene, initial, settings);
    const Eigen::Vector3d start = initial_world.start_pose();
    const physics::Guidance guidance = guidance_ == "auto"
                                      ? physics::generate_guidance(initial_world, initial_world.state_of(initial, start),
                                                          initial_world.hand(start).head<2>(), max_guides_, diameter_)
                                      : io::load_guidance(guidance_file(context.problem), scene, initial_world.support_region());
    result.guidance = GuidanceRecord{guidance_ == "auto" ? std::string("auto") : guidance_file(context.problem).string(), {}};
    for (const physics::Guide& g : guidance) result.guidance->guides.push_back({g.object, g.centre, g.diameter, false, ""});
    result.counters[counter::guides] = guidance.size();
    result.counters[counter::guides_satisfied] = 0;
    result.counters[counter::guides_skipped] = 0;

    // Algorithm 1, lines 2-6: satisfy each guide in order, from where the last push left things.
    WorldState state = initial;
    Eigen::Vector3d gripper = start;
    if (!satisfy(guidance, unsatisfied_ == "skip", context, state, gripper, result)) return finish(result, context, started);
    // The guidance time t_g counts as task planning, the remaining reach as motion planning.
    result.time.task_planning = std::chrono::duration<double>(Clock::now() - started).count();

    // Line 7: the remaining reaching problem, in the time left.
    const physics::PushWorld world(scene, state, settings);
    const physics::ReachGoal goal(world, scene.target, reach_);
    const physics::KinodynamicOutcome out =
        physics::plan_pushes(world, world.state_of(state, gripper), goal, search_,
                             physics::PushBudget::of(search_, context.deadline.remaining()),
                             context.seed + guidance.size() + 1);
    context.count(counter::propagations, out.propagations);
    if (!out.path) {
      const std::uint64_t skipped = result.counters[counter::guides_skipped];
      result.reason = (skipped == 0 ? "the guidance was satisfied (" + std::to_string(guidance.size()) + " guides)"
                                    : std::to_string(result.counters[counter::guides_satisfied]) + " of " +
                                          std::to_string(guidance.size()) + " guides satisfied, " +
                                          std::to_string(skipped) + " skipped") +
                      ", then reaching the target failed: " + out.reason;
      result.failures.push_back(Failure{"reach", result.reason, {}});
      return finish(result, context, started);
    }
    add_step(physics::push_step(world, *out.path, state), result);
    result.solved = true;
    return finish(result, context, started);
  }

 private:
  // Relative paths are read from the directory of the file that names them.
  std::filesystem::path guidance_file(const Problem& problem) const {
    const std::filesystem::path path(guidance_);
    if (path.is_absolute()) return path;
    const std::filesystem::path base = !guidance_where_.file.empty() ? std::filesystem::path(guidance_where_.file.str())
                                                                     : problem.source_file;
    return base.parent_path() / path;
  }

  // Pushes each guide's object into its region in turn, each within the push sampler's
  // own work budget (propagations: a guide's outcome does not depend on the machine);
  // `state` and `gripper` follow. A guide not satisfied is kept as a failure
  // and, with `skip`, passed over (the world as the last satisfied guide left it);
  // otherwise false, with the reason.
  static bool satisfy(const physics::Guidance& guidance, bool skip, plugin::PlanningContext& context, WorldState& state,
                      Eigen::Vector3d& gripper, Result& result) {
    const Scene& scene = context.scene();
    for (std::size_t k = 0; k < guidance.size(); ++k) {
      const physics::Guide& g = guidance[k];
      plugin::PushAnswer answer = context.samplers.get<plugin::PushSampler>()->push(context, {g.object, g.centre, g.diameter / 2, state, gripper});
      if (!answer.step) {
        Failure f = answer.failure.value_or(Failure{"push", "the push sampler gave no push and no reason", {}});
        f.reason = "guide " + std::to_string(k + 1) + " (" + describe(scene, g) + ") not satisfied: " + f.reason;
        result.failures.push_back(f);
        result.guidance->guides[k].reason = f.reason;
        if (skip) {
          result.counters[counter::guides_skipped] += 1;
          continue;
        }
        result.reason = f.reason;
        return false;
      }
      answer.step->values["guide"] = {double(k + 1)};
      answer.step->values["region"] = {g.centre.x(), g.centre.y(), g.diameter};
      add_step(std::move(*answer.step), result);
      state = std::move(*answer.resulting_state);
      gripper = answer.gripper_end;
      result.counters[counter::guides_satisfied] += 1;
      result.guidance->guides[k].satisfied = true;
    }
    return true;
  }

  // Appends a push step; the objects it moved join moved_objects, each once.
  static void add_step(PlanStep step, Result& result) {
    for (ObjectIndex i : step.objects) {
      if (std::find(result.moved_objects.begin(), result.moved_objects.end(), i) == result.moved_objects.end()) {
        result.moved_objects.push_back(i);
      }
    }
    result.plan.push_back(std::move(step));
  }

  static Result& finish(Result& result, const plugin::PlanningContext& context, Clock::time_point started) {
    result.time.total = std::chrono::duration<double>(Clock::now() - started).count();
    if (!result.solved && result.counters[counter::guides_satisfied] + result.counters[counter::guides_skipped] < result.counters[counter::guides]) {
      result.time.task_planning = result.time.total;  // stopped at a guide: no reach
    }
    result.time.motion_planning = result.time.total - result.time.task_planning;
    const auto it = context.counters.find("propagations");  // counted by the push sampler too
    result.counters[counter::samples] = it == context.counters.end() ? 0 : it->second;
    return result;
  }

  physics::KinodynamicSettings search_;
  std::string guidance_ = "auto";
  SourceLocation guidance_where_;
  int max_guides_ = 1;  // on the ten shelves one guide solved 23 of 30 runs, two 16 of 30 (20 s)
  double diameter_ = 0.1;        // m: generated guides' regions
  // A guide not satisfied: "skip" it and go on (ours; Algorithm 1 does not say), or
  // "stop" the run. On the ten shelves no bundled guide failed in 120 runs (20 s); before
  // push_ompl lined up with its fingertips, 3 of 20 did.
  std::string unsatisfied_ = "skip";
  physics::ReachTolerances reach_;
};

}  // namespace

CLUTTERTAMP_EXPORT_TASK_PLANNER(GrtcPlanner, grtc,
                                "Guided reaching through clutter: satisfy a guidance (file or generated) with the push "
                                "sampler, then kinodynamic RRT or KPIECE1 to the target (Papallas & Dogar 2020, Alg. 1)",
                                "0.1.0")
