#include "bench/ompl_log.hpp"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <ctime>
#include <iomanip>
#include <set>
#include <sstream>

#include "cluttertamp/io/text_file.hpp"
#include "cluttertamp/version.hpp"

namespace cluttertamp::bench {

namespace {

std::string host_name() {
  char name[256] = {};
  return gethostname(name, sizeof name - 1) == 0 ? std::string(name) : std::string("unknown");
}

std::string now_text() {
  const std::time_t t = std::time(nullptr);
  std::tm utc{};
  gmtime_r(&t, &utc);
  std::ostringstream out;
  out << std::put_time(&utc, "%Y-%m-%dT%H:%M:%S");
  return out.str();
}

// A value as the log holds it: numbers as they are, booleans 0/1, nothing for absent.
std::string value_text(const Record* value) {
  if (!value || value->is_null()) return "";
  if (value->is_boolean()) return value->get<bool>() ? "1" : "0";
  if (value->is_number_integer() || value->is_number_unsigned()) return value->dump();
  if (value->is_number_float()) {
    std::ostringstream out;
    out << std::setprecision(17) << value->get<double>();
    return out.str();
  }
  return "";
}

// The run properties every planner of ours has, with the record field each comes from.
struct Property {
  std::string name, type, field;
};
const Property kProperties[] = {{"time", "REAL", "time_s"},        {"solved", "BOOLEAN", "solved"},
                                {"seed", "INTEGER", "seed"},       {"removed", "INTEGER", "removed"},
                                {"task_time", "REAL", "task_s"},   {"motion_time", "REAL", "motion_s"}};

void write_planner(std::ostream& out, const OmplLogPlanner& planner) {
  out << planner.name << "\n0 common properties\n";
  std::set<std::string> counters;  // the union over the planner's runs
  for (const Record* r : planner.runs) {
    if (const auto c = r->find("counters"); c != r->end() && c->is_object()) {
      for (const auto& [name, value] : c->items()) counters.insert(name);
    }
  }
  out << std::size(kProperties) + counters.size() << " properties for each run\n";
  for (const Property& p : kProperties) out << p.name << " " << p.type << "\n";
  for (const std::string& c : counters) out << c << " INTEGER\n";
  out << planner.runs.size() << " runs\n";
  for (const Record* r : planner.runs) {
    for (const Property& p : kProperties) {
      const auto it = r->find(p.field);
      out << value_text(it == r->end() ? nullptr : &*it) << "; ";
    }
    const auto c = r->find("counters");
    for (const std::string& name : counters) {
      const Record* value = nullptr;
      if (c != r->end() && c->contains(name)) value = &(*c)[name];
      out << value_text(value) << "; ";
    }
    out << "\n";
  }
  out << ".\n";
}

}  // namespace

void write_ompl_log(const std::filesystem::path& file, const OmplLogExperiment& experiment, const std::vector<OmplLogPlanner>& planners) {
  double total = 0;
  std::size_t runs_per_planner = 0;
  for (const OmplLogPlanner& p : planners) {
    for (const Record* r : p.runs) total += number(*r, "time_s");
    runs_per_planner = std::max(runs_per_planner, p.runs.size());
  }
  std::ostringstream out;
  out << "cluttertamp version " << version() << "\n"
      << "Experiment " << experiment.name << "\n"
      << "0 experiment properties\n"
      << "Running on " << host_name() << "\n"
      << "Starting at " << now_text() << "\n"
      << "<<<|\n" << experiment.setup << (experiment.setup.empty() || experiment.setup.back() == '\n' ? "" : "\n") << "|>>>\n"
      << "<<<|\n|>>>\n"
      << experiment.seed << " is the random seed\n"
      << experiment.time_limit << " seconds per run\n"
      << "0 MB per run\n"
      << runs_per_planner << " runs per planner\n"
      << total << " seconds spent to collect the data\n"
      << "0 enum types\n"
      << planners.size() << " planners\n";
  for (const OmplLogPlanner& p : planners) write_planner(out, p);
  io::write_text_file(file, out.str(), "OMPL benchmark log");
}

}  // namespace cluttertamp::bench
