#include <cmath>

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

TEST(Parameters, RangesRejectValuesOutsideThemAndNaN) {
  EXPECT_TRUE(Range::open(0, 1).contains(0.5));
  EXPECT_FALSE(Range::open(0, 1).contains(0));
  EXPECT_TRUE(Range::closed_open(0, 1).contains(0));
  EXPECT_FALSE(Range::closed_open(0, 1).contains(1));
  EXPECT_TRUE(Range::at_least(1).contains(1e9));
  EXPECT_FALSE(Range::above(0).contains(std::nan("")));
  EXPECT_FALSE(Range{}.contains(std::nan("")));
  EXPECT_EQ(Range::open_closed(0, 100).str(), "(0, 100]");
  EXPECT_EQ(Range::at_least(1).str(), "at least 1");
  EXPECT_EQ(Range{}.str(), "");

  Parameters p;
  p.set("step", 2.0, {"problem.yaml", 3, 9});
  p.set("heights", std::vector<double>{0.5, 1.5}, {"problem.yaml", 4, 12});
  p.set("count", std::int64_t{0}, {"problem.yaml", 5, 10});
  const Diagnostics d = test::expect_input_error([&] { p.get_double("step", 0.1, "m", Range::open(0, 1)); });
  EXPECT_TRUE(test::has_error(d, 3, 9, "parameter 'step' must be in (0, 1), not 2"));
  const Diagnostics h = test::expect_input_error([&] { p.get_vector("heights", {}, "", Range::open(0, 1)); });
  EXPECT_TRUE(test::has_error(h, 4, 12, "parameter 'heights' must be in (0, 1), not 1.5"));
  const Diagnostics c = test::expect_input_error([&] { p.get_int("count", 1, "", Range::at_least(1)); });
  EXPECT_TRUE(test::has_error(c, 5, 10, "parameter 'count' must be at least 1, not 0"));
}

// The registry's copies collect every bad value (getters return the default), so one
// run reports them all; the declarations carry help and range for `plugins -v`.
TEST(Parameters, CollectingCopiesReportEveryBadValue) {
  Parameters given;
  given.set("step", 2.0, {"problem.yaml", 3, 9});
  given.set("name", std::int64_t{4}, {"problem.yaml", 4, 9});
  const Parameters p = given.fresh(/*collect=*/true);
  EXPECT_DOUBLE_EQ(p.get_double("step", 0.1, "m per step", Range::open(0, 1)), 0.1);
  EXPECT_EQ(p.get_string("name", "rrt"), "rrt");
  p.require(false, "step", "must agree with name");
  ASSERT_EQ(p.errors().size(), 3u) << p.errors().str();
  EXPECT_TRUE(test::has_error(p.errors(), 4, 9, "parameter 'name' must be a string, not an integer"));
  EXPECT_TRUE(test::has_error(p.errors(), 3, 9, "parameter 'step' must agree with name"));
  ASSERT_EQ(p.declarations().size(), 2u);
  EXPECT_EQ(p.declarations()[0].help, "m per step");
  EXPECT_EQ(p.declarations()[0].range, "(0, 1)");
  EXPECT_TRUE(given.fresh().errors().empty());
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

namespace cluttertamp {
namespace {

TEST(Parameters, MapsAndListsAreValuesWithLocations) {
  Parameters p;
  Value::Map workspace{{"min_x", Value(std::int64_t{-2}, {"p.yaml", 3, 20})}, {"max_x", Value(2.5, {"p.yaml", 3, 31})}};
  p.set("workspace", Value(std::move(workspace), {"p.yaml", 3, 12}));
  const Value* w = p.get("workspace", "where the tip reaches");
  ASSERT_NE(w, nullptr);
  EXPECT_EQ(w->find("min_x")->number(), -2.0);
  EXPECT_EQ(w->find("max_x")->where().column, 31u);
  EXPECT_EQ(w->find("absent"), nullptr);
  EXPECT_TRUE(p.unused().empty());
  // A map where a number is asked for is refused at the map's place.
  const Diagnostics d = test::expect_input_error([&] { p.get_double("workspace", 0); });
  EXPECT_TRUE(test::has_error(d, 3, 12, "parameter 'workspace' must be a number, not a map"));
  // A list of numbers serves get_vector, a list of anything else does not.
  p.set("xs", std::vector<double>{1, 2});
  EXPECT_EQ(p.get_vector("xs", {}), (std::vector<double>{1, 2}));
  p.set("names", Value(Value::List{Value(std::string("a"))}, {"p.yaml", 5, 8}));
  EXPECT_TRUE(test::has_error(test::expect_input_error([&] { p.get_vector("names", {}); }), 5, 8,
                              "must be a list of numbers, not a list"));
}

// What configure() asks is what `plugins -v` lists: key, type, default and help, once each.
TEST(Parameters, GettersDeclareWhatTheyRead) {
  const Parameters none;
  none.get_double("step", 0.1, "m between checks");
  none.get_int("tries", 3);
  none.get_vector("heights", {0.5, 0.25});
  none.get_string("planner", "rrt");
  none.get_bool("trace", false);
  none.get("shape", "any YAML");
  none.get_double("step", 0.2);  // asked again: declared once
  const auto& d = none.declarations();
  ASSERT_EQ(d.size(), 6u);
  EXPECT_EQ(d[0].key, "step");
  EXPECT_EQ(d[0].type, "number");
  EXPECT_EQ(d[0].fallback, "0.1");
  EXPECT_EQ(d[0].help, "m between checks");
  EXPECT_EQ(d[1].fallback, "3");
  EXPECT_EQ(d[2].type, "list of numbers");
  EXPECT_EQ(d[2].fallback, "[0.5, 0.25]");
  EXPECT_EQ(d[3].fallback, "rrt");
  EXPECT_EQ(d[4].fallback, "false");
  EXPECT_EQ(d[5].type, "any");
}

// Every plugin object is configured from a fresh copy: one problem's parameters can
// configure many objects, each seeing every key unread.
TEST(Parameters, AFreshCopyHasNothingRead) {
  Parameters p;
  p.set("a", 1.0);
  p.get_double("a", 0);
  EXPECT_TRUE(p.unused().empty());
  const Parameters copy = p.fresh();
  EXPECT_EQ(copy.unused(), std::vector<std::string>{"a"});
  EXPECT_TRUE(copy.declarations().empty());
  EXPECT_EQ(copy.to_yaml(), "{a: 1.0}");
}

TEST(ValueTest, YamlTextReadsBackAsTheSameKinds) {
  Value::Map m{{"s", Value(std::string("true"))}, {"e", Value(std::string(""))}, {"n", Value()},
               {"x", Value(0.1)}, {"i", Value(std::int64_t{7})}, {"colon", Value(std::string("a: b"))},
               {"on", Value(std::string("Yes"))}, {"word", Value(std::string("plain words"))}};
  // The problem reader takes YAML 1.1's y/n/yes/no/on/off as booleans: such strings, keys too, are quoted.
  EXPECT_EQ(Value(std::move(m)).to_yaml(),
            "{s: \"true\", e: \"\", \"n\": null, x: 0.1, i: 7, colon: \"a: b\", \"on\": \"Yes\", word: plain words}");
}

}  // namespace
}  // namespace cluttertamp
