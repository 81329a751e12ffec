// Benches as sweeps: shards, child processes (-j) and `bench merge` give the figures of
// one unsharded run for the same runs; the options of each bench are its own.
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "test_support.hpp"

namespace cluttertamp {
namespace {

namespace fs = std::filesystem;
using test::run_cli;

class BenchSweep : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("cluttertamp_sweep_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override {
    if (!HasFailure()) fs::remove_all(dir_);
  }
  std::string at(const std::string& name) const { return (dir_ / name).string(); }
  fs::path dir_;
};

// The lines of a records file as JSON: the header, then the runs.
std::vector<nlohmann::json> records(const fs::path& file) {
  std::vector<nlohmann::json> out;
  std::ifstream in(file);
  for (std::string line; std::getline(in, line);) out.push_back(nlohmann::json::parse(line));
  return out;
}

// `j` without what the clock measured (keys of times: "..._s", "...seconds...", "...time...",
// "...median...", rates "..._hz"):
// what must be the same for the same runs, however they were spread.
nlohmann::json without_times(nlohmann::json j) {
  if (j.is_object()) {
    nlohmann::json out = nlohmann::json::object();
    for (auto& [key, value] : j.items()) {
      const auto ends_with = [&key](const std::string& tail) { return key.size() > tail.size() && key.substr(key.size() - tail.size()) == tail; };
      const bool time = key.find("seconds") != std::string::npos || key.find("time") != std::string::npos ||
                        key.find("median") != std::string::npos || ends_with("_s") || ends_with("_hz");
      if (!time) out[key] = without_times(value);
    }
    return out;
  }
  if (j.is_array()) {
    for (auto& value : j) value = without_times(value);
  }
  return j;
}

// Six runs of Table I (retrieval_graph's three limits on one 12-object shelf, two seeds
// each), once in one process, once as shard 0/2 in two child processes (-j 2) beside
// shard 1/2: merged, the shards are the unsharded run, record for record and figure for
// figure but the times; the unsharded run's own records merged are its report exactly.
TEST_F(BenchSweep, ShardsAndChildProcessesMergeIntoTheUnshardedRun) {
  const std::string bench = "bench retrieval -q --sizes 12 --scenes 1 --runs 2 --planner retrieval_graph --time-limit 600 ";
  const auto whole = run_cli(bench + "--records " + at("all.jsonl") + " --json " + at("all.json") + " --csv " + at("all.csv"));
  ASSERT_EQ(whole.exit_code, 0) << whole.output;
  const auto first = run_cli(bench + "--shard 0/2 -j 2 --records " + at("s0.jsonl"));
  ASSERT_EQ(first.exit_code, 0) << first.output;
  const auto second = run_cli(bench + "--shard 1/2 --records " + at("s1.jsonl"));
  ASSERT_EQ(second.exit_code, 0) << second.output;
  EXPECT_FALSE(fs::exists(at("s1.jsonl.partial")));

  const auto all = records(at("all.jsonl")), s0 = records(at("s0.jsonl")), s1 = records(at("s1.jsonl"));
  ASSERT_EQ(all.size(), 7u);  // the header and six runs
  EXPECT_EQ(all[0]["bench"], "retrieval");
  EXPECT_EQ(all[0]["runs"], 6);
  EXPECT_EQ(all[0]["shard"], "0/1");
  EXPECT_EQ(s0[0]["shard"], "0/2");
  EXPECT_EQ(s0[0]["settings"], all[0]["settings"]);
  ASSERT_EQ(s0.size(), 4u);
  ASSERT_EQ(s1.size(), 4u);
  for (std::size_t k = 1; k < s0.size(); ++k) {
    EXPECT_EQ(s0[k]["index"], 2 * (k - 1));  // run i belongs to shard i % 2
    EXPECT_EQ(without_times(s0[k]), without_times(all[s0[k]["index"].get<std::size_t>() + 1])) << s0[k].dump();
    EXPECT_EQ(without_times(s1[k]), without_times(all[s1[k]["index"].get<std::size_t>() + 1])) << s1[k].dump();
  }
  for (std::size_t k = 1; k < all.size(); ++k) {
    for (const char* field : {"problem", "scene_seed", "planner", "parameters", "seed", "solved", "time_s", "removed", "counters", "reason", "version"}) {
      EXPECT_TRUE(all[k].contains(field)) << field << " in " << all[k].dump();
    }
  }

  const auto merged = run_cli("bench merge -q " + at("s1.jsonl") + " " + at("s0.jsonl") + " --json " + at("merged.json") + " --records " +
                              at("merged.jsonl"));
  ASSERT_EQ(merged.exit_code, 0) << merged.output;
  EXPECT_EQ(without_times(nlohmann::json::parse(test::read_text(at("merged.json")))),
            without_times(nlohmann::json::parse(test::read_text(at("all.json")))));
  const auto merged_records = records(at("merged.jsonl"));
  ASSERT_EQ(merged_records.size(), all.size());
  for (std::size_t k = 1; k < all.size(); ++k) EXPECT_EQ(without_times(merged_records[k]), without_times(all[k]));

  const auto again = run_cli("bench merge -q " + at("all.jsonl") + " --json " + at("again.json") + " --csv " + at("again.csv"));
  ASSERT_EQ(again.exit_code, 0) << again.output;
  EXPECT_EQ(test::read_text(at("again.json")), test::read_text(at("all.json")));
  EXPECT_EQ(test::read_text(at("again.csv")), test::read_text(at("all.csv")));
  const std::size_t table = whole.output.find("Table I");
  ASSERT_NE(table, std::string::npos) << whole.output;
  EXPECT_EQ(again.output.substr(again.output.find("Table I")), whole.output.substr(table));

  // Shards that overlap, another sweep's file and a file that is no records file are
  // bad input, located.
  const auto twice = run_cli("bench merge -q " + at("s0.jsonl") + " " + at("merged.jsonl"));
  EXPECT_EQ(twice.exit_code, 2) << twice.output;
  EXPECT_NE(twice.output.find("merged.jsonl:2:1: error: run 0 is also in"), std::string::npos) << twice.output;
  auto other = records(at("s1.jsonl"));
  other[0]["settings"]["runs"] = 3;
  std::ofstream(at("other.jsonl")) << other[0].dump() << "\n";
  const auto mixed = run_cli("bench merge -q " + at("s0.jsonl") + " " + at("other.jsonl"));
  EXPECT_EQ(mixed.exit_code, 2) << mixed.output;
  EXPECT_NE(mixed.output.find("other.jsonl:1:1: error: another sweep"), std::string::npos) << mixed.output;
  std::ofstream(at("garbage.jsonl")) << all[0].dump() << "\n{\"index\": 99}\n";
  const auto garbage = run_cli("bench merge -q " + at("garbage.jsonl"));
  EXPECT_EQ(garbage.exit_code, 2) << garbage.output;
  EXPECT_NE(garbage.output.find("garbage.jsonl:2:1: error: a run without a valid \"index\" (0 to 5)"), std::string::npos) << garbage.output;
  // A merge of part of the shards reports the runs it has and says so.
  const auto part = run_cli("bench merge " + at("s0.jsonl") + " --json " + at("part.json"));
  EXPECT_EQ(part.exit_code, 0) << part.output;
  EXPECT_NE(part.output.find("3 of 6 runs are in these files"), std::string::npos) << part.output;
}

// The runs in OMPL's benchmark log format load into ompl_benchmark_statistics' SQLite
// database: a planner per row, a database row per run, our counters as run properties.
TEST_F(BenchSweep, TheOmplLogLoadsIntoOmplBenchmarkStatistics) {
  const auto r = run_cli("bench retrieval -q --sizes 12 --scenes 1 --runs 2 --planner retrieval_graph --time-limit 600 --ompl-log " +
                         at("runs.log") + " --records " + at("runs.jsonl"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto load = test::run_command("cd " + dir_.string() + " && ompl_benchmark_statistics runs.log -d runs.db 2>&1");
  ASSERT_EQ(load.exit_code, 0) << load.output;
  const auto query = test::run_command(
      "/usr/bin/python3 -c \"import sqlite3; c = sqlite3.connect('" + at("runs.db") +
      "'); print(c.execute('SELECT p.name, COUNT(*), SUM(r.solved), SUM(r.removed), SUM(r.collision_checks), SUM(r.seed) FROM runs r "
      "JOIN plannerConfigs p ON r.plannerid = p.id GROUP BY p.name ORDER BY p.name').fetchall()); "
      "print(c.execute('SELECT name, timelimit, runcount FROM experiments').fetchall())\" 2>&1");
  ASSERT_EQ(query.exit_code, 0) << query.output;
  std::map<std::string, std::vector<long>> expected;  // planner -> runs, solved, removed, checks, seeds
  const auto all = records(at("runs.jsonl"));
  for (std::size_t k = 1; k < all.size(); ++k) {
    const auto& run = all[k];
    auto& sums = expected["shelf12/retrieval_graph[initial_L=" + run["parameters"]["initial_L"].get<std::string>() + "]"];
    sums.resize(5);
    sums[0] += 1;
    sums[1] += run["solved"].get<bool>();
    sums[2] += run["removed"].get<long>();
    sums[3] += run["counters"]["collision_checks"].get<long>();
    sums[4] += run["seed"].get<long>();
  }
  std::string rows = "[";
  for (const auto& [name, sums] : expected) {
    rows += std::string(rows.size() > 1 ? ", " : "") + "('" + name + "'";
    for (long v : sums) rows += ", " + std::to_string(v);
    rows += ")";
  }
  rows += "]\n[('cluttertamp_bench_retrieval', 600.0, 2)]\n";
  EXPECT_EQ(query.output, rows);
}

// bench push the same way: three shards, one of them in two child processes, merged,
// are the unsharded run but for the times. An easy scene every planner solves, so
// that the time limit is only an outer limit.
TEST_F(BenchSweep, PushShardsMergeIntoTheUnshardedRun) {
  fs::create_directories(dir_ / "scenes");
  std::string problem = test::read_text(fs::path(CLUTTERTAMP_SOURCE_DIR) / "problems/push/easy.yaml");
  problem = test::replaced(problem, "../../domains/", std::string(CLUTTERTAMP_SOURCE_DIR) + "/domains/");
  problem = test::replaced(problem, "scene: easy-scene.yaml", "scene: " + std::string(CLUTTERTAMP_SOURCE_DIR) + "/problems/push/easy-scene.yaml");
  std::ofstream(dir_ / "scenes/p01.yaml") << problem;
  const std::string bench = "bench push -q --runs 2 --time-limit 600 --push-scenes " + at("scenes") + " ";
  const auto whole = run_cli(bench + "--records " + at("all.jsonl") + " --json " + at("all.json") + " --ompl-log " + at("all.log"));
  ASSERT_EQ(whole.exit_code, 0) << whole.output;
  for (const char* shard : {"0/3 -j 2", "1/3", "2/3"}) {
    const auto r = run_cli(bench + "--shard " + shard + " --records " + at(std::string("s") + shard[0] + ".jsonl"));
    ASSERT_EQ(r.exit_code, 0) << shard << ": " << r.output;
  }
  const auto merged = run_cli("bench merge -q " + at("s2.jsonl") + " " + at("s0.jsonl") + " " + at("s1.jsonl") + " --json " + at("merged.json"));
  ASSERT_EQ(merged.exit_code, 0) << merged.output;
  const auto all = nlohmann::json::parse(test::read_text(at("all.json")));
  EXPECT_EQ(all["planners"].size(), 3u);
  EXPECT_EQ(all["planners"][0]["runs"], 2);
  EXPECT_EQ(without_times(nlohmann::json::parse(test::read_text(at("merged.json")))), without_times(all));
  EXPECT_NE(test::read_text(at("all.log")).find("\n3 planners\nrrt\n"), std::string::npos);
}

// bench occlusion the same way: two shards, one of them in two child processes, merged,
// are the unsharded run but for the times, in its JSON, CSV and OMPL log.
TEST_F(BenchSweep, OcclusionShardsMergeIntoTheUnshardedRun) {
  const std::string bench = "bench occlusion -q --sizes 8 --sizes 12 --scenes 1 --runs 2 --occlusion-layout columns --time-limit 600 ";
  const auto whole = run_cli(bench + "--records " + at("all.jsonl") + " --json " + at("all.json") + " --csv " + at("all.csv"));
  ASSERT_EQ(whole.exit_code, 0) << whole.output;
  const auto first = run_cli(bench + "--shard 0/2 -j 2 --records " + at("s0.jsonl"));
  ASSERT_EQ(first.exit_code, 0) << first.output;
  const auto second = run_cli(bench + "--shard 1/2 --records " + at("s1.jsonl"));
  ASSERT_EQ(second.exit_code, 0) << second.output;
  const auto all = records(at("all.jsonl"));
  ASSERT_EQ(all.size(), 5u);  // the header and 2 sizes x 1 shelf x 2 seeds
  EXPECT_EQ(all[0]["bench"], "occlusion");
  EXPECT_EQ(all[1]["objects"], 8);
  EXPECT_EQ(all[3]["objects"], 12);
  EXPECT_EQ(all[2]["seed"], 1);
  const auto merged = run_cli("bench merge -q " + at("s1.jsonl") + " " + at("s0.jsonl") + " --json " + at("merged.json") + " --csv " +
                              at("merged.csv") + " --ompl-log " + at("merged.log"));
  ASSERT_EQ(merged.exit_code, 0) << merged.output;
  const auto table = nlohmann::json::parse(test::read_text(at("all.json")));
  ASSERT_EQ(table["sizes"].size(), 2u);
  EXPECT_EQ(table["sizes"][1]["runs"], 2);
  EXPECT_EQ(without_times(nlohmann::json::parse(test::read_text(at("merged.json")))), without_times(table));
  EXPECT_EQ(test::read_text(at("merged.csv")).substr(0, 40), test::read_text(at("all.csv")).substr(0, 40));
  EXPECT_NE(test::read_text(at("merged.log")).find("\n2 planners\ncolumns8/occlusion\n"), std::string::npos);
  // A size a layout cannot hold is refused before any run, in a shard too.
  const auto odd = run_cli("bench occlusion -q --sizes 10 --occlusion-layout columns --shard 1/2");
  EXPECT_EQ(odd.exit_code, 2) << odd.output;
  EXPECT_NE(odd.output.find("not a multiple of 4"), std::string::npos) << odd.output;
}

// bench mobile the same way. The tables are chosen before the runs, and the records'
// settings carry the chosen seeds (a child of -j plans on them without choosing again).
TEST_F(BenchSweep, MobileShardsMergeIntoTheUnshardedRun) {
  const std::string bench = "bench mobile -q --seed 0 --scenes 2 --runs 1 --time-limit 3000 --mobile-tables random ";
  const auto whole = run_cli(bench + "--records " + at("all.jsonl") + " --json " + at("all.json"));
  ASSERT_EQ(whole.exit_code, 0) << whole.output;
  const auto first = run_cli(bench + "--shard 0/2 -j 2 --records " + at("s0.jsonl"));
  ASSERT_EQ(first.exit_code, 0) << first.output;
  const auto second = run_cli(bench + "--shard 1/2 --records " + at("s1.jsonl"));
  ASSERT_EQ(second.exit_code, 0) << second.output;
  const auto all = records(at("all.jsonl"));
  ASSERT_EQ(all.size(), 7u);  // the header and 3 limits x 2 tables x 1 seed
  EXPECT_EQ(all[0]["settings"]["mobile_table_seeds"], nlohmann::json::parse("[0, 1]"));
  EXPECT_EQ(all[1]["parameters"]["initial_L"], "one");
  EXPECT_EQ(all[2]["scene_seed"], 1);
  EXPECT_EQ(all[6]["parameters"]["initial_L"], "objects");
  const auto merged = run_cli("bench merge -q " + at("s1.jsonl") + " " + at("s0.jsonl") + " --json " + at("merged.json"));
  ASSERT_EQ(merged.exit_code, 0) << merged.output;
  const auto table = nlohmann::json::parse(test::read_text(at("all.json")));
  EXPECT_EQ(table["table_seeds"], nlohmann::json::parse("[0, 1]"));
  EXPECT_EQ(table["strategies"][0]["runs"], 2);
  EXPECT_EQ(without_times(nlohmann::json::parse(test::read_text(at("merged.json")))), without_times(table));
}

// A sweep file's runs the same way: shards merged are the unsharded run; every planner
// of the grid is checked before any run, so a misspelt one is bad input at once.
TEST_F(BenchSweep, ASweepFileRunsAsASweep) {
  const std::string problem = std::string(CLUTTERTAMP_SOURCE_DIR) + "/problems/default.yaml";
  std::ofstream(dir_ / "sweep.yaml") << "version: 1\n"
                                     << "problems: [" << problem << "]\n"
                                     << "planners:\n"
                                     << "  - plugin: retrieval_graph\n"
                                     << "    grid: {initial_L: [one, objects]}\n"
                                     << "  - {plugin: exhaustive, parameters: {max_removals: 3}}\n"
                                     << "seeds: 2\n"
                                     << "time_limit: 600\n";
  const std::string bench = "bench sweep -q " + at("sweep.yaml") + " ";
  const auto whole = run_cli(bench + "--records " + at("all.jsonl") + " --json " + at("all.json") + " --csv " + at("all.csv"));
  ASSERT_EQ(whole.exit_code, 0) << whole.output;
  EXPECT_NE(whole.output.find("retrieval_graph[initial_L=objects]"), std::string::npos) << whole.output;
  const auto first = run_cli(bench + "--shard 0/2 -j 2 --records " + at("s0.jsonl"));
  ASSERT_EQ(first.exit_code, 0) << first.output;
  const auto second = run_cli(bench + "--shard 1/2 --records " + at("s1.jsonl"));
  ASSERT_EQ(second.exit_code, 0) << second.output;
  const auto all = records(at("all.jsonl"));
  ASSERT_EQ(all.size(), 7u);  // the header and 3 planners x 2 seeds
  EXPECT_EQ(all[0]["settings"]["sweep"]["planners"].size(), 3u);
  EXPECT_EQ(all[3]["planner"], "retrieval_graph[initial_L=objects]");
  EXPECT_EQ(all[3]["parameters"], "{initial_L: objects}");
  EXPECT_EQ(all[6]["planner"], "exhaustive");
  EXPECT_EQ(all[6]["seed"], 1);
  for (std::size_t k = 1; k < all.size(); ++k) {
    EXPECT_TRUE(all[k]["solved"].get<bool>()) << all[k].dump();
    EXPECT_EQ(all[k]["exit_code"], 0);
  }
  const auto merged = run_cli("bench merge -q " + at("s1.jsonl") + " " + at("s0.jsonl") + " --json " + at("merged.json"));
  ASSERT_EQ(merged.exit_code, 0) << merged.output;
  const auto table = nlohmann::json::parse(test::read_text(at("all.json")));
  ASSERT_EQ(table["rows"].size(), 3u);
  EXPECT_EQ(table["rows"][2]["runs"], 2);
  EXPECT_EQ(without_times(nlohmann::json::parse(test::read_text(at("merged.json")))), without_times(table));

  std::ofstream(dir_ / "misspelt.yaml") << "version: 1\nproblems: [" << problem << "]\nplanners: [{plugin: retrieval_grap}]\n";
  const auto misspelt = run_cli("bench sweep -q " + at("misspelt.yaml") + " --records " + at("m.jsonl"));
  EXPECT_EQ(misspelt.exit_code, 2) << misspelt.output;
  EXPECT_NE(misspelt.output.find("misspelt.yaml:3:"), std::string::npos) << misspelt.output;
  EXPECT_NE(misspelt.output.find("did you mean 'retrieval_graph'"), std::string::npos) << misspelt.output;
  EXPECT_FALSE(fs::exists(at("m.jsonl")));
}

// compare the same way: two shards merged are the unsharded run, in its JSON and CSV
// but the times; its OMPL log has a planner per row.
TEST_F(BenchSweep, CompareShardsMergeIntoTheUnshardedRun) {
  const std::string compare = "compare -q " + std::string(CLUTTERTAMP_SOURCE_DIR) + "/problems/stacked/stacked4.yaml --runs 2 --time-limit 600 ";
  const auto whole = run_cli(compare + "--records " + at("all.jsonl") + " --json " + at("all.json") + " --csv " + at("all.csv") +
                             " --ompl-log " + at("all.log"));
  ASSERT_EQ(whole.exit_code, 0) << whole.output;
  EXPECT_NE(whole.output.find("incremental, all movable"), std::string::npos) << whole.output;
  const auto first = run_cli(compare + "--shard 0/2 -j 2 --records " + at("s0.jsonl"));
  ASSERT_EQ(first.exit_code, 0) << first.output;
  const auto second = run_cli(compare + "--shard 1/2 --records " + at("s1.jsonl"));
  ASSERT_EQ(second.exit_code, 0) << second.output;
  const auto all = records(at("all.jsonl"));
  ASSERT_EQ(all.size(), 9u);  // the header and 4 settings x 2 seeds
  EXPECT_EQ(all[0]["bench"], "compare");
  EXPECT_EQ(all[1]["parameters"]["algorithm"], "adaptive");
  EXPECT_EQ(all[2]["seed"], 1);
  EXPECT_EQ(all[8]["parameters"]["prune"], false);
  const auto merged = run_cli("bench merge -q " + at("s1.jsonl") + " " + at("s0.jsonl") + " --json " + at("merged.json") + " --csv " +
                              at("merged.csv") + " --svg " + at("merged.svg"));
  ASSERT_EQ(merged.exit_code, 0) << merged.output;
  // Its plot: a column per setting with the paper's mean time (Table IV) as a diamond.
  const std::string svg = test::read_text(at("merged.svg"));
  EXPECT_EQ(svg.rfind("<svg", 0), 0u);
  for (const char* label : {"Table IV", "adaptive + pruning", "incremental, all movable", "planning time of solved runs", "stacked4"}) {
    EXPECT_NE(svg.find(label), std::string::npos) << label;
  }
  std::size_t diamonds = 0;
  for (std::size_t p = svg.find("<polygon"); p != std::string::npos; p = svg.find("<polygon", p + 1)) ++diamonds;
  EXPECT_EQ(diamonds, 1u + 4u);  // the legend's and one per setting
  const auto table = nlohmann::json::parse(test::read_text(at("all.json")));
  ASSERT_EQ(table.size(), 4u);
  EXPECT_EQ(table[3]["runs"], 2);
  EXPECT_EQ(without_times(nlohmann::json::parse(test::read_text(at("merged.json")))), without_times(table));
  // The CSV's rows are the same runs in the same order (the time column aside).
  auto cells = [](const std::string& csv) {
    std::vector<std::string> rows;
    std::istringstream in(csv);
    for (std::string line; std::getline(in, line);) {
      const std::size_t time = line.find(',', line.find(',', line.find(',', line.find(',', line.find(',', line.find(',') + 1) + 1) + 1) + 1) + 1);
      rows.push_back(line.substr(0, time) + line.substr(line.find(',', time + 1)));
    }
    return rows;
  };
  EXPECT_EQ(cells(test::read_text(at("merged.csv"))), cells(test::read_text(at("all.csv"))));
  EXPECT_NE(test::read_text(at("all.log")).find("\n4 planners\nstacked4/stream_planner[algorithm=adaptive,prune=true]\n"), std::string::npos);
}

// bench pddl the same way: three shards of the test tree merged are the unsharded run;
// a refused file is refused by the merged report too (exit code 2, after the rest).
TEST_F(BenchSweep, PddlShardsMergeIntoTheUnshardedRun) {
  fs::create_directories(dir_ / "tree");
  fs::copy(test::data("pddl/gripper"), dir_ / "tree/gripper");
  fs::copy(test::data("pddl/blocks"), dir_ / "tree/blocks");
  std::ofstream(dir_ / "tree/blocks/p0-broken.pddl") << "(define (problem broken) (:domain blocks)";
  const std::string bench = "bench pddl -q --instances " + at("tree") + " --per-domain 2 --runs 1 --parse-objects 0 "
                            "--search lama-first --search astar-lmcut ";
  const auto whole = run_cli(bench + "--records " + at("all.jsonl") + " --json " + at("all.json"));
  ASSERT_EQ(whole.exit_code, 2) << whole.output;
  EXPECT_NE(whole.output.find("p0-broken.pddl:1:"), std::string::npos) << whole.output;
  for (const char* shard : {"0/3 -j 2", "1/3", "2/3"}) {
    const auto r = run_cli(bench + "--shard " + shard + " --records " + at(std::string("s") + shard[0] + ".jsonl"));
    EXPECT_TRUE(r.exit_code == 0 || r.exit_code == 2) << shard << ": " << r.output;
  }
  const auto all = records(at("all.jsonl"));
  ASSERT_EQ(all.size(), 9u);  // the header and 4 instances x 2 searches
  EXPECT_EQ(all[1]["problem"], "blocks/p0-broken");
  EXPECT_NE(all[1]["reason"].get<std::string>().find("input refused"), std::string::npos);
  EXPECT_EQ(all[4]["planner"], "astar-lmcut");
  for (std::size_t k = 3; k < all.size(); ++k) EXPECT_TRUE(all[k]["valid"].get<bool>()) << all[k].dump();
  const auto merged = run_cli("bench merge -q " + at("s2.jsonl") + " " + at("s0.jsonl") + " " + at("s1.jsonl") + " --json " +
                              at("merged.json") + " --svg " + at("merged.svg"));
  EXPECT_EQ(merged.exit_code, 2) << merged.output;
  EXPECT_NE(merged.output.find("p0-broken.pddl:1:"), std::string::npos) << merged.output;
  EXPECT_EQ(without_times(nlohmann::json::parse(test::read_text(at("merged.json")))),
            without_times(nlohmann::json::parse(test::read_text(at("all.json")))));
  EXPECT_EQ(test::read_text(at("merged.svg")).rfind("<svg", 0), 0u);
}

// The timing benches as sweeps: a run is one timed batch (collision: 50 configurations
// of each query, samplers: one shelf, physics: 10 pushes). Shards (one of them in child
// processes) merged give the unsharded run's counts; only the times may differ.
TEST_F(BenchSweep, TimingBenchesShardAndMerge) {
  const std::map<std::string, std::pair<std::string, std::size_t>> benches{
      {"collision", {"--samples 1000", 20}}, {"samplers", {"--samples 2000", 2}}, {"physics", {"", 5}}};
  for (const auto& [name, setup] : benches) {
    SCOPED_TRACE(name);
    const std::string bench = "bench " + name + " -q " + setup.first + " ";
    const auto whole = run_cli(bench + "--records " + at(name + ".jsonl") + " --json " + at(name + ".json") + " --svg " + at(name + ".svg"));
    ASSERT_EQ(whole.exit_code, 0) << whole.output;
    const auto first = run_cli(bench + "--shard 0/2 -j 2 --records " + at(name + "0.jsonl"));
    ASSERT_EQ(first.exit_code, 0) << first.output;
    const auto second = run_cli(bench + "--shard 1/2 --records " + at(name + "1.jsonl"));
    ASSERT_EQ(second.exit_code, 0) << second.output;
    const auto all = records(at(name + ".jsonl"));
    ASSERT_EQ(all.size(), setup.second + 1);
    EXPECT_EQ(all[0]["bench"], name);
    EXPECT_EQ(all[1]["planner"], name);
    EXPECT_FALSE(all[1]["host"].get<std::string>().empty());
    const auto merged = run_cli("bench merge -q " + at(name + "1.jsonl") + " " + at(name + "0.jsonl") + " --json " + at(name + "m.json") +
                                " --svg " + at(name + "m.svg"));
    ASSERT_EQ(merged.exit_code, 0) << merged.output;
    const auto table = nlohmann::json::parse(test::read_text(at(name + ".json")));
    EXPECT_EQ(without_times(nlohmann::json::parse(test::read_text(at(name + "m.json")))), without_times(table));
    EXPECT_EQ(test::read_text(at(name + ".svg")).rfind("<svg", 0), 0u);
    EXPECT_NE(test::read_text(at(name + "m.svg")).find("goal"), std::string::npos);
  }
  // The counts a batch of each bench reports: the same for the same seed however run.
  const auto collision = nlohmann::json::parse(test::read_text(at("collision.json")));
  EXPECT_EQ(collision["results"][0]["calls"], 1000);
  EXPECT_EQ(collision["ik_reachable"]["poses"], 1000);
  const auto physics = nlohmann::json::parse(test::read_text(at("physics.json")));
  EXPECT_EQ(physics["pushes"], 50);
  EXPECT_EQ(physics["pusher"], "gripper");
  // With the arm on its base, in a pushing shelf: its pushes touch objects too.
  ASSERT_EQ(run_cli("bench physics -q --pusher arm --json " + at("arm.json")).exit_code, 0);
  const auto arm = nlohmann::json::parse(test::read_text(at("arm.json")));
  EXPECT_EQ(arm["pusher"], "arm");
  EXPECT_EQ(arm["pushes"], 50);
  EXPECT_GT(arm["touching"].get<int>(), 0);
  EXPECT_EQ(arm["goal"], 10.0);
  EXPECT_EQ(run_cli("bench physics --pusher hand").exit_code, 2);
  // Records timed elsewhere merge too, and the report says whose speeds it mixes.
  std::string shard = test::read_text(at("physics1.jsonl"));
  for (std::size_t host = shard.find("\"host\":\""); host != std::string::npos; host = shard.find("\"host\":\"", host + 1)) {
    const std::size_t value = host + 8, end = shard.find('"', value);
    shard.replace(value, end - value, "elsewhere");
  }
  std::ofstream(at("physics1e.jsonl")) << shard;
  const auto mixed = run_cli("bench merge " + at("physics0.jsonl") + " " + at("physics1e.jsonl"));
  EXPECT_EQ(mixed.exit_code, 0) << mixed.output;
  EXPECT_NE(mixed.output.find("Timed on 2 machines ("), std::string::npos) << mixed.output;
  EXPECT_NE(mixed.output.find("elsewhere"), std::string::npos) << mixed.output;
  const auto samplers = nlohmann::json::parse(test::read_text(at("samplers.json")));
  ASSERT_EQ(samplers.size(), 4u);
  EXPECT_EQ(samplers[0]["calls"].get<int>() + samplers[1]["calls"].get<int>(), 2 * 20);  // every object of the 2 shelves
}

TEST_F(BenchSweep, AShardIsKOfN) {
  for (const char* shard : {"2/2", "1/0", "-1/2", "a/b", "1", "1/2/3"}) {
    const auto r = run_cli("bench retrieval --shard " + std::string(shard));
    EXPECT_EQ(r.exit_code, 2) << shard << ": " << r.output;
    EXPECT_NE(r.output.find("--shard"), std::string::npos) << r.output;
  }
  EXPECT_EQ(run_cli("bench retrieval -j 0").exit_code, 2);
}

// Each bench takes only its own options, with the defaults it uses in its --help.
TEST_F(BenchSweep, EachBenchTakesOnlyItsOwnOptions) {
  const auto stray = run_cli("bench collision --ompl-log " + at("x.log") + " --table V");
  EXPECT_EQ(stray.exit_code, 2) << stray.output;
  EXPECT_NE(stray.output.find("--ompl-log"), std::string::npos) << stray.output;
  EXPECT_FALSE(fs::exists(at("x.log")));
  EXPECT_EQ(run_cli("bench").exit_code, 2);
  EXPECT_EQ(run_cli("bench nonsense").exit_code, 2);
  EXPECT_EQ(run_cli("bench mobile --sizes 20 30").exit_code, 2);  // one table size
  const std::map<std::string, std::vector<std::string>> defaults{
      {"mobile", {"--scenes", "=20", "--robot", "pr2_mobile.yaml"}},
      {"occlusion", {"--scenes", "=20", "--sizes", "=[12,16,20]"}},
      {"retrieval", {"--scenes", "=5", "--runs", "=3", "--time-limit", "=60"}},
      {"physics", {"--objects", "=10"}},
      {"collision", {"--objects", "=20", "--samples", "=5000"}},
  };
  for (const auto& [bench, expected] : defaults) {
    const auto help = run_cli("bench " + bench + " --help");
    EXPECT_EQ(help.exit_code, 0) << help.output;
    for (std::size_t k = 0; k + 1 < expected.size(); k += 2) {
      const std::size_t option = help.output.find(expected[k]);
      ASSERT_NE(option, std::string::npos) << bench << ": " << help.output;
      const std::size_t end = help.output.find('\n', option);
      EXPECT_NE(help.output.substr(option, end - option).find(expected[k + 1]), std::string::npos)
          << bench << " " << expected[k] << ": " << help.output.substr(option, end - option);
    }
  }
  EXPECT_EQ(run_cli("bench physics --help").output.find("--table"), std::string::npos);
}

}  // namespace
}  // namespace cluttertamp
