#pragma once
// Internal: the order of many short tuples of small numbers (a schema's bindings, a
// task's operators by their objects), found by sorting 64-bit keys where the tuples fit
// in them: comparing keys is a fraction of comparing tuples item by item.

#include <algorithm>
#include <bit>
#include <cstdint>
#include <utility>
#include <vector>

namespace cluttertamp::search::detail {

/// Ids 0 .. count-1 in lexicographic order of their tuples, equal tuples in id order:
/// `item(id, i)` is item i (below `width`) of tuple `id`, each at most `max_item`.
template <class Item>
std::vector<std::uint32_t> lexicographic_order(std::size_t count, std::size_t width, std::uint64_t max_item, const Item& item) {
  std::vector<std::uint32_t> order(count);
  for (std::uint32_t k = 0; k < count; ++k) order[k] = k;
  const auto bits = static_cast<std::size_t>(std::bit_width(max_item));
  if (width * bits <= 64) {
    std::vector<std::pair<std::uint64_t, std::uint32_t>> keyed(count);
    for (std::uint32_t k = 0; k < count; ++k) {
      std::uint64_t key = 0;
      for (std::size_t i = 0; i < width; ++i) key = (bits == 64 ? 0 : key << bits) | item(k, i);
      keyed[k] = {key, k};
    }
    std::sort(keyed.begin(), keyed.end());
    for (std::uint32_t k = 0; k < count; ++k) order[k] = keyed[k].second;
    return order;
  }
  std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
    for (std::size_t i = 0; i < width; ++i) {
      const std::uint64_t x = item(a, i), y = item(b, i);
      if (x != y) return x < y;
    }
    return a < b;
  });
  return order;
}

}  // namespace cluttertamp::search::detail
