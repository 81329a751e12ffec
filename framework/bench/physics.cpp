// `cluttertamp bench physics`: how much faster than real time the pushing physics
// runs on a generated shelf (issue goal: at least 20 times for 10 objects).
#include <chrono>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <random>

#include <nlohmann/json.hpp>

#include "bench/json_file.hpp"
#include "cluttertamp/bench/bench.hpp"
#include "bench/statistics.hpp"
#include "cluttertamp/physics/push_world.hpp"
#include "cluttertamp/run/runner.hpp"
#include "cluttertamp/scenes/shelf_generator.hpp"

namespace cluttertamp::bench {

namespace {
constexpr double kGoal = 20.0;      // times real time
constexpr double kDuration = 1.0;   // s of each control
constexpr std::size_t kBatch = 10;  // controls per timed batch
}  // namespace

int physics(const BenchArgs& args) {
  scenes::ShelfSpec spec;
  spec.objects = args.objects;
  const Scene scene = scenes::generate_shelf_scene(spec, args.seed);
  const WorldState initial = WorldState::initial(scene);
  const physics::PushWorld world(scene, initial);
  const Eigen::Vector3d size = scenes::cabinet_size(spec);
  std::mt19937_64 rng(args.seed);
  auto uniform = [&](double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng); };

  // Pushes into the clutter from the open side: the gripper starts just inside the
  // front, heading in, and moves forward (5 to 15 cm/s) with a little sideways drift
  // and turn for kDuration.
  const std::size_t n = std::max<std::size_t>(5 * kBatch, args.samples / 100);
  std::vector<double> factors;
  std::size_t touching = 0, fallen = 0;
  for (std::size_t start = 0; start + kBatch <= n; start += kBatch) {
    std::vector<std::pair<physics::PushState, physics::PushControl>> batch;
    for (std::size_t i = 0; i < kBatch; ++i) {
      const Eigen::Vector3d gripper(spec.front + 0.03, uniform(-size.y() / 2 + 0.08, size.y() / 2 - 0.08), uniform(-0.3, 0.3));
      batch.push_back({world.state_of(initial, gripper),
                       physics::PushControl{{uniform(0.05, 0.15), uniform(-0.03, 0.03), uniform(-0.2, 0.2)}, kDuration}});
    }
    const auto t0 = std::chrono::steady_clock::now();
    for (const auto& [state, control] : batch) {
      const physics::PushOutcome out = world.propagate(state, control);
      touching += !out.touched.empty();
      fallen += !out.fallen.empty();
    }
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    factors.push_back(double(kBatch) * kDuration / wall);
  }
  const double factor = median(factors);
  const bool met = spec.objects != 10 || factor >= kGoal;
  std::cout << "pushing physics (Bullet, " << 1.0 / world.settings().time_step << " Hz) on a " << scene.objects.size()
            << "-cylinder shelf (" << scene.name << "): " << factors.size() * kBatch << " pushes of " << kDuration
            << " s from the open side, " << touching << " touching objects, " << fallen << " dropping one\n";
  std::cout << "median speed: " << std::fixed << std::setprecision(1) << factor << " x real time";
  if (spec.objects == 10) std::cout << " (goal >= " << kGoal << ": " << (met ? "met" : "NOT met") << ")";
  std::cout << "\n";
  if (!args.json.empty()) {
    nlohmann::ordered_json json{{"scene", scene.name},   {"objects", scene.objects.size()},
                                {"pushes", factors.size() * kBatch}, {"touching", touching},
                                {"dropping", fallen},     {"median_real_time_factor", factor},
                                {"goal", kGoal}};
    write_json_file(args.json, json);
  }
  return goal_exit_code(args.check_goals, met);
}

}  // namespace cluttertamp::bench
