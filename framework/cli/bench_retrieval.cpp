// `cluttertamp bench retrieval`: Table I of Tian et al. (T-RO 2023) — the retrieval
// planner on generated shelves of 12, 16 and 20 cylinders with the three initial
// exploration limits — beside the paper's numbers, as a table, CSV and JSON.
#include <chrono>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <iostream>

#include <nlohmann/json.hpp>

#include "cli/commands.hpp"
#include "cli/shelf_support.hpp"
#include "cli/statistics.hpp"
#include "cluttertamp/collision/collision_world.hpp"
#include "cluttertamp/manipulation/actions.hpp"
#include "cluttertamp/plugin/grasp_sampler.hpp"
#include "cluttertamp/plugin/motion_sampler.hpp"
#include "cluttertamp/plugin/placement_sampler.hpp"
#include "cluttertamp/plugin/registry.hpp"
#include "cluttertamp/plugin/task_planner.hpp"
#include "cluttertamp/run/runner.hpp"
#include "cluttertamp/scenes/shelf_generator.hpp"

namespace cluttertamp::cli {

namespace {


// Table I of the paper: |O_r| (incl. target), time (s), iterations, success (%).
struct Paper {
  double removed, removed_sd, time, time_sd, iterations, success;
};
const std::map<std::pair<int, std::string>, Paper> kTableI{
    {{12, "one"}, {2.14, 0.34, 10.54, 5.89, 1.78, 100}},    {{12, "nodecol"}, {2.35, 0.47, 9.85, 4.91, 1.5, 100}},
    {{12, "objects"}, {2.36, 1.08, 8.95, 5.74, 1, 100}},   {{16, "one"}, {2.81, 0.52, 20.50, 6.71, 3.18, 95}},
    {{16, "nodecol"}, {3.15, 0.53, 16.25, 6.0, 1.76, 100}}, {{16, "objects"}, {3.35, 1.0, 21.43, 7.50, 1, 100}},
    {{20, "one"}, {3.28, 0.58, 21.73, 7.13, 3.28, 95}},    {{20, "nodecol"}, {3.57, 0.62, 17.63, 7.18, 1.92, 95}},
    {{20, "objects"}, {4.25, 0.82, 15.73, 7.38, 1, 100}},
};

std::string ms(double mean, double sd) {
  char text[48];
  std::snprintf(text, sizeof text, "%.2f(%.2f)", mean, sd);
  return text;
}

}  // namespace

int bench_retrieval(const BenchArgs& args) {
  const plugin::Registry registry(plugin::Registry::default_search_paths());
  const plugin::Samplers samplers = shipped_samplers(registry);
  const auto robot = std::make_shared<const robot::RobotDescription>(robot::RobotDescription::load(args.robot));
  const std::vector<int> sizes = args.sizes.empty() ? std::vector<int>{12, 16, 20} : args.sizes;
  const std::vector<std::string> strategies{"one", "nodecol", "objects"};

  // Instances: generated scenes whose target needs a removal (as the paper's).
  std::map<int, std::vector<Scene>> scenes;
  for (int n : sizes) {
    scenes::ShelfSpec spec;
    spec.objects = n;
    for (std::uint64_t seed = args.seed; static_cast<int>(scenes[n].size()) < args.instances && seed < args.seed + 1000; ++seed) {
      Scene scene;
      try {
        scene = scenes::generate_shelf_scene(spec, seed);
      } catch (const std::runtime_error& e) {
        std::cerr << "bench retrieval: --sizes " << n << ": " << e.what() << "\n";
        return run::ExitCode::bad_input;
      }
      if (!target_comes_out_directly(scene, robot, samplers, seed)) scenes[n].push_back(std::move(scene));
    }
  }

  nlohmann::ordered_json rows = nlohmann::ordered_json::array();
  std::ofstream csv;
  if (!args.csv.empty()) {
    csv.open(args.csv);
    csv << "objects,initial_L,instance,run,solved,removed,time_s,task_s,motion_s,iterations\n";
  }
  const int total = static_cast<int>(sizes.size() * strategies.size()) * args.instances * args.runs;
  int done = 0;
  std::cout << std::left << std::setw(8) << "|O|" << std::setw(9) << "L init" << std::setw(15) << "|O_r|" << std::setw(15)
            << "paper" << std::setw(16) << "time s" << std::setw(9) << "median" << std::setw(15) << "paper" << std::setw(15)
            << "task s" << std::setw(15) << "motion s" << std::setw(13) << "iterations" << std::setw(8) << "paper" << std::setw(9) << "success" << "paper\n";
  for (int n : sizes) {
    for (const std::string& strategy : strategies) {
      std::vector<double> removed, time, iterations, task, motion;
      int solved = 0, attempts = 0;
      for (std::size_t i = 0; i < scenes[n].size(); ++i) {
        for (int run = 0; run < args.runs; ++run) {
          Problem problem;
          problem.scene = scenes[n][i];
          problem.robot.loaded = robot;
          problem.task = RetrievalTask{"target"};
          Parameters parameters;
          parameters.set("initial_L", strategy);
          const auto planner = registry.create<plugin::TaskPlanner>("retrieval_graph", parameters);
          collision::CollisionWorld world(problem.scene, robot);
          std::map<std::string, std::uint64_t> counters;
          const std::uint64_t seed = args.seed + static_cast<std::uint64_t>(run);
          plugin::PlanningContext context{problem, plugin::Deadline::after(args.time_limit), seed, counters, samplers, &world};
          WorldState state = WorldState::initial(problem.scene);
          state.robot_configuration = robot->home();
          const auto t0 = std::chrono::steady_clock::now();
          const Result r = planner->solve(context, state);
          const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
          ++attempts;
          if (r.solved) {
            ++solved;
            removed.push_back(double(r.moved_objects.size()));
            time.push_back(seconds);
            task.push_back(r.time.task_planning);
            motion.push_back(r.time.motion_planning);
            iterations.push_back(double(r.counters.count("iterations") ? r.counters.at("iterations") : 0));
          }
          if (csv.is_open()) {
            csv << n << "," << strategy << "," << i << "," << run << "," << r.solved << "," << r.moved_objects.size() << ","
                << seconds << "," << r.time.task_planning << "," << r.time.motion_planning << ","
                << (r.counters.count("iterations") ? r.counters.at("iterations") : 0) << "\n";
          }
          ++done;
          if (args.verbosity != Verbosity::quiet) {
            std::cerr << "\r[" << std::string(static_cast<std::size_t>(30 * done / total), '#')
                      << std::string(static_cast<std::size_t>(30 - 30 * done / total), ' ') << "] " << done << "/" << total
                      << std::flush;
          }
        }
      }
      if (args.verbosity != Verbosity::quiet) std::cerr << "\r" << std::string(50, ' ') << "\r";
      const Paper p = kTableI.count({n, strategy}) ? kTableI.at({n, strategy}) : Paper{};
      const double success = attempts ? 100.0 * solved / attempts : 0.0;
      std::cout << std::left << std::setw(8) << n << std::setw(9) << strategy << std::setw(15)
                << ms(mean(removed), stddev(removed)) << std::setw(15) << ms(p.removed, p.removed_sd) << std::setw(16)
                << ms(mean(time), stddev(time)) << std::setw(9) << std::fixed << std::setprecision(2) << median(time)
                << std::setw(15) << ms(p.time, p.time_sd) << std::setw(15) << ms(mean(task), stddev(task))
                << std::setw(15) << ms(mean(motion), stddev(motion)) << std::setw(13) << mean(iterations) << std::setw(8)
                << p.iterations << std::setw(9) << std::setprecision(0) << success << p.success << "\n";
      std::cout.unsetf(std::ios::floatfield);
      rows.push_back({{"objects", n},
                      {"initial_L", strategy},
                      {"instances", scenes[n].size()},
                      {"runs", args.runs},
                      {"success_rate", success},
                      {"removed_mean", mean(removed)},
                      {"removed_std", stddev(removed)},
                      {"time_mean_s", mean(time)},
                      {"time_std_s", stddev(time)},
                      {"time_median_s", median(time)},
                      {"task_time_mean_s", mean(task)},
                      {"task_time_std_s", stddev(task)},
                      {"task_time_median_s", median(task)},
                      {"motion_time_mean_s", mean(motion)},
                      {"motion_time_std_s", stddev(motion)},
                      {"motion_time_median_s", median(motion)},
                      {"iterations_mean", mean(iterations)},
                      {"paper", {{"removed", p.removed}, {"time_s", p.time}, {"iterations", p.iterations}, {"success", p.success}}}});
    }
  }
  if (!args.json.empty()) std::ofstream(args.json) << rows.dump(2) << "\n";
  return run::ExitCode::solved;
}

}  // namespace cluttertamp::cli
