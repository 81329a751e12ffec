// The grounder's sorts of tuples (bindings, operators by name): packed into one 64-bit word
// or into several, the order is lexicographic, equal tuples in id order.
#include <algorithm>
#include <cstdint>
#include <random>
#include <set>
#include <vector>

#include <gtest/gtest.h>

#include "search/tuple_order.hpp"

namespace cluttertamp::search::detail {
namespace {

std::vector<std::vector<std::uint64_t>> distinct_tuples(std::size_t count, std::size_t width, std::uint64_t max_item,
                                                        unsigned seed) {
  std::mt19937_64 random(seed);
  std::uniform_int_distribution<std::uint64_t> item(0, max_item);
  std::set<std::vector<std::uint64_t>> seen;
  std::vector<std::vector<std::uint64_t>> tuples;
  while (tuples.size() < count) {
    std::vector<std::uint64_t> t(width);
    for (auto& x : t) x = item(random);
    if (seen.insert(t).second) tuples.push_back(t);
  }
  return tuples;
}

TEST(PddlTupleOrder, PackedAndItemByItemOrdersAreLexicographic) {
  // Widths and item sizes that fit in one word (3 x 21 bits, 1 x 64, 2 x 1) and that take
  // two or more (3 x 22, 9 x 8, 5 x 64).
  const std::vector<std::pair<std::size_t, std::uint64_t>> shapes{
      {3, (1u << 21) - 1}, {1, ~std::uint64_t{0}}, {2, 1}, {3, 1u << 21}, {9, 200}, {5, ~std::uint64_t{0}}};
  for (const auto& [width, max_item] : shapes) {
    const std::size_t count = max_item == 1 ? 4 : 500;
    const auto tuples = distinct_tuples(count, width, max_item, static_cast<unsigned>(width * 31 + max_item % 97));
    const std::vector<std::uint32_t> order =
        lexicographic_order(tuples.size(), width, max_item, [&](std::uint32_t k, std::size_t i) { return tuples[k][i]; });
    ASSERT_EQ(order.size(), tuples.size());
    std::vector<std::vector<std::uint64_t>> ordered;
    for (std::uint32_t k : order) ordered.push_back(tuples[k]);
    std::vector<std::vector<std::uint64_t>> expected = tuples;
    std::sort(expected.begin(), expected.end());
    EXPECT_EQ(ordered, expected) << width << " items of at most " << max_item;
  }
  // Equal tuples keep their ids' order, packed or not.
  for (const std::size_t width : {2u, 12u}) {
    const std::vector<std::uint64_t> first{3, 1, 3, 0, 1, 3};
    const std::vector<std::uint32_t> order =
        lexicographic_order(first.size(), width, 200, [&](std::uint32_t k, std::size_t i) { return i == 0 ? first[k] : 7; });
    EXPECT_EQ(order, (std::vector<std::uint32_t>{3, 1, 4, 0, 2, 5})) << width;
  }
}

}  // namespace
}  // namespace cluttertamp::search::detail
