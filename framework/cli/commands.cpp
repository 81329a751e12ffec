#include "cli/commands.hpp"

#include <algorithm>
#include <chrono>
#include <fstream>
#include <condition_variable>
#include <cstdio>
#include <iomanip>
#include <iostream>
#include <mutex>
#include <set>
#include <sstream>
#include <thread>

#include <unistd.h>

#include "cluttertamp/pddl/parser.hpp"
#include "cluttertamp/pddl/sexpr.hpp"
#include "cluttertamp/stream/stream_file.hpp"
#include "cluttertamp/stream/stream_task.hpp"

#include "cluttertamp/io/problem_io.hpp"
#include "cluttertamp/io/result_json.hpp"
#include "cluttertamp/io/scene_io.hpp"
#include "cluttertamp/run/runner.hpp"
#include "cluttertamp/viewer/plan_html.hpp"
#include "cli/determinism.hpp"
#include "cluttertamp/io/text_file.hpp"

#include <nlohmann/json.hpp>

namespace cluttertamp::cli {

namespace fs = std::filesystem;
using run::ExitCode;

namespace {

std::string seconds(double s) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3f s", s);
  return text;
}

std::string object_names(const Scene& scene, const std::vector<ObjectIndex>& objects) {
  std::string out;
  for (ObjectIndex i : objects) out += (out.empty() ? "" : ", ") + scene.objects.at(i).id;
  return out.empty() ? "(none)" : out;
}

std::string describe_scene(const Scene& scene) {
  std::ostringstream out;
  if (scene.objects.empty()) return "(none)";
  out << scene.name << ": " << scene.objects.size() << " objects (target '" << scene.objects.at(scene.target).id
      << "'), " << scene.fixed.size() << " fixed bodies, " << scene.regions.size() << " regions";
  return out.str();
}

// The values bound to a symbolic step's arguments, short ones in full:
// "  p0=(1, 0) #t4=(42 numbers)".
void print_values(std::ostream& out, const PlanStep& step) {
  const char* sep = "   ";
  for (const std::string& arg : step.arguments) {
    const auto v = step.values.find(arg);
    if (v == step.values.end()) continue;
    out << sep << arg << "=(";
    sep = " ";
    if (v->second.size() > 7) {
      out << v->second.size() << " numbers)";
      continue;
    }
    for (std::size_t k = 0; k < v->second.size(); ++k) out << (k ? ", " : "") << v->second[k];
    out << ")";
  }
}

void print_summary(std::ostream& out, const Problem& problem, const run::RunOutcome& outcome,
                   const fs::path& result_file) {
  const Result& r = outcome.result;
  out << "problem   " << problem.name << " (" << problem.source_file.string() << ")\n"
      << "scene     " << describe_scene(problem.scene) << "\n"
      << "planner   " << outcome.info.planner << " (seed " << outcome.info.seed << ", time limit "
      << outcome.info.time_limit << " s)\n";
  if (r.solved) {
    out << "result    SOLVED: " << r.plan.size() << " steps";
    if (r.cost) out << ", cost " << *r.cost;
    if (!problem.scene.objects.empty()) out << ", " << r.moved_objects.size() << " objects moved";
    out << "\n";
    for (std::size_t i = 0; i < r.plan.size(); ++i) {
      const PlanStep& step = r.plan[i];
      out << "  " << std::setw(3) << i + 1 << ". " << step.action << " ";
      if (!step.arguments.empty()) {  // a symbolic step says what it was given
        for (std::size_t a = 0; a < step.arguments.size(); ++a) out << (a ? " " : "") << step.arguments[a];
        print_values(out, step);
      } else {
        out << object_names(problem.scene, step.objects);
      }
      out << "\n";
    }
    if (!problem.scene.objects.empty()) out << "moved     " << object_names(problem.scene, r.moved_objects) << "\n";
  } else {
    std::string reason = r.reason;
    if (auto nl = reason.find('\n'); nl != std::string::npos) reason = reason.substr(0, nl) + " (details above)";
    out << "result    NOT SOLVED (exit code " << outcome.info.exit_code << "): " << reason << "\n";
  }
  out << "time      task planning " << seconds(r.time.task_planning) << ", motion planning "
      << seconds(r.time.motion_planning) << ", total " << seconds(r.time.total) << "\n";
  out << "counters ";
  for (const auto& [key, value] : r.counters) out << " " << key << "=" << value;
  if (r.counters.empty()) out << " (none)";
  out << "\n";
  for (const Failure& f : r.failures) {
    out << "failure   [" << f.stage << "] " << f.reason;
    if (!f.blocking_objects.empty()) out << " (blocked by " << object_names(problem.scene, f.blocking_objects) << ")";
    out << "\n";
  }
  out << "output    " << fs::absolute(result_file).lexically_normal().string() << "\n";
}

// While a run plans, a line on the terminal with the time spent: a run may take its
// whole time limit (60 s by default) and print nothing until it ends. Only on a
// terminal (scripts and logs read the summary), cleared when the run ends.
class ElapsedLine {
 public:
  ElapsedLine(bool on, std::string planner, double limit) {
    if (!on) return;
    thread_ = std::jthread([planner = std::move(planner), limit](std::stop_token stop) {
      const auto start = std::chrono::steady_clock::now();
      std::mutex m;
      std::condition_variable_any wake;
      std::unique_lock lock(m);
      while (!wake.wait_for(lock, stop, std::chrono::milliseconds(500), [] { return false; }) && !stop.stop_requested()) {
        const double spent = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        char line[96];
        std::snprintf(line, sizeof line, "\rplanning  %s: %.1f s of %g s", planner.c_str(), spent, limit);
        std::cerr << line << std::flush;
      }
    });
  }
  ~ElapsedLine() {
    if (!thread_.joinable()) return;
    thread_.request_stop();
    thread_.join();
    std::cerr << "\r" << std::string(72, ' ') << "\r" << std::flush;
  }

 private:
  std::jthread thread_;
};

}  // namespace

namespace {

struct PlanRun {
  run::RunOutcome outcome;
  std::optional<InputError> plugin_error;
};

PlanRun plan_once(const Problem& problem, const plugin::Registry& registry, const run::RunOptions& options,
                  const PlanArgs& args) {
  PlanRun r;
  try {
    const ElapsedLine elapsed(args.verbosity != Verbosity::quiet && isatty(fileno(stderr)), problem.planner.name,
                              options.time_limit.value_or(problem.time_limit));
    const CpuLoad load(args.load);
    r.outcome = run::plan(problem, registry, options);
  } catch (const InputError& e) {
    // A plugin the problem names is missing or rejects its parameters: bad input, but
    // the run is still recorded so that scripts find a result.json with the reason.
    r.plugin_error = e;
    r.outcome.info = {problem.planner.name, options.time_limit.value_or(problem.time_limit),
                      options.seed.value_or(problem.seed), ExitCode::bad_input, {}};
    r.outcome.result.reason = e.diagnostics().items().empty() ? e.what() : e.diagnostics().items().front().message;
  }
  return r;
}

// Runs 2..N of plan --repeat against the first: the first difference, or nothing.
std::optional<std::string> repeat_difference(const Problem& problem, const plugin::Registry& registry,
                                             const run::RunOptions& options, const PlanArgs& args,
                                             const std::string& first, double& fastest, double& slowest) {
  for (int k = 2; k <= args.repeat; ++k) {
    if (args.verbosity != Verbosity::quiet) std::cerr << "repeat    run " << k << " of " << args.repeat << "\n";
    const PlanRun again = plan_once(problem, registry, options, args);
    fastest = std::min(fastest, again.outcome.result.time.total);
    slowest = std::max(slowest, again.outcome.result.time.total);
    const std::string text = io::result_to_json(problem, again.outcome.result, again.outcome.info);
    if (auto d = result_difference(first, text)) {
      const fs::path file = args.output / ("result-run" + std::to_string(k) + ".json");
      io::write_text_file(file, text, "result file");
      return "run " + std::to_string(k) + " differs from run 1 at " + *d + " (its result: " + file.string() + ")";
    }
  }
  return std::nullopt;
}

}  // namespace

std::vector<Diagnostic> check_pddl_task(const Problem& problem);

int plan(const PlanArgs& args) {
  Problem problem = io::load_problem(args.problem);
  try {  // warnings about the PDDL files; their errors the planner reports as it always has
    for (const Diagnostic& w : check_pddl_task(problem)) {
      if (args.verbosity != Verbosity::quiet) std::cerr << w.str() << "\n";
    }
  } catch (const InputError&) {
  }
  if (args.planner && *args.planner != problem.planner.name) problem.planner = PluginChoice{*args.planner, {}, {"--planner", 0, 0}};
  run::RunOptions options;
  if (args.seed) options.seed = static_cast<std::uint64_t>(*args.seed);
  options.time_limit = args.time_limit;
  options.plugin_paths = args.plugin_paths;
  // The expected result is read and parsed first: a bad file is bad input before any planning.
  std::optional<std::string> expected;
  if (args.expect) {
    expected = io::read_text_file(*args.expect, "expected result file");
    if (!nlohmann::json::accept(*expected)) throw InputError({args.expect->string(), 0, 0}, "not a result.json: not JSON");
  }
  // Where the results go is checked before planning: a long run's plan is never lost
  // to an unwritable --output (bad input, exit 2, nothing planned).
  io::check_writable_directory(args.output, "output directory (--output)");
  const plugin::Registry registry(run::plugin_search_paths(problem, options));
  if (args.verbosity == Verbosity::verbose) std::cerr << registry.describe_search();

  PlanRun first = plan_once(problem, registry, options, args);
  run::RunOutcome& outcome = first.outcome;
  const fs::path result_file = args.output / "result.json";
  const std::string first_text = io::result_to_json(problem, outcome.result, outcome.info);
  // Verdicts of --repeat and --expect come before anything is written, so that
  // result.json's exit_code is the process's.
  const std::string load = args.load > 0 ? ", " + std::to_string(args.load) + " busy threads on its CPU" : "";
  std::vector<std::string> verdicts;
  if (args.repeat > 1 && !first.plugin_error) {
    double fastest = outcome.result.time.total, slowest = fastest;
    if (auto d = repeat_difference(problem, registry, options, args, first_text, fastest, slowest)) {
      verdicts.push_back("repeat    NOT DETERMINISTIC: " + *d);
      outcome.info.exit_code = ExitCode::internal_error;
      outcome.result.reason = "plan --repeat: not deterministic: " + *d;
    } else {
      verdicts.push_back("repeat    " + std::to_string(args.repeat) + " runs" + load +
                         ": identical apart from time fields (total " + seconds(fastest) + " to " + seconds(slowest) + ")");
    }
  }
  if (expected && !first.plugin_error) {
    if (const std::optional<std::string> d = result_difference(*expected, first_text)) {
      verdicts.push_back("expect    DIFFERENT from " + args.expect->string() + " at " + *d);
      outcome.info.exit_code = ExitCode::internal_error;
      outcome.result.reason = "plan --expect: different from " + args.expect->string() + " at " + *d;
    } else {
      verdicts.push_back("expect    identical to " + args.expect->string() + " apart from time fields" + load);
    }
  }
  // The planner's drawings beside the result (a roadmap is tens of times the rest),
  // never stale; written first, so that result.json can say when they could not be.
  const fs::path drawings_file = args.output / "drawings.json";
  const std::string drawings_text = io::drawings_to_json(outcome.result);
  std::optional<std::string> write_fault;
  try {
    std::error_code ec;
    if (outcome.result.drawings.empty()) fs::remove(drawings_file, ec);
    else io::write_text_file(drawings_file, drawings_text, "drawings file");
  } catch (const io::WriteError& e) {
    write_fault = e.what();
    outcome.info.exit_code = ExitCode::internal_error;
    outcome.result.reason = std::string("the run's drawings could not be written: ") + e.what();
  }
  const std::string result_text = io::result_to_json(problem, outcome.result, outcome.info);
  io::write_text_file(result_file, result_text, "result file");
  if (write_fault) std::cerr << *write_fault << "\n";
  if (first.plugin_error) std::cerr << first.plugin_error->diagnostics().str();
  if (args.verbosity != Verbosity::quiet) print_summary(std::cout, problem, outcome, result_file);
  if (args.html) {
    // The page is a view of the run: failing to write it is reported, not the run's outcome.
    const fs::path page = args.output / "plan.html";
    try {
      viewer::write_plan_html(page, problem, {result_text, drawings_text, result_file.string()});
      if (args.verbosity != Verbosity::quiet) std::cout << "replay: " << page.string() << " (open it in a browser)\n";
    } catch (const io::WriteError& e) {
      std::cerr << "warning: no replay page: " << e.what() << "\n";
    }
  }
  // Same seed, same result: the verdicts print even with --quiet, they are what was asked.
  for (const std::string& v : verdicts) std::cout << v << "\n";
  return outcome.info.exit_code;
}

int view(const ViewArgs& args) {
  const std::string text = io::read_text_file(args.result, "result file");
  fs::path problem_file;
  if (args.problem) {
    problem_file = *args.problem;
  } else {
    try {
      problem_file = nlohmann::json::parse(text).at("problem").get<std::string>();
    } catch (const nlohmann::json::exception& e) {
      throw InputError({args.result.string(), 0, 0}, std::string("not a result.json with a \"problem\": ") + e.what());
    }
    if (!fs::exists(problem_file)) {
      throw InputError({args.result.string(), 0, 0}, "the problem it was planned for, " + problem_file.string() +
                                                          ", is gone: name it with --problem");
    }
  }
  const fs::path page = args.output.value_or(args.result.parent_path() / "plan.html");
  io::check_writable(page, "page");
  const Problem problem = io::load_problem(problem_file);
  const fs::path drawings = args.result.parent_path() / "drawings.json";
  viewer::write_plan_html(page, problem,
                          {text, fs::exists(drawings) ? io::read_text_file(drawings, "drawings file") : "",
                           args.result.string()});
  if (args.verbosity != Verbosity::quiet) std::cout << "wrote " << page.string() << " (open it in a browser)\n";
  return 0;
}

namespace {

void print_objects(std::ostream& out, const Scene& scene) {
  for (const SceneObject& o : scene.objects) {
    const Eigen::Vector3d p = o.world_T_object.translation();
    out << "  " << std::left << std::setw(12) << o.id << std::setw(9) << shape_name(o.shape) << std::fixed
        << std::setprecision(3) << "at (" << p.x() << ", " << p.y() << ", " << p.z() << ")"
        << (o.movable ? "" : "  fixed") << (&o == &scene.objects[scene.target] ? "  TARGET" : "");
    if (!o.supports.empty()) out << "  on " << object_names(scene, o.supports);
    out << "\n";
  }
  out.unsetf(std::ios::floatfield);
}

}  // namespace

// The warnings of a `task: pddl` problem's files (io::load_problem parsed them and
// checked its stream bindings, so errors have been thrown already).
std::vector<Diagnostic> check_pddl_task(const Problem& problem) {
  const auto* task = std::get_if<PddlTask>(&problem.task);
  return task ? stream::parsed_task(*task)->warnings : std::vector<Diagnostic>{};
}

int validate(const ValidateArgs& args) {
  int exit_code = ExitCode::solved;
  for (const fs::path& file : args.files) {
    try {
      if (io::detect_file_kind(file) == io::FileKind::problem) {
        // Every error of the problem's files, its plugins' and its start's in one run:
        // each check runs on the parts that read without error.
        Diagnostics errors;
        const io::ProblemReading reading = io::read_problem(file, errors);
        const Problem& problem = reading.problem;
        if (reading.whole) {
          for (const Diagnostic& w : check_pddl_task(problem)) {
            if (args.verbosity != Verbosity::quiet) std::cerr << w.str() << "\n";
          }
        }
        if (!args.skip_plugins && reading.plugin_paths_whole) {
          run::RunOptions options;
          options.plugin_paths = args.plugin_paths;
          const plugin::Registry registry(run::plugin_search_paths(problem, options));
          const run::ProblemPart part = reading.whole           ? run::ProblemPart::whole
                                        : reading.plugins_whole ? run::ProblemPart::plugins
                                                                : run::ProblemPart::some_plugins;
          run::create_plugins(problem, registry, errors, part);
        }
        if (reading.whole) {
          try {
            run::check_start_configuration(problem);
          } catch (const InputError& e) {
            errors.append(e.diagnostics());
          }
        }
        errors.throw_if_any();
        if (args.verbosity != Verbosity::quiet) {
          std::cout << file.string() << ": valid problem '" << problem.name << "', scene " << describe_scene(problem.scene)
                    << "\n";
          if (args.verbosity == Verbosity::verbose) print_objects(std::cout, problem.scene);
        }
      } else {
        const Scene scene = io::load_scene(file);
        if (args.verbosity != Verbosity::quiet) std::cout << file.string() << ": valid scene " << describe_scene(scene) << "\n";
        if (args.verbosity == Verbosity::verbose) print_objects(std::cout, scene);
      }
    } catch (const InputError& e) {
      std::cerr << e.diagnostics().str();
      if (args.verbosity != Verbosity::quiet) {
        std::cerr << file.string() << ": " << e.diagnostics().size() << " error"
                  << (e.diagnostics().size() == 1 ? "" : "s") << "\n";
      }
      exit_code = ExitCode::bad_input;
    } catch (const std::exception& e) {
      std::cerr << file.string() << ": internal error: " << e.what() << "\n";
      if (exit_code == ExitCode::solved) exit_code = ExitCode::internal_error;
    }
  }
  return exit_code;
}

namespace {

// A plugin's parameters as its configure() reads them; a plugin that cannot be
// created says why instead (the listing goes on).
void print_parameters(const plugin::Registry& registry, const plugin::PluginDescriptor& d) {
  try {
    const auto declared = registry.declared_parameters(d.kind, d.name);
    if (declared.empty()) std::cout << "    parameters: none\n";
    else std::cout << "    parameters:\n";
    for (const ParameterDeclaration& p : declared) {
      const std::string fallback = p.fallback.empty() ? "-" : p.fallback;
      std::cout << "      " << std::setw(22) << p.key << std::setw(16) << p.type << std::setw(14) << fallback
                << (fallback.size() >= 14 ? " " : "") << p.help
                << (p.range.empty() ? "" : (p.help.empty() ? "" : "; ") + p.range) << "\n";
    }
  } catch (const std::exception& e) {
    std::cout << "    parameters: unknown (creating it failed: " << e.what() << ")\n";
  }
}

}  // namespace

int plugins(const PluginsArgs& args) {
  const plugin::Registry registry(plugin::Registry::default_search_paths(args.plugin_paths));
  const std::vector<plugin::PluginDescriptor> all = registry.plugins();
  std::vector<plugin::PluginDescriptor> found;
  for (const plugin::PluginDescriptor& d : all) {
    if (args.names.empty() || std::find(args.names.begin(), args.names.end(), d.name) != args.names.end()) found.push_back(d);
  }
  for (const std::string& name : args.names) {
    if (std::none_of(all.begin(), all.end(), [&](const plugin::PluginDescriptor& d) { return d.name == name; })) {
      std::set<std::string> names;
      for (const plugin::PluginDescriptor& d : all) names.insert(d.name);
      std::string list;
      for (const std::string& n : names) list += (list.empty() ? "" : ", ") + n;
      std::cerr << "cluttertamp plugins: no plugin named '" << name << "'; found: " << (list.empty() ? "none" : list)
                << "\n" << registry.describe_search();
      return ExitCode::bad_input;
    }
  }
  if (args.verbosity != Verbosity::quiet) {
    std::cout << std::left << std::setw(18) << "KIND" << std::setw(22) << "NAME" << std::setw(9) << "VERSION"
              << std::setw(5) << "ABI" << "DESCRIPTION\n";
    for (const plugin::PluginDescriptor& d : found) {
      std::cout << std::setw(18) << d.kind << std::setw(22) << d.name << std::setw(9) << d.version
                << std::setw(5) << d.abi_version << d.description << "\n";
      if (args.verbosity == Verbosity::verbose) {
        std::cout << "    " << d.library.string() << "\n";
        print_parameters(registry, d);
      }
    }
    if (found.empty()) std::cout << "(no plugins found)\n";
    if (args.names.empty()) std::cout << "\n" << registry.describe_search();
  }
  return ExitCode::solved;
}

}  // namespace cluttertamp::cli
