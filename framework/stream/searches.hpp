#pragma once
// Internal: the two stream search algorithms over a SearchCore (see
// cluttertamp/stream/stream_search.hpp for what each does). Both return when solved,
// when no plan exists, or when the time limit passes (some by throwing
// search::TimeLimit); the core's run() turns that into the solution.

#include "stream/search_core.hpp"
#include "stream/skeleton_queue.hpp"

namespace cluttertamp::stream::detail {

/// PDDLStream's incremental algorithm: every instance whose domain facts hold is
/// called once per round, then the symbolic search runs on the real facts.
void incremental_search(SearchCore& core);

/// PDDLStream's adaptive (focused) algorithm. `queue` holds its skeletons; the caller
/// owns it, to free it beside the caller after a time limit.
void adaptive_search(SearchCore& core, SkeletonQueue& queue);

}  // namespace cluttertamp::stream::detail
