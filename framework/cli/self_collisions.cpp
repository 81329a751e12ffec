// `cluttertamp self-collisions`: which pairs of a robot's links ever touch, over random
// configurations — the pairs that never do can go into the description's
// `disabled_collisions`, so validity checks skip them (as MoveIt's setup assistant
// does with its "never in collision" pairs).
#include <algorithm>
#include <cmath>
#include <iomanip>
#include <iostream>
#include <map>
#include <random>

#include "cli/commands.hpp"
#include "cluttertamp/io/robot_description_io.hpp"
#include "cluttertamp/io/srdf.hpp"
#include "cluttertamp/io/text_file.hpp"
#include "cluttertamp/collision/collision_world.hpp"
#include "cluttertamp/robot/robot_description.hpp"
#include "cluttertamp/robot/robot_model.hpp"
#include "cluttertamp/run/runner.hpp"

namespace cluttertamp::cli {

int self_collisions(const SelfCollisionArgs& args) {
  const auto robot = std::make_shared<const robot::RobotDescription>(io::load_robot_description(args.robot));
  if (!args.srdf.empty()) io::check_writable(args.srdf, "SRDF file (--srdf)");
  const robot::RobotModel& model = *robot->model();
  Scene empty;
  empty.world_T_robot_base = Eigen::Isometry3d::Identity();
  const collision::CollisionWorld world(empty, robot);
  auto context = world.make_context();

  std::mt19937_64 rng(args.seed);
  std::map<std::pair<std::size_t, std::size_t>, std::size_t> touching;
  Eigen::VectorXd q = robot->home();
  for (std::size_t i = 0; i < args.samples; ++i) {
    for (Eigen::Index v = 0; v < q.size(); ++v) {
      const double lo = std::isfinite(model.lower_limits()[v]) ? model.lower_limits()[v] : -M_PI;
      const double hi = std::isfinite(model.upper_limits()[v]) ? model.upper_limits()[v] : M_PI;
      q[v] = std::uniform_real_distribution<double>(lo, hi)(rng);
    }
    for (const auto& pair : world.self_contacts(q, *context)) ++touching[pair];
  }

  const auto& links = model.links();
  std::size_t width = 22;  // a column fits the longest name
  for (const auto& link : links) width = std::max(width, link.name.size() + 2);
  std::cout << robot->name() << ": " << args.samples << " random configurations (seed " << args.seed << ")\n";
  std::vector<std::pair<std::size_t, std::size_t>> never, always;
  for (std::size_t a = 0; a < links.size(); ++a) {
    for (std::size_t b = a + 1; b < links.size(); ++b) {
      if (links[a].collision.empty() || links[b].collision.empty()) continue;
      const auto& disabled = robot->disabled_collisions();
      const std::pair<robot::LinkIndex, robot::LinkIndex> key{static_cast<robot::LinkIndex>(a), static_cast<robot::LinkIndex>(b)};
      if (std::binary_search(disabled.begin(), disabled.end(), key)) continue;
      const auto it = touching.find({a, b});
      const std::size_t count = it == touching.end() ? 0 : it->second;
      if (count == 0) never.emplace_back(a, b);
      if (args.samples > 0 && count * 100 >= args.samples * 99) always.emplace_back(a, b);
      if (args.verbosity == Verbosity::verbose || count > 0) {
        std::cout << "  " << std::left << std::setw(static_cast<int>(width)) << links[a].name << std::setw(static_cast<int>(width))
                  << links[b].name << std::right
                  << std::setw(8) << count << " (" << std::fixed << std::setprecision(2)
                  << 100.0 * double(count) / double(args.samples) << " %)\n";
        std::cout.unsetf(std::ios::floatfield);
      }
    }
  }
  std::cout << never.size() << " checked pairs never touched; for the description's disabled_collisions:\n";
  for (const auto& [a, b] : never) std::cout << "  - [" << links[a].name << ", " << links[b].name << "]\n";
  if (!always.empty()) {
    std::cout << always.size() << " pairs touched in 99 % of the configurations or more (their geometry overlaps for good: disable them "
              << "too if the model means it, as MoveIt's setup does):\n";
    for (const auto& [a, b] : always) std::cout << "  - [" << links[a].name << ", " << links[b].name << "]\n";
  }
  const auto home_contacts = world.self_contacts(robot->home(), *context);
  if (home_contacts.empty()) std::cout << "home: clear of itself\n";
  for (const auto& [a, b] : home_contacts) {
    std::cout << "home: in self collision, '" << links[a].name << "' touches '" << links[b].name << "'\n";
  }
  if (!args.srdf.empty()) {
    std::vector<io::DisabledPair> pairs;
    const auto& adjacent = model.adjacent_links();
    for (const auto& [a, b] : robot->disabled_collisions()) {
      const bool is_adjacent = std::binary_search(adjacent.begin(), adjacent.end(), std::pair{a, b});
      pairs.push_back({a, b, is_adjacent ? "Adjacent" : "User"});
    }
    for (const auto& [a, b] : never) pairs.push_back({static_cast<robot::LinkIndex>(a), static_cast<robot::LinkIndex>(b), "Never"});
    io::write_text_file(args.srdf, io::srdf_text(model, pairs), "SRDF file");
    std::cout << "wrote " << args.srdf.string() << " (" << pairs.size() << " disabled pairs)\n";
  }
  return run::ExitCode::solved;
}

}  // namespace cluttertamp::cli
