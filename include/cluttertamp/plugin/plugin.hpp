#pragma once

#include <cstdint>
#include <optional>
#include <string_view>

#include "cluttertamp/core/parameters.hpp"
#include "cluttertamp/export.hpp"

namespace cluttertamp::plugin {

/// Raised whenever the SDK (the headers of core/ and plugin/) changes: an interface, a
/// type it passes by value, or a core class plugins build on their own stack. The test
/// `plugin_abi` fails when the SDK's fingerprint changes without it (cmake/plugin_abi.txt
/// records both). The registry refuses plugins built against another value. 17: queries
/// hold `const WorldState&`, samplers see the world through WorldView
/// (PlanningContext::world_at).
/// It is part of every exported symbol name (cluttertamp_abi<N>_<kind>_<name>), so a
/// mismatch is seen before the library is loaded.
#define CLUTTERTAMP_PLUGIN_ABI_VERSION 17
inline constexpr std::uint32_t kAbiVersion = CLUTTERTAMP_PLUGIN_ABI_VERSION;

/// Marks a PluginEntry, so a stray symbol in the plugin section is never trusted.
inline constexpr std::uint32_t kEntryMagic = 0x43545047;  // "CTPG"

/// What a plugin does; each kind has one interface header and one export macro.
enum class Kind : std::uint32_t {
  task_planner = 1,
  object_pruner = 2,
  grasp_sampler = 3,
  placement_sampler = 4,
  motion_sampler = 5,
  push_sampler = 6,
  stream_sampler = 7,
};

/// "task_planner", "grasp_sampler", ...; "unknown" for a value outside the enum.
CLUTTERTAMP_API const char* kind_name(Kind kind);
/// The inverse of kind_name.
CLUTTERTAMP_API std::optional<Kind> kind_from_name(std::string_view name);

/// KindOf<Interface>::value is the Kind whose plugins implement Interface;
/// each interface header specializes it.
template <class Interface>
struct KindOf;

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
  Kind kind;
  const char* name;         ///< unique per kind; a C identifier
  const char* description;  ///< one line
  const char* version;      ///< the plugin's own version
  Plugin* (*create)();      ///< a new object of the kind's interface; caller owns it
};

}  // namespace cluttertamp::plugin
