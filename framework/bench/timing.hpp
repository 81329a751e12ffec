#pragma once
// What the speed benches (`bench collision`, `samplers`, `physics`) share. Each is a
// sweep whose runs are timed batches: a shard times its batches on the machine it runs
// on, so a merge of shards from several machines mixes their speeds. Every record
// names its host, and the report says when they differ.

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "bench/settings.hpp"
#include "bench/sweep.hpp"

namespace cluttertamp::bench {

/// A speed bench's sweep: `batches` runs, run b the record `Runner::run(b)` of one
/// Runner made from `args` (`noun` names a batch in the progress line: "shelf 2 of 5"),
/// then `report(args, records)`.
template <class Runner, class Report>
int run_timed_batches(const std::string& bench, const BenchArgs& args, std::size_t batches, const std::string& noun, Report&& report) {
  const SweepPlan plan{bench, settings_of(args), batches,
                       [=](std::size_t b) { return noun + " " + std::to_string(b + 1) + " of " + std::to_string(batches); }};
  return run_and_report(
      plan, args, [&] { return std::make_unique<Runner>(args); }, [](Runner& runner, std::size_t b) { return runner.run(b); }, report);
}

/// This machine's host name ("unknown" when it has none).
std::string host_name();

/// "" when every record was timed on one host; else a line naming the hosts, to print
/// under the table.
std::string hosts_note(const std::vector<Record>& records);

/// One timed query of a speed bench.
struct TimedQuery {
  std::string label;           ///< a few words, under its box
  std::vector<double> values;  ///< its times (or speeds), one per batch or call
  double goal = 0;             ///< 0: no goal
};

/// A box plot per query on one panel (a log axis when the values span more than a
/// decade), each goal a dashed red line, a legend saying whether goals are limits from
/// above (`goals_are_minimums` false: at most) or below. Throws as SvgPlot::write.
void write_timing_svg(const std::filesystem::path& file, const std::string& title, const std::string& axis,
                      const std::vector<TimedQuery>& queries, bool goals_are_minimums = false);

}  // namespace cluttertamp::bench
