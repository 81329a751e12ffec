#pragma once
// Same seed, same result: comparing two result.json texts apart from what may differ
// between identical runs, and CPU load to plan beside (plan --repeat, --load, --expect).

#include <memory>
#include <optional>
#include <string>

namespace cluttertamp::cli {

/// The first place where two result.json texts differ, ignoring their time fields
/// (`time` and every key ending in `_time`) and the file paths they name (`problem`,
/// `scene`; a PDDL task's `domain`, `problem`, `streams`): "/counters/collision_checks: 627544 against 627545". Nothing when
/// they agree. Throws nlohmann::json::parse_error for a text that is not JSON.
std::optional<std::string> result_difference(const std::string& a, const std::string& b);

/// While alive, `threads` busy loops run on the CPU the calling thread runs on, and the
/// calling thread (and every thread it starts) is held to that CPU: a planner then
/// gets a fraction of one core, as on a loaded machine. The affinity is restored when
/// it ends. No threads for 0.
class CpuLoad {
 public:
  explicit CpuLoad(int threads);
  ~CpuLoad();
  CpuLoad(const CpuLoad&) = delete;
  CpuLoad& operator=(const CpuLoad&) = delete;
  int cpu() const;  ///< the CPU shared, -1 without load

 private:
  void stop();
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace cluttertamp::cli
