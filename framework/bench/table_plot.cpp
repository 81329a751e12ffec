#include "bench/table_plot.hpp"

#include <algorithm>

#include "bench/svg_plot.hpp"

namespace cluttertamp::bench {
namespace {

constexpr double kLeft = 70, kPanelHeight = 150, kGap = 60;

// A column's width and a group's: one column is wide, several share a group.
double column_width(const PlotGroup& g) { return g.columns.size() <= 1 ? 45.0 : 26.0; }
double group_width(const PlotGroup& g) {
  return g.columns.size() <= 1 ? 90.0 : column_width(g) * double(g.columns.size()) + 34.0;
}

double panel_width(const TablePlot& t) {
  double w = 0;
  for (const PlotGroup& g : t.groups) w += group_width(g);
  return std::max(300.0, w);
}

bool any_of_columns(const TablePlot& t, bool (*has)(const PlotColumn&)) {
  for (const PlotGroup& g : t.groups) {
    for (const PlotColumn& c : g.columns) {
      if (has(c)) return true;
    }
  }
  return false;
}

double header_height(const TablePlot& t) { return t.series.empty() ? 68.0 : 86.0; }

// The title and the legends; returns the top of the panels.
double draw_header(SvgPlot& plot, const TablePlot& t, double top) {
  plot.text(kLeft, top + 20, t.title);
  double x = kLeft;
  if (any_of_columns(t, [](const PlotColumn& c) { return c.paper_success.has_value(); })) {
    plot.legend(x, top + 38, "hatch", "paper's success rate");
    x += 160;
  }
  if (any_of_columns(t, [](const PlotColumn& c) { return c.paper_removed || c.paper_seconds; })) {
    plot.legend(x, top + 38, "diamond", "paper's mean");
    x += 110;
  }
  plot.legend(x, top + 38, "cross", "unsolved runs (count)");
  x = kLeft;
  for (const auto& [colour, name] : t.series) {
    plot.legend(x, top + 56, colour, name);
    x += 30 + 6.5 * double(name.size());
  }
  return top + header_height(t);
}

void draw_table(SvgPlot& plot, const TablePlot& t, double top) {
  const double panel_w = panel_width(t);
  top = draw_header(plot, t, top);
  std::vector<double> removed{1.0}, times;
  for (const PlotGroup& g : t.groups) {
    for (const PlotColumn& c : g.columns) {
      removed.insert(removed.end(), c.removed.begin(), c.removed.end());
      times.insert(times.end(), c.seconds.begin(), c.seconds.end());
      if (c.paper_removed) removed.push_back(*c.paper_removed);
      if (c.paper_seconds) times.push_back(*c.paper_seconds);
    }
  }
  const SvgPlot::Panel rate = plot.panel(kLeft, top, panel_w, kPanelHeight, 100, "success rate", "%");
  const SvgPlot::Panel objects =
      plot.panel(2 * kLeft + panel_w, top, panel_w, kPanelHeight, 1.15 * *std::max_element(removed.begin(), removed.end()), t.removed_title);  // room above the top box
  const SvgPlot::Panel time = plot.panel_for(3 * kLeft + 2 * panel_w, top, panel_w, kPanelHeight, times, "planning time of solved runs, s");
  const bool halves = any_of_columns(t, [](const PlotColumn& c) { return c.paper_success.has_value(); });
  double start = 0;
  for (const PlotGroup& g : t.groups) {
    const double w = column_width(g), pad = (group_width(g) - w * double(g.columns.size())) / 2;
    for (std::size_t k = 0; k < g.columns.size(); ++k) {
      const PlotColumn& c = g.columns[k];
      const double offset = start + pad + w * (double(k) + 0.5), inner = g.columns.size() <= 1 ? w : w * 0.8;
      if (halves) {  // ours beside the paper's, in every group alike
        plot.bar(rate, rate.left + offset - inner / 2, inner / 2, c.success, c.colour);
        if (c.paper_success) plot.bar(rate, rate.left + offset, inner / 2, *c.paper_success, "hatch", c.colour);
      } else {
        plot.bar(rate, rate.left + offset - inner / 2, inner, c.success, c.colour);
      }
      plot.box(objects, objects.left + offset, inner, c.removed, c.colour);
      plot.box(time, time.left + offset, inner, c.seconds, c.colour);
      if (c.paper_removed) plot.diamond(objects, objects.left + offset, *c.paper_removed);
      if (c.paper_seconds) plot.diamond(time, time.left + offset, *c.paper_seconds);
      if (c.paper_seconds && !c.paper_seconds_note.empty()) {
        plot.text(time.left + offset, time.y(*c.paper_seconds) - 9, c.paper_seconds_note, "middle");
      }
      plot.unsolved(objects, objects.left + offset, c.unsolved);
      plot.unsolved(time, time.left + offset, c.unsolved);
    }
    for (const SvgPlot::Panel* p : {&rate, &objects, &time}) plot.x_label(*p, p->left + start + group_width(g) / 2, g.label);
    start += group_width(g);
  }
}

}  // namespace

void write_table_svg(const std::filesystem::path& file, const std::vector<TablePlot>& tables) {
  double width = 0, height = 0;
  for (const TablePlot& t : tables) {
    width = std::max({width, 3 * (panel_width(t) + kLeft) + 20, kLeft + 6.5 * double(t.title.size()) + 20});
    height += header_height(t) + kPanelHeight + kGap;
  }
  SvgPlot plot(width, height + 10);
  double top = 0;
  for (const TablePlot& t : tables) {
    draw_table(plot, t, top);
    top += header_height(t) + kPanelHeight + kGap;
  }
  plot.write(file);
}

}  // namespace cluttertamp::bench
