#pragma once
// Internal: the order of many short tuples of small numbers (a schema's bindings, a
// task's operators by their objects), found by sorting keys of 64-bit words into which
// the tuples are packed: comparing a word or two is a fraction of comparing tuples item
// by item.

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
  const auto bits = std::max<std::size_t>(1, static_cast<std::size_t>(std::bit_width(max_item)));
  const std::size_t per_word = 64 / bits;
  const std::size_t words = std::max<std::size_t>(1, (width + per_word - 1) / per_word);
  // Word w of a tuple: its items from w * per_word on, the first in the highest bits
  // (every tuple has the same width, so a word holds as many items in each).
  const auto key = [&](std::uint32_t k, std::size_t w) {
    std::uint64_t packed = 0;
    for (std::size_t i = w * per_word; i < std::min(width, (w + 1) * per_word); ++i) {
      packed = (bits == 64 ? 0 : packed << bits) | item(k, i);
    }
    return packed;
  };
  if (words == 1) {
    std::vector<std::pair<std::uint64_t, std::uint32_t>> keyed(count);
    for (std::uint32_t k = 0; k < count; ++k) keyed[k] = {key(k, 0), k};
    std::sort(keyed.begin(), keyed.end());
    for (std::uint32_t k = 0; k < count; ++k) order[k] = keyed[k].second;
    return order;
  }
  std::vector<std::uint64_t> keys(count * words);
  for (std::uint32_t k = 0; k < count; ++k) {
    for (std::size_t w = 0; w < words; ++w) keys[k * words + w] = key(k, w);
  }
  std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
    const std::uint64_t* x = keys.data() + a * words;
    const std::uint64_t* y = keys.data() + b * words;
    for (std::size_t w = 0; w < words; ++w) {
      if (x[w] != y[w]) return x[w] < y[w];
    }
    return a < b;
  });
  return order;
}

}  // namespace cluttertamp::search::detail
