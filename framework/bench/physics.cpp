// `cluttertamp bench physics`: how much faster than real time the pushing physics
// runs on a generated shelf (issue goal: at least 20 times for 10 objects). A sweep
// whose run b is batch b of the pushes (see timing.hpp).
#include <chrono>
#include <cmath>
#include <iomanip>
#include <iostream>
#include <limits>
#include <memory>
#include <random>

#include <nlohmann/json.hpp>

#include "bench/json_file.hpp"
#include "bench/reports.hpp"
#include "bench/settings.hpp"
#include "bench/statistics.hpp"
#include "bench/sweep.hpp"
#include "bench/timing.hpp"
#include "cluttertamp/bench/bench.hpp"
#include "cluttertamp/io/robot_description_io.hpp"
#include "cluttertamp/physics/push_world.hpp"
#include "cluttertamp/robot/robot_description.hpp"
#include "cluttertamp/run/runner.hpp"
#include "cluttertamp/scenes/shelf_generator.hpp"
#include "cluttertamp/version.hpp"

namespace cluttertamp::bench {

namespace {
constexpr double kGoal = 20.0;      // times real time, the floating gripper
constexpr double kArmGoal = 10.0;   // ... the arm
constexpr int kGoalObjects = 10;    // the goal is for this many objects
constexpr double kDuration = 1.0;   // s of each control
constexpr std::size_t kBatch = 10;  // controls per timed batch

std::size_t batch_count(const BenchArgs& args) { return std::max<std::size_t>(5 * kBatch, args.samples / 100) / kBatch; }

scenes::ShelfSpec spec_of(const BenchArgs& args) {
  scenes::ShelfSpec spec;
  spec.objects = args.objects;
  return spec;
}

bool with_arm(const BenchArgs& args) { return args.pusher == "arm"; }
double goal_of(const BenchArgs& args) { return with_arm(args) ? kArmGoal : kGoal; }

// The floating gripper in a Table I shelf, or the robot's arm on its planar base in a
// pushing shelf like Papallas & Dogar's (their lever, friction rule and validity rules).
Scene scene_of(const BenchArgs& args) {
  if (!with_arm(args)) return scenes::generate_shelf_scene(spec_of(args), args.seed);
  scenes::PushShelfSpec spec;
  spec.obstacles = args.objects;
  return scenes::generate_push_shelf(spec, args.seed);
}

physics::PushSettings settings_of_pusher(const BenchArgs& args) {
  physics::PushSettings settings;
  if (!with_arm(args)) return settings;
  const robot::RobotDescription robot = io::load_robot_description(args.robot);
  auto arm = std::make_shared<physics::ArmPusher>(physics::arm_pusher(robot, robot.home()));
  arm->base_offset.x() = physics::base_offset_for_lever(*arm, physics::kPaperLever);
  settings.arm = std::move(arm);
  settings.yaw_limits = {-M_PI / 4, M_PI / 4};
  settings.friction_combine = physics::PushSettings::FrictionCombine::max;
  settings.tip_limit = 0.1;  // and objects that tip, with the validity rules of the paper's code
  settings.wall_force_limit = 9.0;
  return settings;
}

// The shelf and every push, made from the seed alone (the same in every process of a
// sweep); batch b of the pushes simulated and timed.
class PhysicsRunner {
 public:
  explicit PhysicsRunner(const BenchArgs& args)
      : args_(args), scene_(scene_of(args)), initial_(WorldState::initial(scene_)), world_(scene_, initial_, settings_of_pusher(args)) {
    // Pushes into the clutter from the open side: the hand starts just inside the
    // front, heading in, and moves forward (5 to 15 cm/s; the arm 5 to 10) with a
    // little sideways drift and turn for kDuration.
    const Eigen::AlignedBox2d support = world_.support_region();
    const double half_width = support.sizes().y() / 2;
    double front = support.min().x();
    if (with_arm(args)) front = std::max(front, clutter_front() - 0.09);  // a pushing shelf's clutter starts deep inside
    const double fastest = with_arm(args) ? 0.1 : 0.15;
    std::mt19937_64 rng(args.seed);
    auto uniform = [&](double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng); };
    for (std::size_t i = 0; i < batch_count(args) * kBatch; ++i) {
      const Eigen::Vector3d hand(front + 0.03, uniform(-half_width + 0.08, half_width - 0.08), uniform(-0.3, 0.3));
      pushes_.push_back({world_.state_of(initial_, world_.pose_for_hand(hand)),
                         physics::PushControl{{uniform(0.05, fastest), uniform(-0.03, 0.03), uniform(-0.2, 0.2)}, kDuration}});
    }
  }

  // The nearest x any pushable object reaches, m.
  double clutter_front() const {
    double nearest = std::numeric_limits<double>::infinity();
    for (ObjectIndex i : world_.pushable()) {
      nearest = std::min(nearest, initial_.world_T_objects[i].translation().x() - world_.footprint_radius(i));
    }
    return nearest;
  }

  Record run(std::size_t b) {
    std::size_t touching = 0, fallen = 0, tipped = 0;
    const auto t0 = std::chrono::steady_clock::now();
    for (std::size_t i = b * kBatch; i < (b + 1) * kBatch; ++i) {
      const physics::PushOutcome out = world_.propagate(pushes_[i].first, pushes_[i].second);
      touching += !out.touched.empty();
      fallen += !out.fallen.empty();
      tipped += !out.tipped.empty();
    }
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return {{"problem", scene_.name},
            {"objects", scene_.objects.size()},
            {"planner", "physics"},
            {"seed", args_.seed},
            {"batch", b},
            {"rate_hz", 1.0 / world_.settings().time_step},
            {"pushes", kBatch},
            {"pusher", args_.pusher},
            {"touching", touching},
            {"dropping", fallen},
            {"tipping", tipped},
            {"real_time_factor", double(kBatch) * kDuration / wall},
            {"host", host_name()},
            {"version", std::string(version())}};
  }

 private:
  const BenchArgs& args_;
  Scene scene_;
  WorldState initial_;
  physics::PushWorld world_;
  std::vector<std::pair<physics::PushState, physics::PushControl>> pushes_;
};

}  // namespace

int physics(const BenchArgs& args) {
  return run_timed_batches<PhysicsRunner>("physics", args, batch_count(args), "batch", report_physics);
}

int report_physics(const BenchArgs& args, const std::vector<Record>& records) {
  std::vector<double> factors;
  std::size_t pushes = 0, touching = 0, fallen = 0, tipped = 0;
  for (const Record& r : records) {
    factors.push_back(r.at("real_time_factor").get<double>());
    pushes += r.at("pushes").get<std::size_t>();
    touching += r.at("touching").get<std::size_t>();
    fallen += r.at("dropping").get<std::size_t>();
    tipped += r.value("tipping", std::size_t{0});  // records of earlier versions have none
  }
  const std::string scene = records.empty() ? std::string("no scene") : records.front().at("problem").get<std::string>();
  const double rate = records.empty() ? 0.0 : records.front().at("rate_hz").get<double>();
  const double factor = median(factors);
  const double goal = goal_of(args);
  const bool has_goal = args.objects == kGoalObjects;
  const bool met = !has_goal || (!factors.empty() && factor >= goal);
  std::cout << "pushing physics (Bullet, " << rate << " Hz) on a " << args.objects << "-cylinder shelf (" << scene << "), pushed by "
            << (with_arm(args) ? "the arm of " + args.robot.filename().string() + " on a planar base" : std::string("a floating gripper"))
            << ":\n"
            << pushes << " pushes of " << kDuration << " s from the open side, " << touching << " touching objects, " << fallen
            << " dropping one" << (with_arm(args) ? ", " + std::to_string(tipped) + " tipping one (beyond 0.1 rad)" : std::string()) << "\n";
  std::cout << "median speed over batches of " << kBatch << " pushes: " << std::fixed << std::setprecision(1) << factor << " x real time";
  if (has_goal) std::cout << " (goal >= " << goal << ": " << (met ? "met" : "NOT met") << ")";
  std::cout << "\n";
  if (const std::string note = hosts_note(records); !note.empty()) std::cout << note << "\n";
  if (!args.json.empty()) {
    write_json_file(args.json, nlohmann::ordered_json{{"scene", scene}, {"objects", args.objects}, {"pushes", pushes},
                                                      {"touching", touching}, {"dropping", fallen}, {"tipping", tipped},
                                                      {"pusher", args.pusher},
                                                      {"median_real_time_factor", factor}, {"goal", goal},
                                                      {"goal_applies", has_goal}});
  }
  if (!args.svg.empty()) {
    write_timing_svg(args.svg,
                     "bench physics: Bullet on " + scene + ", times real time per batch of " + std::to_string(kBatch) + " pushes (" +
                         std::to_string(touching) + " of " + std::to_string(pushes) + " touching objects)",
                     "times real time", {{"pushes", factors, has_goal ? goal : 0.0}}, true);
  }
  return goal_exit_code(args.check_goals, met);
}

}  // namespace cluttertamp::bench
