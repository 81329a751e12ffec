// `cluttertamp bench merge` and the child processes of -j: both find a sweep's bench by
// the name its records (or settings) carry.
#include <iostream>
#include <string>

#include "bench/reports.hpp"
#include "bench/settings.hpp"
#include "bench/sweep.hpp"
#include "cluttertamp/bench/bench.hpp"
#include "cluttertamp/io/text_file.hpp"

namespace cluttertamp::bench {

namespace {

// A bench that runs as a sweep: what runs a shard of it and what reports its records.
struct Sweepable {
  const char* name;
  int (*run)(const BenchArgs&);
  int (*report)(const BenchArgs&, const std::vector<Record>&);
};
const Sweepable kSweepable[] = {
    {"retrieval", retrieval, report_retrieval}, {"push", push, report_push}, {"occlusion", occlusion, report_occlusion},
    {"mobile", mobile, report_mobile}, {"sweep", file_sweep, report_file_sweep},
    {"compare", compare_runs, report_compare}, {"pddl", pddl, report_pddl},
    {"collision", collision, report_collision}, {"samplers", samplers, report_samplers}, {"physics", physics, report_physics}};

const Sweepable& sweepable(const nlohmann::ordered_json& bench, const SourceLocation& where) {
  std::string known;
  for (const Sweepable& s : kSweepable) {
    if (bench.is_string() && bench.get<std::string>() == s.name) return s;
    known += std::string(known.empty() ? "" : ", ") + s.name;
  }
  throw InputError(where, "bench " + bench.dump() + " does not run as a sweep; these do: " + known);
}

}  // namespace

int merge(const MergeArgs& m) {
  const Records records = read_records(m.files, m.verbosity);
  const SourceLocation where{m.files.front().string(), 1, 1};
  const Sweepable& bench = sweepable(records.header["bench"], where);
  BenchArgs args = args_of(records.header["settings"], where);
  args.json = m.json;
  args.csv = m.csv;
  args.svg = m.svg;
  args.ompl_log = m.ompl_log;
  args.check_goals = m.check_goals;
  args.verbosity = m.verbosity;
  if (!m.records.empty()) {
    SweepPlan plan{bench.name, records.header["settings"], records.header["runs"].get<std::size_t>(), {}};
    write_records(m.records, plan, Shard{}, records.runs);
  }
  try {
    return bench.report(args, records.runs);
  } catch (const nlohmann::json::exception& e) {  // a record without a field its report reads, or of another type
    throw InputError(where, "a record of these files is not one that bench " + records.header["bench"].dump() +
                                " writes: " + e.what());
  }
}

int sweep_worker(const std::filesystem::path& settings_file, const SweepOptions& sweep) {
  const SourceLocation where{settings_file.string(), 1, 1};
  const auto file = nlohmann::ordered_json::parse(io::read_text_file(settings_file, "sweep settings"), nullptr, false);
  if (file.is_discarded() || !file.is_object() || !file.contains("settings")) throw InputError(where, "not the settings of a sweep");
  const Sweepable& bench = sweepable(file.value("bench", nlohmann::ordered_json()), where);
  BenchArgs args = args_of(file["settings"], where);
  args.sweep = sweep;
  args.sweep.jobs = 1;
  args.report = false;
  args.verbosity = Verbosity::quiet;
  return bench.run(args);
}

}  // namespace cluttertamp::bench
