#include "bench/timing.hpp"

#include <unistd.h>

#include <algorithm>
#include <set>

#include "bench/svg_plot.hpp"

namespace cluttertamp::bench {

std::string host_name() {
  char name[256] = {};
  if (gethostname(name, sizeof name - 1) != 0 || name[0] == '\0') return "unknown";
  return name;
}

std::string hosts_note(const std::vector<Record>& records) {
  std::set<std::string> hosts;
  for (const Record& r : records) hosts.insert(r.value("host", std::string("unknown")));
  if (hosts.size() < 2) return "";
  std::string names;
  for (const std::string& h : hosts) names += (names.empty() ? "" : ", ") + h;
  return "Timed on " + std::to_string(hosts.size()) + " machines (" + names + "): the medians mix their speeds.";
}

void write_timing_svg(const std::filesystem::path& file, const std::string& title, const std::string& axis,
                      const std::vector<TimedQuery>& queries, bool goals_are_minimums) {
  const double left = 70, slot = 115, top = 80, height = 260;
  const double width = slot * double(std::max<std::size_t>(queries.size(), 2));
  std::vector<double> all;
  for (const TimedQuery& q : queries) {
    all.insert(all.end(), q.values.begin(), q.values.end());
    if (q.goal > 0) all.push_back(q.goal);
  }
  // Wide enough for the title and the legend line (about 6.5 pixels a character).
  SvgPlot plot(std::max({left + width + 30, left + 6.5 * double(title.size()), 640.0}), top + height + 50);
  plot.text(left, 20, title);
  plot.legend(left, 42, "goal", goals_are_minimums ? "goal (at least)" : "goal (at most)");
  plot.text(left + 130, 42, "boxes: quartiles, thick line: median, whiskers: least and greatest");
  const SvgPlot::Panel panel = plot.panel_for(left, top, width, height, all, axis);
  for (std::size_t k = 0; k < queries.size(); ++k) {
    const double x = panel.left + slot * (double(k) + 0.5);
    plot.box(panel, x, slot * 0.45, queries[k].values, series_colour(k));
    if (queries[k].goal > 0) plot.goal(panel, x, slot * 0.7, queries[k].goal);
    plot.x_label(panel, x, queries[k].label);
    if (queries[k].values.empty()) plot.text(x, panel.bottom() - 6, "not measured", "middle", "#d62728");
  }
  plot.write(file);
}

}  // namespace cluttertamp::bench
