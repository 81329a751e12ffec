// `cluttertamp bench collision`: the speed of the geometric queries every planner
// makes, on a UR10 in front of a generated 20-cylinder shelf.
#include <algorithm>
#include <chrono>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <random>

#include <nlohmann/json.hpp>

#include "bench/json_file.hpp"
#include "cluttertamp/bench/bench.hpp"
#include "bench/statistics.hpp"
#include "cluttertamp/io/robot_description_io.hpp"
#include "cluttertamp/collision/collision_world.hpp"
#include "cluttertamp/run/runner.hpp"
#include "cluttertamp/scenes/shelf_generator.hpp"

namespace cluttertamp::bench {

namespace {

using Clock = std::chrono::steady_clock;

struct Measure {
  std::string query;
  double median_us = 0;
  double goal_us = 0;  // 0: no goal
  std::size_t calls = 0;
};

// Median over batches of the mean time per call; `call(i)` runs query number i.
template <class F>
Measure measure(const std::string& name, double goal_us, std::size_t items, std::size_t batch, F&& call) {
  std::vector<double> per_call;
  std::size_t calls = 0;
  for (std::size_t start = 0; start + batch <= items; start += batch) {
    const auto t0 = Clock::now();
    for (std::size_t i = start; i < start + batch; ++i) call(i);
    per_call.push_back(std::chrono::duration<double, std::micro>(Clock::now() - t0).count() / double(batch));
    calls += batch;
  }
  return {name, median(per_call), goal_us, calls};
}

Eigen::Isometry3d tcp_pose(const Eigen::Vector3d& p, double yaw) {
  // Approach (tool z) horizontal along +x turned by yaw; tool y up.
  const Eigen::Vector3d z(std::cos(yaw), std::sin(yaw), 0.0), y(0, 0, 1);
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear().col(0) = y.cross(z);
  t.linear().col(1) = y;
  t.linear().col(2) = z;
  t.translation() = p;
  return t;
}

}  // namespace

int collision(const BenchArgs& args) {
  const auto robot = std::make_shared<const robot::RobotDescription>(
      io::load_robot_description(args.robot));
  scenes::ShelfSpec spec;
  spec.objects = args.objects;
  const Scene scene = scenes::generate_shelf_scene(spec, args.seed);
  const collision::CollisionWorld world(scene, robot);
  auto context = world.make_context();
  const robot::RobotModel& model = *robot->model();
  std::mt19937_64 rng(args.seed);
  const std::size_t n = args.samples;

  // Random configurations, and realistic ones: IK solutions reaching into the cabinet.
  std::vector<Eigen::VectorXd> random_q(n);
  for (auto& q : random_q) {
    q.resize(static_cast<Eigen::Index>(model.variable_count()));
    for (Eigen::Index j = 0; j < q.size(); ++j) q[j] = std::uniform_real_distribution<double>(-M_PI, M_PI)(rng);
  }
  const Eigen::Vector3d size = scenes::cabinet_size(spec);
  std::vector<Eigen::Isometry3d> poses(n);
  std::vector<Eigen::VectorXd> reach_q;
  for (auto& pose : poses) {
    const Eigen::Vector3d p(std::uniform_real_distribution<double>(spec.front, spec.front + size.x())(rng),
                            std::uniform_real_distribution<double>(-size.y() / 2, size.y() / 2)(rng),
                            spec.floor_height + std::uniform_real_distribution<double>(0.08, 0.2)(rng));
    pose = tcp_pose(p, std::uniform_real_distribution<double>(-M_PI / 4, M_PI / 4)(rng));
    pose = scene.world_T_robot_base.inverse() * pose;  // IK works in the robot's base frame
    for (const auto& q : robot->ik().solve(pose, robot->home())) {
      if (reach_q.size() < n) reach_q.push_back(q);
    }
  }
  if (reach_q.size() < 100) {
    std::cerr << "bench collision: only " << reach_q.size() << " reaching configurations were found\n";
    return run::ExitCode::internal_error;
  }
  std::size_t colliding = 0, with_objects = 0;
  std::vector<Eigen::VectorXd> free_q;  // the slowest case of a validity check: nothing to stop at
  for (const auto& q : reach_q) {
    const auto report = world.check(q, *context);
    colliding += !report.valid();
    with_objects += !report.objects.empty();
    if (report.valid()) free_q.push_back(q);
  }

  const ObjectIndex target = scene.target;
  const double r_b = robot->gripper().footprint_radius(std::get<Cylinder>(scene.objects[target].shape).radius);
  const collision::Footprint footprint{r_b, scene.objects[target].world_T_object.translation().z() - 0.12,
                                       scene.objects[target].world_T_object.translation().z() + 0.12};
  std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>> segments(n);
  for (auto& [a, b] : segments) {
    auto point = [&] {
      return Eigen::Vector2d(std::uniform_real_distribution<double>(spec.front, spec.front + size.x())(rng),
                             std::uniform_real_distribution<double>(-size.y() / 2, size.y() / 2)(rng));
    };
    a = point();
    b = a + 0.05 * (point() - a).normalized();  // a roadmap step: 5 cm
  }

  std::vector<Eigen::Isometry3d> link_poses;
  std::size_t sink = 0;  // keeps results alive
  const std::size_t batch = 50;
  const std::size_t m = reach_q.size();
  std::vector<Measure> results;
  results.push_back(measure("forward kinematics (all links)", 1.0, n, batch, [&](std::size_t i) {
    model.link_poses(random_q[i], link_poses);
    sink += link_poses.size();
  }));
  const bool analytic = dynamic_cast<const robot::UrAnalyticIk*>(&robot->ik()) != nullptr;
  results.push_back(measure(analytic ? "analytic IK (all solutions)" : "numeric IK", analytic ? 5.0 : 0.0, n, batch,
                            [&](std::size_t i) {
    sink += robot->ik().solve(poses[i], robot->home()).size();
  }));
  results.push_back(measure("validity check", 10.0, m, batch, [&](std::size_t i) { sink += world.is_valid(reach_q[i], *context); }));
  if (free_q.size() >= batch) {
    results.push_back(measure("validity check, collision-free", 10.0, free_q.size(), batch,
                              [&](std::size_t i) { sink += world.is_valid(free_q[i], *context); }));
  }
  results.push_back(measure("full collision set", 30.0, m, batch, [&](std::size_t i) {
    sink += world.check(reach_q[i], *context).objects.size();
  }));
  results.push_back(measure("footprint sweep (EdgeCol)", 2.0, n, batch, [&](std::size_t i) {
    sink += world.swept_objects(segments[i].first, segments[i].second, footprint).size();
  }));
  results.push_back(measure("minimum distance", 0.0, m, batch, [&](std::size_t i) {
    sink += world.min_distance(reach_q[i], *context) > 0;
  }));

  // IK as planners use it, on poses known to be reachable: the tool poses of random
  // configurations within the limits, each solved from the home configuration and timed alone.
  std::vector<double> ik_us;
  std::size_t ik_solved = 0;
  std::mt19937_64 ik_rng(args.seed);
  for (std::size_t i = 0; i < n; ++i) {
    Eigen::VectorXd q(static_cast<Eigen::Index>(model.variable_count()));
    for (std::size_t v = 0; v < model.variable_count(); ++v) {
      const robot::Joint& joint = model.joints()[model.variables()[v]];
      q[static_cast<Eigen::Index>(v)] = std::uniform_real_distribution<double>(joint.lower, joint.upper)(ik_rng);
    }
    std::vector<Eigen::Isometry3d> frames;
    model.link_poses(q, frames);
    const Eigen::Isometry3d goal = frames[robot->base_link()].inverse() * frames[robot->tip_link()];
    const auto t0 = Clock::now();
    const auto solutions = robot->ik().solve(goal, robot->home(), i);
    ik_us.push_back(std::chrono::duration<double, std::micro>(Clock::now() - t0).count());
    if (!solutions.empty()) {
      model.link_poses(solutions.front(), frames);
      const auto [position, orientation] = robot::pose_error(frames[robot->base_link()].inverse() * frames[robot->tip_link()], goal);
      ik_solved += position < 1e-6 && orientation < 1e-6;
    }
  }
  const double ik_success = 100.0 * double(ik_solved) / double(std::max<std::size_t>(n, 1));
  const double ik_median = median(ik_us);
  const bool ik_met = analytic || (ik_success >= 99.0 && ik_median <= 200.0);

  std::cout << robot->name() << " before a " << scene.objects.size() << "-cylinder shelf (" << scene.name << "), "
            << m << " reaching configurations (" << colliding << " in collision, " << with_objects
            << " touching objects), medians over batches of " << batch << " calls\n\n";
  std::cout << std::left << std::setw(34) << "query" << std::right << std::setw(12) << "median µs" << std::setw(10)
            << "goal µs" << std::setw(8) << "met" << "\n";
  nlohmann::ordered_json json;
  json["scene"] = scene.name;
  json["configurations"] = m;
  json["in_collision"] = colliding;
  json["results"] = nlohmann::ordered_json::array();
  bool all_met = true;
  for (const Measure& r : results) {
    const bool met = r.goal_us == 0 || r.median_us <= r.goal_us;
    all_met = all_met && met;
    std::cout << std::left << std::setw(34) << r.query << std::right << std::fixed << std::setprecision(3)
              << std::setw(12) << r.median_us << std::setw(10);
    if (r.goal_us > 0) std::cout << std::setprecision(1) << r.goal_us << std::setw(8) << (met ? "yes" : "NO");
    else std::cout << "-" << std::setw(8) << "-";
    std::cout << "\n";
    json["results"].push_back({{"query", r.query}, {"median_us", r.median_us}, {"goal_us", r.goal_us}, {"calls", r.calls}});
  }
  std::cout << "\n" << (analytic ? "analytic" : "numeric") << " IK on " << n
            << " reachable poses (the tool poses of random configurations within the joint limits), from the home configuration: " << std::setprecision(2)
            << ik_success << " % solved, median " << std::setprecision(1) << ik_median << " µs per query";
  if (!analytic) std::cout << " (goal: 99 %, 200 µs: " << (ik_met ? "met" : "NOT met") << ")";
  std::cout << "\n";
  json["ik_reachable"] = {{"poses", n}, {"solved_percent", ik_success}, {"median_us", ik_median}};
  all_met = all_met && ik_met;
  if (sink == 42) std::cout << "";
  if (!args.json.empty()) {
    write_json_file(args.json, json);
    std::cout << "\nwrote " << args.json.string() << "\n";
  }
  return goal_exit_code(args.check_goals, all_met);
}

}  // namespace cluttertamp::bench
