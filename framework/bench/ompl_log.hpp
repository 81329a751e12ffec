#pragma once
// OMPL's benchmark log format (ompl::tools::Benchmark::saveResultsToFile), so that
// `ompl_benchmark_statistics` (Debian ompl-demos) loads a bench's runs into its SQLite
// database and Planner Arena plots them beside OMPL's own benchmarks.

#include <filesystem>
#include <string>
#include <vector>

#include "bench/sweep.hpp"

namespace cluttertamp::bench {

/// One planner of the log: a name (a bench row: its planner, parameters and scenes)
/// and its runs' records.
struct OmplLogPlanner {
  std::string name;
  std::vector<const Record*> runs;
};

/// What the log's header says about the experiment.
struct OmplLogExperiment {
  std::string name;       ///< "cluttertamp bench retrieval"
  std::string setup;      ///< free text: the bench's settings
  std::uint64_t seed = 0;
  double time_limit = 0;  ///< s per run
};

/// Writes the log, whole; its "runs per planner" is the most any planner has. Per run: time (s, "time_s"), solved, seed, |O_r| as removed,
/// task and motion time where the records have them, and every counter of the
/// planner's runs as an INTEGER property (empty where a run has not counted it).
void write_ompl_log(const std::filesystem::path& file, const OmplLogExperiment& experiment, const std::vector<OmplLogPlanner>& planners);

}  // namespace cluttertamp::bench
