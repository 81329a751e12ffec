#pragma once
// The reports of the benches that run as sweeps: tables on stdout and the files the
// arguments name (CSV, JSON, SVG), made from run records alone. A bench's own run, a
// -j run and `bench merge` all end in the same function, so they print the same
// figures for the same runs.

#include <vector>

#include "bench/sweep.hpp"
#include "cluttertamp/bench/bench.hpp"

namespace cluttertamp::bench {

/// Tables I, V and VI of Tian et al. from `bench retrieval` records; exit code 0.
int report_retrieval(const BenchArgs& args, const std::vector<Record>& records);

/// Fig. 6 of Papallas & Dogar from `bench push` records; with check_goals, exit code 1
/// when guided planning does not beat RRT and KPIECE on success rate.
int report_push(const BenchArgs& args, const std::vector<Record>& records);

/// Table III of Tian et al. from `bench mobile` records; with check_goals, exit code 1
/// when L = 1 moves more than 2.2 objects on average or its median time is above 1 s.
int report_mobile(const BenchArgs& args, const std::vector<Record>& records);

/// `compare`'s runs as a sweep (CompareArgs in BenchArgs), and Table IV from its records;
/// with check_goals, exit code 1 when a run was not solved.
int compare_runs(const BenchArgs& args);
int report_compare(const BenchArgs& args, const std::vector<Record>& records);

/// `bench pddl`'s tables from its records: per instance and search, per domain folder
/// (coverage, IPC quality score); exit code 2 when a file was refused, 3 when a plan
/// failed validation.
int report_pddl(const BenchArgs& args, const std::vector<Record>& records);

/// The rows of `bench sweep` (a sweep file's runs); with check_goals, exit code 1 when
/// a run was not solved.
int report_file_sweep(const BenchArgs& args, const std::vector<Record>& records);

/// Table II of Tian et al. from `bench occlusion` records; with check_goals, exit code 1
/// when a size's success rate is below 95 % or its median time above 1 s.
int report_occlusion(const BenchArgs& args, const std::vector<Record>& records);

/// The speed benches from their records (timed batches, see timing.hpp); with
/// check_goals, exit code 1 when a speed goal the report lists is missed.
int report_collision(const BenchArgs& args, const std::vector<Record>& records);
int report_samplers(const BenchArgs& args, const std::vector<Record>& records);
int report_physics(const BenchArgs& args, const std::vector<Record>& records);

}  // namespace cluttertamp::bench
