#include "bench/sweep.hpp"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <stdlib.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <map>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <thread>

#include "bench/settings.hpp"
#include "cluttertamp/core/diagnostics.hpp"
#include "cluttertamp/io/text_file.hpp"
#include "cluttertamp/version.hpp"

extern char** environ;

namespace cluttertamp::bench {

namespace fs = std::filesystem;

Shard parse_shard(const std::string& text, const std::string& option) {
  const std::size_t slash = text.find('/');
  auto whole = [](const std::string& digits, std::size_t& out) {
    if (digits.empty() || digits.size() > 9 || digits.find_first_not_of("0123456789") != std::string::npos) return false;
    out = std::stoul(digits);
    return true;
  };
  Shard shard;
  if (slash == std::string::npos || !whole(text.substr(0, slash), shard.index) || !whole(text.substr(slash + 1), shard.count) ||
      shard.count == 0 || shard.index >= shard.count) {
    throw InputError({option, 0, 0}, "'" + text + "' is no shard: expected K/N with 0 <= K < N (K counts from 0, as SLURM_ARRAY_TASK_ID does)");
  }
  return shard;
}

bool progress_shown(Verbosity verbosity) { return verbosity != Verbosity::quiet && isatty(STDERR_FILENO) == 1; }

double number(const Record& record, const char* key, double otherwise) {
  const auto it = record.find(key);
  return it == record.end() || !it->is_number() ? otherwise : it->get<double>();
}

namespace {

std::string shard_text(const Shard& s) { return std::to_string(s.index) + "/" + std::to_string(s.count); }

Record header_of(const SweepPlan& plan, const Shard& shard) {
  return {{"cluttertamp_records", 1}, {"bench", plan.bench}, {"version", std::string(version())}, {"shard", shard_text(shard)},
          {"runs", plan.runs}, {"settings", plan.settings}};
}

// A record with "index" first, then the run's own fields.
Record indexed(std::size_t index, const Record& fields) {
  Record out{{"index", index}};
  for (const auto& [key, value] : fields.items()) {
    if (key != "index") out[key] = value;
  }
  return out;
}

// A records file written as the runs end: FILE.partial, one flushed line per run,
// renamed to FILE when the shard is done. A run cut short leaves the runs done so far.
class RecordsStream {
 public:
  RecordsStream(fs::path file, const Record& header) : file_(std::move(file)) {
    if (file_.empty()) return;
    partial_ = file_;
    partial_ += ".partial";
    out_.open(partial_, std::ios::trunc);
    if (!out_) throw io::WriteError(partial_.string() + ": cannot write the records file");
    write(header);
  }
  void write(const Record& line) {
    if (file_.empty()) return;
    out_ << line.dump() << "\n" << std::flush;
    if (!out_) throw io::WriteError(partial_.string() + ": cannot write the records file (disk full?)");
  }
  void finish() {
    if (file_.empty()) return;
    out_.close();
    std::error_code ec;
    fs::rename(partial_, file_, ec);
    if (ec) throw io::WriteError(file_.string() + ": cannot rename the records file into place: " + ec.message());
  }

 private:
  fs::path file_, partial_;
  std::ofstream out_;
};

// Runs done, failed and the time left, on one line of a terminal; nothing elsewhere. The
// clock only estimates what is left: no run depends on it.
class Progress {
 public:
  Progress(std::size_t total, Verbosity verbosity)
      : total_(total), shown_(progress_shown(verbosity)), start_(std::chrono::steady_clock::now()) {}
  ~Progress() { clear(); }

  void show(std::size_t done, std::size_t failed, const std::string& doing) {
    if (!shown_) return;
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    const int bar = total_ ? static_cast<int>(24 * done / total_) : 24;
    std::ostringstream line;
    line << "\r[" << std::string(static_cast<std::size_t>(bar), '#') << std::string(static_cast<std::size_t>(24 - bar), '.') << "] "
         << done << "/" << total_ << " runs, " << failed << " failed";
    if (done > 0 && done < total_) {
      const double left = elapsed / double(done) * double(total_ - done);
      line << ", about " << (left < 90 ? std::to_string(static_cast<int>(std::ceil(left))) + " s" : std::to_string(static_cast<int>(std::ceil(left / 60))) + " min")
           << " left";
    }
    if (!doing.empty()) line << "; " << doing;
    std::string text = line.str();
    if (text.size() > 99) text.resize(99);
    std::cerr << text << std::string(width_ > text.size() ? width_ - text.size() : 0, ' ') << std::flush;
    width_ = text.size();
  }
  void clear() {
    if (!shown_ || width_ == 0) return;
    std::cerr << "\r" << std::string(width_, ' ') << "\r" << std::flush;
    width_ = 0;
  }

 private:
  std::size_t total_;
  bool shown_;
  std::chrono::steady_clock::time_point start_;
  std::size_t width_ = 0;
};

bool failed(const Record& r) {
  const auto it = r.find("solved");
  return it != r.end() && it->is_boolean() && !it->get<bool>();
}

std::size_t runs_in(const Shard& shard, std::size_t total) {
  return total > shard.index ? (total - shard.index + shard.count - 1) / shard.count : 0;
}

std::vector<Record> run_here(const SweepPlan& plan, const SweepOptions& options, Verbosity verbosity, const RunOne& run_one) {
  RecordsStream stream(options.records, header_of(plan, options.shard));
  Progress progress(runs_in(options.shard, plan.runs), verbosity);
  std::vector<Record> out;
  std::size_t failures = 0;
  for (std::size_t i = options.shard.index; i < plan.runs; i += options.shard.count) {
    progress.show(out.size(), failures, plan.label ? plan.label(i) : "");
    out.push_back(indexed(i, run_one(i)));
    failures += failed(out.back());
    stream.write(out.back());
  }
  progress.show(out.size(), failures, "");
  stream.finish();
  return out;
}

// A temporary directory, removed with everything in it.
class TemporaryDirectory {
 public:
  TemporaryDirectory() {
    std::string pattern = (fs::temp_directory_path() / "cluttertamp-sweep-XXXXXX").string();
    if (!mkdtemp(pattern.data())) throw std::runtime_error("cannot make a temporary directory in " + fs::temp_directory_path().string());
    path_ = pattern;
  }
  ~TemporaryDirectory() {
    std::error_code ignored;
    fs::remove_all(path_, ignored);
  }
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

struct Child {
  pid_t pid = -1;
  Shard shard;
  fs::path records, log;
  std::optional<int> exit_code;
};

Child spawn(const fs::path& executable, const fs::path& settings, const SweepOptions& options, const Shard& shard, const fs::path& dir) {
  Child child;
  child.shard = shard;
  child.records = dir / ("shard-" + std::to_string(shard.index) + ".jsonl");
  child.log = dir / ("shard-" + std::to_string(shard.index) + ".log");
  std::vector<std::string> args{executable.string(), "bench", "worker", settings.string(), "--shard", shard_text(shard), "--records",
                                child.records.string()};
  if (options.memory_limit_mib) {
    args.push_back("--memory-limit");
    args.push_back(std::to_string(options.memory_limit_mib));
  }
  for (const fs::path& p : options.package_paths) {
    args.push_back("--package-path");
    args.push_back(p.string());
  }
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, child.log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
  const int error = posix_spawn(&child.pid, executable.c_str(), &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (error != 0) throw std::runtime_error("cannot start " + executable.string() + ": " + std::strerror(error));
  return child;
}

// Runs and failures in a child's records file so far (its header not counted).
std::pair<std::size_t, std::size_t> count_records(const Child& child) {
  fs::path partial = child.records;
  partial += ".partial";
  std::ifstream in(fs::exists(child.records) ? child.records : partial);
  std::string line;
  std::size_t lines = 0, failures = 0;
  while (std::getline(in, line)) {
    ++lines;
    failures += line.find("\"solved\":false") != std::string::npos;
  }
  return {lines > 0 ? lines - 1 : 0, failures};
}

std::string tail_of(const fs::path& log) {
  std::ifstream in(log);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  std::string out;
  for (std::size_t i = lines.size() > 20 ? lines.size() - 20 : 0; i < lines.size(); ++i) out += "  " + lines[i] + "\n";
  return out;
}

std::vector<Record> run_in_children(const SweepPlan& plan, const SweepOptions& options, Verbosity verbosity) {
  const TemporaryDirectory dir;
  const fs::path settings = dir.path() / "settings.json";
  io::write_text_file(settings, Record{{"bench", plan.bench}, {"settings", plan.settings}}.dump(2) + "\n", "sweep settings");
  const fs::path executable = options.executable.empty() ? fs::read_symlink("/proc/self/exe") : options.executable;
  // Child j of J runs the runs of this shard K/N with i % (N J) == K + N j: together
  // exactly this shard's runs.
  std::vector<Child> children;
  const std::size_t jobs = static_cast<std::size_t>(std::max(1, options.jobs));
  for (std::size_t j = 0; j < jobs; ++j) {
    children.push_back(spawn(executable, settings, options, {options.shard.index + options.shard.count * j, options.shard.count * jobs},
                             dir.path()));
  }
  Progress progress(runs_in(options.shard, plan.runs), verbosity);
  for (bool running = true; running;) {
    running = false;
    std::size_t done = 0, failures = 0;
    for (Child& c : children) {
      if (!c.exit_code) {
        int status = 0;
        if (waitpid(c.pid, &status, WNOHANG) == c.pid) {
          c.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
        } else {
          running = true;
        }
      }
      const auto [d, f] = count_records(c);
      done += d;
      failures += f;
    }
    progress.show(done, failures, std::to_string(jobs) + " processes");
    const auto bad = std::find_if(children.begin(), children.end(), [](const Child& c) { return c.exit_code && *c.exit_code != 0; });
    if (bad != children.end()) {
      for (Child& c : children) {
        if (!c.exit_code) kill(c.pid, SIGTERM);
      }
      for (Child& c : children) {
        if (!c.exit_code) waitpid(c.pid, nullptr, 0);
      }
      progress.clear();
      throw WorkerFailed(*bad->exit_code, "shard " + shard_text(bad->shard) + " (a child process of -j " + std::to_string(jobs) +
                                               ") ended with exit code " + std::to_string(*bad->exit_code) + ":\n" + tail_of(bad->log));
    }
    if (running) std::this_thread::sleep_for(std::chrono::milliseconds(200));
  }
  progress.clear();
  std::vector<fs::path> files;
  for (const Child& c : children) files.push_back(c.records);
  Records records = read_records(files, Verbosity::quiet);
  if (!options.records.empty()) write_records(options.records, plan, options.shard, records.runs);
  return std::move(records.runs);
}

}  // namespace

WorkerFailed::WorkerFailed(int code, const std::string& message) : std::runtime_error(message), exit_code(code) {}
WorkerFailed::~WorkerFailed() = default;

std::vector<Record> run_sweep(const SweepPlan& plan, const SweepOptions& options, Verbosity verbosity, const RunOne& run_one) {
  if (options.jobs > 1 && runs_in(options.shard, plan.runs) > 1) return run_in_children(plan, options, verbosity);
  return run_here(plan, options, verbosity, run_one);
}

void write_records(const fs::path& file, const SweepPlan& plan, const Shard& shard, const std::vector<Record>& records) {
  std::string text = header_of(plan, shard).dump() + "\n";
  for (const Record& r : records) text += r.dump() + "\n";
  io::write_text_file(file, text, "records file");
}

Records read_records(const std::vector<fs::path>& files, Verbosity verbosity) {
  Records out;
  std::map<std::size_t, std::pair<std::string, Record>> by_index;  // index -> (where, record)
  std::string first;
  for (const fs::path& file : files) {
    std::istringstream in(io::read_text_file(file, "records file"));
    std::string line;
    std::size_t number = 0;
    Record header;
    while (std::getline(in, line)) {
      ++number;
      const SourceLocation at{file.string(), number, 1};
      if (line.empty()) continue;
      Record r = Record::parse(line, nullptr, false);
      if (r.is_discarded() || !r.is_object()) throw InputError(at, "not a JSON object: a records file holds one JSON record per line");
      if (header.is_null()) {
        if (!r.contains("cluttertamp_records") || !r.contains("bench") || !r.contains("settings") || !r.contains("runs") ||
            !r["runs"].is_number_unsigned()) {
          throw InputError(at, "no records header: the first line of a records file names its bench, settings and runs "
                               "(files written by --records)");
        }
        if (r["cluttertamp_records"] != 1) throw InputError(at, "records format " + r["cluttertamp_records"].dump() + " is not known here (1 is)");
        header = r;
        if (out.header.is_null()) {
          out.header = r;
          first = at.str();
        } else if (r["bench"] != out.header["bench"] || r["settings"] != out.header["settings"] || r["runs"] != out.header["runs"]) {
          throw InputError(at, "another sweep: bench " + r["bench"].dump() + " with other settings or run count than " + first +
                                   " (bench " + out.header["bench"].dump() + "); merge the shards of one sweep");
        }
        continue;
      }
      const auto index = r.find("index");
      if (index == r.end() || !index->is_number_unsigned() || index->get<std::size_t>() >= header["runs"].get<std::size_t>()) {
        throw InputError(at, "a run without a valid \"index\" (0 to " + std::to_string(header["runs"].get<std::size_t>() - 1) + ")");
      }
      const auto [it, fresh] = by_index.emplace(index->get<std::size_t>(), std::pair{at.str(), r});
      if (!fresh) {
        throw InputError(at, "run " + index->dump() + " is also in " + it->second.first + ": shards that overlap (the same --shard twice?)");
      }
    }
    if (header.is_null()) throw InputError({file.string(), 0, 0}, "empty: no records header");
  }
  if (out.header.is_null()) throw InputError({"bench merge", 0, 0}, "no records files");
  for (auto& [index, where_record] : by_index) out.runs.push_back(std::move(where_record.second));
  const std::size_t total = out.header["runs"].get<std::size_t>();
  if (out.runs.size() < total && verbosity != Verbosity::quiet) {
    std::cerr << "bench merge: " << out.runs.size() << " of " << total << " runs are in these files; the report covers those\n";
  }
  return out;
}

}  // namespace cluttertamp::bench
