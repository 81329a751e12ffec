#include "cluttertamp/core/memory_limit.hpp"

#include <algorithm>
#include <atomic>

#include <sys/resource.h>
#include <unistd.h>

namespace cluttertamp {

namespace {
#if defined(__SANITIZE_ADDRESS__)
constexpr bool kAddressSanitizer = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
constexpr bool kAddressSanitizer = true;
#else
constexpr bool kAddressSanitizer = false;
#endif
#else
constexpr bool kAddressSanitizer = false;
#endif

std::atomic<std::size_t> limit_mib{0};
constexpr std::size_t kMiB = 1024 * 1024;
}  // namespace

std::size_t default_memory_limit_mib() {
  const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGESIZE);
  const std::size_t physical = pages > 0 && page > 0 ? std::size_t(pages) * std::size_t(page) / kMiB : 0;
  return std::max<std::size_t>(1024, physical / 4 * 3);
}

bool memory_limit_supported() { return !kAddressSanitizer; }

std::size_t set_memory_limit(std::size_t mib) {
  if (!memory_limit_supported()) return 0;
  if (mib == 0) mib = default_memory_limit_mib();
  rlimit current{};
  if (getrlimit(RLIMIT_AS, &current) != 0) return 0;
  rlimit wanted = current;
  wanted.rlim_cur = static_cast<rlim_t>(mib) * kMiB;
  if (current.rlim_max != RLIM_INFINITY) wanted.rlim_cur = std::min(wanted.rlim_cur, current.rlim_max);
  if (setrlimit(RLIMIT_AS, &wanted) != 0) return 0;
  limit_mib = static_cast<std::size_t>(wanted.rlim_cur / kMiB);
  return limit_mib;
}

std::size_t memory_limit_mib() { return limit_mib; }

}  // namespace cluttertamp
