// `cluttertamp bench collision`: the speed of the geometric queries every planner
// makes, on a UR10 in front of a generated 20-cylinder shelf. A sweep whose run b is
// batch b of every query (see timing.hpp).
#include <algorithm>
#include <chrono>
#include <functional>
#include <iomanip>
#include <iostream>
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
#include "cluttertamp/collision/collision_world.hpp"
#include "cluttertamp/io/robot_description_io.hpp"
#include "cluttertamp/run/runner.hpp"
#include "cluttertamp/scenes/shelf_generator.hpp"
#include "cluttertamp/version.hpp"

namespace cluttertamp::bench {

namespace {

using Clock = std::chrono::steady_clock;

constexpr std::size_t kBatch = 50;  // calls per timed batch

// A query the bench times: its name in the table, its label in the plot, its goal (µs
// per call; 0: none).
struct Query {
  std::string name, label;
  double goal_us;
};

// The batched queries, in the table's order. The IK row depends on the robot's solver.
std::vector<Query> queries(bool analytic) {
  return {{"forward kinematics (all links)", "FK", 1.0},
          {analytic ? "analytic IK (all solutions)" : "numeric IK", "IK", analytic ? 5.0 : 0.0},
          {"validity check", "validity", 10.0},
          {"validity check, collision-free", "validity (free)", 10.0},
          {"full collision set", "collision set", 30.0},
          {"footprint sweep (EdgeCol)", "footprint sweep", 2.0},
          {"minimum distance", "min distance", 0.0}};
}

constexpr const char* kReachableLabel = "IK, reachable";
constexpr double kNumericIkGoalUs = 200.0, kNumericIkGoalPercent = 99.0;

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

std::size_t batch_count(const BenchArgs& args) { return (args.samples + kBatch - 1) / kBatch; }

// The queries' inputs, made from the seed alone (the same in every process of a sweep),
// and batch b of each query timed on them.
class CollisionRunner {
 public:
  explicit CollisionRunner(const BenchArgs& args)
      : args_(args),
        robot_(std::make_shared<const robot::RobotDescription>(io::load_robot_description(args.robot))),
        scene_(scenes::generate_shelf_scene(spec(), args.seed)),
        world_(scene_, robot_),
        context_(world_.make_context()),
        analytic_(dynamic_cast<const robot::UrAnalyticIk*>(&robot_->ik()) != nullptr) {
    sample_inputs();
    if (reach_q_.size() < 100) {
      throw std::runtime_error("bench collision: only " + std::to_string(reach_q_.size()) + " reaching configurations were found");
    }
    for (const auto& q : reach_q_) {
      const auto report = world_.check(q, *context_);
      colliding_ += !report.valid();
      with_objects_ += !report.objects.empty();
      if (report.valid()) free_q_.push_back(q);  // the slowest case of a validity check: nothing to stop at
    }
    declare_calls();
  }

  Record run(std::size_t b) {
    std::size_t results = 0;  // what the queries returned, summed: keeps them from being optimised away
    Record times = Record::object();
    const std::vector<Query> names = queries(analytic_);
    for (std::size_t k = 0; k < calls_.size(); ++k) {
      const auto& [items, call] = calls_[k];
      if ((b + 1) * kBatch > items) {
        times[names[k].name] = nullptr;  // fewer inputs than batches: as the unsharded bench, this batch is not timed
        continue;
      }
      const auto t0 = Clock::now();
      for (std::size_t i = b * kBatch; i < (b + 1) * kBatch; ++i) results += call(i);
      times[names[k].name] = std::chrono::duration<double, std::micro>(Clock::now() - t0).count() / double(kBatch);
    }
    const auto [reachable_us, solved] = time_reachable_ik(b);
    return {{"problem", scene_.name},
            {"robot", robot_->name()},
            {"planner", "collision"},
            {"seed", args_.seed},
            {"batch", b},
            {"configurations", reach_q_.size()},
            {"in_collision", colliding_},
            {"touching_objects", with_objects_},
            {"analytic_ik", analytic_},
            {"call_time_us", times},
            {"reachable_ik", {{"poses", reachable_us.size()}, {"solved", solved}, {"times_us", reachable_us}}},
            {"results", results},
            {"host", host_name()},
            {"version", std::string(version())}};
  }

 private:
  scenes::ShelfSpec spec() const {
    scenes::ShelfSpec s;
    s.objects = args_.objects;
    return s;
  }

  // Random configurations; tool poses in the cabinet and the IK solutions reaching them;
  // roadmap steps for the footprint sweep; and reachable tool poses (those of random
  // configurations within the limits) for IK as planners use it.
  void sample_inputs() {
    const robot::RobotModel& model = *robot_->model();
    const std::size_t n = args_.samples;
    std::mt19937_64 rng(args_.seed);
    auto uniform = [&](double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng); };
    random_q_.resize(n);
    for (auto& q : random_q_) {
      q.resize(static_cast<Eigen::Index>(model.variable_count()));
      for (Eigen::Index j = 0; j < q.size(); ++j) q[j] = uniform(-M_PI, M_PI);
    }
    const scenes::ShelfSpec s = spec();
    const Eigen::Vector3d size = scenes::cabinet_size(s);
    poses_.resize(n);
    for (auto& pose : poses_) {
      const Eigen::Vector3d p(uniform(s.front, s.front + size.x()), uniform(-size.y() / 2, size.y() / 2),
                              s.floor_height + uniform(0.08, 0.2));
      pose = tcp_pose(p, uniform(-M_PI / 4, M_PI / 4));
      pose = robot_->world_T_ik_base(scene_.world_T_robot_base).inverse() * pose;  // IK works in its base link's frame
      for (const auto& q : robot_->ik().solve(pose, robot_->home())) {
        if (reach_q_.size() < n) reach_q_.push_back(q);
      }
    }
    const ObjectIndex target = scene_.target;
    const double z = scene_.objects[target].world_T_object.translation().z();
    footprint_ = {robot_->gripper().footprint_radius(std::get<Cylinder>(scene_.objects[target].shape).radius), z - 0.12, z + 0.12};
    segments_.resize(n);
    for (auto& [a, b] : segments_) {
      auto point = [&] { return Eigen::Vector2d(uniform(s.front, s.front + size.x()), uniform(-size.y() / 2, size.y() / 2)); };
      a = point();
      b = a + 0.05 * (point() - a).normalized();  // a roadmap step: 5 cm
    }
    std::mt19937_64 ik_rng(args_.seed);
    std::vector<Eigen::Isometry3d> frames;
    for (std::size_t i = 0; i < n; ++i) {
      Eigen::VectorXd q(static_cast<Eigen::Index>(model.variable_count()));
      for (std::size_t v = 0; v < model.variable_count(); ++v) {
        const robot::Joint& joint = model.joints()[model.variables()[v]];
        q[static_cast<Eigen::Index>(v)] = std::uniform_real_distribution<double>(joint.lower, joint.upper)(ik_rng);
      }
      model.link_poses(q, frames);
      reachable_.push_back(frames[robot_->base_link()].inverse() * frames[robot_->tip_link()]);
    }
  }

  // Each batched query: how many inputs it has, and call i (returning a number of its result).
  void declare_calls() {
    const robot::RobotModel& model = *robot_->model();
    const std::size_t n = args_.samples, m = reach_q_.size();
    calls_ = {
        {n, [this, &model](std::size_t i) { model.link_poses(random_q_[i], link_poses_); return link_poses_.size(); }},
        {n, [this](std::size_t i) { return robot_->ik().solve(poses_[i], robot_->home()).size(); }},
        {m, [this](std::size_t i) { return std::size_t{world_.is_valid(reach_q_[i], *context_)}; }},
        {free_q_.size(), [this](std::size_t i) { return std::size_t{world_.is_valid(free_q_[i], *context_)}; }},
        {m, [this](std::size_t i) { return world_.check(reach_q_[i], *context_).objects.size(); }},
        {n, [this](std::size_t i) { return world_.swept_objects(segments_[i].first, segments_[i].second, footprint_).size(); }},
        {m, [this](std::size_t i) { return std::size_t{world_.min_distance(reach_q_[i], *context_) > 0}; }},
    };
  }

  // The reachable poses of batch b, each solved from the home configuration and timed
  // alone: their times (µs) and how many were solved to 1e-6 (m and rad).
  std::pair<std::vector<double>, std::size_t> time_reachable_ik(std::size_t b) {
    const robot::RobotModel& model = *robot_->model();
    std::vector<double> us;
    std::size_t solved = 0;
    std::vector<Eigen::Isometry3d> frames;
    for (std::size_t i = b * kBatch; i < std::min(reachable_.size(), (b + 1) * kBatch); ++i) {
      const Eigen::Isometry3d& goal = reachable_[i];
      const auto t0 = Clock::now();
      const auto solutions = robot_->ik().solve(goal, robot_->home(), i);
      us.push_back(std::chrono::duration<double, std::micro>(Clock::now() - t0).count());
      if (solutions.empty()) continue;
      model.link_poses(solutions.front(), frames);
      const auto [position, orientation] = robot::pose_error(frames[robot_->base_link()].inverse() * frames[robot_->tip_link()], goal);
      solved += position < 1e-6 && orientation < 1e-6;
    }
    return {us, solved};
  }

  const BenchArgs& args_;
  std::shared_ptr<const robot::RobotDescription> robot_;
  Scene scene_;
  collision::CollisionWorld world_;
  std::unique_ptr<collision::CollisionWorld::Context> context_;
  bool analytic_;
  std::vector<Eigen::VectorXd> random_q_, reach_q_, free_q_;
  std::vector<Eigen::Isometry3d> poses_, reachable_, link_poses_;
  std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>> segments_;
  collision::Footprint footprint_;
  std::size_t colliding_ = 0, with_objects_ = 0;
  std::vector<std::pair<std::size_t, std::function<std::size_t(std::size_t)>>> calls_;
};

}  // namespace

int collision(const BenchArgs& args) {
  return run_timed_batches<CollisionRunner>("collision", args, batch_count(args), "batch", report_collision);
}

int report_collision(const BenchArgs& args, const std::vector<Record>& records) {
  if (records.empty()) {
    std::cout << "bench collision: no batch was timed\n";
    return 0;
  }
  const Record& first = records.front();
  const bool analytic = first.at("analytic_ik").get<bool>();
  std::cout << first.at("robot").get<std::string>() << " before a " << args.objects << "-cylinder shelf ("
            << first.at("problem").get<std::string>() << "), " << first.at("configurations") << " reaching configurations\n("
            << first.at("in_collision") << " in collision, " << first.at("touching_objects")
            << " touching objects); medians over batches of " << kBatch << " calls\n\n";
  std::cout << std::left << std::setw(34) << "query" << std::right << std::setw(12) << "median µs" << std::setw(10) << "goal µs"
            << std::setw(8) << "met" << std::setw(9) << "calls" << "\n";
  nlohmann::ordered_json json{{"scene", first.at("problem")}, {"configurations", first.at("configurations")},
                              {"in_collision", first.at("in_collision")}, {"results", nlohmann::ordered_json::array()}};
  std::vector<TimedQuery> plotted;
  bool all_met = true;
  for (const Query& q : queries(analytic)) {
    std::vector<double> per_call;
    for (const Record& r : records) {
      const auto& t = r.at("call_time_us").at(q.name);
      if (!t.is_null()) per_call.push_back(t.get<double>());
    }
    const double med = median(per_call);
    const std::size_t calls = per_call.size() * kBatch;
    const bool met = q.goal_us == 0 || (!per_call.empty() && med <= q.goal_us);
    all_met = all_met && met;
    std::cout << std::left << std::setw(34) << q.name << std::right << std::fixed << std::setprecision(3) << std::setw(12) << med
              << std::setw(10);
    if (q.goal_us > 0) std::cout << std::setprecision(1) << q.goal_us << std::setw(8) << (met ? "yes" : "NO");
    else std::cout << "-" << std::setw(8) << "-";
    std::cout << std::setw(9) << calls << "\n";
    json["results"].push_back({{"query", q.name}, {"median_us", med}, {"goal_us", q.goal_us}, {"calls", calls}});
    plotted.push_back({q.label, per_call, q.goal_us});
  }
  std::vector<double> reachable_us;
  std::size_t solved = 0;
  for (const Record& r : records) {
    const auto& ik = r.at("reachable_ik");
    for (const auto& t : ik.at("times_us")) reachable_us.push_back(t.get<double>());
    solved += ik.at("solved").get<std::size_t>();
  }
  const double success = 100.0 * double(solved) / double(std::max<std::size_t>(reachable_us.size(), 1));
  const double ik_median = median(reachable_us);
  const bool ik_met = analytic || (success >= kNumericIkGoalPercent && ik_median <= kNumericIkGoalUs);
  all_met = all_met && ik_met;
  plotted.push_back({kReachableLabel, reachable_us, analytic ? 0.0 : kNumericIkGoalUs});
  std::cout << "\n"
            << (analytic ? "analytic" : "numeric") << " IK on " << reachable_us.size()
            << " reachable poses (the tool poses of random configurations within the joint\nlimits), from the home configuration: "
            << std::setprecision(2) << success << " % solved, median " << std::setprecision(1) << ik_median << " µs per query";
  if (!analytic) std::cout << "\n(goal: " << kNumericIkGoalPercent << " %, " << kNumericIkGoalUs << " µs: " << (ik_met ? "met" : "NOT met") << ")";
  std::cout << "\n";
  if (const std::string note = hosts_note(records); !note.empty()) std::cout << note << "\n";
  json["ik_reachable"] = {{"poses", reachable_us.size()}, {"solved_percent", success}, {"median_us", ik_median}};
  if (!args.json.empty()) {
    write_json_file(args.json, json);
    std::cout << "\nwrote " << args.json.string() << "\n";
  }
  if (!args.svg.empty()) {
    write_timing_svg(args.svg,
                     "bench collision: " + first.at("robot").get<std::string>() + " before " + first.at("problem").get<std::string>() +
                         ", µs per call (the mean of each batch of " + std::to_string(kBatch) + "; IK, reachable: each query)",
                     "µs per call", plotted);
  }
  return goal_exit_code(args.check_goals, all_met);
}

}  // namespace cluttertamp::bench
