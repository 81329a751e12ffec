#include "cluttertamp/plugin/registry.hpp"

#include <algorithm>
#include <cstdlib>
#include <functional>
#include <map>
#include <set>
#include <sstream>

#include <boost/dll/library_info.hpp>
#include <boost/dll/runtime_symbol_info.hpp>
#include <boost/dll/shared_library.hpp>

#include "cluttertamp/plugin/grasp_sampler.hpp"
#include "cluttertamp/plugin/motion_sampler.hpp"
#include "cluttertamp/plugin/object_pruner.hpp"
#include "cluttertamp/plugin/placement_sampler.hpp"
#include "cluttertamp/plugin/push_sampler.hpp"
#include "cluttertamp/plugin/stream_sampler.hpp"
#include "cluttertamp/plugin/task_planner.hpp"
#include "plugin/paths.hpp"

namespace cluttertamp::plugin {

namespace fs = std::filesystem;
using Library = boost::dll::shared_library;

namespace {

// The section the CLUTTERTAMP_EXPORT_* macros put their entries in.
constexpr const char* kSection = "ctplugin";

bool implements(Kind kind, const Plugin* object) {
  switch (kind) {
    case Kind::task_planner: return dynamic_cast<const TaskPlanner*>(object) != nullptr;
    case Kind::object_pruner: return dynamic_cast<const ObjectPruner*>(object) != nullptr;
    case Kind::grasp_sampler: return dynamic_cast<const GraspSampler*>(object) != nullptr;
    case Kind::placement_sampler: return dynamic_cast<const PlacementSampler*>(object) != nullptr;
    case Kind::motion_sampler: return dynamic_cast<const MotionSampler*>(object) != nullptr;
    case Kind::push_sampler: return dynamic_cast<const PushSampler*>(object) != nullptr;
    case Kind::stream_sampler: return dynamic_cast<const StreamSampler*>(object) != nullptr;
  }
  return false;
}

bool is_shared_library(const fs::path& file) {
  const std::string name = file.filename().string();
  return name.size() > 3 && (name.ends_with(".so") || name.find(".so.") != std::string::npos);
}

std::vector<fs::path> sorted_files(const fs::path& dir) {
  std::vector<fs::path> files;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    if (entry.is_regular_file(ec) && is_shared_library(entry.path())) files.push_back(entry.path());
  }
  std::sort(files.begin(), files.end());
  return files;
}

}  // namespace

struct Registry::Impl {
  struct Loaded {
    PluginDescriptor descriptor;
    const PluginEntry* entry;
    std::shared_ptr<Library> library;
  };

  std::vector<SearchedDirectory> searched;
  std::vector<PluginDescriptor> descriptors;
  std::vector<Loaded> loaded;
  std::vector<LoadProblem> problems;

  void examine(const fs::path& file);
  void add_entry(const fs::path& file, const std::shared_ptr<Library>& library, const std::string& symbol);
};

void Registry::Impl::examine(const fs::path& file) {
  std::vector<std::string> symbols;
  try {
    // Reads the section table from the file without running any of its code.
    boost::dll::library_info info(boost::dll::fs::path(file.string()));
    symbols = info.symbols(kSection);
  } catch (const std::exception& e) {
    problems.push_back({file, std::string("not a loadable shared library: ") + e.what()});
    return;
  }
  if (symbols.empty()) {
    problems.push_back({file, "exports no cluttertamp plugin (no 'ctplugin' section); not a plugin library"});
    return;
  }
  std::shared_ptr<Library> library;
  try {
    // rtld_now: a library with unresolved symbols fails here, not in the middle of a run.
    library = std::make_shared<Library>(boost::dll::fs::path(file.string()),
                                        boost::dll::load_mode::rtld_now | boost::dll::load_mode::rtld_local);
  } catch (const std::exception& e) {
    problems.push_back({file, std::string("failed to load: ") + e.what()});
    return;
  }
  for (const std::string& symbol : symbols) add_entry(file, library, symbol);
}

void Registry::Impl::add_entry(const fs::path& file, const std::shared_ptr<Library>& library,
                               const std::string& symbol) {
  const auto* entry = static_cast<const PluginEntry*>(library->get<const void*>(symbol));
  if (entry == nullptr || entry->magic != kEntryMagic) {
    problems.push_back({file, "symbol '" + symbol + "' in the plugin section is not a cluttertamp plugin entry"});
    return;
  }
  if (entry->abi_version != kAbiVersion) {
    problems.push_back({file, "plugin '" + symbol + "' was built for plugin ABI version " +
                                  std::to_string(entry->abi_version) + ", but this cluttertamp needs version " +
                                  std::to_string(kAbiVersion) + "; rebuild it against this cluttertamp"});
    return;
  }
  if (std::string(kind_name(entry->kind)) == "unknown" || entry->name == nullptr || entry->create == nullptr) {
    problems.push_back({file, "plugin entry '" + symbol + "' is malformed (unknown kind or missing factory)"});
    return;
  }
  PluginDescriptor descriptor{entry->kind,    entry->name, entry->description ? entry->description : "",
                              entry->version ? entry->version : "", entry->abi_version, file};
  for (const Loaded& other : loaded) {
    if (other.descriptor.kind == descriptor.kind && other.descriptor.name == descriptor.name) {
      problems.push_back({file, std::string("ignored ") + kind_name(descriptor.kind) + " '" + descriptor.name +
                                    "': already provided by " + other.descriptor.library.string()});
      return;
    }
  }
  descriptors.push_back(descriptor);
  loaded.push_back({std::move(descriptor), entry, library});
}

Registry::Registry(const std::vector<fs::path>& search_paths) : impl_(std::make_unique<Impl>()) {
  for (const fs::path& dir : search_paths) {
    SearchedDirectory searched{dir, fs::is_directory(dir), 0};
    if (searched.exists) {
      const std::vector<fs::path> files = sorted_files(dir);
      searched.libraries = files.size();
      for (const fs::path& file : files) impl_->examine(file);
    }
    impl_->searched.push_back(searched);
  }
}

Registry::~Registry() = default;

std::vector<fs::path> Registry::default_search_paths(const std::vector<fs::path>& first) {
  std::vector<fs::path> paths = first;
  if (const char* env = std::getenv("CLUTTERTAMP_PLUGIN_PATH")) {
    std::stringstream entries(env);
    std::string item;
    while (std::getline(entries, item, ':')) {
      if (!item.empty()) paths.emplace_back(item);
    }
  }
  // The directory of libcluttertamp itself: lib/ in the build tree and in an install.
  const fs::path library_dir = fs::path(boost::dll::this_line_location().string()).lexically_normal().parent_path();
  paths.push_back(library_dir / "cluttertamp" / "plugins");
  paths.emplace_back(detail::kInstallPluginDir);

  std::vector<fs::path> unique;
  std::set<fs::path> seen;
  for (const fs::path& p : paths) {
    std::error_code ec;
    fs::path key = fs::weakly_canonical(p, ec);
    if (ec) key = p;
    if (seen.insert(key).second) unique.push_back(p);
  }
  return unique;
}

const std::vector<SearchedDirectory>& Registry::searched() const { return impl_->searched; }
const std::vector<PluginDescriptor>& Registry::plugins() const { return impl_->descriptors; }
const std::vector<LoadProblem>& Registry::problems() const { return impl_->problems; }

const PluginDescriptor* Registry::find(Kind kind, std::string_view name) const {
  for (const PluginDescriptor& d : impl_->descriptors) {
    if (d.kind == kind && d.name == name) return &d;
  }
  return nullptr;
}

std::string Registry::describe_search() const {
  std::ostringstream out;
  out << "searched, in order:\n";
  if (impl_->searched.empty()) out << "  (no directories)\n";
  for (const SearchedDirectory& dir : impl_->searched) {
    out << "  " << dir.path.string() << "  ("
        << (dir.exists ? std::to_string(dir.libraries) + " shared libraries" : std::string("does not exist"))
        << ")\n";
  }
  out << "plugins found:\n";
  if (impl_->descriptors.empty()) out << "  (none)\n";
  for (const PluginDescriptor& d : impl_->descriptors) {
    out << "  " << kind_name(d.kind) << " '" << d.name << "' (" << d.library.filename().string() << ")\n";
  }
  if (!impl_->problems.empty()) {
    out << "libraries not used:\n";
    for (const LoadProblem& p : impl_->problems) out << "  " << p.library.string() << ": " << p.message << "\n";
  }
  return out.str();
}

std::shared_ptr<Plugin> Registry::create(Kind kind, std::string_view name, const Parameters& parameters,
                                         const SourceLocation& where) const {
  const Impl::Loaded* found = nullptr;
  for (const Impl::Loaded& l : impl_->loaded) {
    if (l.descriptor.kind == kind && l.descriptor.name == name) found = &l;
  }
  if (found == nullptr) {
    std::string text = describe_search();
    if (!text.empty() && text.back() == '\n') text.pop_back();
    throw InputError(where, std::string("no ") + kind_name(kind) + " plugin named '" + std::string(name) + "'\n" + text);
  }
  Plugin* raw = found->entry->create();
  // The deleter owns a reference to the library: the code of the object's destructor
  // stays mapped until the object is gone, even if this registry is destroyed first.
  std::shared_ptr<Plugin> object(raw, [library = found->library](Plugin* p) { delete p; });
  if (raw == nullptr || !implements(kind, raw)) {
    throw InputError(where, found->descriptor.library.string() + ": the factory of " + kind_name(kind) + " '" +
                                std::string(name) + "' did not create a " + kind_name(kind));
  }
  object->configure(parameters);
  const std::vector<std::string> unknown = parameters.unused();
  if (!unknown.empty()) {
    Diagnostics diagnostics;
    for (const std::string& key : unknown) {
      diagnostics.error(parameters.location(key), std::string("unknown parameter '") + key + "' for " +
                                                      kind_name(kind) + " '" + std::string(name) + "'");
    }
    throw InputError(diagnostics);
  }
  return object;
}

}  // namespace cluttertamp::plugin
