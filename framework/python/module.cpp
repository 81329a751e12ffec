// The extension `cluttertamp._cluttertamp`: what the Python package (cluttertamp/*.py)
// builds its API on. Results cross as the text of result.json, so that Python sees
// exactly what the command line writes; geometry crosses as numpy arrays.
#include <chrono>
#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <cmath>
#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "cluttertamp/core/diagnostics.hpp"
#include "cluttertamp/core/problem.hpp"
#include "cluttertamp/io/text_file.hpp"
#include "cluttertamp/io/problem_io.hpp"
#include "cluttertamp/io/result_json.hpp"
#include "cluttertamp/io/robot_description_io.hpp"
#include "cluttertamp/io/scene_io.hpp"
#include "cluttertamp/pddl/parser.hpp"
#include "cluttertamp/pddl/validator.hpp"
#include "cluttertamp/plugin/registry.hpp"
#include "cluttertamp/robot/ik.hpp"
#include "cluttertamp/robot/robot_description.hpp"
#include "cluttertamp/run/runner.hpp"
#include "cluttertamp/scenes/shelf_generator.hpp"
#include "cluttertamp/search/grounding.hpp"
#include "cluttertamp/search/planner.hpp"
#include "cluttertamp/viewer/plan_html.hpp"
#include "python/gil.hpp"
#include "python/samplers.hpp"
#include "python/streams.hpp"

namespace py = pybind11;
namespace fs = std::filesystem;

namespace cluttertamp::python {
namespace {

// Registries by search path, kept until the interpreter exits: a registry must outlive
// every object its plugins make, and loading the plugins again for each plan costs.
const plugin::Registry& registry_for(const std::vector<fs::path>& search_paths) {
  static std::mutex mutex;
  static auto* registries = new std::map<std::vector<fs::path>, std::unique_ptr<plugin::Registry>>();
  const std::lock_guard<std::mutex> lock(mutex);
  auto& registry = (*registries)[search_paths];
  if (!registry) registry = std::make_unique<plugin::Registry>(search_paths);
  return *registry;
}

// A loaded problem file: what Python holds between loading and planning.
struct LoadedProblem {
  std::shared_ptr<const Problem> problem;
};

LoadedProblem load_problem(const fs::path& file, const std::vector<fs::path>& package_paths) {
  io::set_command_line_package_paths(package_paths);
  return LoadedProblem{std::make_shared<const Problem>(io::load_problem(file))};
}

// A finished run: result.json's text at once, drawings.json's (a roadmap can be ten
// times the rest) only when asked for.
struct PlanRun {
  std::shared_ptr<const Problem> problem;
  run::RunOutcome outcome;
  std::string result_json() const { return io::result_to_json(*problem, outcome.result, outcome.info); }
  std::string drawings_json() const { return io::drawings_to_json(outcome.result); }
};

// Planning with the GIL released: Python threads run meanwhile.
PlanRun plan(const LoadedProblem& loaded, std::optional<std::uint64_t> seed, std::optional<double> time_limit,
             std::optional<std::string> planner, const std::vector<fs::path>& plugin_paths) {
  PlanRun run{loaded.problem, {}};
  if (planner && *planner != loaded.problem->planner.name) {
    auto changed = std::make_shared<Problem>(*loaded.problem);
    changed->planner = PluginChoice{*planner, {}, {"planner=", 0, 0}};
    run.problem = changed;
  }
  run::RunOptions options;
  options.seed = seed;
  options.time_limit = time_limit;
  options.plugin_paths = plugin_paths;
  {
    const py::gil_scoped_release unlocked;  // Python samplers take it again for each call
    const HoldingGil released(false);
    const plugin::Registry& registry = registry_for(run::plugin_search_paths(*run.problem, options));
    run.outcome = run::plan(*run.problem, registry, options);
  }
  drop_pending_references();  // Python samplers the run let go of without the GIL
  return run;
}

// A robot description with numpy in and out: joint vectors as 1-D arrays (rad, m, URDF
// order), poses as 4 x 4 homogeneous matrices in the URDF root's frame (where a scene's
// robot_base stands), whichever link the IK chain starts from.
struct Robot {
  std::shared_ptr<const robot::RobotDescription> description;

  std::vector<std::string> joint_names() const { return description->model()->variable_names(); }
  Eigen::VectorXd home() const { return description->home(); }
  void check(const Eigen::VectorXd& q) const {
    if (static_cast<std::size_t>(q.size()) != description->model()->variable_count()) {
      throw py::value_error("a configuration of '" + description->name() + "' has " +
                            std::to_string(description->model()->variable_count()) + " values, not " +
                            std::to_string(q.size()));
    }
  }
  Eigen::Matrix4d tool_pose(const Eigen::VectorXd& q) const {
    check(q);
    std::vector<Eigen::Isometry3d> poses;
    description->model()->link_poses(q, poses);
    return poses[static_cast<std::size_t>(description->tip_link())].matrix();
  }
  std::map<std::string, Eigen::Matrix4d> link_poses(const Eigen::VectorXd& q) const {
    check(q);
    std::vector<Eigen::Isometry3d> poses;
    description->model()->link_poses(q, poses);
    std::map<std::string, Eigen::Matrix4d> out;
    for (std::size_t i = 0; i < poses.size(); ++i) out[description->model()->links()[i].name] = poses[i].matrix();
    return out;
  }
  std::vector<Eigen::VectorXd> ik(const Eigen::Matrix4d& root_T_tool, std::optional<Eigen::VectorXd> seed,
                                  std::uint64_t random_seed) const {
    const Eigen::VectorXd start = seed.value_or(description->home());
    check(start);
    const Eigen::Matrix3d rotation = root_T_tool.topLeftCorner<3, 3>();
    if (!(rotation.transpose() * rotation).isApprox(Eigen::Matrix3d::Identity(), 1e-6) || rotation.determinant() < 0) {
      throw py::value_error("the pose's upper left 3 x 3 block is not a rotation");
    }
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.linear() = rotation;
    pose.translation() = root_T_tool.topRightCorner<3, 1>();
    return description->ik().solve(description->root_T_ik_base().inverse() * pose, start, random_seed);
  }
};

Robot load_robot(const fs::path& file, const std::vector<fs::path>& package_paths) {
  io::set_command_line_package_paths(package_paths);
  return Robot{std::make_shared<const robot::RobotDescription>(io::load_robot_description(file))};
}

// A PDDL domain and problem searched as `cluttertamp pddl` does, the plan in IPC format.
py::dict solve_pddl(const fs::path& domain_file, const fs::path& problem_file, const std::string& search,
                    double time_limit, std::optional<std::uint64_t> max_expansions, const std::string& landmarks, bool anytime) {
  // As `cluttertamp pddl`: the time limit counts from the start, parsing included.
  const auto start = std::chrono::steady_clock::now();
  const auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
  const pddl::Domain domain = pddl::load_domain(domain_file);
  const pddl::Problem problem = pddl::load_problem(problem_file, domain);
  search::SearchResult result;
  std::vector<std::string> steps;
  {
    const py::gil_scoped_release unlocked;
    search::Task task;
    try {
      task = search::ground(domain, problem, nullptr, std::max(0.0, time_limit - elapsed()));
    } catch (const InputError&) {
      throw;
    } catch (const std::exception& e) {  // past the time limit, or too large to ground
      result.reason = std::string("grounding: ") + e.what();
    }
    search::SearchOptions options;
    options.algorithm = search;
    options.landmarks = landmarks;
    options.anytime = anytime;
    if (max_expansions) options.max_expansions = *max_expansions;
    if (result.reason.empty()) {
      options.time_limit = std::max(0.0, time_limit - elapsed());
      result = search::plan(task, options);
      for (const search::OperatorId op : result.plan) steps.push_back(task.operators[op].name);
    }
  }
  py::dict out;
  out["solved"] = result.solved;
  out["reason"] = result.solved ? py::object(py::none()) : py::object(py::str(result.reason));
  out["plan"] = steps;
  out["cost"] = result.cost;
  out["expanded"] = result.statistics.expanded;
  out["generated"] = result.statistics.generated;
  out["evaluated"] = result.statistics.evaluated;
  out["search_time"] = result.statistics.seconds;
  out["plans_found"] = result.plans_found;
  return out;
}

py::dict validate_pddl_plan(const fs::path& domain_file, const fs::path& problem_file, const std::string& plan_text,
                            const std::string& plan_name) {
  const pddl::Domain domain = pddl::load_domain(domain_file);
  const pddl::Problem problem = pddl::load_problem(problem_file, domain);
  const std::vector<pddl::PlanStep> plan = pddl::parse_plan(plan_text, plan_name, domain, problem);
  const pddl::PlanValidation v = pddl::validate_plan(domain, problem, plan);
  py::dict out;
  out["valid"] = v.valid;
  out["reason"] = v.valid ? py::object(py::none()) : py::object(py::str(v.reason));
  out["step"] = v.step;
  out["cost"] = v.cost;
  return out;
}

// InputError as the Python exception cluttertamp.InputError(ValueError): its message
// every error with its location, `errors` the (file, line, column, message) tuples.
void translate_input_errors(py::module_& m) {
  // Leaked: its destructor would drop a reference after the interpreter is gone.
  static auto& exception = *new py::exception<InputError>(m, "InputError", PyExc_ValueError);
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const InputError& e) {
      py::list errors;
      for (const Diagnostic& d : e.diagnostics().items()) {
        errors.append(py::make_tuple(d.location.file.str(), d.location.line, d.location.column, d.message));
      }
      std::string text = e.diagnostics().str();
      while (!text.empty() && text.back() == '\n') text.pop_back();
      if (text.empty()) text = e.what();
      py::object instance = py::reinterpret_borrow<py::object>(exception)(text);
      instance.attr("errors") = errors;
      PyErr_SetObject(exception.ptr(), instance.ptr());
    } catch (const io::WriteError& e) {
      PyErr_SetString(PyExc_OSError, e.what());  // a file not written: Python's own error for that
    }
  });
}

}  // namespace
}  // namespace cluttertamp::python

PYBIND11_MODULE(_cluttertamp, m) {
  using namespace cluttertamp::python;
  namespace ct = cluttertamp;
  m.doc() = "cluttertamp's C++ core; use the package `cluttertamp`, which wraps it";
  translate_input_errors(m);
  bind_streams(m);
  bind_samplers(m);

  py::class_<LoadedProblem>(m, "LoadedProblem")
      .def_property_readonly("name", [](const LoadedProblem& p) { return p.problem->name; })
      .def_property_readonly("file", [](const LoadedProblem& p) { return p.problem->source_file; })
      .def_property_readonly("scene_file", [](const LoadedProblem& p) { return p.problem->scene_file; })
      .def_property_readonly("planner", [](const LoadedProblem& p) { return p.problem->planner.name; })
      .def_property_readonly("seed", [](const LoadedProblem& p) { return p.problem->seed; })
      .def_property_readonly("time_limit", [](const LoadedProblem& p) { return p.problem->time_limit; })
      .def_property_readonly("objects",
                             [](const LoadedProblem& p) {
                               std::vector<std::string> ids;
                               for (const ct::SceneObject& o : p.problem->scene.objects) ids.push_back(o.id);
                               return ids;
                             })
      .def_property_readonly("target",
                             [](const LoadedProblem& p) -> std::optional<std::string> {
                               if (p.problem->scene.objects.empty()) return std::nullopt;
                               return p.problem->scene.objects.at(p.problem->scene.target).id;
                             })
      .def_property_readonly("robot",
                             [](const LoadedProblem& p) -> std::optional<Robot> {
                               if (!p.problem->robot.loaded) return std::nullopt;
                               return Robot{p.problem->robot.loaded};
                             })
      .def("check_start", [](const LoadedProblem& p) { ct::run::check_start_configuration(*p.problem); })
      .def(
          "world",
          [](const LoadedProblem& p, std::optional<Eigen::VectorXd> configuration) {
            ct::WorldState state = ct::WorldState::initial(p.problem->scene);
            if (p.problem->robot.loaded) {
              state.robot_configuration = configuration.value_or(ct::robot::initial_configuration(p.problem->robot));
            }
            return world_of(p.problem, state);
          },
          py::arg("configuration") = py::none());

  py::class_<Robot>(m, "Robot")
      .def_property_readonly("name", [](const Robot& r) { return r.description->name(); })
      .def_property_readonly("joint_names", &Robot::joint_names)
      .def_property_readonly("home", &Robot::home)
      .def("tool_pose", &Robot::tool_pose, py::arg("q"))
      .def("link_poses", &Robot::link_poses, py::arg("q"))
      .def("ik", &Robot::ik, py::arg("pose"), py::arg("seed") = py::none(), py::arg("random_seed") = 0);

  m.def("load_problem", &load_problem, py::arg("file"), py::arg("package_paths") = std::vector<fs::path>{});
  m.def("load_robot", &load_robot, py::arg("file"), py::arg("package_paths") = std::vector<fs::path>{});
  m.def(
      "generate_shelf",
      [](const fs::path& file, int objects, std::uint64_t seed, double min_gap, double width, double depth,
         double exit_distance) {
        if (objects < 1) throw py::value_error("a shelf holds at least one object, not " + std::to_string(objects));
        for (const double length : {min_gap, width, depth, exit_distance}) {
          if (!std::isfinite(length) || length < 0) throw py::value_error("lengths must be finite and not negative");
        }
        ct::scenes::ShelfSpec spec;
        spec.objects = objects;
        spec.min_gap = min_gap;
        spec.width = width;
        spec.depth = depth;
        spec.exit_distance = exit_distance;
        ct::Scene scene;
        try {
          scene = ct::scenes::generate_shelf_scene(spec, seed);
        } catch (const std::runtime_error& e) {
          throw py::value_error(e.what());
        }
        ct::io::write_scene(file, scene);
        return scene.objects.at(scene.target).id;
      },
      py::arg("file"), py::arg("objects") = 12, py::arg("seed") = 0, py::arg("min_gap") = 0.0, py::arg("width") = 0.0,
      py::arg("depth") = 0.0, py::arg("exit_distance") = 0.2);
  m.def("check_scene", [](const fs::path& file) { return ct::io::load_scene(file).name; }, py::arg("file"));
  m.def("is_problem_file",
        [](const fs::path& file) { return ct::io::detect_file_kind(file) == ct::io::FileKind::problem; }, py::arg("file"));
  py::class_<PlanRun>(m, "PlanRun")
      .def("result_json", &PlanRun::result_json)
      .def("drawings_json", &PlanRun::drawings_json);
  m.def("plan", &plan, py::arg("problem"), py::arg("seed") = py::none(), py::arg("time_limit") = py::none(),
        py::arg("planner") = py::none(), py::arg("plugin_paths") = std::vector<fs::path>{});
  m.def("solve_pddl", &solve_pddl, py::arg("domain"), py::arg("problem"), py::arg("search") = "lama-first",
        py::arg("time_limit") = 60.0, py::arg("max_expansions") = py::none(), py::arg("landmarks") = "rhw",
        py::arg("anytime") = false);
  m.def("validate_pddl_plan", &validate_pddl_plan, py::arg("domain"), py::arg("problem"), py::arg("plan"),
        py::arg("plan_name") = "plan");
  m.def("search_names", [] { return ct::search::search_names(); });
  m.def(
      "write_page",
      [](const LoadedProblem& p, const fs::path& file, const std::string& result_json, const std::string& drawings_json,
         const std::string& name) {
        ct::viewer::write_plan_html(file, *p.problem, {result_json, drawings_json, name});
      },
      py::arg("problem"), py::arg("file"), py::arg("result_json"), py::arg("drawings_json"), py::arg("name"));
}
