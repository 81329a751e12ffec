#pragma once
// The benches' plots: panels on one SVG canvas, each with a y axis from 0 in round
// steps, labelled ticks and grid lines, and the marks the benches draw on them.

#include <cstddef>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

namespace cluttertamp::bench {

/// Round tick steps for an axis from 0 to at least `max` (1, 2, 2.5 or 5 times a power
/// of ten, about `ticks` of them); `max` <= 0 gives steps of 1.
double tick_step(double max, int ticks = 4);

/// The colour of series `k` in every bench plot (Dark2, repeating after 8).
const char* series_colour(std::size_t k);

/// One SVG drawing. Coordinates are pixels from the canvas's top left; values are the
/// data's own (a panel maps them to pixels).
class SvgPlot {
 public:
  /// A plotting area with its y axis: pixel y of a value, and the axis's range.
  struct Panel {
    double left = 0, top = 0, width = 0, height = 0;
    double y_max = 1;  ///< the axis's top value: a whole number of tick steps (a power of ten on a log axis)
    double y_min = 0;  ///< 0, or on a log axis the bottom power of ten
    bool log = false;  ///< a logarithmic axis (values <= y_min sit on the x axis)
    double y(double value) const;
    double bottom() const { return top + height; }
  };

  SvgPlot(double width, double height, int font_size = 11);

  /// A panel at the given pixels with a y axis from 0 to at least `y_max` in round
  /// steps: ticks labelled with `unit` appended ("%", "" for none) and grey grid lines;
  /// `title` above it.
  Panel panel(double left, double top, double width, double height, double y_max, const std::string& title,
              const std::string& unit = "");
  /// A panel with a logarithmic y axis spanning the decades from below `low` to above
  /// `high` (both > 0), a labelled tick and grid line per decade.
  Panel log_panel(double left, double top, double width, double height, double low, double high, const std::string& title,
                  const std::string& unit = "");
  /// A panel for `values`: logarithmic when they span more than a decade (and are all
  /// > 0), else linear from 0.
  Panel panel_for(double left, double top, double width, double height, const std::vector<double>& values, const std::string& title,
                  const std::string& unit = "");

  /// A bar from 0 to `value` at pixel x; `fill` a colour, or "hatch" for grey hatching
  /// outlined in `stroke`.
  void bar(const Panel& p, double x, double width, double value, const std::string& fill, const std::string& stroke = "");
  /// A vertical line from value `low` to `high` at pixel x (a confidence interval).
  void error_bar(const Panel& p, double x, double low, double high);
  /// A box plot of `values` centred at pixel x: the box from the first to the third
  /// quartile, a thick line at the median, whiskers to the least and greatest value.
  /// Nothing when `values` is empty.
  void box(const Panel& p, double x, double width, const std::vector<double>& values, const std::string& colour);
  /// A hollow diamond at (pixel x, value): a reference figure, such as a paper's mean.
  void diamond(const Panel& p, double x, double value, const std::string& colour = "black");
  /// A goal at `value`: a dashed red line `width` pixels wide centred at pixel x.
  void goal(const Panel& p, double x, double width, double value);
  /// `count` runs without a value (unsolved) at pixel x: a red cross over the axis's
  /// top and the count beside it; nothing when 0.
  void unsolved(const Panel& p, double x, int count);
  /// A line through the points (pixel x, value y) with a dot on each.
  void line(const Panel& p, const std::vector<std::pair<double, double>>& points, const std::string& colour);
  /// `text` at pixels (x, y); `anchor` "start", "middle" or "end".
  void text(double x, double y, const std::string& text, const std::string& anchor = "start",
            const std::string& fill = "");
  /// `text` under the x axis at pixel x.
  void x_label(const Panel& p, double x, const std::string& text);
  /// A coloured square and its name, at pixels (x, y); "hatch" for the hatched fill,
  /// "diamond" for the reference marker, "cross" for the unsolved marker, "goal" for the goal line.
  void legend(double x, double y, const std::string& colour, const std::string& name);

  /// Writes the drawing; throws InputError naming the file when it cannot be written.
  void write(const std::filesystem::path& file) const;

 private:
  double width_, height_;
  int font_size_;
  bool hatched_ = false;
  std::ostringstream body_;
};

}  // namespace cluttertamp::bench
