#pragma once
// Internal: a stable sort for the short ranges a task is full of (an operator's
// preconditions or effects). std::stable_sort asks the heap for a buffer on every call,
// which for thousands of ranges of two or three items costs more than the sorting.

#include <algorithm>
#include <iterator>
#include <utility>

namespace cluttertamp::search::detail {

/// Sorts [first, last) by `less`, keeping equal items in their order. Insertion sort up
/// to 16 items, std::stable_sort beyond.
template <class It, class Less>
void stable_sort_short(It first, It last, Less less) {
  if (last - first > 16) {
    std::stable_sort(first, last, less);
    return;
  }
  for (It i = first; i != last; ++i) {
    auto item = std::move(*i);
    It j = i;
    for (; j != first && less(item, *std::prev(j)); --j) *j = std::move(*std::prev(j));
    *j = std::move(item);
  }
}

}  // namespace cluttertamp::search::detail
