// Test fixture: a plugin as an older cluttertamp would have built it, with another
// plugin ABI version. The registry must refuse it without loading it.
#include <cstdlib>

#include "cluttertamp/plugin/export.hpp"

namespace {
cluttertamp::plugin::Plugin* create() { return nullptr; }
const cluttertamp::plugin::PluginEntry old_entry{cluttertamp::plugin::kEntryMagic, 999,
                                                 "grasp_sampler",
                                                 "old_grasp", "built for ABI 999", "0.0", &create};
}  // namespace

BOOST_DLL_ALIAS_SECTIONED(old_entry, cluttertamp_abi999_grasp_sampler__old_grasp, ctplugin)

// If the registry ever loaded this library, this initializer would end the test run.
[[maybe_unused]] static const int trap = (std::abort(), 0);
