#pragma once

#include <cstddef>

#include "cluttertamp/export.hpp"

namespace cluttertamp {

/// Three quarters of the machine's physical memory, at least 1024 MiB: the default
/// limit, so that a search that grows without bound stops before the machine swaps.
CLUTTERTAMP_API std::size_t default_memory_limit_mib();

/// Limits this process's address space to `mib` MiB (RLIMIT_AS; 0: the default). An
/// allocation beyond it then throws std::bad_alloc, which the planners and commands
/// report as "memory limit reached" (exit code 1, result.json written). Returns the
/// limit set, MiB; 0 when the system refused it, or in a build with AddressSanitizer,
/// which reserves terabytes of address space up front (memory_limit_supported()).
CLUTTERTAMP_API std::size_t set_memory_limit(std::size_t mib);

/// False in a build with AddressSanitizer (scripts/build.sh --sanitize, the fuzzers),
/// where no address-space limit can be set.
CLUTTERTAMP_API bool memory_limit_supported();

/// The limit set_memory_limit() set (MiB), or 0 when none was.
CLUTTERTAMP_API std::size_t memory_limit_mib();

}  // namespace cluttertamp
