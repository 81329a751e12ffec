// Test fixture: a plugin that needs a symbol no library provides, so it cannot be
// loaded (dlopen with RTLD_NOW fails with "undefined symbol").
#include "cluttertamp/plugin/export.hpp"
#include "cluttertamp/plugin/grasp_sampler.hpp"

extern "C" int cluttertamp_symbol_that_does_not_exist(int);

namespace {
class Broken final : public cluttertamp::plugin::GraspSampler {
 public:
  cluttertamp::plugin::GraspAnswer sample(cluttertamp::plugin::PlanningContext&,
                                          const cluttertamp::plugin::GraspQuery& query) override {
    cluttertamp_symbol_that_does_not_exist(static_cast<int>(query.object));
    return {};
  }
};
}  // namespace

CLUTTERTAMP_EXPORT_GRASP_SAMPLER(Broken, broken_grasp, "Test fixture: cannot load", "0.1")
