// The roadmap of Algorithm 2 on a small shelf of cylinders: the edge rule
// |EdgeCol| = |Col ∪ Col'|, the exploration limit on Col, the step delta, no edge
// through fixed geometry, same seed same roadmap, and ends standing near a wall.
#include <gtest/gtest.h>

#include "cluttertamp/collision/collision_world.hpp"
#include "cluttertamp/retrieval/roadmap.hpp"
#include "test_fixtures.hpp"

namespace cluttertamp::retrieval {
namespace {

class RoadmapTest : public ::testing::Test {
 protected:
  void SetUp() override {
    // A shelf 0.6 m deep and 0.6 m wide (x 0.6..1.2, y -0.3..0.3) open towards -x.
    test::add_box(scene_, "back", {0.02, 0.64, 0.5}, {1.21, 0, 0.65});
    test::add_box(scene_, "left", {0.6, 0.02, 0.5}, {0.9, 0.31, 0.65});
    test::add_box(scene_, "right", {0.6, 0.02, 0.5}, {0.9, -0.31, 0.65});
    for (double y : {-0.2, -0.07, 0.07, 0.2}) test::add_cylinder(scene_, "w" + std::to_string(y), 0.85, y, 0.0375);
    target_ = test::add_cylinder(scene_, "target", 1.1, 0.0, 0.0375);
  }

  // Builds the world from the scene on first use; every roadmap reads that world.
  Roadmap make(std::uint64_t seed, const Eigen::Vector2d& x_g = {1.1, 0.0}) {
    if (!world_) world_ = std::make_unique<collision::CollisionWorld>(scene_, nullptr);
    const Eigen::AlignedBox2d area(Eigen::Vector2d(0.35, -0.35), Eigen::Vector2d(1.25, 0.35));
    return Roadmap(*world_, footprint_, area, {0.4, 0.0}, x_g, target_, seed);
  }

  Scene scene_;
  ObjectIndex target_ = 0;
  collision::Footprint footprint_{0.05, 0.41, 0.66};  // r_b = 3.75 cm + 1.25 cm of finger
  std::unique_ptr<collision::CollisionWorld> world_;
};

TEST_F(RoadmapTest, EdgesFollowTheEdgeRuleAndNodesTheExplorationLimit) {
  Roadmap roadmap = make(3);
  const RoadmapOptions options;
  for (int limit : {0, 1, 2}) {
    roadmap.expand(limit, options);
    const RoadmapGraph& g = roadmap.graph();
    ASSERT_GT(boost::num_edges(g), 0u);
    for (std::size_t v = 2; v < boost::num_vertices(g); ++v) {
      EXPECT_LE(static_cast<int>(g[v].col.size()), limit) << "node " << v;
      EXPECT_EQ(g[v].col, roadmap.col(g[v].x));
    }
    for (auto [e, end] = boost::edges(g); e != end; ++e) {
      const RoadmapNode& a = g[boost::source(*e, g)];
      const RoadmapNode& b = g[boost::target(*e, g)];
      EXPECT_EQ(roadmap.edge_col(a.x, b.x).size(), unite(a.col, b.col).size());
      EXPECT_LE((a.x - b.x).norm(), options.step + 1e-9);
      if (boost::source(*e, g) > 1 && boost::target(*e, g) > 1) EXPECT_FALSE(roadmap.hits_fixed(a.x, b.x));
    }
  }
  // No node lies in the target's own collision set.
  for (std::size_t v = 0; v < boost::num_vertices(roadmap.graph()); ++v) {
    const ObjectSet& col = roadmap.graph()[v].col;
    EXPECT_FALSE(std::binary_search(col.begin(), col.end(), target_));
  }
}

TEST_F(RoadmapTest, SameSeedSameRoadmap) {
  Roadmap a = make(7), b = make(7);
  a.expand(1, {});
  b.expand(1, {});
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t v = 0; v < a.size(); ++v) EXPECT_EQ(a.graph()[v].x, b.graph()[v].x);
  EXPECT_EQ(boost::num_edges(a.graph()), boost::num_edges(b.graph()));
}

// A target standing 1 cm from the back wall: its footprint there overlaps the wall,
// yet x_g joins the roadmap by edges that do not come closer to it.
TEST_F(RoadmapTest, AnEndCloserToAWallThanTheFootprintStillConnects) {
  const Eigen::Vector2d x_g(1.2 - 0.0375 - 0.01, 0.0);
  scene_.objects[target_].world_T_object.translation().head<2>() = x_g;
  Roadmap roadmap = make(5, x_g);
  ASSERT_TRUE(world_->sweep_hits_fixed(x_g, x_g, footprint_));
  EXPECT_NEAR(world_->fixed_clearance(x_g, footprint_), 0.0375 + 0.01, 1e-9);
  roadmap.expand(1, {});
  EXPECT_GT(boost::out_degree(1, roadmap.graph()), 0u);
}


// Algorithm 4's incremental update: objects the world did not hold when the roadmap
// grew are revealed; every node's Col is then what it would be from scratch, every
// edge still follows the edge rule, and the nodes and the other edges stay.
TEST_F(RoadmapTest, RevealingObjectsUpdatesTheRoadmapAsIfBuiltWithThem) {
  make(0);  // builds the world
  const ObjectIndex hidden[] = {1, 2};
  for (ObjectIndex o : hidden) world_->remove_object(o);
  Roadmap roadmap = make(5);
  roadmap.expand(1, RoadmapOptions{});
  const std::size_t nodes = roadmap.size();
  const std::size_t edges = boost::num_edges(roadmap.graph());
  for (ObjectIndex o : hidden) world_->restore_object(o);
  EXPECT_GT(roadmap.reveal(hidden), 0u);
  const RoadmapGraph& g = roadmap.graph();
  EXPECT_EQ(roadmap.size(), nodes);
  EXPECT_LE(boost::num_edges(g), edges);  // an edge sweeping past a revealed object between two free ends goes
  EXPECT_GT(boost::num_edges(g), edges / 2);
  for (std::size_t v = 0; v < boost::num_vertices(g); ++v) EXPECT_EQ(g[v].col, roadmap.col(g[v].x)) << "node " << v;
  for (auto [e, end] = boost::edges(g); e != end; ++e) {
    const RoadmapNode& a = g[boost::source(*e, g)];
    const RoadmapNode& b = g[boost::target(*e, g)];
    EXPECT_EQ(roadmap.edge_col(a.x, b.x).size(), unite(a.col, b.col).size());
  }

  // A new goal: node 1 moves there, knows its objects and joins its neighbours.
  roadmap.move_goal({1.0, 0.15}, RoadmapOptions{});
  EXPECT_TRUE(g[1].x.isApprox(Eigen::Vector2d(1.0, 0.15)));
  EXPECT_EQ(g[1].col, roadmap.col(g[1].x));
  EXPECT_GT(boost::degree(1, g), 0u);
}

// The free way of the target's footprint: none while the wall of cylinders stands;
// with one of them gone, a way from x_g to x_s on which every segment sweeps past
// nothing but fixed-free space (the first may start touching, as x_g may).
TEST_F(RoadmapTest, FreeWayPassesOnlyWhatIsGone) {
  Roadmap roadmap = make(5);
  const RoadmapOptions options;
  for (int limit : {0, 1, 1, 1}) roadmap.expand(limit, options);
  std::vector<bool> gone(scene_.objects.size(), false);
  EXPECT_TRUE(roadmap.free_way(gone).empty()) << "the wall of cylinders leaves no gap for the footprint";

  const ObjectIndex opened = 2;  // the cylinder at y = 0.07
  gone[opened] = true;
  world_->remove_object(opened);  // the world as it is once the cylinder is gone
  const std::vector<Eigen::Vector2d> way = roadmap.free_way(gone);
  world_->restore_object(opened);
  ASSERT_GE(way.size(), 2u);
  EXPECT_TRUE(way.front().isApprox(Eigen::Vector2d(1.1, 0.0)));
  EXPECT_TRUE(way.back().isApprox(Eigen::Vector2d(0.4, 0.0)));
  for (std::size_t k = 0; k + 1 < way.size(); ++k) {
    for (ObjectIndex o : roadmap.edge_col(way[k], way[k + 1])) {
      EXPECT_TRUE(gone[o]) << "segment " << k << " meets object " << o;
    }
    if (k > 0) EXPECT_FALSE(roadmap.hits_fixed(way[k], way[k + 1])) << "segment " << k;
  }
  // The way crosses the wall's line through the opened gap: its footprint (5 cm) between
  // the cylinders at y = -0.07 and 0.2 (3.75 cm).
  bool crossed = false;
  for (std::size_t k = 0; k + 1 < way.size(); ++k) {
    const Eigen::Vector2d a = way[k], b = way[k + 1];
    if ((a.x() - 0.85) * (b.x() - 0.85) > 0) continue;
    const double y = a.y() + (b.y() - a.y()) * (0.85 - a.x()) / (b.x() - a.x());
    crossed = crossed || (y > -0.07 + 0.0875 - 1e-3 && y < 0.2 - 0.0875 + 1e-3);
  }
  EXPECT_TRUE(crossed);
}

}  // namespace
}  // namespace cluttertamp::retrieval
