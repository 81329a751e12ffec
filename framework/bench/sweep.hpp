#pragma once
// Sweeps as data. A bench is a numbered list of runs, fixed by its settings alone; any
// shard of that list runs in one process, or spread over child processes (-j); every
// run becomes one JSON record; and the bench's report is made from records alone. So a
// report of merged shard files, of a -j run and of one process are the same figures
// for the same runs.
//
// Records file (JSON Lines): a header line
//   {"cluttertamp_records": 1, "bench": NAME, "version": V, "shard": "K/N", "runs": TOTAL, "settings": {...}}
// then one line per run, each with "index" (its place in the list, 0 <= index < TOTAL).

#include <cstddef>
#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cluttertamp/bench/bench.hpp"

namespace cluttertamp::bench {

using Record = nlohmann::ordered_json;

/// What a sweep is: the bench, the settings its runs and report depend on (the same in
/// every shard), and how many runs it has in all.
struct SweepPlan {
  std::string bench;
  Record settings;
  std::size_t runs = 0;
  /// A few words naming run i, for the progress line ("shelf12 retrieval_graph (one), scene 3, seed 2").
  std::function<std::string(std::size_t)> label;
};

/// Runs one run and returns its record (without "index": the sweep adds it). Called
/// for the runs of this process's shard only, in increasing order.
using RunOne = std::function<Record(std::size_t index)>;

/// Runs the runs of `options.shard` (in child processes when options.jobs > 1), shows
/// progress on a terminal, writes options.records when given, and returns the records
/// of the shard in index order. A record with "solved": false counts as failed in the
/// progress line. Throws InputError / std::runtime_error as the runs do; a child that
/// fails is reported with the end of its output.
std::vector<Record> run_sweep(const SweepPlan& plan, const SweepOptions& options, Verbosity verbosity, const RunOne& run_one);

/// A bench's runs and report: run_sweep with the runner that `make()` returns (a
/// pointer, made on the first run: the parent of -j runs none, so makes none), each run
/// `run(runner, i)`; then `report(args, records)`, or 0 in a child of -j (args.report false).
template <class Make, class Run, class Report>
int run_and_report(const SweepPlan& plan, const BenchArgs& args, Make&& make, Run&& run, Report&& report) {
  decltype(make()) runner;
  const std::vector<Record> records = run_sweep(plan, args.sweep, args.verbosity, [&](std::size_t i) {
    if (!runner) runner = make();
    return run(*runner, i);
  });
  return args.report ? report(args, records) : 0;
}

/// The records of `files` (records files of one sweep: same bench, settings and run
/// count), in index order, with the header of the first. Throws InputError naming the
/// file and line of whatever does not fit: a line that is not a record, another sweep's
/// header, a run given twice. Runs missing from every file are said on stderr.
struct Records {
  Record header;
  std::vector<Record> runs;
};
Records read_records(const std::vector<std::filesystem::path>& files, Verbosity verbosity);

/// Writes `records` as one records file of `plan` (shard `shard`), whole.
void write_records(const std::filesystem::path& file, const SweepPlan& plan, const Shard& shard, const std::vector<Record>& records);

/// Whether progress lines go to stderr: on a terminal, unless `verbosity` is quiet (a
/// log file gets no carriage-return lines).
bool progress_shown(Verbosity verbosity);

/// A number from a record: `key`'s value, or `otherwise` when absent or null.
double number(const Record& record, const char* key, double otherwise = 0.0);

}  // namespace cluttertamp::bench
