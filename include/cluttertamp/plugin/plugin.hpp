#pragma once

#include <cstdint>
#include <string_view>

#include "cluttertamp/core/parameters.hpp"
#include "cluttertamp/export.hpp"

namespace cluttertamp::plugin {

/// Raised whenever the SDK (the headers of core/ and plugin/) changes: an interface, a
/// type it passes by value, or a core class plugins build on their own stack. The test
/// `plugin_abi` fails when the SDK's fingerprint changes without it (cmake/plugin_abi.txt
/// records both). The registry refuses plugins built against another value. 18: plugin
/// kinds are open (named by strings, declared by CLUTTERTAMP_PLUGIN_KIND), Samplers is a
/// map by kind. 19: in-process plugins (provide_plugin: samplers written in Python).
/// 20: TaskPlanner::required_kinds. 21: the plugin section holds PluginRecords (mark
/// and ABI readable from the file, before the library is loaded). 22: the physics layer's
/// PushSettings gains the arm pusher and the problem's physics block. 23: PushSettings'
/// tip and wall-force limits, PushOutcome's tipped objects and wall force.
/// It is part of every exported symbol name (cluttertamp_abi<N>_<kind>__<name>), so a
/// mismatch is seen before the library is loaded.
#define CLUTTERTAMP_PLUGIN_ABI_VERSION 25
inline constexpr std::uint32_t kAbiVersion = CLUTTERTAMP_PLUGIN_ABI_VERSION;

/// Marks a PluginRecord and a PluginEntry, so a stray symbol in the plugin section is
/// never trusted.
inline constexpr std::uint32_t kEntryMagic = 0x43545047;  // "CTPG"

/// KindOf<Interface>::name is the name of the kind whose plugins implement Interface
/// ("grasp_sampler", ...): the key that chooses such a plugin in a problem file's
/// `plugins:` block and the middle of its exported symbol names. An interface's header
/// declares it with CLUTTERTAMP_PLUGIN_KIND.
template <class Interface>
struct KindOf;

/// Aliases of the interfaces by kind name (kinds::grasp_sampler is GraspSampler), for
/// the export macro; declared by CLUTTERTAMP_PLUGIN_KIND.
namespace kinds {}

namespace detail {
/// A kind name is a C identifier that neither holds "__" nor ends in '_': the registry
/// splits symbol names at the first "__" after the kind.
constexpr bool valid_kind_name(std::string_view kind) {
  if (kind.empty() || kind.back() == '_' || kind.find("__") != std::string_view::npos) return false;
  for (char c : kind) {
    if (!((c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_')) return false;
  }
  return !(kind.front() >= '0' && kind.front() <= '9');
}
}  // namespace detail

/// Declares a plugin kind: its plugins implement INTERFACE (fully qualified, derived
/// from Plugin) and are named KIND (a C identifier without "__", e.g. grasp_sampler) in
/// problem files, symbol names and `cluttertamp plugins`. Use once, at global scope,
/// after the interface in its header; that header is all a new kind needs. Plugins of
/// the kind are exported with CLUTTERTAMP_EXPORT_PLUGIN(KIND, ...) (export.hpp) and
/// reach a planner as `context.samplers.get<INTERFACE>()`.
#define CLUTTERTAMP_PLUGIN_KIND(INTERFACE, KIND)                                                     \
  static_assert(::cluttertamp::plugin::detail::valid_kind_name(#KIND),                              \
                "plugin kind '" #KIND "' must be a C identifier without '__' that does not end in '_'"); \
  namespace cluttertamp::plugin {                                                                   \
  namespace kinds {                                                                                 \
  using KIND = INTERFACE;                                                                           \
  }                                                                                                 \
  template <>                                                                                       \
  struct KindOf<INTERFACE> {                                                                        \
    static constexpr const char* name = #KIND;                                                      \
  };                                                                                                \
  }

/// Base of every plugin interface. Objects are created by a plugin's factory and
/// owned through std::shared_ptr handed out by the Registry, which keeps the plugin
/// library loaded for as long as any of its objects lives.
class CLUTTERTAMP_API Plugin {
 public:
  virtual ~Plugin();

  /// Reads the plugin's parameters from the problem file. Called once, before any
  /// other call. Throws InputError for a bad value; keys never read are reported
  /// by the registry as unknown parameters. The default reads nothing.
  virtual void configure(const Parameters& parameters);
};

/// What a plugin library exports for each plugin it contains (one per export macro).
/// The first two fields never move, so the registry can check them on any version.
struct PluginEntry {
  std::uint32_t magic;
  std::uint32_t abi_version;
  const char* kind;         ///< KindOf<Interface>::name of the interface it implements
  const char* name;         ///< unique per kind; a C identifier
  const char* description;  ///< one line
  const char* version;      ///< the plugin's own version
  Plugin* (*create)();      ///< a new object of the kind's interface; caller owns it
};

/// What the export macro places in a library's "ctplugin" section, one per plugin. Its
/// first two fields are plain numbers in the file, so the registry checks every record
/// of the section before it loads the library: a library whose records lack the mark
/// or name another ABI is refused without any of its code running.
struct PluginRecord {
  std::uint32_t magic;        ///< kEntryMagic
  std::uint32_t abi_version;  ///< kAbiVersion of the SDK it was built with
  const PluginEntry* entry;   ///< the plugin's entry (relocated when the library loads)
};
static_assert(sizeof(PluginRecord) == 16, "the registry reads records of 16 bytes from the file");

}  // namespace cluttertamp::plugin
