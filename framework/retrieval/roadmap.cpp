#include "cluttertamp/retrieval/roadmap.hpp"

#include <algorithm>
#include <limits>
#include <map>
#include <queue>

#include "cluttertamp/core/geometry.hpp"
#include <random>

#include <boost/geometry.hpp>
#include <boost/geometry/index/rtree.hpp>
#include <boost/graph/connected_components.hpp>
#include <boost/graph/filtered_graph.hpp>

namespace cluttertamp::retrieval {

namespace bg = boost::geometry;
namespace bgi = boost::geometry::index;
using Point = bg::model::point<double, 2, bg::cs::cartesian>;
using Entry = std::pair<Point, std::size_t>;

struct Roadmap::Index {
  bgi::rtree<Entry, bgi::quadratic<16>> tree;
};

void RoadmapOptions::read(const Parameters& p) {
  samples = static_cast<int>(p.get_int("T", samples, "sampling iterations per roadmap expansion", Range::at_least(10)));
  raise_every = static_cast<int>(p.get_int("T_raise", raise_every,
                                           "sampling iterations between raises of the sampling limit K (at most T)",
                                           Range::at_least(1)));
  step = p.get_double("delta", step, "m, the longest roadmap edge", Range::open(0, 1));
  neighbours = static_cast<int>(
      p.get_int("k", neighbours, "nearest nodes a new node tries to join by an edge", Range::closed(1, 100)));
  p.require(raise_every <= samples, "T_raise", "must be at most T");
}

Roadmap::Roadmap(const collision::CollisionWorld& world, const collision::Footprint& footprint,
                 const Eigen::AlignedBox2d& area, const Eigen::Vector2d& x_s, const Eigen::Vector2d& x_g,
                 ObjectIndex target, std::uint64_t seed)
    : world_(world), footprint_(footprint), area_(area), target_(target), seed_(seed), index_(std::make_unique<Index>()) {
  add_node(x_s, col(x_s));
  add_node(x_g, col(x_g));
}

Roadmap::~Roadmap() = default;

ObjectSet Roadmap::col(const Eigen::Vector2d& x) const {
  const ObjectIndex ignored[] = {target_};
  return world_.footprint_objects(x, footprint_, ignored);
}

ObjectSet Roadmap::edge_col(const Eigen::Vector2d& a, const Eigen::Vector2d& b) const {
  const ObjectIndex ignored[] = {target_};
  return world_.swept_objects(a, b, footprint_, ignored);
}

bool Roadmap::hits_fixed(const Eigen::Vector2d& a, const Eigen::Vector2d& b) const {
  return world_.sweep_hits_fixed(a, b, footprint_);
}

bool Roadmap::leaves_hitting_fixed(std::size_t node, const Eigen::Vector2d& to) const {
  const Eigen::Vector2d& from = graph_[node].x;
  if (node > 1) return hits_fixed(from, to);
  // x_s and x_g may already touch fixed geometry (an object standing less than a
  // finger's width from a wall): their edges need only not come closer.
  constexpr double kTouch = 1e-9;  // what the end already touches does not count
  collision::Footprint inside = footprint_;
  inside.radius = std::min(footprint_.radius, world_.fixed_clearance(from, footprint_) - kTouch);
  return world_.sweep_hits_fixed(from, to, inside);
}

std::size_t Roadmap::add_node(const Eigen::Vector2d& x, ObjectSet c) {
  const std::size_t id = boost::add_vertex(RoadmapNode{x, std::move(c)}, graph_);
  index_->tree.insert({Point(x.x(), x.y()), id});
  return id;
}

void Roadmap::expand(int limit, const RoadmapOptions& o) {
  std::mt19937_64 rng(seed_ + 0x9e3779b97f4a7c15ull * ++expansions_);
  std::uniform_real_distribution<double> ux(area_.min().x(), area_.max().x()), uy(area_.min().y(), area_.max().y());
  double k_limit = 0.0;  // K, the sampling limit
  for (int t = 1; t <= o.samples; ++t) {
    const Eigen::Vector2d rand(ux(rng), uy(rng));
    // NEAREST among nodes within the sampling limit.
    const std::size_t k = static_cast<std::size_t>(k_limit);
    std::vector<Entry> nearest;
    index_->tree.query(bgi::nearest(Point(rand.x(), rand.y()), 1) &&
                           bgi::satisfies([&](const Entry& e) { return graph_[e.second].col.size() <= k; }),
                       std::back_inserter(nearest));
    if (!nearest.empty()) {
      const std::size_t from = nearest.front().second;
      const Eigen::Vector2d near = graph_[from].x;
      const double d = (rand - near).norm();
      Eigen::Vector2d x_new = d > 1e-9 ? Eigen::Vector2d(near + std::min(o.step / d, 1.0) * (rand - near)) : near;
      // EXTEND: bisect until the edge meets at most K objects and no fixed geometry.
      bool ok = false;
      for (int halvings = 0; halvings < 8 && (x_new - near).norm() > 1e-4; ++halvings) {
        if (!leaves_hitting_fixed(from, x_new) && edge_col(near, x_new).size() <= k) {
          ok = true;
          break;
        }
        x_new = near + 0.5 * (x_new - near);
      }
      if (ok) {
        const std::size_t id = add_node(x_new, col(x_new));
        boost::add_edge(from, id, graph_);
        // NEAR: the k nearest nodes closer than delta; the edge must meet only the
        // objects of its two ends (|EdgeCol| = |Col u Col'|).
        std::vector<Entry> around;
        index_->tree.query(bgi::nearest(Point(x_new.x(), x_new.y()), static_cast<unsigned>(o.neighbours + 1)),
                           std::back_inserter(around));
        for (const Entry& e : around) {
          const std::size_t other = e.second;
          if (other == id || other == from || (graph_[other].x - x_new).norm() >= o.step) continue;
          if (leaves_hitting_fixed(other, x_new)) continue;
          if (edge_col(x_new, graph_[other].x).size() == unite(graph_[id].col, graph_[other].col).size()) {
            boost::add_edge(id, other, graph_);
          }
        }
      }
    }
    // The incremental raising rule: K += L / ((T - T_cur) / T_raise), at most L.
    if (t % o.raise_every == 0 && o.samples > t) {
      k_limit += double(limit) / (double(o.samples - t) / double(o.raise_every));
      k_limit = std::min(k_limit, double(limit));
    }
  }
  // x_s and x_g join the roadmap like any sample: connect them to their neighbours.
  connect(0, o);
  connect(1, o);
}

void Roadmap::connect(std::size_t end, const RoadmapOptions& o) {
  std::vector<Entry> around;
  const Eigen::Vector2d x = graph_[end].x;
  index_->tree.query(bgi::nearest(Point(x.x(), x.y()), static_cast<unsigned>(o.neighbours + 1)), std::back_inserter(around));
  for (const Entry& e : around) {
    const std::size_t other = e.second;
    if (other == end || (graph_[other].x - x).norm() >= o.step || boost::edge(end, other, graph_).second) continue;
    if (!leaves_hitting_fixed(end, graph_[other].x) && edge_col(x, graph_[other].x).size() == unite(graph_[end].col, graph_[other].col).size()) {
      boost::add_edge(end, other, graph_);
    }
  }
}

std::size_t Roadmap::reveal(std::span<const ObjectIndex> objects) {
  if (objects.empty()) return 0;
  // A node's footprint or an edge's sweep can meet an object only this near its centre.
  double reach = 0.0;
  for (ObjectIndex o : objects) {
    reach = std::max(reach, footprint_radius(world_.scene().objects.at(o).shape, world_.object_pose(o)));
  }
  reach += footprint_.radius + 1e-6;
  auto near = [&](const Eigen::Vector2d& x) {
    return std::any_of(objects.begin(), objects.end(), [&](ObjectIndex o) {
      return (world_.object_pose(o).translation().head<2>() - x).norm() <= reach;
    });
  };
  auto near_segment = [&](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    return std::any_of(objects.begin(), objects.end(), [&](ObjectIndex o) {
      return distance_to_segment(world_.object_pose(o).translation().head<2>(), a, b) <= reach;
    });
  };
  std::size_t changed = 0;
  for (std::size_t v = 0; v < boost::num_vertices(graph_); ++v) {
    if (!near(graph_[v].x)) continue;
    ObjectSet c = col(graph_[v].x);
    if (c != graph_[v].col) ++changed;
    graph_[v].col = std::move(c);
  }
  std::vector<std::pair<std::size_t, std::size_t>> broken;
  for (auto [e, end] = boost::edges(graph_); e != end; ++e) {
    const std::size_t a = boost::source(*e, graph_), b = boost::target(*e, graph_);
    if (near_segment(graph_[a].x, graph_[b].x) &&
        edge_col(graph_[a].x, graph_[b].x).size() != unite(graph_[a].col, graph_[b].col).size()) {
      broken.emplace_back(a, b);
    }
  }
  for (const auto& [a, b] : broken) boost::remove_edge(a, b, graph_);
  return changed;
}

void Roadmap::move_goal(const Eigen::Vector2d& x_g, const RoadmapOptions& options) {
  // The old goal stays as an ordinary node with its edges: parts of the roadmap may
  // have grown from it.
  const Eigen::Vector2d old = graph_[1].x;
  if (boost::degree(1, graph_) > 0) {
    const std::size_t kept = add_node(old, graph_[1].col);
    std::vector<std::size_t> neighbours;
    for (auto [v, end] = boost::adjacent_vertices(1, graph_); v != end; ++v) neighbours.push_back(*v);
    for (std::size_t v : neighbours) boost::add_edge(kept, v, graph_);
  }
  index_->tree.remove(Entry{Point(old.x(), old.y()), 1});
  boost::clear_vertex(1, graph_);
  graph_[1].x = x_g;
  graph_[1].col = col(x_g);
  index_->tree.insert({Point(x_g.x(), x_g.y()), 1});
  connect(1, options);
}

std::vector<Eigen::Vector2d> Roadmap::free_way(const std::vector<bool>& gone) const {
  const std::size_t n = boost::num_vertices(graph_);
  auto passable = [&](std::size_t v) {
    return std::all_of(graph_[v].col.begin(), graph_[v].col.end(),
                       [&](ObjectIndex o) { return o < gone.size() && gone[o]; });
  };
  // Dijkstra from x_g over passable nodes, edge length as cost.
  std::vector<double> dist(n, std::numeric_limits<double>::infinity());
  std::vector<std::size_t> previous(n, n);
  using Item = std::pair<double, std::size_t>;
  std::priority_queue<Item, std::vector<Item>, std::greater<>> open;
  if (n < 2 || !passable(1)) return {};
  dist[1] = 0.0;
  open.push({0.0, 1});
  while (!open.empty()) {
    const auto [d, v] = open.top();
    open.pop();
    if (d > dist[v]) continue;
    if (v == 0) break;
    for (auto [w, end] = boost::adjacent_vertices(v, graph_); w != end; ++w) {
      const double through = d + (graph_[*w].x - graph_[v].x).norm();
      if (through < dist[*w] && passable(*w)) {
        dist[*w] = through;
        previous[*w] = v;
        open.push({through, *w});
      }
    }
  }
  if (previous[0] == n) return {};
  std::vector<Eigen::Vector2d> way;
  for (std::size_t v = 0; v != n; v = previous[v]) way.push_back(graph_[v].x);
  std::reverse(way.begin(), way.end());
  // Greedy shortcuts: from each kept point, the farthest later point a free sweep reaches.
  const ObjectIndex ignored[] = {target_};
  auto free = [&](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    return !world_.sweep_hits_fixed(a, b, footprint_) && world_.swept_objects(a, b, footprint_, ignored).empty();
  };
  std::vector<Eigen::Vector2d> shortened{way.front()};
  for (std::size_t i = 0; i + 1 < way.size();) {
    std::size_t j = way.size() - 1;
    while (j > i + 1 && !free(way[i], way[j])) --j;
    shortened.push_back(way[j]);
    i = j;
  }
  return shortened;
}

RetrievalGraph Roadmap::cluster(const std::vector<bool>& removed, std::function<Eigen::Vector2d(ObjectIndex)> position,
                                std::vector<int>& node_of) const {
  const std::size_t n = boost::num_vertices(graph_);
  auto live = [&](const ObjectSet& s) {
    ObjectSet out;
    for (ObjectIndex o : s) {
      if (o >= removed.size() || !removed[o]) out.push_back(o);
    }
    return out;
  };
  std::vector<ObjectSet> cols(n);
  for (std::size_t v = 0; v < n; ++v) cols[v] = live(graph_[v].col);
  // Connected components of the roadmap restricted to edges between equal collision
  // sets; x_s and x_g are clusters of their own.
  struct SameCol {
    const RoadmapGraph* g;
    const std::vector<ObjectSet>* cols;
    bool operator()(RoadmapGraph::edge_descriptor e) const {
      const std::size_t a = boost::source(e, *g), b = boost::target(e, *g);
      return a > 1 && b > 1 && (*cols)[a] == (*cols)[b];
    }
  };
  boost::filtered_graph<RoadmapGraph, SameCol> same(graph_, SameCol{&graph_, &cols});
  std::vector<int> component(n);
  const int count = boost::connected_components(same, component.data());
  RetrievalGraph graph(std::move(position));
  std::vector<int> node(static_cast<std::size_t>(count), -1);
  std::vector<Eigen::Vector2d> sum(static_cast<std::size_t>(count), Eigen::Vector2d::Zero());
  std::vector<std::vector<std::size_t>> members(static_cast<std::size_t>(count));
  for (std::size_t v = 0; v < n; ++v) {
    sum[component[v]] += graph_[v].x;
    members[component[v]].push_back(v);
  }
  for (int c = 0; c < count; ++c) {
    const auto& m = members[static_cast<std::size_t>(c)];
    node[c] = graph.add_node(cols[m.front()], sum[c] / double(m.size()), m);
  }
  node_of.assign(n, -1);
  for (std::size_t v = 0; v < n; ++v) node_of[v] = node[component[v]];
  for (auto [e, end] = boost::edges(graph_); e != end; ++e) {
    graph.add_edge(node_of[boost::source(*e, graph_)], node_of[boost::target(*e, graph_)]);
  }
  graph.set_start(node_of[0]);
  graph.set_goal(node_of[1]);
  return graph;
}

}  // namespace cluttertamp::retrieval
