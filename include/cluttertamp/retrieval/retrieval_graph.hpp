#pragma once

#include <functional>
#include <optional>
#include <vector>

#include <Eigen/Core>
#include <boost/graph/adjacency_list.hpp>

#include "cluttertamp/core/scene.hpp"
#include "cluttertamp/export.hpp"

namespace cluttertamp::retrieval {

/// Objects, sorted by index, without repeats.
using ObjectSet = std::vector<ObjectIndex>;

/// A node of the retrieval graph (Tian et al., Section IV-C): a cluster of connected
/// roadmap nodes with the same collision set, or a set of robot-obstacle collisions
/// reported by feasibility checking.
struct GraphNode {
  std::vector<std::size_t> cluster;       ///< roadmap nodes (empty for feedback nodes)
  ObjectSet node_col;                     ///< NodeCol
  std::optional<ObjectSet> path_col;      ///< PathCol; absent: not reached (INF)
  int best_neighbor = -1;                 ///< BestNeighbor
  double path_distance = 0.0;             ///< tie-break: distance between consecutive obstacles
  Eigen::Vector2d position = Eigen::Vector2d::Zero();  ///< where the node lies in the plane
  bool blocked = false;                   ///< holds an object that cannot be removed
  /// Metres added to the tie-break distance of a path entering the node: ranks
  /// alternatives of equal |PathCol| that distance cannot (robot feedback nodes).
  double entry_cost = 0.0;
};

using Graph = boost::adjacency_list<boost::setS, boost::vecS, boost::undirectedS, GraphNode>;

/// The retrieval graph with its greedy minimum-constraint-removal search (Algorithm 3):
/// PathCol of a node is the smallest collision set of a path from the start node; ties
/// are broken by the accumulated distance between consecutive obstacles on the path.
class CLUTTERTAMP_API RetrievalGraph {
 public:
  /// `object_position` gives an object's position in the plane, for tie-breaking.
  explicit RetrievalGraph(std::function<Eigen::Vector2d(ObjectIndex)> object_position);

  int add_node(ObjectSet node_col, const Eigen::Vector2d& position, std::vector<std::size_t> cluster = {});
  void add_edge(int a, int b);
  void remove_edge(int a, int b);
  bool has_edge(int a, int b) const;
  /// Adds `objects` (sorted) to the node's NodeCol: robot feedback that a way through
  /// the node needs them gone too.
  void add_to_node_col(int node, const ObjectSet& objects);
  /// Takes `objects` out of the node's NodeCol: objects a way through the node may pass.
  void remove_from_node_col(int node, const ObjectSet& objects);
  /// See GraphNode::entry_cost; metres, >= 0.
  void set_entry_cost(int node, double metres) { graph_[static_cast<std::size_t>(node)].entry_cost = metres; }
  void set_start(int node) { start_ = node; }
  void set_goal(int node) { goal_ = node; }
  int start() const { return start_; }
  int goal() const { return goal_; }
  /// Puts a node with NodeCol `blockers` on every edge between a node holding `object`
  /// and one that does not (one such node per outside node), so that every path meets
  /// the blockers before the object (robot feedback about the object itself, not about
  /// one edge). Returns the new nodes.
  std::vector<int> guard_object(ObjectIndex object, const ObjectSet& blockers, const Eigen::Vector2d& position);
  /// Marks every node whose NodeCol holds `object` as impassable.
  void block_object(ObjectIndex object);

  /// Recomputes PathCol and BestNeighbor of every node by the greedy search from the
  /// start node (a priority queue on |PathCol|, then path distance). Stops once the
  /// goal node is settled.
  void update();

  /// The best path (start to goal) and its objects in the order they are met: each
  /// object once, at its first node; objects within a node nearest-first from the
  /// previous obstacle. Absent when the goal is not reached.
  struct Removal {
    ObjectSet objects_in_order;  // not sorted: removal order
    std::vector<int> nodes;
  };
  std::optional<Removal> removal_sequence() const;

  const Graph& graph() const { return graph_; }
  std::size_t size() const { return boost::num_vertices(graph_); }
  const GraphNode& node(int n) const { return graph_[static_cast<std::size_t>(n)]; }

 private:
  Graph graph_;
  std::function<Eigen::Vector2d(ObjectIndex)> position_;
  int start_ = -1;
  int goal_ = -1;
};

/// The union of two sorted sets.
CLUTTERTAMP_API ObjectSet unite(const ObjectSet& a, const ObjectSet& b);

}  // namespace cluttertamp::retrieval
