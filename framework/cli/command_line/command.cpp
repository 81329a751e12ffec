#include "cli/command_line/command.hpp"

#include <charconv>
#include <cmath>
#include <cstdint>
#include <functional>
#include <sstream>

#include "cluttertamp/core/diagnostics.hpp"
#include "cluttertamp/core/memory_limit.hpp"

namespace cluttertamp::cli {

void add_verbosity(CLI::App& app, Verbosity& verbosity, const std::string& verbose_help) {
  auto* quiet = app.add_flag_callback("-q,--quiet", [&] { verbosity = Verbosity::quiet; }, "Print only errors");
  app.add_flag_callback("-v,--verbose", [&] { verbosity = Verbosity::verbose; }, verbose_help)->excludes(quiet);
}

void add_memory_limit(CLI::App& app, CommonOptions& common) {
  app.add_option("--memory-limit", common.memory_limit_mib,
                 "Address space limit, MiB (default " + std::to_string(default_memory_limit_mib()) +
                     ": three quarters of this machine's memory); a search that reaches it ends with \"memory limit "
                     "reached\" (exit code 1, result.json written)")
      ->check(CLI::Range(std::size_t{64}, std::size_t{1} << 40));
}

void add_plugin_paths(CLI::App& app, std::vector<std::filesystem::path>& paths) {
  app.add_option("--plugin-path", paths, "Search this plugin directory first (repeatable)")
      ->expected(1)
      ->allow_extra_args(false)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
}

void add_package_paths(CLI::App& app, CommonOptions& common) {
  app.add_option("--package-path", common.package_paths,
                 "Look for a URDF's package://NAME/... meshes in DIR: DIR itself when named NAME, DIR/NAME or "
                 "DIR/*/NAME (repeatable; searched before the robot description's package_paths and ROS_PACKAGE_PATH)")
      ->expected(1)
      ->allow_extra_args(false)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
}

CLI::Validator seed_validator() {
  return CLI::Validator(
      [](const std::string& text) {
        std::int64_t value = 0;
        const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
        return error == std::errc() && end == text.data() + text.size() && value >= 0
                   ? std::string()
                   : "must be a whole number from 0 to 9223372036854775807";
      },
      "SEED", "non-negative integer");
}

CLI::Validator seconds_validator() {
  return CLI::Validator(
      [](const std::string& text) {
        double value = 0;
        return CLI::detail::lexical_cast(text, value) && std::isfinite(value) && value > 0
                   ? std::string()
                   : "must be a finite number of seconds greater than 0";
      },
      "SECONDS", "finite positive");
}

namespace {
// A validator of one parsed number: `ok` decides, `what` says what is allowed.
CLI::Validator number_validator(std::function<bool(double)> ok, std::string what, std::string name) {
  return CLI::Validator(
      [ok = std::move(ok), what](const std::string& text) {
        double value = 0;
        return CLI::detail::lexical_cast(text, value) && std::isfinite(value) && ok(value) ? std::string()
                                                                                          : "must be " + what;
      },
      name, name);
}

std::string number_text(double x) {
  std::ostringstream out;
  out << x;
  return out.str();
}
}  // namespace

CLI::Validator finite_positive() {
  return number_validator([](double x) { return x > 0; }, "a finite number greater than 0", "POSITIVE");
}

CLI::Validator finite_non_negative() {
  return number_validator([](double x) { return x >= 0; }, "a finite number of at least 0", "NONNEGATIVE");
}

CLI::Validator finite_range(double low, double high) {
  const std::string range = "[" + number_text(low) + " - " + number_text(high) + "]";
  return number_validator([low, high](double x) { return x >= low && x <= high; },
                          "a finite number in " + range, range);
}

CLI::Validator count_validator() {
  return CLI::Validator(
      [](const std::string& text) {
        std::uint64_t value = 0;
        const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
        return error == std::errc() && end == text.data() + text.size() && !text.empty()
                   ? std::string()
                   : "must be a whole number from 0 to 18446744073709551615";
      },
      "COUNT", "non-negative integer");
}

std::filesystem::path source_file(const std::string& relative) {
  return std::filesystem::path(CLUTTERTAMP_SOURCE_DIR) / relative;
}

CLI::Validator shard_validator() {
  return CLI::Validator(
      [](const std::string& text) {
        try {
          bench::parse_shard(text);
          return std::string();
        } catch (const InputError& e) {
          const std::string message = e.what();
          return message.substr(message.find("error: ") == std::string::npos ? 0 : message.find("error: ") + 7);
        }
      },
      "K/N");
}

void add_sweep_options(CLI::App& app, bench::SweepOptions& sweep, std::filesystem::path* ompl_log, const std::string& jobs_help) {
  app.add_option_function<std::string>(
         "--shard", [&sweep](const std::string& text) { sweep.shard = bench::parse_shard(text); },
         "Run only shard K of N (K from 0): the runs i with i % N == K; write them with --records and report the "
         "shards together with 'bench merge'")
      ->type_name("K/N")
      ->check(shard_validator());
  app.add_option("-j,--jobs", sweep.jobs, jobs_help.empty() ? "Runs at once, each in a child process of its own (results as with -j 1)" : jobs_help)
      ->capture_default_str()
      ->check(CLI::Range(1, 1024));
  app.add_option("--records", sweep.records,
                 "Also write every run as a JSON Lines record to this file (FILE.partial while running), for 'bench merge'");
  if (!ompl_log) return;
  app.add_option("--ompl-log", *ompl_log,
                 "Also write the runs in OMPL's benchmark log format, for ompl_benchmark_statistics and Planner Arena");
}

}  // namespace cluttertamp::cli
