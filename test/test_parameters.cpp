#include <gtest/gtest.h>

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

}  // namespace
}  // namespace cluttertamp
