#pragma once
// The retrieval graph with what the robot taught it: Tian et al.'s feedback (Fig. 5).

#include <cstdint>
#include <map>
#include <optional>
#include <set>
#include <variant>
#include <vector>

#include <Eigen/Core>

#include "cluttertamp/core/world_state.hpp"
#include "cluttertamp/retrieval/retrieval_graph.hpp"
#include "cluttertamp/retrieval/roadmap.hpp"

namespace cluttertamp::retrieval_graph_plugin {

using retrieval::ObjectSet;

// A place a feedback node attaches to: a roadmap cluster (by one of its roadmap nodes)
// or an earlier feedback node (by its index), so the graph can be rebuilt after the
// roadmap grows.
using Endpoint = std::variant<std::size_t, int>;
// A feedback node goes on the edge before → after (carrying the target out failed
// there); or on every edge into the nodes holding `object` (the robot could not remove
// it: whichever way a path comes, the blockers go first); or before the start node (an
// object every path meets first is blocked); or after the goal node, the target's
// position (the target itself cannot be reached): on every path.
// A target grasp failure may also name other grasps' blockers (`alternatives`): each
// becomes a branch from the goal, so the search takes whichever way costs least once
// later feedback prices them (on Table VI's min4 shelf two grasps tie at two blockers,
// and one of them needs a third object moved first).
struct Feedback {
  enum class Where { edge, object, before_start, after_goal, branch };
  Endpoint before, after;
  ObjectSet objects;
  Where where = Where::edge;
  ObjectIndex object = 0;  ///< Where::object: the object the blockers must precede
  std::vector<ObjectSet> alternatives = {};  ///< Where::after_goal: other grasps' blockers
};
// (Where::branch: the blockers join the NodeCol of the goal branch `before`, as the
// target's grasp that way needs them gone too.)


/// The feedback a planning round collected and the retrieval graph it makes of a
/// roadmap: the roadmap's clusters (made once per roadmap size) with a node for every
/// failure's blockers where the failure happened, the objects the graph must avoid, and
/// those it may pass because only the target's leaving frees them. Indices of feedback
/// records are stable within a round, so the graph can be rebuilt after the roadmap grows.
class FeedbackGraph {
 public:
  /// `initial`: the state every check starts from (its removed objects never count).
  FeedbackGraph(const WorldState& initial, ObjectIndex target) : initial_(initial), target_(target) {}

  /// The graph of `roadmap` with every feedback node; objects already removed do not count.
  retrieval::RetrievalGraph graph(const retrieval::Roadmap& roadmap);
  /// The place a node of the last graph() attaches to; throws std::logic_error for a
  /// node that is neither a cluster nor feedback.
  Endpoint endpoint(int node) const;

  void add(Feedback feedback) { feedback_.push_back(std::move(feedback)); }
  bool empty() const { return feedback_.empty(); }
  std::size_t size() const { return feedback_.size(); }
  /// True when feedback record `index` is a goal branch (a target grasp's blockers).
  bool is_branch(int index) const { return branches_.count(index) > 0; }
  /// Cuts a goal branch's edges; false when it was cut already.
  bool kill_branch(int branch) { return dead_branches_.insert(branch).second; }
  /// Keeps the graph away from `object`; false when it was kept away already.
  bool block(ObjectIndex object);
  bool stays(ObjectIndex object) const;
  /// Lets the graph's ways pass `object`, which only the target's leaving frees.
  void let_stay(ObjectIndex object);
  /// Forgets the round's feedback (the roadmap's clusters are kept).
  void clear();

  /// The objects of `objects` that removing could still help with: sorted, once each,
  /// neither the target nor already removed.
  ObjectSet removable(const std::vector<ObjectIndex>& objects) const;
  /// False when `blocking` holds an object that cannot leave before `object` does: the
  /// target (for any other object) or one the graph avoids.
  bool freeable_for(ObjectIndex object, const std::vector<ObjectIndex>& blocking) const;
  /// The path's objects in the path's order, the objects fed back as blocking one first.
  ObjectSet in_precedence_order(ObjectSet remaining) const;
  /// What the feedback holds, to tell a round that learnt exactly what an earlier one did.
  std::vector<std::vector<std::uint64_t>> signature() const;

 private:
  // Branches rank by kBranchRank metres each: more than any tie-break distance in a shelf.
  static constexpr double kBranchRank = 100.0;
  void add_goal_branches(retrieval::RetrievalGraph& g, const Feedback& f, std::vector<int>& feedback_node);
  Eigen::Vector2d centre(const ObjectSet& objects, const Eigen::Vector2d& if_empty) const;
  ObjectSet with_blockers(ObjectSet set, ObjectIndex except) const;

  const WorldState& initial_;
  ObjectIndex target_;
  std::vector<Feedback> feedback_;
  std::vector<int> feedback_nodes_;
  std::set<int> branches_, dead_branches_;  // goal branches' feedback nodes (endpoint indices)
  std::map<int, int> guard_of_;  // every guard node of the last graph: its feedback's index
  std::optional<retrieval::RetrievalGraph> clustered_;  // the roadmap's clusters, no feedback
  std::size_t clustered_size_ = 0;  // roadmap nodes when clustered_ was made
  std::vector<int> node_of_;
  std::vector<ObjectIndex> blocked_;
  ObjectSet stays_;  // objects only the target's leaving frees: the graph's ways may pass them
};

}  // namespace cluttertamp::retrieval_graph_plugin
