#pragma once
// The benches' plots: panels on one SVG canvas, each with a y axis from 0 in round
// steps, labelled ticks and grid lines, and the marks the benches draw on them.

#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

namespace cluttertamp::bench {

/// Round tick steps for an axis from 0 to at least `max` (1, 2, 2.5 or 5 times a power
/// of ten, about `ticks` of them); `max` <= 0 gives steps of 1.
double tick_step(double max, int ticks = 4);

/// One SVG drawing. Coordinates are pixels from the canvas's top left; values are the
/// data's own (a panel maps them to pixels).
class SvgPlot {
 public:
  /// A plotting area with its y axis: pixel y of a value, and the axis's top value.
  struct Panel {
    double left = 0, top = 0, width = 0, height = 0;
    double y_max = 1;  ///< the axis's top value: a whole number of tick steps
    double y(double value) const { return top + height - value / y_max * height; }
    double bottom() const { return top + height; }
  };

  SvgPlot(double width, double height, int font_size = 11);

  /// A panel at the given pixels with a y axis from 0 to at least `y_max` in round
  /// steps: ticks labelled with `unit` appended ("%", "" for none) and grey grid lines;
  /// `title` above it.
  Panel panel(double left, double top, double width, double height, double y_max, const std::string& title,
              const std::string& unit = "");

  /// A bar from 0 to `value` at pixel x; `fill` a colour, or "hatch" for grey hatching
  /// outlined in `stroke`.
  void bar(const Panel& p, double x, double width, double value, const std::string& fill, const std::string& stroke = "");
  /// A vertical line from value `low` to `high` at pixel x (a confidence interval).
  void error_bar(const Panel& p, double x, double low, double high);
  /// A line through the points (pixel x, value y) with a dot on each.
  void line(const Panel& p, const std::vector<std::pair<double, double>>& points, const std::string& colour);
  /// `text` at pixels (x, y); `anchor` "start", "middle" or "end".
  void text(double x, double y, const std::string& text, const std::string& anchor = "start",
            const std::string& fill = "");
  /// `text` under the x axis at pixel x.
  void x_label(const Panel& p, double x, const std::string& text);
  /// A coloured square and its name, at pixels (x, y).
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
