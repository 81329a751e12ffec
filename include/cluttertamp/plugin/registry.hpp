#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "cluttertamp/core/diagnostics.hpp"
#include "cluttertamp/core/parameters.hpp"
#include "cluttertamp/export.hpp"
#include "cluttertamp/plugin/plugin.hpp"

namespace cluttertamp::plugin {

/// A plugin the registry found and can create.
struct PluginDescriptor {
  std::string kind;  ///< KindOf<Interface>::name of its interface
  std::string name;
  std::string description;
  std::string version;
  std::uint32_t abi_version = 0;
  std::filesystem::path library;
};

/// A plugin made by a factory of this process rather than found in a library: a sampler
/// written in Python, an application's own planner, a test's stand-in.
struct InProcessPlugin {
  std::string kind;  ///< KindOf<Interface>::name of the interface its objects implement
  std::string name;  ///< a C identifier, unique per kind among in-process plugins
  std::string description;
  std::string version;
  /// Where it comes from, shown where a library's file name would be (e.g.
  /// "python:my_samplers.TopGrasps"); also its PluginDescriptor::library.
  std::string origin;
  /// Makes a new object of the kind's interface. Called with no lock held; may throw.
  std::function<std::shared_ptr<Plugin>()> create;
};

/// Makes `plugin` known to every Registry of this process, those that exist and those
/// made later. It is found before any library's plugin of the same kind and name (which
/// is then shadowed). Providing the same kind and name again replaces it for the objects
/// created afterwards. Throws std::invalid_argument when the kind or name is not a C
/// identifier (the kind as CLUTTERTAMP_PLUGIN_KIND asks) or there is no factory.
/// Thread-safe. The factory is kept until the process ends (a descriptor handed out
/// stays valid), also after it is replaced or withdrawn.
CLUTTERTAMP_API void provide_plugin(InProcessPlugin plugin);

/// Forgets the in-process plugin of `kind` and `name` for the objects created
/// afterwards; false when there was none. Thread-safe.
CLUTTERTAMP_API bool withdraw_plugin(std::string_view kind, std::string_view name);

/// A library or entry the registry could not use, and why (not a shared library,
/// unresolved symbols, another plugin ABI, a name already taken, ...).
struct LoadProblem {
  std::filesystem::path library;
  std::string message;
};

/// A search directory and what the registry saw there.
struct SearchedDirectory {
  std::filesystem::path path;
  bool exists = false;
  std::size_t libraries = 0;  ///< shared libraries examined
};

/// Finds plugin libraries, checks their ABI version and creates plugin objects.
///
/// Construction lists the plugins of every library from its exported symbol names
/// (cluttertamp_abi<N>_<kind>__<name>) without loading it, so libraries built for
/// another ABI are refused unloaded. A library is loaded when one of its plugins is
/// first found or created, or by plugins(). Loaded libraries stay loaded until the
/// process ends, so every object a plugin creates may outlive the registry.
class CLUTTERTAMP_API Registry {
 public:
  /// Examines every `*.so` file directly in each directory, in order. When two
  /// libraries export the same kind and name, the first one wins and the second is
  /// reported as a LoadProblem. Safe to use from several threads.
  explicit Registry(const std::vector<std::filesystem::path>& search_paths);
  ~Registry();
  Registry(const Registry&) = delete;
  Registry& operator=(const Registry&) = delete;

  /// The directories searched when a run names none of its own, in order:
  /// `first` (e.g. a problem file's `plugins: paths:`), the entries of the
  /// CLUTTERTAMP_PLUGIN_PATH environment variable (':'-separated), the plugin
  /// directory next to libcluttertamp (build tree or relocated install:
  /// <libdir>/cluttertamp/plugins) and the install prefix's plugin directory.
  /// Duplicates are dropped.
  static std::vector<std::filesystem::path> default_search_paths(
      const std::vector<std::filesystem::path>& first = {});

  /// The directories examined, in order (fixed at construction).
  const std::vector<SearchedDirectory>& searched() const;
  /// The in-process plugins, then every library's that loaded (loading them all): a
  /// copy, other threads may load libraries or provide plugins meanwhile.
  std::vector<PluginDescriptor> plugins() const;
  /// Libraries and entries not used so far, and why (a copy of a list that grows as
  /// libraries are loaded).
  std::vector<LoadProblem> problems() const;

  /// The in-process plugin of that kind and name (provide_plugin) if there is one, else
  /// the library's, loading it if needed; null when no usable plugin of that kind and
  /// name exists. The descriptor lives as long as the registry.
  const PluginDescriptor* find(std::string_view kind, std::string_view name) const;
  /// The kinds of the plugins found (loaded or not), in name order.
  std::vector<std::string> kinds() const;

  /// Creates and configures a plugin of `kind`. `where` is the place in a problem file
  /// that names the plugin, used in errors. Throws InputError when the plugin does not
  /// exist (listing what was searched, what exists and what failed to load, and the
  /// kinds found when none is `kind`), when configure() rejects a parameter, or when a
  /// parameter is never read; throws std::runtime_error when the plugin's factory fails.
  std::shared_ptr<Plugin> create(std::string_view kind, std::string_view name, const Parameters& parameters = {},
                                 const SourceLocation& where = {}) const;

  /// create() for the kind of Interface; also throws std::runtime_error when the object
  /// made does not implement Interface.
  template <class Interface>
  std::shared_ptr<Interface> create(std::string_view name, const Parameters& parameters = {},
                                    const SourceLocation& where = {}) const {
    auto typed = std::dynamic_pointer_cast<Interface>(create(KindOf<Interface>::name, name, parameters, where));
    if (!typed) not_of_kind(KindOf<Interface>::name, name);
    return typed;
  }

  /// The parameters the plugin reads (key, type, default, help), found by configuring a
  /// new object with none set (when configure() then throws, what it read before). A
  /// parameter read only when another has some value is not seen. Throws as create()
  /// does when the plugin cannot be found or made.
  std::vector<ParameterDeclaration> declared_parameters(std::string_view kind, std::string_view name) const;

  /// A multi-line report of the search, for errors and `cluttertamp plugins`.
  std::string describe_search() const;

 private:
  std::shared_ptr<Plugin> make(std::string_view kind, std::string_view name, const SourceLocation& where,
                               std::string& who) const;
  [[noreturn]] static void not_of_kind(std::string_view kind, std::string_view name);
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace cluttertamp::plugin
