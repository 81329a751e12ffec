#include "cluttertamp/run/runner.hpp"

#include <chrono>
#include <cstdio>
#include <optional>
#include <new>

#include "cluttertamp/core/memory_limit.hpp"

#include "cluttertamp/collision/collision_world.hpp"
#include "cluttertamp/collision/shared_world.hpp"
#include "cluttertamp/core/world_state.hpp"
#include "cluttertamp/physics/push_world.hpp"
#include "cluttertamp/plugin/stream_sampler.hpp"
#include "cluttertamp/robot/robot_description.hpp"
#include "cluttertamp/plugin/task_planner.hpp"

namespace cluttertamp::run {

namespace fs = std::filesystem;

std::vector<fs::path> plugin_search_paths(const Problem& problem, const RunOptions& options) {
  std::vector<fs::path> first = options.plugin_paths;
  first.insert(first.end(), problem.plugin_paths.begin(), problem.plugin_paths.end());
  return plugin::Registry::default_search_paths(first);
}

namespace {

// Runs `make`; its InputError goes into `errors` (every plugin of a problem is tried, so
// that all misspelt names and bad parameters are reported in one run).
template <class Make>
void collecting(Diagnostics& errors, Make&& make) {
  try {
    make();
  } catch (const InputError& e) {
    errors.append(e.diagnostics());
  }
}

// A kind the planner cannot plan without that the problem does not name is bad input,
// found before planning (the planner would only fail with a reason).
void check_required_kinds(const Problem& problem, const plugin::TaskPlanner& planner, const plugin::Samplers& samplers,
                          const plugin::Registry& registry, Diagnostics& errors) {
  for (const std::string& kind : planner.required_kinds()) {
    if (samplers.get(kind) || problem.samplers.count(kind)) continue;  // named: its own error says what is wrong
    std::string found;
    for (const plugin::PluginDescriptor& d : registry.plugins()) {
      if (d.kind == kind) found += (found.empty() ? "" : ", ") + d.name;
    }
    errors.error(problem.planner.where, "planner '" + problem.planner.name + "' needs a " + kind +
                                            ": add `" + kind + ": NAME` to the problem's plugins block (found: " +
                                            (found.empty() ? std::string("none") : found) + ")");
  }
}

plugin::Samplers create_samplers(const plugin::Registry& registry, const Problem& problem, Diagnostics& errors) {
  plugin::Samplers samplers;
  // Named pairs, not structured bindings: clang 14 cannot capture those in a lambda.
  for (const auto& entry : problem.samplers) {
    const std::string& kind = entry.first;
    const PluginChoice& choice = entry.second;
    collecting(errors, [&] { samplers.set(kind, registry.create(kind, choice.name, choice.parameters, choice.where)); });
  }
  // Bindings naming the same plugin with the same parameters share one object, so a
  // plugin serving several streams keeps one state (caches, a shared world model).
  std::map<std::string, std::shared_ptr<plugin::StreamSampler>> by_choice;
  for (const auto& entry : problem.streams) {
    const PluginChoice& choice = entry.second;
    auto& shared = by_choice[choice.name + " " + choice.parameters.to_yaml()];
    if (!shared) {
      collecting(errors, [&] { shared = registry.create<plugin::StreamSampler>(choice.name, choice.parameters, choice.where); });
    }
    samplers.streams[entry.first] = shared;
  }
  return samplers;
}

}  // namespace

std::string memory_limit_reason() {
  const std::size_t mib = memory_limit_mib();
  return mib ? "memory limit reached (" + std::to_string(mib) + " MiB)" : std::string("memory limit reached (out of memory)");
}

Plugins create_plugins(const Problem& problem, const plugin::Registry& registry, Diagnostics& errors,
                       ProblemPart read) {
  Plugins plugins;
  plugins.samplers = create_samplers(registry, problem, errors);
  if (read == ProblemPart::whole || !problem.planner.name.empty()) {  // a part read may leave it unnamed
    collecting(errors, [&] {
      plugins.planner =
          registry.create<plugin::TaskPlanner>(problem.planner.name, problem.planner.parameters, problem.planner.where);
    });
  }
  if (plugins.planner && read != ProblemPart::some_plugins) {
    check_required_kinds(problem, *plugins.planner, plugins.samplers, registry, errors);
    // The planner's own checks read the rest of the problem: they judge only a whole one.
    if (read == ProblemPart::whole) {
      collecting(errors, [&] { plugins.planner->check_inputs(problem); });
    }
  }
  // The physics block is read by whichever plugin pushes: checked here, whole, once.
  if (read == ProblemPart::whole && problem.physics.size() > 0) collecting(errors, [&] { physics::push_settings(problem); });
  return plugins;
}

Plugins create_plugins(const Problem& problem, const plugin::Registry& registry) {
  Diagnostics errors;
  Plugins plugins = create_plugins(problem, registry, errors, ProblemPart::whole);
  errors.throw_if_any();
  return plugins;
}

namespace {

// A retrieval whose target no configuration of the arm can reach fails before planning,
// saying so, instead of sampling grasps until the time limit.
std::optional<std::string> out_of_reach(const Problem& problem) {
  if (!problem.robot.loaded || !std::holds_alternative<RetrievalTask>(problem.task)) return std::nullopt;
  const SceneObject& target = problem.scene.objects.at(problem.scene.target);
  const robot::IkSolver::Reach reach = problem.robot.loaded->ik().reach();
  const Eigen::Isometry3d world_T_base = problem.robot.loaded->world_T_ik_base(problem.scene.world_T_robot_base);
  const Eigen::Vector3d centre = world_T_base * reach.centre;
  const Eigen::Vector3d at = target.world_T_object.translation();
  const Eigen::AlignedBox3d bounds = world_bounds(target.shape, target.world_T_object);
  const double half_size = 0.5 * (bounds.max() - bounds.min()).norm();
  const double distance = (at - centre).norm();
  if (distance - half_size <= reach.radius) return std::nullopt;
  auto point = [](const Eigen::Vector3d& p) {
    char text[96];
    std::snprintf(text, sizeof text, "(%.3f, %.3f, %.3f)", p.x(), p.y(), p.z());
    return std::string(text);
  };
  char figures[160];
  std::snprintf(figures, sizeof figures, "%.3f m from the arm's first joint at %s, which the tool reaches at most %.3f m from",
                distance, point(centre).c_str(), reach.radius);
  return "the target '" + target.id + "' at " + point(at) + " is out of the robot's reach from its base at " +
         point(world_T_base.translation()) + ": " + figures;
}

}  // namespace

namespace {

// check_start_configuration in `world`, the problem's scene and robot as loaded.
void check_start_in(const Problem& problem, const collision::CollisionWorld& world) {
  if (!problem.robot.loaded || !std::holds_alternative<RetrievalTask>(problem.task)) return;
  const Eigen::VectorXd q = robot::initial_configuration(problem.robot);
  auto context = world.make_context();
  const collision::CollisionReport contacts = world.check(q, *context);
  if (contacts.valid()) return;
  const std::string start = problem.robot.configuration ? "the robot's start configuration (the problem's `configuration`)"
                                                        : "the robot's start configuration (its description's `home`)";
  Diagnostics errors;
  for (const ObjectIndex o : contacts.objects) {
    const SceneObject& object = problem.scene.objects[o];
    errors.error(object.where, "object '" + object.id + "' overlaps " + start + "; no plan can start there");
  }
  std::map<std::size_t, std::vector<std::string>> links_on_body;
  for (const collision::FixedContact& c : world.fixed_contacts(q, *context)) {
    links_on_body[c.fixed_body].push_back(c.link ? problem.robot.loaded->model()->links()[*c.link].name : "the held object");
  }
  for (const auto& [body, links] : links_on_body) {
    std::string names;
    for (const std::string& link : links) names += (names.empty() ? "" : ", ") + link;
    const FixedBody& fixed = problem.scene.fixed[body];
    errors.error(fixed.where, "fixed body '" + fixed.id + "' overlaps " + start + " (" + names + "); no plan can start there");
  }
  for (const auto& [a, b] : world.self_contacts(q, *context)) {
    const robot::RobotModel& model = *problem.robot.loaded->model();
    errors.error(problem.robot.where, start + " is in self collision: '" + model.links()[a].name + "' touches '" +
                                          model.links()[b].name + "'");
  }
  if (errors.empty()) errors.error(problem.robot.where, start + " is in collision");  // a contact none of the above names
  errors.throw_if_any();
}

}  // namespace

void check_start_configuration(const Problem& problem) {
  if (!problem.robot.loaded || !std::holds_alternative<RetrievalTask>(problem.task)) return;
  check_start_in(problem, collision::CollisionWorld(problem.scene, problem.robot.loaded));
}

RunOutcome plan(const Problem& problem, const plugin::Registry& registry, const RunOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  RunOutcome outcome;
  outcome.info.planner = problem.planner.name;
  outcome.info.seed = options.seed.value_or(problem.seed);
  outcome.info.time_limit = options.time_limit.value_or(problem.time_limit);

  // Bad plugins are bad input: this throws InputError before any planning starts.
  const Plugins plugins = create_plugins(problem, registry);
  const plugin::Samplers& samplers = plugins.samplers;
  const auto& planner = plugins.planner;

  std::map<std::string, std::uint64_t> counters;
  std::unique_ptr<collision::SharedWorld> world;
  if (problem.robot.loaded) {
    world = std::make_unique<collision::SharedWorld>(problem.scene, problem.robot.loaded);
    check_start_in(problem, world->world());  // the geometry built once, for both
  }
  plugin::PlanningContext context{problem, plugin::Deadline::after(outcome.info.time_limit), outcome.info.seed,
                                  counters, samplers, world.get()};
  std::map<std::string, PhaseTotals> phases;
  context.phases = &phases;
  WorldState initial = WorldState::initial(problem.scene);
  initial.robot_configuration = robot::initial_configuration(problem.robot);
  if (auto why = out_of_reach(problem)) {
    outcome.result.reason = *why;
    outcome.info.exit_code = ExitCode::no_plan;
    outcome.result.time.total = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return outcome;
  }
  try {
    outcome.result = planner->solve(context, initial);
    outcome.info.exit_code = outcome.result.solved ? ExitCode::solved : ExitCode::no_plan;
  } catch (const InputError&) {
    throw;
  } catch (const std::bad_alloc&) {
    // The search grew past the memory limit: a limit reached, like the time limit.
    outcome.result = Result{};
    outcome.result.reason = memory_limit_reason();
    outcome.info.exit_code = ExitCode::no_plan;
  } catch (const std::exception& e) {
    outcome.result = Result{};
    outcome.result.reason = "internal error in task_planner '" + problem.planner.name + "': " + e.what();
    outcome.info.exit_code = ExitCode::internal_error;
  } catch (...) {
    outcome.result = Result{};
    outcome.result.reason = "internal error in task_planner '" + problem.planner.name + "': an exception of unknown type";
    outcome.info.exit_code = ExitCode::internal_error;
  }
  for (const auto& [key, value] : counters) outcome.result.counters[key] += value;
  for (const auto& [name, totals] : phases) {
    PhaseTotals& sum = outcome.result.phases[name];
    sum.calls += totals.calls;
    sum.collision_checks += totals.collision_checks;
    sum.seconds += totals.seconds;
  }
  outcome.result.time.total = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (!outcome.result.solved && outcome.result.reason.empty()) {
    outcome.result.reason = "the planner returned no plan and gave no reason";
  }
  return outcome;
}

}  // namespace cluttertamp::run
