#pragma once
// Test fixture: a plugin kind that cluttertamp does not know, declared the way a third
// party would, in one header (the interface and its CLUTTERTAMP_PLUGIN_KIND line).
#include "cluttertamp/plugin/plugin.hpp"

namespace light {

/// Measures the light on the scene's target (lux).
class LightSensor : public cluttertamp::plugin::Plugin {
 public:
  ~LightSensor() override;
  virtual double lux() const = 0;
};

}  // namespace light

CLUTTERTAMP_PLUGIN_KIND(::light::LightSensor, light_sensor)
