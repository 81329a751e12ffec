#include <dlfcn.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "cluttertamp/run/runner.hpp"

#include "cluttertamp/io/problem_io.hpp"
#include "cluttertamp/plugin/grasp_sampler.hpp"
#include "cluttertamp/plugin/registry.hpp"
#include "cluttertamp/plugin/task_planner.hpp"
#include "test_support.hpp"

namespace cluttertamp {
namespace {

using plugin::Registry;
using test::plugin_dir;

bool mentions(const std::vector<plugin::LoadProblem>& problems, const std::string& file, const std::string& text) {
  for (const auto& p : problems) {
    if (p.library.filename() == file && p.message.find(text) != std::string::npos) return true;
  }
  return false;
}

TEST(Registry, LoadsARealPluginLibrary) {
  const Registry registry({plugin_dir("good")});
  ASSERT_EQ(registry.plugins().size(), 3u);
  const plugin::PluginDescriptor* planner = registry.find("task_planner", "test_planner");
  ASSERT_NE(planner, nullptr);
  EXPECT_EQ(planner->version, "1.2.3");
  EXPECT_EQ(planner->abi_version, plugin::kAbiVersion);
  EXPECT_EQ(planner->description, "Test fixture: outcome chosen by a parameter");
  EXPECT_EQ(planner->library.filename(), "libtest_good_plugins.so");
  EXPECT_NE(registry.find("grasp_sampler", "test_grasp"), nullptr);
  EXPECT_EQ(registry.find("grasp_sampler", "test_planner"), nullptr);  // names are per kind
  EXPECT_TRUE(registry.problems().empty());
}

TEST(Registry, CreatesConfiguredObjectsOfTheRightInterface) {
  const Registry registry({plugin_dir("good")});
  Parameters params;
  params.set("outcome", std::string("solve"));
  auto planner = registry.create<plugin::TaskPlanner>("test_planner", params);
  ASSERT_NE(planner, nullptr);
  auto grasps = registry.create<plugin::GraspSampler>("test_grasp");
  EXPECT_NE(dynamic_cast<plugin::GraspSampler*>(grasps.get()), nullptr);
}

// The problem's parameters serve every object made from them: each is configured from a
// fresh copy, so a second object sees the same keys unread (compare, bench).
TEST(Registry, EveryObjectReadsItsParametersAfresh) {
  const Registry registry({plugin_dir("good")});
  Parameters unknown;
  unknown.set("outcome", std::string("solve"));
  unknown.set("outcom", std::string("solve"), {"p.yaml", 10, 3});
  for (int run = 0; run < 2; ++run) {
    const Diagnostics d = test::expect_input_error([&] { registry.create<plugin::TaskPlanner>("test_planner", unknown); });
    EXPECT_TRUE(test::has_error(d, 10, 3, "unknown parameter 'outcom'")) << "run " << run;
  }
  const auto declared = registry.declared_parameters("task_planner", "test_planner");
  ASSERT_FALSE(declared.empty());
  EXPECT_EQ(declared[0].key, "outcome");
  EXPECT_EQ(declared[0].type, "string");
  EXPECT_EQ(declared[0].fallback, "fail");
}

// Stream bindings naming the same plugin with the same parameters share one object.
TEST(Registry, StreamBindingsWithOneChoiceShareAnObject) {
  const Registry registry({plugin_dir("good")});
  Problem problem;
  problem.planner.name = "test_planner";
  PluginChoice rings{"toy_stream", {}, {}};
  rings.parameters.set("rings", std::int64_t{3});
  problem.streams["a"] = rings;
  problem.streams["b"] = rings;
  problem.streams["c"] = PluginChoice{"toy_stream", {}, {}};
  const run::Plugins plugins = run::create_plugins(problem, registry);
  EXPECT_EQ(plugins.samplers.streams.at("a"), plugins.samplers.streams.at("b"));
  EXPECT_NE(plugins.samplers.streams.at("a"), plugins.samplers.streams.at("c"));
}

TEST(Registry, PluginParameterErrorsAreInputErrors) {
  const Registry registry({plugin_dir("good")});
  Parameters bad_value;
  bad_value.set("outcome", std::string("dance"), {"p.yaml", 9, 14});
  const Diagnostics d1 = test::expect_input_error([&] { registry.create<plugin::TaskPlanner>("test_planner", bad_value); });
  EXPECT_TRUE(test::has_error(d1, 9, 14, "parameter 'outcome' must be one of"));

  Parameters unknown;
  unknown.set("outcom", std::string("solve"), {"p.yaml", 10, 3});
  const Diagnostics d2 = test::expect_input_error([&] { registry.create<plugin::TaskPlanner>("test_planner", unknown); });
  EXPECT_TRUE(test::has_error(d2, 10, 3, "unknown parameter 'outcom' for task_planner 'test_planner'"));
  EXPECT_TRUE(test::has_error(d2, 10, 3, "(did you mean 'outcome'?)"));
}

TEST(Registry, RefusesAnAbiMismatchedPlugin) {
  const Registry registry({plugin_dir("abi"), plugin_dir("good")});
  EXPECT_EQ(registry.find("grasp_sampler", "old_grasp"), nullptr);
  // The fixture aborts the process if it is ever loaded: the refusal comes from its
  // exported symbol name alone.
  EXPECT_TRUE(mentions(registry.problems(), "libtest_abi_mismatch.so", "plugin ABI version 999"));
  EXPECT_EQ(registry.plugins().size(), 3u);
  const Diagnostics d = test::expect_input_error([&] { registry.create<plugin::GraspSampler>("old_grasp"); });
  ASSERT_EQ(d.size(), 1u);
  // The error lists what was searched, what exists and what failed to load.
  const std::string& message = d.items()[0].message;
  EXPECT_NE(message.find("no usable grasp_sampler plugin named 'old_grasp'"), std::string::npos) << message;
  EXPECT_NE(message.find(plugin_dir("abi").string()), std::string::npos) << message;
  EXPECT_NE(message.find("grasp_sampler 'test_grasp'"), std::string::npos) << message;
  EXPECT_NE(message.find("plugin ABI version 999"), std::string::npos) << message;
}

// A library whose plugin section holds a record under a current plugin name but without
// cluttertamp's mark is refused from the file: the fixture aborts the process if loaded.
TEST(Registry, RefusesALibraryWhoseRecordsLackTheMarkBeforeLoadingIt) {
  const Registry registry({plugin_dir("forged"), plugin_dir("good")});
  EXPECT_EQ(registry.find("grasp_sampler", "forged_grasp"), nullptr);
  EXPECT_TRUE(mentions(registry.problems(), "libtest_wrong_mark.so", "lacks cluttertamp's mark")) << registry.describe_search();
  const Diagnostics d = test::expect_input_error([&] { registry.create<plugin::GraspSampler>("forged_grasp"); });
  ASSERT_EQ(d.size(), 1u);
  EXPECT_NE(d.items()[0].message.find("lacks cluttertamp's mark"), std::string::npos) << d.items()[0].message;
  EXPECT_NE(registry.find("grasp_sampler", "test_grasp"), nullptr) << "the good plugins beside it still load";
}

TEST(Registry, RefusesBrokenLibraries) {
  const Registry registry({plugin_dir("broken")});
  EXPECT_TRUE(registry.plugins().empty());
  EXPECT_TRUE(mentions(registry.problems(), "libtest_broken.so", "cluttertamp_symbol_that_does_not_exist"));
  EXPECT_TRUE(mentions(registry.problems(), "libnot_elf.so", "not a loadable shared library: not an ELF file"));
  EXPECT_THROW(registry.create<plugin::GraspSampler>("broken_grasp"), InputError);
}

// A truncated library used to be refused with "basic_ios::clear: iostream error".
TEST(Registry, ATruncatedLibraryIsCalledTruncated) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "cluttertamp_truncated_plugin";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const std::string whole = test::read_text(plugin_dir("good") / "libtest_good_plugins.so");
  std::ofstream(dir / "libcut.so", std::ios::binary) << whole.substr(0, 3000);
  const Registry registry({dir});
  EXPECT_TRUE(registry.plugins().empty());
  EXPECT_TRUE(mentions(registry.problems(), "libcut.so", "not a loadable shared library: truncated")) << registry.describe_search();
  std::filesystem::remove_all(dir);
}

TEST(Registry, MissingDirectoriesAreReportedNotFatal) {
  const Registry registry({"/nonexistent/cluttertamp/plugins", plugin_dir("good")});
  ASSERT_EQ(registry.searched().size(), 2u);
  EXPECT_FALSE(registry.searched()[0].exists);
  EXPECT_TRUE(registry.searched()[1].exists);
  EXPECT_NE(registry.describe_search().find("does not exist"), std::string::npos);
}

TEST(Registry, FirstDirectoryWinsOnDuplicateNames) {
  const Registry registry({plugin_dir("good"), plugin_dir("good") / "."});
  EXPECT_EQ(registry.plugins().size(), 3u);
  EXPECT_TRUE(mentions(registry.problems(), "libtest_good_plugins.so", "already provided by"));
}

TEST(Registry, ObjectsOutliveTheRegistryAndTheirLibraryStaysLoaded) {
  std::shared_ptr<plugin::TaskPlanner> planner;
  {
    const Registry registry({plugin_dir("good")});
    planner = registry.create<plugin::TaskPlanner>("test_planner");
  }
  // The registry is gone; the library must still be mapped while the object lives.
  const std::string library = (plugin_dir("good") / "libtest_good_plugins.so").string();
  void* handle = dlopen(library.c_str(), RTLD_NOW | RTLD_NOLOAD);
  ASSERT_NE(handle, nullptr) << "the library was unloaded while one of its objects lived";
  auto live = reinterpret_cast<int (*)()>(dlsym(handle, "cluttertamp_test_live_objects"));
  ASSERT_NE(live, nullptr);
  EXPECT_EQ(live(), 1);
  planner.reset();  // runs the plugin's destructor: its code must still be there
  EXPECT_EQ(live(), 0);
  dlclose(handle);
  // Code of a plugin may still be needed after its last object (an exception's
  // what(), a control block), so libraries stay loaded for the life of the process.
  void* again = dlopen(library.c_str(), RTLD_NOW | RTLD_NOLOAD);
  EXPECT_NE(again, nullptr);
  if (again) dlclose(again);
}

TEST(Registry, ListsPluginsWithoutLoadingTheirLibraries) {
  const Registry registry({plugin_dir("good")});
  const std::string library = (plugin_dir("good") / "libtest_good_plugins.so").string();
  // ctest runs each test in its own process; a whole-binary run may have loaded it before.
  if (dlopen(library.c_str(), RTLD_NOW | RTLD_NOLOAD) != nullptr) GTEST_SKIP() << "loaded by an earlier test";
  EXPECT_NE(registry.describe_search().find("task_planner 'test_planner'"), std::string::npos);
  EXPECT_EQ(dlopen(library.c_str(), RTLD_NOW | RTLD_NOLOAD), nullptr) << "listing loaded the library";
  EXPECT_NE(registry.find("task_planner", "test_planner"), nullptr);
  EXPECT_NE(dlopen(library.c_str(), RTLD_NOW | RTLD_NOLOAD), nullptr) << "find() should load it";
}

TEST(Registry, DefaultSearchPathsHonourTheEnvironmentAndProblemFirst) {
  setenv("CLUTTERTAMP_PLUGIN_PATH", "/env/a:/env/b", 1);
  const auto paths = Registry::default_search_paths({"/problem/dir"});
  unsetenv("CLUTTERTAMP_PLUGIN_PATH");
  ASSERT_GE(paths.size(), 5u);
  EXPECT_EQ(paths[0], "/problem/dir");
  EXPECT_EQ(paths[1], "/env/a");
  EXPECT_EQ(paths[2], "/env/b");
  // Then the directory beside libcluttertamp, which in the build tree holds the built plugins.
  EXPECT_EQ(paths[3].filename(), "plugins");
  EXPECT_EQ(paths[3].parent_path().filename(), "cluttertamp");
}

// A kind cluttertamp does not know, declared in one header of the plugin's own
// (test/plugins/new_kind/light_sensor.hpp): listed, chosen by its key in a problem
// file's plugins block, and handed to the planner as context.samplers.get<LightSensor>().
TEST(Registry, APluginKindIsOneHeader) {
  const Registry registry({plugin_dir("kinds")});
  ASSERT_NE(registry.find("light_sensor", "lamp"), nullptr);
  EXPECT_EQ(registry.find("grasp_sampler", "lamp"), nullptr);
  EXPECT_EQ(registry.kinds(), (std::vector<std::string>{"light_sensor", "task_planner"}));
  EXPECT_TRUE(registry.problems().empty());
  const auto declared = registry.declared_parameters("light_sensor", "lamp");
  ASSERT_EQ(declared.size(), 1u);
  EXPECT_EQ(declared[0].key, "lux");

  const Problem problem = io::load_problem(test::data("problems/new_kind.yaml"));
  EXPECT_EQ(problem.samplers.at("light_sensor").name, "lamp");
  const run::RunOutcome outcome = run::plan(problem, registry, {});
  ASSERT_TRUE(outcome.result.solved) << outcome.result.reason;
  EXPECT_EQ(outcome.result.counters.at("lux"), 3u);

  // Without the sensor the planner is told so, and reports it as its reason.
  Problem without = problem;
  without.samplers.clear();
  EXPECT_EQ(run::plan(without, registry, {}).result.reason, "no light_sensor configured");
}

// A misspelt kind is only known not to exist when the plugins are made: the error is
// at the key's plugin name and lists the kinds found.
TEST(Registry, AnUnknownKindListsTheKindsFound) {
  const Registry registry({plugin_dir("good")});
  const Diagnostics d = test::expect_input_error(
      [&] { registry.create("grasp_samplr", "test_grasp", {}, SourceLocation{"p.yaml", 7, 19}); });
  ASSERT_EQ(d.size(), 1u);
  EXPECT_TRUE(test::has_error(d, 7, 19, "no usable grasp_samplr plugin named 'test_grasp'"));
  EXPECT_NE(d.items()[0].message.find("no plugin of kind 'grasp_samplr' was found; kinds found: grasp_sampler "
                                      "stream_sampler task_planner"),
            std::string::npos)
      << d.items()[0].message;
}

TEST(Registry, SamplersHandOutEachKindAsItsInterface) {
  const Registry registry({plugin_dir("good")});
  plugin::Samplers samplers;
  EXPECT_EQ(samplers.get<plugin::GraspSampler>(), nullptr);
  samplers.set(registry.create<plugin::GraspSampler>("test_grasp"));
  EXPECT_NE(samplers.get<plugin::GraspSampler>(), nullptr);
  EXPECT_EQ(samplers.kinds(), std::vector<std::string>{"grasp_sampler"});
  // An object set under a kind whose interface it does not implement is refused on use.
  samplers.set("task_planner", registry.create<plugin::GraspSampler>("test_grasp"));
  EXPECT_THROW(samplers.get<plugin::TaskPlanner>(), std::logic_error);
  samplers.set("task_planner", nullptr);
  EXPECT_EQ(samplers.get<plugin::TaskPlanner>(), nullptr);
}

// A grasp sampler made in the process, which reads one parameter.
class StandIn final : public plugin::GraspSampler {
 public:
  void configure(const Parameters& p) override { width = p.get_double("width", 0.1, "m", Range::above(0)); }
  plugin::GraspAnswer sample(plugin::PlanningContext&, const plugin::GraspQuery&) override { return {}; }
  double width = 0.0;
};

// Plugins provided in the process (Python samplers) are found before a library's of the
// same kind and name, by registries made before and after; withdrawn, the library's is
// found again.
TEST(Registry, InProcessPluginsAreFoundFirstAndCanBeWithdrawn) {
  const Registry registry({plugin_dir("good")});
  int made = 0;
  plugin::provide_plugin({"grasp_sampler", "test_grasp", "stand-in", "2.0", "test:StandIn", [&made] {
                            ++made;
                            return std::make_shared<StandIn>();
                          }});
  const plugin::PluginDescriptor* found = registry.find("grasp_sampler", "test_grasp");
  ASSERT_NE(found, nullptr);
  EXPECT_EQ(found->library, "test:StandIn");
  EXPECT_EQ(found->version, "2.0");
  Parameters wide;
  wide.set("width", 0.25);
  const auto object = registry.create<plugin::GraspSampler>("test_grasp", wide);
  ASSERT_NE(dynamic_cast<StandIn*>(object.get()), nullptr);
  EXPECT_EQ(dynamic_cast<StandIn*>(object.get())->width, 0.25);
  EXPECT_EQ(made, 1);
  EXPECT_NE(registry.describe_search().find("grasp_sampler 'test_grasp' (test:StandIn)"), std::string::npos);
  const Registry later({plugin_dir("good")});
  EXPECT_EQ(later.find("grasp_sampler", "test_grasp")->library, "test:StandIn");
  const auto listed = later.plugins();
  EXPECT_EQ(listed.front().library, "test:StandIn");
  // Its parameters are checked as a library plugin's: unknown keys and bad values.
  Parameters bad;
  bad.set("width", -1.0, {"p.yaml", 4, 7});
  bad.set("colour", std::string("red"), {"p.yaml", 5, 7});
  const Diagnostics d = test::expect_input_error([&] { registry.create<plugin::GraspSampler>("test_grasp", bad); });
  EXPECT_TRUE(test::has_error(d, 4, 7, "width"));
  EXPECT_TRUE(test::has_error(d, 5, 7, "unknown parameter 'colour'"));

  EXPECT_TRUE(plugin::withdraw_plugin("grasp_sampler", "test_grasp"));
  EXPECT_FALSE(plugin::withdraw_plugin("grasp_sampler", "test_grasp"));
  EXPECT_EQ(found->library, "test:StandIn");  // a descriptor handed out stays valid
  EXPECT_EQ(registry.find("grasp_sampler", "test_grasp")->library.filename(), "libtest_good_plugins.so");
  EXPECT_EQ(dynamic_cast<StandIn*>(registry.create<plugin::GraspSampler>("test_grasp").get()), nullptr);
}

TEST(Registry, InProcessPluginsNeedIdentifiersAndAFactory) {
  auto factory = [] { return std::make_shared<StandIn>(); };
  EXPECT_THROW(plugin::provide_plugin({"grasp sampler", "x", "", "", "", factory}), std::invalid_argument);
  EXPECT_THROW(plugin::provide_plugin({"grasp_sampler", "front-grasps", "", "", "", factory}), std::invalid_argument);
  EXPECT_THROW(plugin::provide_plugin({"grasp_sampler", "x", "", "", "", nullptr}), std::invalid_argument);
  // A factory that fails is a runtime error naming the plugin.
  plugin::provide_plugin({"grasp_sampler", "failing", "", "", "test:Failing",
                          []() -> std::shared_ptr<plugin::Plugin> { throw std::runtime_error("no memory today"); }});
  const Registry registry({});
  try {
    registry.create<plugin::GraspSampler>("failing");
    ADD_FAILURE() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("grasp_sampler 'failing' (test:Failing) threw: no memory today"), std::string::npos)
        << e.what();
  }
  EXPECT_TRUE(plugin::withdraw_plugin("grasp_sampler", "failing"));
}

}  // namespace
}  // namespace cluttertamp
