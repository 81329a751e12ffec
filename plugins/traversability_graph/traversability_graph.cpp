// traversability_graph: the retrieval baseline of Nam et al. (T-RO 2021) as Tian et al.
// describe it (T-RO 2023, Section VI-F): a graph over the robot's side of the shelf and
// every object, with an edge wherever the largest object could travel in a
// straight line between two positions touching nothing but the objects at the ends.
// The shortest path from the robot to the target — fewest objects, then shortest —
// names the objects to remove, nearest the robot first. When the robot cannot remove
// one of them, the edge into it is deleted and the path searched again; the graph
// never learns which obstacle was in the robot's way.
#include <chrono>
#include <limits>
#include <vector>

#include <boost/graph/adjacency_list.hpp>
#include <boost/graph/dijkstra_shortest_paths.hpp>

#include "cluttertamp/collision/shared_world.hpp"
#include "cluttertamp/core/geometry.hpp"
#include "cluttertamp/plugin/export.hpp"
#include "cluttertamp/plugin/task_planner.hpp"
#include "cluttertamp/retrieval/removal_checker.hpp"

namespace {

using namespace cluttertamp;
using Clock = std::chrono::steady_clock;
// Vertex 0: the exit pose x_s on the robot's side; vertex i + 1: object i. Arcs both
// ways, weighted by what entering their head costs.
using Graph = boost::adjacency_list<boost::setS, boost::vecS, boost::directedS, boost::no_property,
                                    boost::property<boost::edge_weight_t, double>>;
// An object to remove outweighs any length inside a shelf.
constexpr double kObjectCost = 1000.0;

class TraversabilityGraph final : public plugin::TaskPlanner {
 public:
  void configure(const Parameters& p) override {
    region_ = p.get_string("region", region_, "the scene's region removed objects are placed in");
  }

  std::vector<std::string> required_kinds() const override { return retrieval::retrieval_sampler_kinds(); }

  Result solve(plugin::PlanningContext& context, const WorldState& initial) override {
    Result result;
    if (auto why = retrieval::retrieval_inputs_missing(context, "traversability_graph")) {
      result.reason = *why;
      return result;
    }
    const auto start = Clock::now();
    const ObjectIndex target = context.scene().target;
    retrieval::RemovalChecker checker(context, initial, region_);
    Graph graph = build(context, initial);
    result.counters[counter::traversability_edges] = boost::num_edges(graph) / 2;

    std::uint64_t sequences = 0;
    while (!context.deadline.expired()) {
      const std::vector<std::size_t> path = shortest_path(graph, target + 1);
      if (path.empty()) {
        result.reason = "no path to the target is left in the traversability graph";
        break;
      }
      std::vector<ObjectIndex> order;
      for (std::size_t i = 1; i + 1 < path.size(); ++i) order.push_back(static_cast<ObjectIndex>(path[i] - 1));
      ++sequences;
      const retrieval::RemovalCheck check = checker.retrieve(order);
      if (check.ok) {
        checker.write_plan(order, 0, result);
        result.solved = true;
        break;
      }
      if (context.deadline.expired()) break;
      if (check.failure) retrieval::record_failure_once(result, *check.failure);
      // The edge into the object the robot could not remove (or into the target).
      const std::size_t head = *check.failed_object + 1;
      const std::size_t tail = path[check.removed];
      boost::remove_edge(tail, head, graph);
      boost::remove_edge(head, tail, graph);
    }
    if (!result.solved && result.reason.empty()) result.reason = "time limit reached before the target was retrieved";
    checker.record_times(result, start);
    result.counters[counter::planning_sequences] = sequences;
    return result;
  }

 private:
  // Edges wherever the largest object sweeps freely between two vertices. (The object
  // alone, as Nam et al. move it: with the fingers' width it would touch the
  // neighbours of every object it starts from, 1 cm away.)
  static Graph build(plugin::PlanningContext& context, const WorldState& initial) {
    const Scene& scene = context.scene();
    const std::size_t n = scene.objects.size();
    collision::Footprint footprint{0.0, std::numeric_limits<double>::max(), std::numeric_limits<double>::lowest()};
    for (ObjectIndex o = 0; o < n; ++o) {
      const Eigen::AlignedBox3d box = world_bounds(scene.objects[o].shape, initial.world_T_objects[o]);
      footprint = {std::max(footprint.radius, box.sizes().head<2>().maxCoeff() / 2), std::min(footprint.z_min, box.min().z()),
                   std::max(footprint.z_max, box.max().z())};
    }
    footprint.z_min += 0.005;  // carried just clear of the board the objects stand on
    std::vector<Eigen::Vector2d> at{scene.world_T_exit.translation().head<2>()};
    for (ObjectIndex o = 0; o < n; ++o) at.push_back(initial.world_T_objects[o].translation().head<2>());

    collision::CollisionWorld& world = *collision::shared_world(context);
    world.sync(initial);
    Graph graph(n + 1);
    for (std::size_t u = 0; u <= n; ++u) {
      for (std::size_t v = u + 1; v <= n; ++v) {
        std::vector<ObjectIndex> ends{static_cast<ObjectIndex>(v - 1)};
        if (u > 0) ends.push_back(static_cast<ObjectIndex>(u - 1));
        if (world.sweep_hits_fixed(at[u], at[v], footprint) || !world.swept_objects(at[u], at[v], footprint, ends).empty()) {
          continue;
        }
        const double length = (at[u] - at[v]).norm();
        auto cost = [&](std::size_t head) { return (head == scene.target + 1 ? 0.0 : kObjectCost) + length; };
        boost::add_edge(u, v, cost(v), graph);
        if (u > 0) boost::add_edge(v, u, cost(u), graph);
      }
    }
    return graph;
  }

  // Vertices from 0 to `goal`, or nothing when the goal cannot be reached.
  static std::vector<std::size_t> shortest_path(const Graph& graph, std::size_t goal) {
    const std::size_t n = boost::num_vertices(graph);
    std::vector<std::size_t> parent(n);
    std::vector<double> distance(n);
    boost::dijkstra_shortest_paths(graph, 0, boost::predecessor_map(parent.data()).distance_map(distance.data()));
    if (parent[goal] == goal) return {};
    std::vector<std::size_t> path{goal};
    while (path.back() != 0) path.push_back(parent[path.back()]);
    return {path.rbegin(), path.rend()};
  }

    std::string region_ = "buffer";
};

}  // namespace

CLUTTERTAMP_EXPORT_TASK_PLANNER(TraversabilityGraph, traversability_graph,
                                "Traversability graph with edge deletion on failure: the Nam et al. (2021) baseline",
                                "0.1.0")
