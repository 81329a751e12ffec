// The shipped corridor pruner, loaded from the build tree's plugin directory like any
// plugin a user runs.
#include <gtest/gtest.h>

#include "cluttertamp/io/problem_io.hpp"
#include "cluttertamp/plugin/object_pruner.hpp"
#include "cluttertamp/plugin/registry.hpp"
#include "test_support.hpp"

namespace cluttertamp {
namespace {

class CorridorPruner : public ::testing::Test {
 protected:
  plugin::PruneAnswer prune(const WorldState& state) {
    plugin::PlanningContext context{problem_, plugin::Deadline::after(10), 0, counters_, samplers_};
    return pruner_->prune(context, state);
  }
  std::vector<std::string> ids(const std::vector<ObjectIndex>& objects) const {
    std::vector<std::string> out;
    for (ObjectIndex i : objects) out.push_back(problem_.scene.objects[i].id);
    return out;
  }

  Problem problem_ = io::load_problem(test::data("problems/good.yaml"));
  plugin::Registry registry_{plugin::Registry::default_search_paths()};
  std::shared_ptr<plugin::ObjectPruner> pruner_ = registry_.create<plugin::ObjectPruner>("corridor");
  std::map<std::string, std::uint64_t> counters_;
  plugin::Samplers samplers_;
};

TEST_F(CorridorPruner, IsFoundInTheBuildTree) {
  const plugin::PluginDescriptor* d = registry_.find("object_pruner", "corridor");
  ASSERT_NE(d, nullptr);
  EXPECT_EQ(d->version, "1.0.0");
}

TEST_F(CorridorPruner, RemovesTheLoadBeforeTheObjectInTheWay) {
  // good.yaml: b stands between the target a and the exit; the lid rests on b and c.
  const plugin::PruneAnswer answer = prune(WorldState::initial(problem_.scene));
  ASSERT_FALSE(answer.failure.has_value());
  ASSERT_EQ(answer.removal_sequences.size(), 1u);
  EXPECT_EQ(ids(answer.removal_sequences[0]), (std::vector<std::string>{"lid", "b"}));
  EXPECT_EQ(ids(answer.movable_objects()), (std::vector<std::string>{"b", "lid"}));
  EXPECT_EQ(counters_[counter::collision_checks], 3u);
}

TEST_F(CorridorPruner, RemovedObjectsNoLongerBlock) {
  WorldState state = WorldState::initial(problem_.scene);
  state.removed[*problem_.scene.find_object("b")] = true;
  state.removed[*problem_.scene.find_object("lid")] = true;
  const plugin::PruneAnswer answer = prune(state);
  ASSERT_EQ(answer.removal_sequences.size(), 1u);
  EXPECT_TRUE(answer.removal_sequences[0].empty());
}

TEST_F(CorridorPruner, FingerThicknessWidensTheCorridor) {
  Parameters wide;
  wide.set("finger_thickness", 0.2);
  pruner_ = registry_.create<plugin::ObjectPruner>("corridor", wide);
  const plugin::PruneAnswer answer = prune(WorldState::initial(problem_.scene));
  ASSERT_EQ(answer.removal_sequences.size(), 1u);
  EXPECT_EQ(ids(answer.removal_sequences[0]), (std::vector<std::string>{"lid", "b", "c"}));
}

TEST_F(CorridorPruner, RejectsANegativeFingerThickness) {
  Parameters bad;
  bad.set("finger_thickness", -0.01, {"p.yaml", 4, 20});
  const Diagnostics d = test::expect_input_error([&] { registry_.create<plugin::ObjectPruner>("corridor", bad); });
  EXPECT_TRUE(test::has_error(d, 4, 20, "finger_thickness"));
}

}  // namespace
}  // namespace cluttertamp
