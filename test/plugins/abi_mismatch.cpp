// Test fixture: a plugin as an older cluttertamp would have built it, with another
// plugin ABI version. The registry must refuse it without loading it: loading it
// aborts the process.
#include <cstdlib>

#include "cluttertamp/plugin/plugin.hpp"

namespace {
cluttertamp::plugin::Plugin* create() { return nullptr; }
const cluttertamp::plugin::PluginEntry old_entry{cluttertamp::plugin::kEntryMagic, 999,
                                                 "grasp_sampler",
                                                 "old_grasp", "built for ABI 999", "0.0", &create};
[[maybe_unused]] const int abort_when_loaded = (std::abort(), 0);
}  // namespace

extern "C" __attribute__((visibility("default"), section("ctplugin"), used))
const cluttertamp::plugin::PluginRecord cluttertamp_abi999_grasp_sampler__old_grasp{cluttertamp::plugin::kEntryMagic, 999,
                                                                                   &old_entry};
