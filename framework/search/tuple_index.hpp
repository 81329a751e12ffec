#pragma once
// Internal: tuples of one length, each kept once, end to end in one array and found by
// an open-addressing index; a tuple's id is its place in the order of insertion. The
// search's state registry and the grounder's bindings of a schema are both this: a new
// tuple costs no allocation of its own, one seen again a hash and a compare.

#include <algorithm>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

namespace cluttertamp::search::detail {

template <class T>
class TupleIndex {
 public:
  /// `length`: the items of every tuple (0 allowed: then one tuple at most).
  explicit TupleIndex(std::size_t length) : length_(length) {}
  std::size_t size() const { return size_; }
  /// The items of every tuple.
  std::size_t length() const { return length_; }
  std::span<const T> operator[](std::size_t id) const { return {items_.data() + id * length_, length_}; }
  bool contains(std::span<const T> t) const { return !slots_.empty() && slots_[slot(t, slots_)] != 0; }
  /// The id of `t` (of the index's length), and whether it was added now.
  std::pair<std::size_t, bool> insert(std::span<const T> t) {
    if (2 * (size_ + 1) > slots_.size()) grow();  // at most half full
    const std::size_t at = slot(t, slots_);
    if (slots_[at] != 0) return {slots_[at] - 1, false};
    slots_[at] = static_cast<std::uint32_t>(++size_);
    items_.insert(items_.end(), t.begin(), t.end());
    return {size_ - 1, true};
  }

 private:
  // Each item combined in (boost's hash_combine, widened), then MurmurHash3's 64-bit
  // finish: slots are chosen by the low bits, which the combination alone leaves clustered.
  static std::uint64_t hash(std::span<const T> t) {
    std::uint64_t h = 1469598103934665603ull;
    for (const T& v : t) h ^= static_cast<std::uint64_t>(v) + 0x9e3779b97f4a7c15ull + (h << 6) + (h >> 2);
    h ^= h >> 33;
    h *= 0xff51afd7ed558ccdull;
    h ^= h >> 33;
    h *= 0xc4ceb9fe1a85ec53ull;
    return h ^ (h >> 33);
  }
  /// The slot of `slots` holding `t`, or the empty one where it would go.
  std::size_t slot(std::span<const T> t, const std::vector<std::uint32_t>& slots) const {
    const std::size_t mask = slots.size() - 1;
    for (std::size_t at = hash(t) & mask;; at = (at + 1) & mask) {
      const std::uint32_t k = slots[at];
      if (k == 0 || std::equal(t.begin(), t.end(), items_.begin() + static_cast<std::ptrdiff_t>((k - 1) * length_))) return at;
    }
  }
  void grow() {
    std::vector<std::uint32_t> slots(std::max<std::size_t>(16, 2 * slots_.size()), 0);
    for (std::size_t id = 0; id < size_; ++id) slots[slot((*this)[id], slots)] = static_cast<std::uint32_t>(id + 1);
    slots_ = std::move(slots);
  }

  std::size_t length_, size_ = 0;
  std::vector<T> items_;               // tuple id * length_: its items
  std::vector<std::uint32_t> slots_;  // tuple id + 1 by hash, 0 where none; a power of two long
};

}  // namespace cluttertamp::search::detail
