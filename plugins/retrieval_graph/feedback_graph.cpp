#include "feedback_graph.hpp"

#include <algorithm>
#include <stdexcept>

namespace cluttertamp::retrieval_graph_plugin {

// The graph of the current roadmap with every feedback node; objects already removed
// do not count.
retrieval::RetrievalGraph FeedbackGraph::graph(const retrieval::Roadmap& roadmap) {
  auto position = [&](ObjectIndex o) -> Eigen::Vector2d { return initial_.world_T_objects[o].translation().head<2>(); };
  // Clustering depends on the roadmap only: once per expansion.
  if (!clustered_ || clustered_size_ != roadmap.size()) {
    clustered_ = roadmap.cluster(initial_.removed, position, node_of_);
    clustered_size_ = roadmap.size();
  }
  retrieval::RetrievalGraph g = *clustered_;
  std::vector<int> feedback_node;
  guard_of_.clear();
  auto resolve = [&](const Endpoint& e) {
    return std::holds_alternative<std::size_t>(e) ? node_of_[std::get<std::size_t>(e)] : feedback_node[std::get<int>(e)];
  };
  for (const Feedback& f : feedback_) {
    using Where = Feedback::Where;
    const ObjectSet live = with_blockers(removable(f.objects), f.where == Where::object ? f.object : target_);
    if (f.where == Where::object) {
      const auto guards = g.guard_object(f.object, live, centre(live, position(f.object)));
      for (int guard : guards) guard_of_[guard] = static_cast<int>(feedback_node.size());
      feedback_node.push_back(guards.empty() ? g.goal() : guards.front());
      continue;
    }
    if (f.where == Where::branch) {
      const int branch = resolve(f.before);
      g.add_to_node_col(branch, live);
      feedback_node.push_back(branch);  // endpoint() finds the branch's own index first
      continue;
    }
    if (f.where == Where::after_goal && !f.alternatives.empty()) {
      add_goal_branches(g, f, feedback_node);
      continue;
    }
    const int a = f.where == Where::edge ? resolve(f.before) : f.where == Where::before_start ? g.start() : g.goal();
    const int b = f.where == Where::edge ? resolve(f.after) : a;
    const int n = g.add_node(live, centre(live, g.node(b).position));
    if (f.where != Where::edge) {
      g.add_edge(n, a);
      f.where == Where::before_start ? g.set_start(n) : g.set_goal(n);
    } else {
      g.remove_edge(a, b);
      g.add_edge(a, n);
      g.add_edge(n, b);
    }
    feedback_node.push_back(n);
  }
  feedback_nodes_ = feedback_node;
  // Objects that can leave only after the target (every grasp of theirs is blocked by
  // it: cylinders touching) stand next to it, where no way out can go around them:
  // the graph lets the target's way pass them, and the robot's check says whether it
  // can. Blocking them cut every way out at once, and each restart found the same.
  for (std::size_t v = 0; v < g.size(); ++v) g.remove_from_node_col(static_cast<int>(v), stays_);
  for (ObjectIndex o : blocked_) g.block_object(o);
  g.update();
  return g;
}

// Every grasp's blockers of `f` on a branch from the goal to a new goal. Adds the
// same number of feedback nodes (branches, then the new goal) whatever the graph.
// A branch that failed twice with nothing to blame keeps its node but loses its edges.
// Branches rank by kBranchRank metres each: more than any tie-break distance in a shelf.
void FeedbackGraph::add_goal_branches(retrieval::RetrievalGraph& g, const Feedback& f, std::vector<int>& feedback_node) {
  const int goal = g.goal();
  const int joined = g.add_node({}, g.node(goal).position);
  std::vector<ObjectSet> sets{f.objects};
  sets.insert(sets.end(), f.alternatives.begin(), f.alternatives.end());
  for (std::size_t k = 0; k < sets.size(); ++k) {
    const ObjectSet& set = sets[k];
    const ObjectSet live = with_blockers(removable(set), target_);
    const int branch = g.add_node(live, centre(live, g.node(goal).position));
    // Among equally blocked grasps, the sampler's order (its least blocked first).
    g.set_entry_cost(branch, kBranchRank * static_cast<double>(k));
    const int index = static_cast<int>(feedback_node.size());
    branches_.insert(index);
    if (!dead_branches_.count(index)) {
      g.add_edge(goal, branch);
      g.add_edge(branch, joined);
    }
    feedback_node.push_back(branch);
  }
  g.set_goal(joined);
  feedback_node.push_back(joined);
}

// Where a feedback node with `objects` lies in the plane: their mean initial position.
Eigen::Vector2d FeedbackGraph::centre(const ObjectSet& objects, const Eigen::Vector2d& if_empty) const {
  if (objects.empty()) return if_empty;
  Eigen::Vector2d sum = Eigen::Vector2d::Zero();
  for (ObjectIndex o : objects) sum += initial_.world_T_objects[o].translation().head<2>();
  return sum / double(objects.size());
}

Endpoint FeedbackGraph::endpoint(int node) const {
  if (const auto it = guard_of_.find(node); it != guard_of_.end()) return it->second;
  for (std::size_t i = 0; i < feedback_nodes_.size(); ++i) {
    if (feedback_nodes_[i] == node) return static_cast<int>(i);
  }
  const auto it = std::find(node_of_.begin(), node_of_.end(), node);
  if (it == node_of_.end()) throw std::logic_error("retrieval_graph: a graph node that is neither a cluster nor feedback");
  return static_cast<std::size_t>(it - node_of_.begin());
}

// `set` with the objects fed back as blocking its objects, and theirs, but never
// `except` (the object a guard node guards): a feedback node that holds an object
// must hold what has to go before it, as the object's guard is passed only on the
// way into the roadmap's nodes that hold it.
ObjectSet FeedbackGraph::with_blockers(ObjectSet set, ObjectIndex except) const {
  std::vector<ObjectIndex> todo = set;
  while (!todo.empty()) {
    const ObjectIndex o = todo.back();
    todo.pop_back();
    for (const Feedback& f : feedback_) {
      if (f.where != Feedback::Where::object || f.object != o) continue;
      for (ObjectIndex b : removable(f.objects)) {
        if (b == except || std::find(set.begin(), set.end(), b) != set.end()) continue;
        set.push_back(b);
        todo.push_back(b);
      }
    }
  }
  std::sort(set.begin(), set.end());
  return set;
}

// The path's objects in the path's order, except that the objects fed back as
// blocking one go before it (a guard node can be passed before a node holding the
// object that a later guard added); objects blocking each other keep the path's order.
ObjectSet FeedbackGraph::in_precedence_order(ObjectSet remaining) const {
  auto waits = [&](ObjectIndex o) {
    for (const Feedback& f : feedback_) {
      if (f.where != Feedback::Where::object || f.object != o) continue;
      for (ObjectIndex b : f.objects) {
        if (b != o && std::find(remaining.begin(), remaining.end(), b) != remaining.end()) return true;
      }
    }
    return false;
  };
  ObjectSet order;
  while (!remaining.empty()) {
    auto next = std::find_if_not(remaining.begin(), remaining.end(), waits);
    if (next == remaining.end()) next = remaining.begin();
    order.push_back(*next);
    remaining.erase(next);
  }
  return order;
}

// The objects of `objects` that removing could still help with: sorted, once each,
// neither the target nor already removed.
ObjectSet FeedbackGraph::removable(const std::vector<ObjectIndex>& objects) const {
  ObjectSet out;
  for (ObjectIndex o : objects) {
    if (o != target_ && !initial_.removed[o]) out.push_back(o);
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

// False when `blocking` holds an object that cannot leave before `object` does: the
// target (for any other object) or one the graph avoids.
bool FeedbackGraph::freeable_for(ObjectIndex object, const std::vector<ObjectIndex>& blocking) const {
  return std::none_of(blocking.begin(), blocking.end(), [&](ObjectIndex b) {
    return (b == target_ && object != target_) || std::find(blocked_.begin(), blocked_.end(), b) != blocked_.end();
  });
}

// What the feedback of this round holds, to tell a round after a restart that learnt
// exactly what an earlier one did: then fresh draws change nothing.
std::vector<std::vector<std::uint64_t>> FeedbackGraph::signature() const {
  std::vector<std::vector<std::uint64_t>> out;
  for (const Feedback& f : feedback_) {
    std::vector<std::uint64_t> row{static_cast<std::uint64_t>(f.where), f.object};
    row.insert(row.end(), f.objects.begin(), f.objects.end());
    out.push_back(std::move(row));
  }
  out.emplace_back(blocked_.begin(), blocked_.end());
  out.emplace_back(stays_.begin(), stays_.end());
  return out;
}

bool FeedbackGraph::block(ObjectIndex object) {
  if (std::find(blocked_.begin(), blocked_.end(), object) != blocked_.end()) return false;
  blocked_.push_back(object);
  return true;
}

bool FeedbackGraph::stays(ObjectIndex object) const {
  return std::find(stays_.begin(), stays_.end(), object) != stays_.end();
}

void FeedbackGraph::let_stay(ObjectIndex object) {
  stays_.push_back(object);
  std::sort(stays_.begin(), stays_.end());
}

void FeedbackGraph::clear() {
  feedback_.clear();
  feedback_nodes_.clear();
  branches_.clear();
  dead_branches_.clear();
  guard_of_.clear();
  blocked_.clear();
  stays_.clear();
}

}  // namespace cluttertamp::retrieval_graph_plugin
