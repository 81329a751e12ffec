#pragma once
// Freeing what a search or grounding made, beside it: after one that ran to its time
// limit, freeing millions of states or instances takes a second or more that the limit
// has not left (`pddl --time-limit 5` on a 3000-block problem freed for 1.1 s). The
// caller gets control back at once; a thread of its own frees the memory meanwhile.

#include <system_error>
#include <thread>
#include <type_traits>
#include <utility>

namespace cluttertamp {

/// Moves `heavy` to a thread of its own, which destroys it, and returns at once; when no
/// thread can be started (near the memory limit), destroys it here. Precondition: its
/// destructor runs no code of a plugin (plugins may be unloaded meanwhile).
template <class T>
void free_beside(T&& heavy) {
  static_assert(!std::is_lvalue_reference_v<T>, "free_beside takes what it frees: std::move it");
  try {
    std::thread([gone = std::move(heavy)]() mutable { auto last = std::move(gone); }).detach();
  } catch (const std::system_error&) {
    auto last = std::move(heavy);
  }
}

}  // namespace cluttertamp
