// rtc_ompl: reaching through clutter (RTC) by pushing, Papallas & Dogar (ICRA 2020),
// Section IV — a kinodynamic planner of OMPL's control layer (RRT or KPIECE1) over the
// planar pushing physics (physics::plan_pushes), with the problem's pusher (`physics:`:
// a floating gripper, or the robot's arm on a planar base). The hand starts at the exit
// x_s facing into the shelf; the goal: the target in the hand, within a tolerance.
#include <chrono>
#include <cmath>

#include "cluttertamp/physics/push_planning.hpp"
#include "cluttertamp/plugin/export.hpp"
#include "cluttertamp/plugin/task_planner.hpp"

namespace {

using namespace cluttertamp;
using Clock = std::chrono::steady_clock;

class RtcPlanner final : public plugin::TaskPlanner {
 public:
  void configure(const Parameters& p) override {
    search_.read(p);
    reach_.read(p);
  }

  Result solve(plugin::PlanningContext& context, const WorldState& initial) override {
    const auto start_time = Clock::now();
    Result result;
    const Scene& scene = context.scene();
    if (!std::get_if<ReachTask>(&context.problem.task)) {
      result.reason = "rtc_ompl plans reach tasks only (task: {reach: <target>})";
      return result;
    }
    const physics::PushWorld world(scene, initial, physics::push_settings(context.problem));
    const physics::PushState start = world.state_of(initial, world.start_pose());
    const physics::ReachGoal goal(world, scene.target, reach_);
    const physics::KinodynamicOutcome out =
        physics::plan_pushes(world, start, goal, search_, physics::PushBudget::of(search_, context.deadline.remaining()),
                             context.seed);
    result.counters[counter::propagations] = out.propagations;
    result.counters[counter::samples] = out.propagations;
    if (!out.path) {
      result.reason = out.reason;
    } else {
      PlanStep step = physics::push_step(world, *out.path, initial);
      result.moved_objects = step.objects;
      result.counters[counter::plan_controls] = out.path->controls.size();
      result.plan.push_back(std::move(step));
      result.solved = true;
    }
    result.time.total = std::chrono::duration<double>(Clock::now() - start_time).count();
    result.time.task_planning = result.time.total;  // the kinodynamic search is the whole task
    return result;
  }

 private:
  physics::KinodynamicSettings search_;
  physics::ReachTolerances reach_;
};

}  // namespace

CLUTTERTAMP_EXPORT_TASK_PLANNER(RtcPlanner, rtc_ompl,
                                "Reaching through clutter by pushing: kinodynamic RRT or KPIECE1 over the pushing physics "
                                "(Papallas & Dogar 2020)",
                                "0.1.0")
