// The retrieval graph's greedy PathCol search on hand-built graphs, including the
// feedback insertion of Tian et al., Figs. 5 and 6.
#include <algorithm>

#include <gtest/gtest.h>

#include "cluttertamp/retrieval/retrieval_graph.hpp"

namespace cluttertamp::retrieval {
namespace {

// Obstacles O1..O8 at fixed positions (index = object number).
Eigen::Vector2d position(ObjectIndex o) {
  static const std::map<ObjectIndex, Eigen::Vector2d> p{{1, {0.6, 0.3}}, {2, {0.7, 0.35}}, {3, {0.8, 0.3}},
                                                         {4, {0.9, 0.0}}, {5, {0.8, -0.1}}, {8, {0.7, 0.0}}};
  return p.count(o) ? p.at(o) : Eigen::Vector2d::Zero();
}

TEST(RetrievalGraph, FindsTheMinimumCollisionPathAndItsRemovalOrder) {
  RetrievalGraph g(position);
  const int s = g.add_node({}, {0.4, 0.0});
  const int n8 = g.add_node({8}, {0.7, 0.0});
  const int n4 = g.add_node({4}, {0.9, 0.0});
  const int goal = g.add_node({}, {1.0, 0.0});
  // A detour through three objects.
  const int n1 = g.add_node({1}, {0.6, 0.3});
  const int n12 = g.add_node({1, 2}, {0.7, 0.35});
  const int n123 = g.add_node({1, 2, 3}, {0.8, 0.3});
  for (auto [a, b] : {std::pair{s, n8}, {n8, n4}, {n4, goal}, {s, n1}, {n1, n12}, {n12, n123}, {n123, goal}}) g.add_edge(a, b);
  g.set_start(s);
  g.set_goal(goal);
  g.update();
  const auto r = g.removal_sequence();
  ASSERT_TRUE(r.has_value());
  EXPECT_EQ(r->objects_in_order, (ObjectSet{8, 4}));
  EXPECT_EQ(r->nodes, (std::vector<int>{s, n8, n4, goal}));
  // Overlapping NodeCol sets count once: {1} then {1, 2} is a PathCol of 2, not 3.
  EXPECT_EQ(g.node(n12).path_col->size(), 2u);
  EXPECT_EQ(*g.node(n123).path_col, (ObjectSet{1, 2, 3}));
}

TEST(RetrievalGraph, FeedbackNodesReplaceTheFailedEdge) {
  // Fig. 5: O8 removed, picking O4 fails as the robot hits O3 with one grasp and O5
  // with another: the edge n8-n4 goes, nodes {O3} and {O5} join n8 and n4.
  RetrievalGraph g(position);
  const int s = g.add_node({}, {0.4, 0.0});
  const int n8 = g.add_node({8}, {0.7, 0.0});
  const int n4 = g.add_node({4}, {0.9, 0.0});
  const int goal = g.add_node({}, {1.0, 0.0});
  for (auto [a, b] : {std::pair{s, n8}, {n8, n4}, {n4, goal}}) g.add_edge(a, b);
  g.set_start(s);
  g.set_goal(goal);
  g.update();
  g.remove_edge(n8, n4);
  const int n41 = g.add_node({3}, position(3));
  const int n42 = g.add_node({5}, position(5));
  for (int n : {n41, n42}) {
    g.add_edge(n8, n);
    g.add_edge(n, n4);
  }
  EXPECT_FALSE(g.has_edge(n8, n4));
  g.update();
  const auto r = g.removal_sequence();
  ASSERT_TRUE(r.has_value());
  // Both detours remove three objects; O5 lies nearer the way (Fig. 6(b)).
  EXPECT_EQ(r->objects_in_order, (ObjectSet{8, 5, 4}));
  EXPECT_EQ(r->nodes, (std::vector<int>{s, n8, n42, n4, goal}));
  EXPECT_EQ(g.node(n41).path_col->size(), 2u);
  EXPECT_EQ(g.node(n4).path_col->size(), 3u);
}

// Feedback about an object (O4 cannot be picked while O3 stands) guards every way into
// the nodes that hold O4, not only the edge the failed path took.
TEST(RetrievalGraph, AGuardGoesOnEveryEdgeIntoTheObjectsNodes) {
  RetrievalGraph g(position);
  const int s = g.add_node({}, {0.4, 0.0});
  const int n8 = g.add_node({8}, {0.7, 0.0});
  const int n7 = g.add_node({7}, {0.7, 0.2});
  const int n4 = g.add_node({4}, {0.9, 0.0});
  const int n46 = g.add_node({4, 6}, {0.9, 0.1});
  const int goal = g.add_node({}, {1.0, 0.0});
  for (auto [a, b] : {std::pair{s, n8}, {n8, n4}, {s, n7}, {n7, n46}, {n46, n4}, {n4, goal}}) g.add_edge(a, b);
  g.set_start(s);
  g.set_goal(goal);
  const std::vector<int> guards = g.guard_object(4, {3}, position(3));
  ASSERT_EQ(guards.size(), 3u);  // one per outside node: n8, n7 and the goal
  EXPECT_FALSE(g.has_edge(n8, n4));
  EXPECT_FALSE(g.has_edge(n7, n46));
  EXPECT_FALSE(g.has_edge(n4, goal));
  EXPECT_TRUE(g.has_edge(n46, n4));  // inside to inside: no guard
  for (int guard : guards) EXPECT_EQ(g.node(guard).node_col, (ObjectSet{3}));
  g.update();
  const auto r = g.removal_sequence();
  ASSERT_TRUE(r.has_value());
  ASSERT_EQ(r->objects_in_order.size(), 3u);
  const auto at = [&](ObjectIndex o) { return std::find(r->objects_in_order.begin(), r->objects_in_order.end(), o); };
  EXPECT_LT(at(3), at(4));  // the blocker before the object
}

TEST(RetrievalGraph, UnreachableGoalsAndBlockedObjects) {
  RetrievalGraph g(position);
  const int s = g.add_node({}, {0.4, 0.0});
  const int n8 = g.add_node({8}, {0.7, 0.0});
  const int goal = g.add_node({}, {1.0, 0.0});
  g.add_edge(s, n8);
  g.add_edge(n8, goal);
  g.set_start(s);
  g.set_goal(goal);
  g.update();
  ASSERT_TRUE(g.removal_sequence().has_value());
  g.block_object(8);  // O8 cannot be removed: the only way is closed
  g.update();
  EXPECT_FALSE(g.removal_sequence().has_value());
  EXPECT_FALSE(g.node(goal).path_col.has_value());
}

// Two grasps of the target blocked by two objects each, fed back as branches from the
// goal to a new goal: the entry cost ranks them where |PathCol| ties, and once O2
// turns out to need O4 first (a guard), the other branch costs less and wins.
TEST(RetrievalGraph, GoalBranchesRankByEntryCostUntilFeedbackPricesThem) {
  RetrievalGraph g(position);
  const int s = g.add_node({}, {0.4, 0.0});
  const int goal = g.add_node({}, {1.0, 0.0});
  g.add_edge(s, goal);
  const int joined = g.add_node({}, {1.0, 0.0});
  const int first = g.add_node({1, 2}, {0.65, 0.3});
  const int second = g.add_node({5, 8}, {0.75, -0.05});
  for (int branch : {first, second}) {
    g.add_edge(goal, branch);
    g.add_edge(branch, joined);
  }
  g.set_start(s);
  g.set_goal(joined);
  g.update();
  ASSERT_TRUE(g.removal_sequence().has_value());
  // By distance alone the nearer pair wins: O8 and O5.
  EXPECT_EQ(g.removal_sequence()->nodes, (std::vector<int>{s, goal, second, joined}));
  g.set_entry_cost(second, 100.0);
  g.update();
  EXPECT_EQ(g.removal_sequence()->nodes, (std::vector<int>{s, goal, first, joined}));
  EXPECT_EQ(g.node(joined).path_col->size(), 2u);
  g.guard_object(2, {4}, position(4));
  g.update();
  const auto r = g.removal_sequence();
  ASSERT_TRUE(r.has_value());
  EXPECT_EQ(r->objects_in_order, (ObjectSet{8, 5}));
  EXPECT_EQ(g.node(joined).path_col->size(), 2u);
  // The target's grasp that way needs O3 and O4 gone too: it now costs 4, the other 3.
  g.add_to_node_col(second, {3, 4});
  EXPECT_EQ(g.node(second).node_col, (ObjectSet{3, 4, 5, 8}));
  g.update();
  ASSERT_TRUE(g.removal_sequence().has_value());
  EXPECT_EQ(*g.node(joined).path_col, (ObjectSet{1, 2, 4}));
}

}  // namespace
}  // namespace cluttertamp::retrieval
