#include "cluttertamp/retrieval/retrieval_graph.hpp"

#include <algorithm>
#include <map>
#include <queue>
#include <tuple>

namespace cluttertamp::retrieval {

ObjectSet unite(const ObjectSet& a, const ObjectSet& b) {
  ObjectSet out;
  std::set_union(a.begin(), a.end(), b.begin(), b.end(), std::back_inserter(out));
  return out;
}

RetrievalGraph::RetrievalGraph(std::function<Eigen::Vector2d(ObjectIndex)> object_position)
    : position_(std::move(object_position)) {}

int RetrievalGraph::add_node(ObjectSet node_col, const Eigen::Vector2d& position, std::vector<std::size_t> cluster) {
  std::sort(node_col.begin(), node_col.end());
  node_col.erase(std::unique(node_col.begin(), node_col.end()), node_col.end());
  GraphNode n;
  n.node_col = std::move(node_col);
  n.position = position;
  n.cluster = std::move(cluster);
  return static_cast<int>(boost::add_vertex(n, graph_));
}

void RetrievalGraph::add_edge(int a, int b) {
  if (a != b) boost::add_edge(static_cast<std::size_t>(a), static_cast<std::size_t>(b), graph_);
}

void RetrievalGraph::remove_edge(int a, int b) {
  boost::remove_edge(static_cast<std::size_t>(a), static_cast<std::size_t>(b), graph_);
}

bool RetrievalGraph::has_edge(int a, int b) const {
  return boost::edge(static_cast<std::size_t>(a), static_cast<std::size_t>(b), graph_).second;
}

void RetrievalGraph::block_object(ObjectIndex object) {
  for (std::size_t v = 0; v < boost::num_vertices(graph_); ++v) {
    const ObjectSet& col = graph_[v].node_col;
    if (std::binary_search(col.begin(), col.end(), object)) graph_[v].blocked = true;
  }
}

void RetrievalGraph::add_to_node_col(int node, const ObjectSet& objects) {
  GraphNode& n = graph_[static_cast<std::size_t>(node)];
  n.node_col = unite(n.node_col, objects);
}

void RetrievalGraph::remove_from_node_col(int node, const ObjectSet& objects) {
  ObjectSet sorted = objects;
  std::sort(sorted.begin(), sorted.end());
  GraphNode& n = graph_[static_cast<std::size_t>(node)];
  ObjectSet kept;
  std::set_difference(n.node_col.begin(), n.node_col.end(), sorted.begin(), sorted.end(), std::back_inserter(kept));
  n.node_col = std::move(kept);
}

std::vector<int> RetrievalGraph::guard_object(ObjectIndex object, const ObjectSet& blockers, const Eigen::Vector2d& position) {
  auto holds = [&](std::size_t v) {
    const ObjectSet& col = graph_[v].node_col;
    return std::binary_search(col.begin(), col.end(), object);
  };
  // The edges from each node outside the object's nodes into them. One guard per
  // outside node: a guard shared by two outside nodes would join them past the object.
  std::map<std::size_t, std::vector<std::size_t>> inside_of;
  const std::size_t n = boost::num_vertices(graph_);
  for (std::size_t v = 0; v < n; ++v) {
    if (!holds(v)) continue;
    for (auto [e, end] = boost::out_edges(v, graph_); e != end; ++e) {
      const std::size_t u = boost::target(*e, graph_);
      if (!holds(u)) inside_of[u].push_back(v);
    }
  }
  std::vector<int> guards;
  for (const auto& [outside, insides] : inside_of) {
    const int guard = add_node(blockers, position);
    add_edge(static_cast<int>(outside), guard);
    for (std::size_t inside : insides) {
      boost::remove_edge(outside, inside, graph_);
      add_edge(guard, static_cast<int>(inside));
    }
    guards.push_back(guard);
  }
  return guards;
}

void RetrievalGraph::update() {
  const std::size_t n = boost::num_vertices(graph_);
  for (std::size_t v = 0; v < n; ++v) {
    graph_[v].path_col.reset();
    graph_[v].best_neighbor = -1;
    graph_[v].path_distance = 0.0;
  }
  if (start_ < 0 || graph_[start_].blocked) return;
  // The position of the last obstacle met on the best path to each node, for ties.
  std::vector<Eigen::Vector2d> last(n, Eigen::Vector2d::Zero());
  GraphNode& s = graph_[start_];
  s.path_col = s.node_col;
  last[start_] = s.position;
  using Entry = std::tuple<std::size_t, double, int>;  // |PathCol|, distance, node
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> queue;
  queue.push({s.path_col->size(), 0.0, start_});
  std::vector<bool> settled(n, false);
  while (!queue.empty()) {
    const auto [size, distance, u] = queue.top();
    queue.pop();
    if (settled[u] || !graph_[u].path_col || size != graph_[u].path_col->size() || distance != graph_[u].path_distance) continue;
    settled[u] = true;
    if (u == goal_) break;
    for (auto [e, end] = boost::out_edges(static_cast<std::size_t>(u), graph_); e != end; ++e) {
      const int w = static_cast<int>(boost::target(*e, graph_));
      GraphNode& next = graph_[w];
      if (settled[w] || next.blocked) continue;
      ObjectSet candidate = unite(*graph_[u].path_col, next.node_col);
      // New obstacles, met nearest-first from the last one: the path's distance.
      ObjectSet fresh;
      std::set_difference(next.node_col.begin(), next.node_col.end(), graph_[u].path_col->begin(), graph_[u].path_col->end(),
                          std::back_inserter(fresh));
      Eigen::Vector2d from = last[u];
      double d = graph_[u].path_distance + next.entry_cost;
      while (!fresh.empty()) {
        auto nearest = std::min_element(fresh.begin(), fresh.end(), [&](ObjectIndex a, ObjectIndex b) {
          return (position_(a) - from).norm() < (position_(b) - from).norm();
        });
        d += (position_(*nearest) - from).norm();
        from = position_(*nearest);
        fresh.erase(nearest);
      }
      const bool better = !next.path_col || candidate.size() < next.path_col->size() ||
                          (candidate.size() == next.path_col->size() && d < next.path_distance - 1e-12);
      if (!better) continue;
      next.path_col = std::move(candidate);
      next.best_neighbor = u;
      next.path_distance = d;
      last[w] = from;
      queue.push({next.path_col->size(), d, w});
    }
  }
}

std::optional<RetrievalGraph::Removal> RetrievalGraph::removal_sequence() const {
  if (goal_ < 0 || !graph_[goal_].path_col) return std::nullopt;
  Removal r;
  for (int v = goal_; v >= 0; v = graph_[v].best_neighbor) {
    r.nodes.push_back(v);
    if (v == start_) break;
  }
  std::reverse(r.nodes.begin(), r.nodes.end());
  Eigen::Vector2d from = graph_[start_].position;
  for (int v : r.nodes) {
    ObjectSet fresh;
    for (ObjectIndex o : graph_[v].node_col) {
      if (std::find(r.objects_in_order.begin(), r.objects_in_order.end(), o) == r.objects_in_order.end()) fresh.push_back(o);
    }
    while (!fresh.empty()) {
      auto nearest = std::min_element(fresh.begin(), fresh.end(), [&](ObjectIndex a, ObjectIndex b) {
        return (position_(a) - from).norm() < (position_(b) - from).norm();
      });
      from = position_(*nearest);
      r.objects_in_order.push_back(*nearest);
      fresh.erase(nearest);
    }
  }
  return r;
}

}  // namespace cluttertamp::retrieval
