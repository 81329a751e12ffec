// Test fixture: a library whose plugin section holds a record under a current plugin
// name but without cluttertamp's mark (as a stray or forged library would). The
// registry must refuse it from the file alone: loading it aborts the process.
#include <cstdlib>

#include "cluttertamp/plugin/plugin.hpp"

namespace {
cluttertamp::plugin::Plugin* create() { return nullptr; }
const cluttertamp::plugin::PluginEntry forged_entry{0x0badf00d, cluttertamp::plugin::kAbiVersion, "grasp_sampler",
                                                    "forged_grasp", "no mark", "0.0", &create};
[[maybe_unused]] const int abort_when_loaded = (std::abort(), 0);
}  // namespace

#define WRONG_MARK_RECORD(ABI) WRONG_MARK_RECORD2(ABI)
#define WRONG_MARK_RECORD2(ABI)                                                                            \
  extern "C" __attribute__((visibility("default"), section("ctplugin"), used))                          \
  const cluttertamp::plugin::PluginRecord cluttertamp_abi##ABI##_grasp_sampler__forged_grasp{0x0badf00d, \
                                                                                            ABI, &forged_entry};
WRONG_MARK_RECORD(CLUTTERTAMP_PLUGIN_ABI_VERSION)
