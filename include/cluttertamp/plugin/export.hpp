#pragma once

/// Export macros: one per interface. Use each at namespace scope in a plugin's .cpp:
///
///     class MyGrasps final : public cluttertamp::plugin::GraspSampler { ... };
///     CLUTTERTAMP_EXPORT_GRASP_SAMPLER(MyGrasps, my_grasps, "Side grasps on a ring", "1.0")
///
/// NAME is a C identifier, unique among the plugins of the same kind that a run can
/// see. The class must be default-constructible and derive from the interface of the
/// macro's kind (checked at compile time). Each macro exports one PluginEntry under the
/// name cluttertamp_abi<ABI>_<kind>_<NAME> in the library's "ctplugin" section, which
/// the registry lists (kind, name, ABI) without loading the library.

#include <type_traits>

#include <boost/dll/alias.hpp>

#include "cluttertamp/plugin/plugin.hpp"

#define CLUTTERTAMP_DETAIL_EXPORT(INTERFACE, KIND, CLASS, NAME, DESCRIPTION, VERSION)          \
  static_assert(std::is_base_of_v<INTERFACE, CLASS>,                                          \
                #CLASS " must derive from " #INTERFACE " to be exported as " #KIND);           \
  namespace cluttertamp_export_##KIND##_##NAME {                                              \
  static ::cluttertamp::plugin::Plugin* create() { return new CLASS(); }                      \
  static const ::cluttertamp::plugin::PluginEntry entry{                                      \
      ::cluttertamp::plugin::kEntryMagic, ::cluttertamp::plugin::kAbiVersion,                 \
      ::cluttertamp::plugin::Kind::KIND,  #NAME,                                              \
      DESCRIPTION,                        VERSION,                                            \
      &create};                                                                               \
  }                                                                                           \
  CLUTTERTAMP_DETAIL_ALIAS(cluttertamp_export_##KIND##_##NAME::entry, CLUTTERTAMP_PLUGIN_ABI_VERSION, KIND, NAME)

// Two levels so that the ABI version macro is expanded before it is pasted.
#define CLUTTERTAMP_DETAIL_ALIAS(ENTRY, ABI, KIND, NAME) CLUTTERTAMP_DETAIL_ALIAS2(ENTRY, ABI, KIND, NAME)
#define CLUTTERTAMP_DETAIL_ALIAS2(ENTRY, ABI, KIND, NAME) \
  BOOST_DLL_ALIAS_SECTIONED(ENTRY, cluttertamp_abi##ABI##_##KIND##_##NAME, ctplugin)

#define CLUTTERTAMP_EXPORT_TASK_PLANNER(CLASS, NAME, DESCRIPTION, VERSION) \
  CLUTTERTAMP_DETAIL_EXPORT(::cluttertamp::plugin::TaskPlanner, task_planner, CLASS, NAME, DESCRIPTION, VERSION)
#define CLUTTERTAMP_EXPORT_OBJECT_PRUNER(CLASS, NAME, DESCRIPTION, VERSION) \
  CLUTTERTAMP_DETAIL_EXPORT(::cluttertamp::plugin::ObjectPruner, object_pruner, CLASS, NAME, DESCRIPTION, VERSION)
#define CLUTTERTAMP_EXPORT_GRASP_SAMPLER(CLASS, NAME, DESCRIPTION, VERSION) \
  CLUTTERTAMP_DETAIL_EXPORT(::cluttertamp::plugin::GraspSampler, grasp_sampler, CLASS, NAME, DESCRIPTION, VERSION)
#define CLUTTERTAMP_EXPORT_PLACEMENT_SAMPLER(CLASS, NAME, DESCRIPTION, VERSION) \
  CLUTTERTAMP_DETAIL_EXPORT(::cluttertamp::plugin::PlacementSampler, placement_sampler, CLASS, NAME, DESCRIPTION, VERSION)
#define CLUTTERTAMP_EXPORT_MOTION_SAMPLER(CLASS, NAME, DESCRIPTION, VERSION) \
  CLUTTERTAMP_DETAIL_EXPORT(::cluttertamp::plugin::MotionSampler, motion_sampler, CLASS, NAME, DESCRIPTION, VERSION)
#define CLUTTERTAMP_EXPORT_PUSH_SAMPLER(CLASS, NAME, DESCRIPTION, VERSION) \
  CLUTTERTAMP_DETAIL_EXPORT(::cluttertamp::plugin::PushSampler, push_sampler, CLASS, NAME, DESCRIPTION, VERSION)
#define CLUTTERTAMP_EXPORT_STREAM_SAMPLER(CLASS, NAME, DESCRIPTION, VERSION) \
  CLUTTERTAMP_DETAIL_EXPORT(::cluttertamp::plugin::StreamSampler, stream_sampler, CLASS, NAME, DESCRIPTION, VERSION)
