#include "cluttertamp/plugin/registry.hpp"

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <functional>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>

#include <cctype>
#include <mutex>
#include <optional>

#include <boost/dll/library_info.hpp>
#include <boost/dll/runtime_symbol_info.hpp>
#include <boost/dll/shared_library.hpp>

#include "plugin/paths.hpp"

namespace cluttertamp::plugin {

namespace fs = std::filesystem;
using Library = boost::dll::shared_library;

namespace {

// The section the CLUTTERTAMP_EXPORT_* macros put their entries in.
constexpr const char* kSection = "ctplugin";

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

// Calls a plugin's factory; its failures as std::runtime_error naming `who`.
template <class Factory>
std::shared_ptr<Plugin> create_with(const std::string& who, Factory&& factory) {
  std::shared_ptr<Plugin> object;
  try {
    object = factory();
  } catch (const std::exception& e) {
    throw std::runtime_error("the factory of " + who + " threw: " + e.what());
  } catch (...) {
    throw std::runtime_error("the factory of " + who + " threw a non-standard exception");
  }
  if (!object) throw std::runtime_error("the factory of " + who + " returned no object");
  return object;
}

}  // namespace

// Libraries are never unloaded: code of a plugin (a destructor, an exception's
// what(), a control block) may still run after the last object the registry knows
// of is gone, so its mapping must last as long as the process.
std::mutex g_libraries_mutex;
std::vector<std::shared_ptr<Library>>& loaded_libraries() {
  static auto* libraries = new std::vector<std::shared_ptr<Library>>();  // never destroyed
  return *libraries;
}

namespace {

// The in-process plugins (provide_plugin), newest registration last. Entries replaced
// or withdrawn move to `retired`: a descriptor handed out by find() must stay valid.
struct Provided {
  PluginDescriptor descriptor;
  std::function<std::shared_ptr<Plugin>()> create;
};
struct ProvidedTable {
  std::mutex mutex;
  std::vector<std::shared_ptr<const Provided>> current;
  std::vector<std::shared_ptr<const Provided>> retired;
};
ProvidedTable& provided_table() {
  static auto* table = new ProvidedTable();  // never destroyed: factories may hold foreign objects
  return *table;
}

std::shared_ptr<const Provided> find_provided(std::string_view kind, std::string_view name) {
  ProvidedTable& table = provided_table();
  const std::lock_guard<std::mutex> lock(table.mutex);
  for (const auto& p : table.current) {
    if (p->descriptor.kind == kind && p->descriptor.name == name) return p;
  }
  return nullptr;
}

std::vector<std::shared_ptr<const Provided>> all_provided() {
  ProvidedTable& table = provided_table();
  const std::lock_guard<std::mutex> lock(table.mutex);
  return table.current;
}

bool is_identifier(std::string_view name) {
  if (name.empty() || std::isdigit(static_cast<unsigned char>(name.front()))) return false;
  return std::all_of(name.begin(), name.end(),
                     [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; });
}

}  // namespace

void provide_plugin(InProcessPlugin plugin) {
  if (!detail::valid_kind_name(plugin.kind)) {
    throw std::invalid_argument("plugin kind '" + plugin.kind +
                                "' must be a C identifier without '__' that does not end in '_'");
  }
  if (!is_identifier(plugin.name)) {
    throw std::invalid_argument("plugin name '" + plugin.name + "' must be a C identifier (letters, digits, '_')");
  }
  if (!plugin.create) throw std::invalid_argument(plugin.kind + " '" + plugin.name + "' has no factory");
  auto entry = std::make_shared<Provided>();
  entry->descriptor = {plugin.kind, plugin.name, plugin.description, plugin.version, kAbiVersion,
                       plugin.origin.empty() ? fs::path("in-process") : fs::path(plugin.origin)};
  entry->create = std::move(plugin.create);
  ProvidedTable& table = provided_table();
  const std::lock_guard<std::mutex> lock(table.mutex);
  for (auto& p : table.current) {
    if (p->descriptor.kind == entry->descriptor.kind && p->descriptor.name == entry->descriptor.name) {
      table.retired.push_back(std::move(p));
      p = std::move(entry);
      return;
    }
  }
  table.current.push_back(std::move(entry));
}

bool withdraw_plugin(std::string_view kind, std::string_view name) {
  ProvidedTable& table = provided_table();
  const std::lock_guard<std::mutex> lock(table.mutex);
  const auto it = std::find_if(table.current.begin(), table.current.end(), [&](const auto& p) {
    return p->descriptor.kind == kind && p->descriptor.name == name;
  });
  if (it == table.current.end()) return false;
  table.retired.push_back(std::move(*it));
  table.current.erase(it);
  return true;
}

struct Registry::Impl {
  // A plugin named by a symbol of a library's plugin section; loaded on first use.
  struct Candidate {
    std::string kind;
    std::string name;
    fs::path library;
    std::string symbol;
    enum class State { unloaded, loaded, failed } state = State::unloaded;
    PluginDescriptor descriptor;
    const PluginEntry* entry = nullptr;
  };

  std::vector<SearchedDirectory> searched;
  std::vector<Candidate> candidates;
  std::vector<PluginDescriptor> descriptors;  // of the loaded candidates, in discovery order
  std::vector<LoadProblem> problems;
  std::map<fs::path, std::shared_ptr<Library>> libraries;
  std::mutex mutex;

  void examine(const fs::path& file);
  bool load(Candidate& candidate);
  void refresh_descriptors();
};

namespace {
// Why `file` cannot be a shared library of this machine, read from its ELF header
// alone; empty when the header and the section table it points to are whole.
std::string elf_fault(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  unsigned char header[64] = {};
  in.read(reinterpret_cast<char*>(header), sizeof header);
  const std::streamsize got = in.gcount();
  if (got < 4 || header[0] != 0x7f || header[1] != 'E' || header[2] != 'L' || header[3] != 'F') {
    return "not an ELF file (no ELF header)";
  }
  if (got < 64 || header[4] != 2 || header[5] != 1) return "not a 64-bit little-endian ELF file, or truncated in its header";
  auto read = [&](std::size_t at, std::size_t bytes) {
    std::uint64_t value = 0;
    for (std::size_t i = 0; i < bytes; ++i) value |= std::uint64_t(header[at + i]) << (8 * i);
    return value;
  };
  const std::uint64_t section_table = read(0x28, 8), entry_size = read(0x3A, 2), entries = read(0x3C, 2);
  std::error_code ec;
  const std::uintmax_t size = fs::file_size(file, ec);
  if (!ec && section_table + entry_size * entries > size) {
    return "truncated: its section table ends at byte " + std::to_string(section_table + entry_size * entries) +
           ", the file has " + std::to_string(size);
  }
  return "";
}

// The bytes of the ELF section `name` read from the file (a 64-bit little-endian ELF
// file whose header elf_fault passed); nothing when there is no such section or its
// bounds leave the file. Nothing of the library runs.
std::optional<std::string> elf_section(const fs::path& file, const std::string& name) {
  std::ifstream in(file, std::ios::binary);
  auto bytes = [&](std::uint64_t at, std::uint64_t count) -> std::optional<std::string> {
    if (count > (std::uint64_t(1) << 24)) return std::nullopt;  // no plugin section is 16 MiB
    std::string out(count, '\0');
    in.clear();
    in.seekg(static_cast<std::streamoff>(at));
    in.read(out.data(), static_cast<std::streamsize>(count));
    if (!in || in.gcount() != static_cast<std::streamsize>(count)) return std::nullopt;
    return out;
  };
  auto number = [](const std::string& b, std::size_t at, std::size_t width) {
    std::uint64_t value = 0;
    for (std::size_t i = 0; i < width && at + i < b.size(); ++i) value |= std::uint64_t(static_cast<unsigned char>(b[at + i])) << (8 * i);
    return value;
  };
  const std::optional<std::string> header = bytes(0, 64);
  if (!header) return std::nullopt;
  const std::uint64_t table = number(*header, 0x28, 8), entry_size = number(*header, 0x3A, 2),
                      entries = number(*header, 0x3C, 2), names_index = number(*header, 0x3E, 2);
  if (entry_size < 64 || names_index >= entries) return std::nullopt;
  const std::optional<std::string> sections = bytes(table, entry_size * entries);
  if (!sections) return std::nullopt;
  auto field = [&](std::uint64_t index, std::size_t at, std::size_t width) { return number(*sections, index * entry_size + at, width); };
  const std::optional<std::string> names = bytes(field(names_index, 24, 8), field(names_index, 32, 8));
  if (!names) return std::nullopt;
  for (std::uint64_t i = 0; i < entries; ++i) {
    const std::uint64_t at = field(i, 0, 4);
    if (at >= names->size() || names->compare(at, name.size() + 1, name.c_str(), name.size() + 1) != 0) continue;
    constexpr std::uint64_t kNoBits = 8;  // SHT_NOBITS: no bytes in the file
    if (field(i, 4, 4) == kNoBits) return std::nullopt;
    return bytes(field(i, 24, 8), field(i, 32, 8));
  }
  return std::nullopt;
}

// Why the plugin section's records cannot be trusted, from the file alone; empty when
// there is one record per plugin symbol, each with the mark and this ABI.
std::string record_fault(const fs::path& file, std::size_t symbols) {
  const std::optional<std::string> section = elf_section(file, kSection);
  if (!section) return "its plugin section cannot be read from the file";
  if (section->size() != symbols * sizeof(PluginRecord)) {
    return "its plugin section holds " + std::to_string(section->size()) + " bytes for " + std::to_string(symbols) +
           " plugin records of " + std::to_string(sizeof(PluginRecord)) + " bytes";
  }
  for (std::size_t i = 0; i < symbols; ++i) {
    std::uint32_t magic = 0, abi = 0;
    std::memcpy(&magic, section->data() + i * sizeof(PluginRecord), sizeof magic);
    std::memcpy(&abi, section->data() + i * sizeof(PluginRecord) + sizeof magic, sizeof abi);
    if (magic != kEntryMagic) return "a record in its plugin section lacks cluttertamp's mark: not a cluttertamp plugin";
    if (abi != kAbiVersion) {
      return "a record in its plugin section was built for plugin ABI version " + std::to_string(abi) +
             ", but this cluttertamp needs version " + std::to_string(kAbiVersion) + "; rebuild it against this cluttertamp";
    }
  }
  return "";
}
}  // namespace

void Registry::Impl::examine(const fs::path& file) {
  if (const std::string fault = elf_fault(file); !fault.empty()) {
    problems.push_back({file, "not a loadable shared library: " + fault});
    return;
  }
  std::vector<std::string> symbols;
  try {
    // Reads the file's section table; nothing of the library runs.
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
  const std::string prefix = "cluttertamp_abi";
  // Names with this ABI are trusted only when the section's records carry the mark:
  // checked in the file, so a forged or stray library is refused before any of its code
  // (its constructors included) runs. Other ABIs are refused by name below.
  const std::string current = prefix + std::to_string(kAbiVersion) + "_";
  if (std::any_of(symbols.begin(), symbols.end(), [&](const std::string& x) { return x.rfind(current, 0) == 0; })) {
    if (const std::string fault = record_fault(file, symbols.size()); !fault.empty()) {
      problems.push_back({file, "not loaded: " + fault});
      return;
    }
  }
  for (const std::string& symbol : symbols) {
    // cluttertamp_abi<N>_<kind>__<name>
    std::size_t pos = prefix.size();
    std::size_t digits_end = pos;
    while (digits_end < symbol.size() && std::isdigit(static_cast<unsigned char>(symbol[digits_end]))) ++digits_end;
    if (symbol.compare(0, prefix.size(), prefix) != 0 || digits_end == pos || digits_end >= symbol.size() ||
        symbol[digits_end] != '_') {
      problems.push_back({file, "symbol '" + symbol + "' in the plugin section is not a cluttertamp plugin entry"});
      continue;
    }
    const unsigned long abi = std::stoul(symbol.substr(pos, digits_end - pos));
    const std::string rest = symbol.substr(digits_end + 1);
    const std::size_t split = rest.find("__");
    const bool named = split != std::string::npos && split > 0 && split + 2 < rest.size();
    const std::string kind = named ? rest.substr(0, split) : "";
    const std::string name = named ? rest.substr(split + 2) : rest;
    if (abi != kAbiVersion) {
      problems.push_back({file, "plugin '" + name + "' was built for plugin ABI version " + std::to_string(abi) +
                                    ", but this cluttertamp needs version " + std::to_string(kAbiVersion) +
                                    "; rebuild it against this cluttertamp"});
      continue;
    }
    if (!named) {
      problems.push_back({file, "symbol '" + symbol + "' names no plugin kind and name (<kind>__<name>)"});
      continue;
    }
    const auto same = std::find_if(candidates.begin(), candidates.end(),
                                   [&](const Candidate& c) { return c.kind == kind && c.name == name; });
    if (same != candidates.end()) {
      problems.push_back({file, "ignored " + kind + " '" + name +
                                    "': already provided by " + same->library.string()});
      continue;
    }
    Candidate candidate;
    candidate.kind = kind;
    candidate.name = name;
    candidate.library = file;
    candidate.symbol = symbol;
    candidates.push_back(std::move(candidate));
  }
}

bool Registry::Impl::load(Candidate& candidate) {
  if (candidate.state != Candidate::State::unloaded) return candidate.state == Candidate::State::loaded;
  candidate.state = Candidate::State::failed;
  std::shared_ptr<Library>& library = libraries[candidate.library];
  if (!library) {
    try {
      // rtld_now: a library with unresolved symbols fails here, not in the middle of a run.
      library = std::make_shared<Library>(boost::dll::fs::path(candidate.library.string()),
                                          boost::dll::load_mode::rtld_now | boost::dll::load_mode::rtld_local);
    } catch (const std::exception& e) {
      problems.push_back({candidate.library, std::string("failed to load: ") + e.what()});
      for (Candidate& other : candidates) {
        if (other.library == candidate.library) other.state = Candidate::State::failed;
      }
      return false;
    }
    std::lock_guard<std::mutex> lock(g_libraries_mutex);
    loaded_libraries().push_back(library);
  }
  const PluginRecord& record = library->get<const PluginRecord>(candidate.symbol);
  const PluginEntry* entry = record.magic == kEntryMagic && record.abi_version == kAbiVersion ? record.entry : nullptr;
  if (entry == nullptr || entry->magic != kEntryMagic || entry->abi_version != kAbiVersion ||
      entry->kind == nullptr || candidate.kind != entry->kind || entry->name == nullptr || candidate.name != entry->name ||
      entry->create == nullptr) {
    problems.push_back({candidate.library, "plugin entry '" + candidate.symbol +
                                               "' is malformed (its fields disagree with its exported name)"});
    return false;
  }
  candidate.entry = entry;
  candidate.descriptor = {candidate.kind,
                          candidate.name,
                          entry->description ? entry->description : "",
                          entry->version ? entry->version : "",
                          entry->abi_version,
                          candidate.library};
  candidate.state = Candidate::State::loaded;
  refresh_descriptors();
  return true;
}

void Registry::Impl::refresh_descriptors() {
  descriptors.clear();
  for (const Candidate& c : candidates) {
    if (c.state == Candidate::State::loaded) descriptors.push_back(c.descriptor);
  }
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

std::vector<PluginDescriptor> Registry::plugins() const {
  std::vector<PluginDescriptor> out;
  for (const auto& p : all_provided()) out.push_back(p->descriptor);
  std::lock_guard<std::mutex> lock(impl_->mutex);
  for (Impl::Candidate& c : impl_->candidates) impl_->load(c);
  out.insert(out.end(), impl_->descriptors.begin(), impl_->descriptors.end());
  return out;
}

std::vector<LoadProblem> Registry::problems() const {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  return impl_->problems;
}

const PluginDescriptor* Registry::find(std::string_view kind, std::string_view name) const {
  if (const auto provided = find_provided(kind, name)) return &provided->descriptor;
  std::lock_guard<std::mutex> lock(impl_->mutex);
  for (Impl::Candidate& c : impl_->candidates) {
    if (c.kind == kind && c.name == name) return impl_->load(c) ? &c.descriptor : nullptr;
  }
  return nullptr;
}

std::vector<std::string> Registry::kinds() const {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  std::set<std::string> kinds;
  for (const Impl::Candidate& c : impl_->candidates) kinds.insert(c.kind);
  for (const auto& p : all_provided()) kinds.insert(p->descriptor.kind);
  return {kinds.begin(), kinds.end()};
}

std::string Registry::describe_search() const {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  std::ostringstream out;
  out << "searched, in order:\n";
  if (impl_->searched.empty()) out << "  (no directories)\n";
  for (const SearchedDirectory& dir : impl_->searched) {
    out << "  " << dir.path.string() << "  ("
        << (dir.exists ? std::to_string(dir.libraries) + " shared libraries" : std::string("does not exist"))
        << ")\n";
  }
  const auto provided = all_provided();
  if (!provided.empty()) {
    out << "provided in this process (found first):\n";
    for (const auto& p : provided) {
      out << "  " << p->descriptor.kind << " '" << p->descriptor.name << "' (" << p->descriptor.library.string() << ")\n";
    }
  }
  out << "plugins found:\n";
  if (impl_->candidates.empty()) out << "  (none)\n";
  for (const Impl::Candidate& c : impl_->candidates) {
    out << "  " << c.kind << " '" << c.name << "' (" << c.library.filename().string()
        << (c.state == Impl::Candidate::State::failed ? ", failed to load" : "") << ")\n";
  }
  if (!impl_->problems.empty()) {
    out << "libraries or entries not used:\n";
    for (const LoadProblem& p : impl_->problems) out << "  " << p.library.string() << ": " << p.message << "\n";
  }
  return out.str();
}

std::shared_ptr<Plugin> Registry::make(std::string_view kind, std::string_view name, const SourceLocation& where,
                                       std::string& who) const {
  // The names of the plugins of `kind` found, loaded or not (for "did you mean").
  auto names_of_kind = [this](std::string_view k) {
    std::vector<std::string> out;
    for (const auto& p : all_provided()) {
      if (p->descriptor.kind == k) out.push_back(p->descriptor.name);
    }
    const std::lock_guard<std::mutex> lock(impl_->mutex);
    for (const Impl::Candidate& c : impl_->candidates) {
      if (c.kind == k) out.push_back(c.name);
    }
    return out;
  };
  if (const auto provided = find_provided(kind, name)) {
    who = std::string(kind) + " '" + std::string(name) + "' (" + provided->descriptor.library.string() + ")";
    return create_with(who, [&] { return provided->create(); });
  }
  const PluginDescriptor* descriptor = find(kind, name);
  const PluginEntry* entry = nullptr;
  {
    std::lock_guard<std::mutex> lock(impl_->mutex);
    for (const Impl::Candidate& c : impl_->candidates) {
      if (descriptor && &c.descriptor == descriptor) entry = c.entry;
    }
  }
  if (entry == nullptr) {
    const std::string hint = did_you_mean(std::string(name), names_of_kind(kind));
    std::string text = describe_search();
    if (!text.empty() && text.back() == '\n') text.pop_back();
    const std::vector<std::string> found = kinds();
    std::string kinds_line;
    if (std::find(found.begin(), found.end(), kind) == found.end()) {
      kinds_line = "\nno plugin of kind '" + std::string(kind) + "' was found; kinds found:";
      for (const std::string& k : found) kinds_line += " " + k;
      if (found.empty()) kinds_line += " (none)";
    }
    throw InputError(where, "no usable " + std::string(kind) + " plugin named '" + std::string(name) + "'" + hint +
                                kinds_line + "\n" + text);
  }
  who = std::string(kind) + " '" + std::string(name) + "' (" + descriptor->library.filename().string() + ")";
  return create_with(who, [&] { return std::shared_ptr<Plugin>(entry->create()); });
}

void Registry::not_of_kind(std::string_view kind, std::string_view name) {
  throw std::runtime_error("the factory of " + std::string(kind) + " '" + std::string(name) + "' did not create a " +
                           std::string(kind));
}

std::vector<ParameterDeclaration> Registry::declared_parameters(std::string_view kind, std::string_view name) const {
  std::string who;
  const std::shared_ptr<Plugin> object = make(kind, name, {}, who);
  const Parameters none;
  try {
    object->configure(none);
  } catch (...) {
    // A plugin that needs some parameter stops here: what it read so far is still its list.
  }
  return none.declarations();
}

std::shared_ptr<Plugin> Registry::create(std::string_view kind, std::string_view name, const Parameters& parameters,
                                         const SourceLocation& where) const {
  std::string who;
  std::shared_ptr<Plugin> object = make(kind, name, where, who);
  // A fresh copy: what this object reads is checked alone, however often the problem's
  // parameters are used (compare, bench and sessions create plugins once per run).
  // Collecting: every bad value the plugin reads is reported, not only the first.
  const Parameters given = parameters.fresh(/*collect=*/true);
  Diagnostics diagnostics;
  try {
    object->configure(given);
  } catch (const InputError& e) {
    diagnostics.append(e.diagnostics());
  } catch (const std::exception& e) {
    diagnostics.error(where, who + " rejected its parameters: " + e.what());
  } catch (...) {
    diagnostics.error(where, who + " rejected its parameters (non-standard exception)");
  }
  Diagnostics all = given.errors();
  all.append(diagnostics);
  std::vector<std::string> read;
  for (const ParameterDeclaration& d : given.declarations()) read.push_back(d.key);
  for (const std::string& key : given.unused()) {
    all.error(given.location(key), std::string("unknown parameter '") + key + "' for " + std::string(kind) + " '" +
                                       std::string(name) + "'" + did_you_mean(key, read));
  }
  all.throw_if_any();
  return object;
}

}  // namespace cluttertamp::plugin
