#include <gtest/gtest.h>

#include "cluttertamp/plugin/context.hpp"

#include "cluttertamp/core/parameters.hpp"
#include "test_support.hpp"

namespace cluttertamp {
namespace {

TEST(Parameters, TypedGettersAndFallbacks) {
  Parameters p;
  p.set("T", std::int64_t{1000});
  p.set("step", 0.02);
  p.set("name", std::string("rrt"));
  EXPECT_EQ(p.get_int("T", 1), 1000);
  EXPECT_DOUBLE_EQ(p.get_double("T", 0), 1000.0);  // integers serve where numbers are asked
  EXPECT_DOUBLE_EQ(p.get_double("step", 0), 0.02);
  EXPECT_EQ(p.get_string("name", ""), "rrt");
  EXPECT_EQ(p.get_bool("absent", true), true);
}

TEST(Parameters, WrongTypeNamesTheValuesLocation) {
  Parameters p;
  p.set("T", std::string("many"), {"problem.yaml", 12, 8});
  const Diagnostics d = test::expect_input_error([&] { p.get_int("T", 1); });
  EXPECT_TRUE(test::has_error(d, 12, 8, "parameter 'T' must be an integer, not a string"));
}

TEST(Parameters, UnreadKeysAreReported) {
  Parameters p;
  p.set("used", 1.0);
  p.set("typo", 1.0);
  p.get_double("used", 0);
  EXPECT_EQ(p.unused(), std::vector<std::string>{"typo"});
}

// A sub-task's work budget counts the run's collision checks and is never more than
// its parent's; a context is stopped when its budget is spent.
TEST(PlanningContextTest, WorkBudgetsNestAndNeverGrow) {
  Problem problem;
  std::map<std::string, std::uint64_t> counters{{counter::collision_checks, 100}};
  plugin::Samplers samplers;
  const plugin::PlanningContext run{problem, plugin::Deadline::never(), 0, counters, samplers};
  EXPECT_FALSE(run.stopped());
  const plugin::PlanningContext task = run.with_checks(50);
  EXPECT_EQ(task.checks_left(), 50u);
  counters[counter::collision_checks] += 30;
  EXPECT_EQ(task.checks_left(), 20u);
  const plugin::PlanningContext sub = task.with_checks(100);
  EXPECT_EQ(sub.checks_left(), 20u) << "never more than the parent's budget";
  counters[counter::collision_checks] += 20;
  EXPECT_TRUE(sub.stopped());
  EXPECT_TRUE(task.stopped());
  EXPECT_FALSE(run.stopped());
  EXPECT_EQ(run.with_seed(7).checks_until, run.checks_until);
  EXPECT_EQ(sub.with_seed(7).checks_until, sub.checks_until) << "a new seed keeps the budget";
}

}  // namespace
}  // namespace cluttertamp
