#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include <Eigen/Geometry>
#include <boost/graph/adjacency_list.hpp>

#include "cluttertamp/collision/collision_world.hpp"
#include "cluttertamp/core/parameters.hpp"
#include "cluttertamp/export.hpp"
#include "cluttertamp/retrieval/retrieval_graph.hpp"

namespace cluttertamp::retrieval {

/// A roadmap node: a position of the held target in the plane and the objects its
/// footprint overlaps there (Col).
struct RoadmapNode {
  Eigen::Vector2d x = Eigen::Vector2d::Zero();
  ObjectSet col;
};

using RoadmapGraph = boost::adjacency_list<boost::vecS, boost::vecS, boost::undirectedS, RoadmapNode>;

/// Algorithm 2's parameters (Tian et al., Section VI-A: T = 1000, T_raise = 100).
struct RoadmapOptions {
  int samples = 1000;      ///< T: sampling iterations per expansion
  int raise_every = 100;   ///< T_raise
  double step = 0.05;      ///< delta: longest edge, m
  int neighbours = 10;     ///< k of NEAR

  /// Reads the planner parameters `T`, `T_raise`, `delta` and `k`; throws InputError
  /// naming a bad one.
  void read(const Parameters& parameters);
};

/// The roadmap of the target's positions (x, y) with the footprint of the target plus
/// gripper (radius r_b), grown by EXTEND with bisection under a sampling limit K that
/// rises every T_raise steps towards the exploration limit L. Nearest neighbours come
/// from an R-tree. Node 0 is x_s, node 1 is x_g.
class CLUTTERTAMP_API Roadmap {
 public:
  /// `area`: where samples are drawn (the plane's box around the clutter and x_s).
  /// `target` is never in a collision set. The world is read, never changed.
  Roadmap(const collision::CollisionWorld& world, const collision::Footprint& footprint, const Eigen::AlignedBox2d& area,
          const Eigen::Vector2d& x_s, const Eigen::Vector2d& x_g, ObjectIndex target, std::uint64_t seed);
  ~Roadmap();

  /// One call of EXPANDROADMAP with exploration limit L (samples colliding with at most L objects).
  void expand(int exploration_limit, const RoadmapOptions& options);

  /// Objects that became known (now present in the world, e.g. newly observed behind
  /// others; Tian et al., Algorithm 4): Col is recomputed for the nodes near them and
  /// the edges that now meet more than their two ends' objects are dropped. Every other
  /// node and edge stays: the roadmap is updated, not rebuilt. Returns the number of
  /// nodes whose Col changed.
  std::size_t reveal(std::span<const ObjectIndex> objects);

  /// Moves x_g (node 1) to `x_g` (a new goal, e.g. a temporary one): a node with its
  /// edges stays where it was (the roadmap may have grown from it), node 1's Col is
  /// recomputed there and it joins its neighbours as expand() joins the ends.
  void move_goal(const Eigen::Vector2d& x_g, const RoadmapOptions& options);

  /// The shortest way of the target's footprint from x_g (node 1) to x_s (node 0)
  /// through roadmap nodes whose Col holds only objects marked in `gone` (their edges
  /// then meet nothing else), shortened where a straight sweep in the world as it is
  /// now meets no object and no fixed geometry: positions in the plane, x_g first and
  /// x_s last. Empty when the roadmap joins them by no such way.
  /// Precondition: the world is synced to the state the way is for.
  std::vector<Eigen::Vector2d> free_way(const std::vector<bool>& gone) const;
  ObjectSet col(const Eigen::Vector2d& x) const;
  ObjectSet edge_col(const Eigen::Vector2d& a, const Eigen::Vector2d& b) const;
  bool hits_fixed(const Eigen::Vector2d& a, const Eigen::Vector2d& b) const;

  const RoadmapGraph& graph() const { return graph_; }
  std::size_t size() const { return boost::num_vertices(graph_); }

  /// The retrieval graph over this roadmap: clusters of connected nodes with the same
  /// collision set (objects in `removed` no longer count); `node_of` receives the
  /// retrieval-graph node of every roadmap node. Start and goal are set.
  RetrievalGraph cluster(const std::vector<bool>& removed, std::function<Eigen::Vector2d(ObjectIndex)> position,
                         std::vector<int>& node_of) const;

 private:
  std::size_t add_node(const Eigen::Vector2d& x, ObjectSet col);
  // Joins node `end` to its neighbours closer than delta by edges that follow the edge rule.
  void connect(std::size_t end, const RoadmapOptions& options);
  // The fixed-geometry test of an edge from roadmap node `node` to `to`.
  bool leaves_hitting_fixed(std::size_t node, const Eigen::Vector2d& to) const;

  const collision::CollisionWorld& world_;
  collision::Footprint footprint_;
  Eigen::AlignedBox2d area_;
  ObjectIndex target_;
  std::uint64_t seed_;
  std::uint64_t expansions_ = 0;
  RoadmapGraph graph_;
  struct Index;
  std::unique_ptr<Index> index_;
};

}  // namespace cluttertamp::retrieval
