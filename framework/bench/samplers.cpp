// `cluttertamp bench samplers`: grasp queries with feedback, motion queries and whole
// pick-and-place actions of the shipped samplers, on a UR10 before generated shelves.
// A sweep whose run k is shelf k: every object's queries on it (see timing.hpp).
#include <algorithm>
#include <chrono>
#include <iomanip>
#include <iostream>
#include <memory>

#include <nlohmann/json.hpp>

#include "bench/json_file.hpp"
#include "bench/reports.hpp"
#include "bench/settings.hpp"
#include "bench/statistics.hpp"
#include "bench/sweep.hpp"
#include "bench/timing.hpp"
#include "cluttertamp/bench/bench.hpp"
#include "cluttertamp/collision/shared_world.hpp"
#include "cluttertamp/io/robot_description_io.hpp"
#include "cluttertamp/manipulation/actions.hpp"
#include "cluttertamp/plugin/grasp_sampler.hpp"
#include "cluttertamp/plugin/motion_sampler.hpp"
#include "cluttertamp/plugin/placement_sampler.hpp"
#include "cluttertamp/plugin/registry.hpp"
#include "cluttertamp/run/runner.hpp"
#include "cluttertamp/run/shelf_runs.hpp"
#include "cluttertamp/scenes/shelf_generator.hpp"
#include "cluttertamp/version.hpp"

namespace cluttertamp::bench {

namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

std::size_t shelf_count(const BenchArgs& args) { return std::max<std::size_t>(1, args.samples / 1000); }

// The queries of the table: the key of their times in a record, the count of their
// calls that went well (none for the grasp rows: a record's split is the count), goal.
struct Query {
  const char* name;
  const char* label;
  const char* times;  ///< record key of the times (ms per call)
  const char* ok;     ///< record key of the calls that succeeded; nullptr: none
  const char* ok_word;  ///< what those calls did, in the note
  double goal_ms;
};
const Query kQueries[] = {
    {"grasp query, a grasp usable", "grasp (usable)", "grasp_usable_times_ms", nullptr, "", 2.0},
    {"grasp query, all blocked (feedback)", "grasp (blocked)", "grasp_blocked_times_ms", nullptr, "", 2.0},
    {"motion query (home to pre-grasp)", "motion", "motion_times_ms", "motions_solved", "solved", 20.0},
    {"pick and place (into the buffer)", "pick and place", "pick_place_times_ms", "pick_places_succeeded", "succeeded", 50.0},
};

// Times every object's queries on the shelves it is given, with one set of samplers.
class SamplersRunner {
 public:
  explicit SamplersRunner(const BenchArgs& args)
      : args_(args),
        registry_(plugin::Registry::default_search_paths()),
        samplers_(run::shipped_samplers(registry_)),
        robot_(std::make_shared<const robot::RobotDescription>(io::load_robot_description(args.robot))) {}

  Record run(std::size_t k) {
    Problem problem;
    scenes::ShelfSpec spec;
    spec.objects = args_.objects;
    const std::uint64_t scene_seed = args_.seed + k;
    problem.scene = scenes::generate_shelf_scene(spec, scene_seed);
    problem.robot.loaded = robot_;
    collision::SharedWorld world(problem.scene, problem.robot.loaded);
    std::map<std::string, std::uint64_t> counters;
    plugin::PlanningContext context{problem, plugin::Deadline::after(1e6), args_.seed, counters, samplers_, &world};
    WorldState state = WorldState::initial(problem.scene);
    state.robot_configuration = robot_->home();
    std::vector<double> grasp_ms, blocked_ms, motion_ms, pick_place_ms;
    std::size_t motions_ok = 0, pick_place_ok = 0;
    for (ObjectIndex o = 0; o < problem.scene.objects.size(); ++o) {
      auto t0 = Clock::now();
      const plugin::GraspAnswer answer = samplers_.get<plugin::GraspSampler>()->sample(context, {o, state});
      (answer.usable.empty() ? blocked_ms : grasp_ms).push_back(ms_since(t0));
      if (answer.usable.empty()) continue;
      t0 = Clock::now();
      const plugin::MotionAnswer m =
          samplers_.get<plugin::MotionSampler>()->plan(context, {state.robot_configuration, answer.usable[0].motions[0].pregrasp, state});
      motion_ms.push_back(ms_since(t0));
      motions_ok += m.trajectory.has_value();
      t0 = Clock::now();
      const manipulation::ActionOutcome picked = manipulation::pick(context, state, o);
      const bool ok = picked.ok && manipulation::place(context, picked.after, "buffer").ok;
      pick_place_ms.push_back(ms_since(t0));
      pick_place_ok += ok;
    }
    return {{"problem", problem.scene.name},
            {"robot", robot_->name()},
            {"planner", "samplers"},
            {"scene_seed", scene_seed},
            {"seed", args_.seed},
            {"grasp_usable_times_ms", grasp_ms},
            {"grasp_blocked_times_ms", blocked_ms},
            {"motion_times_ms", motion_ms},
            {"motions_solved", motions_ok},
            {"pick_place_times_ms", pick_place_ms},
            {"pick_places_succeeded", pick_place_ok},
            {"counters", counters},
            {"host", host_name()},
            {"version", std::string(version())}};
  }

 private:
  const BenchArgs& args_;
  plugin::Registry registry_;
  plugin::Samplers samplers_;
  std::shared_ptr<const robot::RobotDescription> robot_;
};

}  // namespace

int samplers(const BenchArgs& args) {
  return run_timed_batches<SamplersRunner>("samplers", args, shelf_count(args), "shelf", report_samplers);
}

int report_samplers(const BenchArgs& args, const std::vector<Record>& records) {
  const std::string robot = records.empty() ? std::string("the robot") : records.front().at("robot").get<std::string>();
  std::cout << robot << " before " << records.size() << " generated shelf(s) of " << args.objects << " cylinders; medians per call\n\n"
            << std::left << std::setw(40) << "query" << std::right << std::setw(11) << "median ms" << std::setw(9) << "goal ms"
            << std::setw(6) << "met" << "   " << "note\n";
  nlohmann::ordered_json json = nlohmann::ordered_json::array();
  std::vector<TimedQuery> plotted;
  bool all = true;
  for (const Query& q : kQueries) {
    std::vector<double> ms;
    std::size_t ok = 0;
    for (const Record& r : records) {
      for (const auto& t : r.at(q.times)) ms.push_back(t.get<double>());
      if (q.ok) ok += r.at(q.ok).get<std::size_t>();
    }
    const double med = median(ms);
    const bool met = !ms.empty() && med <= q.goal_ms;
    all = all && met;
    const std::string note = q.ok ? std::to_string(ok) + "/" + std::to_string(ms.size()) + " " + q.ok_word
                                  : std::to_string(ms.size()) + " objects";
    std::cout << std::left << std::setw(40) << q.name << std::right << std::fixed << std::setprecision(3) << std::setw(11) << med
              << std::setprecision(1) << std::setw(9) << q.goal_ms << std::setw(6) << (met ? "yes" : "NO") << "   " << note << "\n";
    json.push_back({{"query", q.name}, {"median_ms", med}, {"goal_ms", q.goal_ms}, {"calls", ms.size()}, {"note", note}});
    plotted.push_back({q.label, ms, q.goal_ms});
  }
  if (const std::string note = hosts_note(records); !note.empty()) std::cout << note << "\n";
  if (!args.json.empty()) {
    write_json_file(args.json, json);
    std::cout << "\nwrote " << args.json.string() << "\n";
  }
  if (!args.svg.empty()) {
    write_timing_svg(args.svg, "bench samplers: " + robot + " before " + std::to_string(records.size()) + " generated shelves of " +
                                   std::to_string(args.objects) + " cylinders, ms per call",
                     "ms per call", plotted);
  }
  return goal_exit_code(args.check_goals, all);
}

}  // namespace cluttertamp::bench
