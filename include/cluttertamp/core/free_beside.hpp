#pragma once
// Freeing what a search or grounding made, beside it: after one that ran to its time
// limit, freeing millions of states or instances takes a second or more that the limit
// has not left (`pddl --time-limit 5` on a 3000-block problem freed for 1.1 s). The
// caller gets control back at once; a thread of its own frees the memory meanwhile.

#include <thread>
#include <utility>

namespace cluttertamp {

/// Moves `heavy` to a thread of its own, which destroys it; returns at once.
template <class T>
void free_beside(T&& heavy) {
  std::thread([gone = std::forward<T>(heavy)]() mutable { auto last = std::move(gone); }).detach();
}

}  // namespace cluttertamp
