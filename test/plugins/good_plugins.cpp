// Test plugins: a task planner whose outcome a parameter chooses, a grasp sampler and a
// stream sampler.
// They exist to exercise the registry and the CLI's exit codes; they do not plan.
#include <stdexcept>

#include "cluttertamp/plugin/export.hpp"
#include "cluttertamp/plugin/grasp_sampler.hpp"
#include "cluttertamp/plugin/stream_sampler.hpp"
#include "cluttertamp/plugin/task_planner.hpp"

namespace {

using namespace cluttertamp;

// Counts live objects so a test can see that destruction ran plugin code.
int g_live_objects = 0;

class ScriptedPlanner final : public plugin::TaskPlanner {
 public:
  ScriptedPlanner() { ++g_live_objects; }
  ~ScriptedPlanner() override { --g_live_objects; }

  void configure(const Parameters& parameters) override {
    outcome_ = parameters.get_string("outcome", "fail");
    parameters.require(outcome_ == "solve" || outcome_ == "fail" || outcome_ == "throw" || outcome_ == "wait",
                       "outcome", "must be one of solve, fail, throw, wait");
  }

  Result solve(plugin::PlanningContext& context, const WorldState& initial) override {
    context.count(counter::samples, 7);
    Result result;
    if (outcome_ == "throw") throw std::runtime_error("scripted failure");
    if (outcome_ == "wait") {
      while (!context.deadline.expired()) {
      }
      result.reason = "time limit reached";
      return result;
    }
    if (outcome_ == "fail") {
      result.reason = "scripted: no plan";
      result.failures.push_back({"grasp", "scripted blocked grasp", {context.scene().target}});
      return result;
    }
    const ObjectIndex target = context.scene().target;
    PlanStep step;
    step.action = "retrieve";
    step.objects = {target};
    const auto& p = initial.world_T_objects.at(target).translation();
    step.values["start_xyz"] = {p.x(), p.y(), p.z()};
    result.plan.push_back(step);
    result.moved_objects = {target};
    result.solved = true;
    return result;
  }

 private:
  std::string outcome_;
};

class RingGrasps final : public plugin::GraspSampler {
 public:
  plugin::GraspAnswer sample(plugin::PlanningContext&, const plugin::GraspQuery&) override { return {}; }
};

// Yields the numbers start, start + 1, ... up to `count` values, then is exhausted.
class CountingStream final : public plugin::StreamSampler {
 public:
  void configure(const Parameters& parameters) override { count_ = parameters.get_int("rings", 2); }
  std::unique_ptr<plugin::StreamGenerator> instantiate(plugin::PlanningContext&, std::string_view,
                                                       const std::vector<plugin::StreamValue>&,
                                                       const std::vector<plugin::StreamFact>&) override {
    struct Generator final : plugin::StreamGenerator {
      std::int64_t left;
      double next_value = 0;
      explicit Generator(std::int64_t n) : left(n) {}
      plugin::StreamBatch next(plugin::PlanningContext&) override {
        plugin::StreamBatch batch;
        if (left-- > 0) batch.outputs.push_back({next_value++});
        batch.exhausted = left <= 0;
        return batch;
      }
    };
    return std::make_unique<Generator>(count_);
  }

 private:
  std::int64_t count_ = 2;
};

}  // namespace

extern "C" __attribute__((visibility("default"))) int cluttertamp_test_live_objects() { return g_live_objects; }

CLUTTERTAMP_EXPORT_TASK_PLANNER(ScriptedPlanner, test_planner, "Test fixture: outcome chosen by a parameter", "1.2.3")
CLUTTERTAMP_EXPORT_GRASP_SAMPLER(RingGrasps, test_grasp, "Test fixture: returns no grasps", "0.1")
CLUTTERTAMP_EXPORT_STREAM_SAMPLER(CountingStream, toy_stream, "Test fixture: yields 0, 1, ... then stops", "0.1")
