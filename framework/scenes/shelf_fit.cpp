#include "cluttertamp/scenes/shelf_fit.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <tuple>
#include <vector>

#include "cluttertamp/collision/collision_world.hpp"
#include "cluttertamp/robot/ik.hpp"

namespace cluttertamp::scenes {

namespace {

// m: how far in front of the robot base's vertical axis the exit must stand.
constexpr double kExitBeforeBase = 0.05;

// The tool holding a cylinder's axis at `at` from the side, approaching horizontally
// along `approach` (unit), fingers vertical, the tool's x axis up or down (`up` = +-1).
Eigen::Isometry3d side_grasp(const Eigen::Vector3d& at, double up, const Eigen::Vector3d& approach) {
  Eigen::Isometry3d tool = Eigen::Isometry3d::Identity();
  tool.linear().col(0) = up * Eigen::Vector3d::UnitZ();
  tool.linear().col(1) = approach.cross(tool.linear().col(0));
  tool.linear().col(2) = approach;
  tool.translation() = at;
  return tool;
}

// The grasp poses a placement is judged by, in the robot's base frame (at the origin),
// but the exit's (judged apart, as its distance from the opening is chosen).
std::vector<Eigen::Isometry3d> test_grasps(const ShelfSpec& spec, const Scene& scene) {
  const Eigen::Vector3d size = cabinet_size(spec);
  const double z = spec.floor_height + 0.5 * (spec.height_min + spec.height_max) / 2;
  std::vector<Eigen::Vector3d> points;
  for (const double x : {spec.front + 0.1, spec.front + size.x() / 2, spec.front + size.x() - 0.08}) {
    for (const double y : {-size.y() / 2 + 0.08, 0.0, size.y() / 2 - 0.08}) points.emplace_back(x, y, z);
  }
  for (const Region& r : scene.regions) {
    points.push_back(r.world_T_region.translation() + Eigen::Vector3d(0, 0, z - spec.floor_height - r.size.z() / 2));
  }
  std::vector<Eigen::Isometry3d> out;
  for (const Eigen::Vector3d& p : points) {
    // Approaching from the robot's base, which stands at the origin.
    for (const double up : {-1.0, 1.0}) out.push_back(side_grasp(p, up, Eigen::Vector3d(p.x(), p.y(), 0).normalized()));
  }
  return out;
}

// A start clear of `world` (the cabinet with its interior as one object) when the
// home is not: the home's tool pose drawn back horizontally towards the base in 5 cm
// steps, and raised, solved from the home so that the arm keeps its posture.
std::optional<std::pair<Eigen::VectorXd, double>> clear_start(const collision::CollisionWorld& world,
                                                              collision::CollisionWorld::Context& context,
                                                              const robot::IkSolver& ik, const Eigen::Isometry3d& base_T_world,
                                                              const Eigen::VectorXd& home) {
  const Eigen::Isometry3d home_tool = world.tool_pose(home, context);
  Eigen::Vector3d towards_base(-home_tool.translation().x(), -home_tool.translation().y(), 0);
  if (towards_base.norm() < 1e-6) return std::nullopt;  // the tool stands over the base already
  towards_base.normalize();
  std::uint64_t seed = 0;
  for (int back = 1; back <= 12; ++back) {
    for (const double up : {0.0, 0.1, 0.2}) {
      Eigen::Isometry3d tool = home_tool;
      tool.translation() += 0.05 * back * towards_base + up * Eigen::Vector3d::UnitZ();
      for (const Eigen::VectorXd& q : ik.solve(base_T_world * tool, home, seed++)) {
        if (world.is_valid(q, context)) return std::make_pair(q, 0.05 * back);
      }
    }
  }
  return std::nullopt;
}

}  // namespace

std::string describe_placement(const ShelfFit& fit) {
  char text[200];
  std::snprintf(text, sizeof text,
                "opening at x = %.2f m, floor at z = %.2f m, %.2f m deep, exit %.2f m in front of it: %d of %d test grasps "
                "reachable",
                fit.spec.front, fit.spec.floor_height, cabinet_size(fit.spec).x(), fit.spec.exit_distance, fit.reached, fit.tried);
  return text;
}

ShelfFit fit_shelf_to_robot(const ShelfSpec& spec, std::shared_ptr<const robot::RobotDescription> robot) {
  // A closed form answers at once; a numeric solver gets fewer restarts than planning
  // does (a few hundred placements are tried, most poses out of reach).
  std::unique_ptr<robot::NumericIk> numeric;
  const robot::IkSolver* ik = &robot->ik();
  if (!dynamic_cast<const robot::UrAnalyticIk*>(ik)) {
    robot::NumericIk::Options options;
    options.restarts = 4;
    options.max_solutions = 3;
    numeric = std::make_unique<robot::NumericIk>(robot->model(), robot->base_link(), robot->tip_link(), options);
    ik = numeric.get();
  }
  auto judge = [&](const ShelfSpec& candidate) {
    ShelfSpec boards = candidate;  // the furniture alone, at the size the objects give it
    const Eigen::Vector3d size = cabinet_size(candidate);
    boards.depth = size.x();
    boards.width = size.y();
    boards.objects = 0;
    ShelfFit fit;
    fit.spec = candidate;
    Scene scene = generate_shelf_scene(boards, 0);
    // The objects may stand anywhere inside, so the home configuration must keep out of
    // the whole interior: it is one more object, which the test grasps ignore.
    SceneObject interior;
    interior.id = "interior";
    interior.shape = Box{size};
    interior.world_T_object.translation() = Eigen::Vector3d(candidate.front + size.x() / 2, 0, candidate.floor_height + size.z() / 2);
    // The target as the exit holds it: the largest cylinder the spec draws, out of the
    // way until the exit's test grasps hold it.
    SceneObject target;
    target.id = "target";
    target.shape = Cylinder{candidate.radius_max, candidate.height_max};
    target.world_T_object.translation() = Eigen::Vector3d(0, 0, -10);
    scene.objects = {interior, target};
    scene.target = 1;
    collision::CollisionWorld world(scene, robot);
    const Eigen::Isometry3d base_T_world = robot->world_T_ik_base(scene.world_T_robot_base).inverse();
    auto context = world.make_context();
    const std::vector<Eigen::Isometry3d> grasps = test_grasps(candidate, scene);
    fit.tried = static_cast<int>(grasps.size()) + 2;  // and the exit's two, below
    Eigen::VectorXd start = robot->home();
    if (!world.is_valid(start, *context)) {
      const auto clear = clear_start(world, *context, *ik, base_T_world, start);
      if (!clear) return fit;
      fit.start = start = clear->first;
      fit.start_drawn_back = clear->second;
    }
    const ObjectIndex ignored[] = {0, 1};
    std::uint64_t seed = 0;
    auto reaches = [&](const Eigen::Isometry3d& grasp) {
      const auto solutions = ik->solve(base_T_world * grasp, start, seed++);
      return std::any_of(solutions.begin(), solutions.end(),
                         [&](const Eigen::VectorXd& q) { return world.is_valid(q, *context, ignored); });
    };
    for (const Eigen::Isometry3d& grasp : grasps) fit.reached += reaches(grasp);
    // The exit: as far in front of the opening as the arm holds the target there, taken
    // out of the cabinet as it was grasped inside (approaching along +x), touching
    // neither the arm nor the furniture (a short arm cannot hold it over its own base),
    // both ways up.
    std::vector<double> distances{candidate.exit_distance};
    for (const double nearer : {0.15, 0.1}) {
      if (nearer < candidate.exit_distance) distances.push_back(nearer);
    }
    auto holds = [&](const Eigen::Vector3d& exit, double up) {
      const Eigen::Isometry3d grasp = side_grasp(exit, up, Eigen::Vector3d::UnitX());
      world.attach(1, grasp.inverse() * Eigen::Translation3d(exit));  // upright, its centre at the tool
      const bool held = reaches(grasp);
      world.detach(target.world_T_object);
      return held;
    };
    for (const double distance : distances) {
      Eigen::Vector3d exit = scene.world_T_exit.translation();
      exit.x() = candidate.front - distance;
      // Not over the base: an arm folded back over itself may hold the target there,
      // but carrying it there from the shelf is a hard motion problem for every removal.
      if (exit.x() < kExitBeforeBase) continue;
      const int held = int{holds(exit, -1.0)} + int{holds(exit, 1.0)};
      if (held > 0) {
        fit.spec.exit_distance = distance;
        fit.reached += held;
        break;
      }
    }
    return fit;
  };
  const ShelfFit as_given = judge(spec);
  ShelfFit best = as_given;
  if (best.reached == best.tried) {
    best.reached_as_given = best.reached;
    return best;
  }
  auto distance = [&](const ShelfSpec& s) { return std::hypot(s.front - spec.front, s.floor_height - spec.floor_height); };
  for (int f = 0; f <= 14; ++f) {
    for (int h = 0; h <= 18; ++h) {
      ShelfSpec candidate = spec;
      candidate.front = 0.2 + 0.05 * f;
      candidate.floor_height = 0.05 * h;
      const ShelfFit fit = judge(candidate);
      // At equal reach, a placement the robot's own home clears wins.
      const auto rank = [&](const ShelfFit& f) { return std::make_tuple(f.reached, !f.start, -distance(f.spec)); };
      if (rank(fit) > rank(best)) best = fit;
    }
  }
  // A short arm may reach the back of no cabinet this deep, wherever it stands: shallower
  // ones at the placement found (5 cm steps, down to 0.4 m), the deepest that reaches
  // the most.
  if (best.reached < best.tried) {
    for (double depth = cabinet_size(best.spec).x() - 0.05; depth >= 0.4 - 1e-9; depth -= 0.05) {
      ShelfSpec candidate = best.spec;
      candidate.depth = depth;
      const ShelfFit fit = judge(candidate);
      if (fit.reached > best.reached) best = fit;
    }
  }
  best.reached_as_given = as_given.reached;
  return best;
}

}  // namespace cluttertamp::scenes
