// `cluttertamp bench samplers`: grasp queries with feedback, motion queries and whole
// pick-and-place actions of the shipped samplers, on a UR10 before generated shelves.
#include <algorithm>
#include <chrono>
#include <fstream>
#include <iomanip>
#include <iostream>

#include <nlohmann/json.hpp>

#include "bench/json_file.hpp"
#include "cluttertamp/bench/bench.hpp"
#include "bench/statistics.hpp"
#include "cluttertamp/run/shelf_runs.hpp"
#include "cluttertamp/io/robot_description_io.hpp"
#include "cluttertamp/collision/shared_world.hpp"
#include "cluttertamp/manipulation/actions.hpp"
#include "cluttertamp/plugin/grasp_sampler.hpp"
#include "cluttertamp/plugin/motion_sampler.hpp"
#include "cluttertamp/plugin/placement_sampler.hpp"
#include "cluttertamp/plugin/registry.hpp"
#include "cluttertamp/run/runner.hpp"
#include "cluttertamp/scenes/shelf_generator.hpp"

namespace cluttertamp::bench {

namespace {
using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

}  // namespace

int samplers(const BenchArgs& args) {
  const plugin::Registry registry(plugin::Registry::default_search_paths());
  const plugin::Samplers samplers = run::shipped_samplers(registry);

  std::vector<double> grasp_ms, grasp_blocked_ms, motion_ms, pick_place_ms;
  std::size_t grasps_usable = 0, grasps_blocked = 0, motions_ok = 0, motions = 0, pick_place_ok = 0, pick_places = 0;
  const int scenes = std::max(1, static_cast<int>(args.samples / 1000));
  for (int k = 0; k < scenes; ++k) {
    Problem problem;
    scenes::ShelfSpec spec;
    spec.objects = args.objects;
    problem.scene = scenes::generate_shelf_scene(spec, args.seed + static_cast<std::uint64_t>(k));
    problem.robot.loaded = std::make_shared<const robot::RobotDescription>(io::load_robot_description(args.robot));
    collision::SharedWorld world(problem.scene, problem.robot.loaded);
    std::map<std::string, std::uint64_t> counters;
    plugin::PlanningContext context{problem, plugin::Deadline::after(1e6), args.seed, counters, samplers, &world};
    WorldState state = WorldState::initial(problem.scene);
    state.robot_configuration = problem.robot.loaded->home();
    for (ObjectIndex o = 0; o < problem.scene.objects.size(); ++o) {
      auto t0 = Clock::now();
      const plugin::GraspAnswer answer = samplers.get<plugin::GraspSampler>()->sample(context, {o, state});
      const double ms = ms_since(t0);
      (answer.usable.empty() ? grasp_blocked_ms : grasp_ms).push_back(ms);
      (answer.usable.empty() ? grasps_blocked : grasps_usable) += 1;
      if (answer.usable.empty()) continue;
      ++motions;
      t0 = Clock::now();
      const plugin::MotionAnswer m =
          samplers.get<plugin::MotionSampler>()->plan(context, {state.robot_configuration, answer.usable[0].motions[0].pregrasp, state});
      motion_ms.push_back(ms_since(t0));
      motions_ok += m.trajectory.has_value();
      ++pick_places;
      t0 = Clock::now();
      const manipulation::ActionOutcome picked = manipulation::pick(context, state, o);
      const bool ok = picked.ok && manipulation::place(context, picked.after, "buffer").ok;
      pick_place_ms.push_back(ms_since(t0));
      pick_place_ok += ok;
    }
  }
  struct Row {
    const char* query;
    double median_ms;
    double goal_ms;
    std::string note;
  };
  const std::vector<Row> rows{
      {"grasp query, a grasp usable", median(grasp_ms), 2.0, std::to_string(grasps_usable) + " objects"},
      {"grasp query, all blocked (feedback)", median(grasp_blocked_ms), 2.0, std::to_string(grasps_blocked) + " objects"},
      {"motion query (home to pre-grasp)", median(motion_ms), 20.0,
       std::to_string(motions_ok) + "/" + std::to_string(motions) + " solved"},
      {"pick and place (into the buffer)", median(pick_place_ms), 50.0,
       std::to_string(pick_place_ok) + "/" + std::to_string(pick_places) + " succeeded"},
  };
  std::cout << io::load_robot_description(args.robot).name() << " before " << scenes << " generated shelf(s) of "
            << args.objects << " cylinders; medians per call\n\n"
            << std::left << std::setw(40) << "query" << std::right << std::setw(11) << "median ms" << std::setw(9)
            << "goal ms" << std::setw(6) << "met" << "   " << "note\n";
  nlohmann::ordered_json json = nlohmann::ordered_json::array();
  bool all = true;
  for (const Row& r : rows) {
    const bool met = r.median_ms <= r.goal_ms;
    all = all && met;
    std::cout << std::left << std::setw(40) << r.query << std::right << std::fixed << std::setprecision(3)
              << std::setw(11) << r.median_ms << std::setprecision(1) << std::setw(9) << r.goal_ms << std::setw(6)
              << (met ? "yes" : "NO") << "   " << r.note << "\n";
    json.push_back({{"query", r.query}, {"median_ms", r.median_ms}, {"goal_ms", r.goal_ms}, {"note", r.note}});
  }
  if (!args.json.empty()) {
    write_json_file(args.json, json);
    std::cout << "\nwrote " << args.json.string() << "\n";
  }
  return goal_exit_code(args.check_goals, all);
}

}  // namespace cluttertamp::bench
