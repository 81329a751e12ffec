// Test fixture: a plugin of a new kind (light_sensor) and a task planner that asks for
// it through context.samplers, as a problem file's `plugins: light_sensor:` fills it.
#include <cmath>
#include <string>

#include "cluttertamp/plugin/export.hpp"
#include "cluttertamp/plugin/task_planner.hpp"
#include "light_sensor.hpp"

namespace light {

LightSensor::~LightSensor() = default;

namespace {

using namespace cluttertamp;

class Lamp final : public LightSensor {
 public:
  void configure(const Parameters& parameters) override {
    lux_ = parameters.get_double("lux", 1.0, "the light it reports (lux)", Range::at_least(0));
  }
  double lux() const override { return lux_; }

 private:
  double lux_ = 1;
};

// Solves when a light sensor is configured; counts its reading.
class SensingPlanner final : public plugin::TaskPlanner {
 public:
  Result solve(plugin::PlanningContext& context, const WorldState&) override {
    Result result;
    const auto sensor = context.samplers.get<LightSensor>();
    if (!sensor) {
      result.reason = "no light_sensor configured";
      return result;
    }
    context.count("lux", static_cast<std::uint64_t>(std::lround(sensor->lux())));
    result.solved = true;
    return result;
  }
};

}  // namespace
}  // namespace light

CLUTTERTAMP_EXPORT_PLUGIN(light_sensor, light::Lamp, lamp, "Test fixture: a sensor of a kind cluttertamp does not know", "0.1")
CLUTTERTAMP_EXPORT_TASK_PLANNER(light::SensingPlanner, sensing_planner, "Test fixture: reads the light_sensor", "0.1")
