#pragma once

/// Exporting plugins. Use the macro at namespace scope in a plugin's .cpp:
///
///     class MyGrasps final : public cluttertamp::plugin::GraspSampler { ... };
///     CLUTTERTAMP_EXPORT_PLUGIN(grasp_sampler, MyGrasps, my_grasps, "Side grasps on a ring", "1.0")
///
/// KIND is a kind declared with CLUTTERTAMP_PLUGIN_KIND in its interface's header
/// (included before this use); NAME is a C identifier, unique among the plugins of the
/// same kind that a run can see. The class must be default-constructible and derive
/// from the kind's interface (checked at compile time; a misspelt kind does not
/// compile). Each use exports one PluginRecord (mark, ABI, entry) under the name
/// cluttertamp_abi<ABI>_<KIND>__<NAME> in the library's "ctplugin" section, which the
/// registry lists and checks (kind, name, ABI, mark) without loading the library.
///
/// Each bundled interface header also defines a shorthand, e.g.
/// CLUTTERTAMP_EXPORT_GRASP_SAMPLER(CLASS, NAME, DESCRIPTION, VERSION).

#include <type_traits>

#include "cluttertamp/plugin/plugin.hpp"

#define CLUTTERTAMP_EXPORT_PLUGIN(KIND, CLASS, NAME, DESCRIPTION, VERSION)                             \
  static_assert(std::is_base_of_v<::cluttertamp::plugin::kinds::KIND, CLASS>,                          \
                #CLASS " must derive from the interface of kind " #KIND " to be exported as one");      \
  namespace cluttertamp_export_##KIND##_##NAME {                                                      \
  static ::cluttertamp::plugin::Plugin* create() { return new CLASS(); }                               \
  static const ::cluttertamp::plugin::PluginEntry entry{                                               \
      ::cluttertamp::plugin::kEntryMagic, ::cluttertamp::plugin::kAbiVersion, #KIND, #NAME, DESCRIPTION, \
      VERSION, &create};                                                                               \
  }                                                                                                    \
  CLUTTERTAMP_DETAIL_RECORD(cluttertamp_export_##KIND##_##NAME::entry, CLUTTERTAMP_PLUGIN_ABI_VERSION, KIND, NAME)

// Two levels so that the ABI version macro is expanded before it is pasted. The record
// is visible (plugins are built with hidden visibility) and kept by the linker.
#define CLUTTERTAMP_DETAIL_RECORD(ENTRY, ABI, KIND, NAME) CLUTTERTAMP_DETAIL_RECORD2(ENTRY, ABI, KIND, NAME)
#define CLUTTERTAMP_DETAIL_RECORD2(ENTRY, ABI, KIND, NAME)                                           \
  extern "C" __attribute__((visibility("default"), section("ctplugin"), used))                      \
  const ::cluttertamp::plugin::PluginRecord cluttertamp_abi##ABI##_##KIND##__##NAME{                \
      ::cluttertamp::plugin::kEntryMagic, ::cluttertamp::plugin::kAbiVersion, &ENTRY};
