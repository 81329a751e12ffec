#include "bench/svg_plot.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include "cluttertamp/io/text_file.hpp"

#include "cluttertamp/core/diagnostics.hpp"

namespace cluttertamp::bench {
namespace {

std::string number(double v) {
  std::ostringstream out;
  out << std::round(v * 100) / 100;
  return out.str();
}

std::string escaped(const std::string& text) {
  std::string out;
  for (char c : text) {
    if (c == '<') out += "&lt;";
    else if (c == '>') out += "&gt;";
    else if (c == '&') out += "&amp;";
    else out += c;
  }
  return out;
}

}  // namespace

const char* series_colour(std::size_t k) {
  static const char* colours[] = {"#1b9e77", "#d95f02", "#7570b3", "#e7298a", "#66a61e", "#e6ab02", "#a6761d", "#666666"};
  return colours[k % std::size(colours)];
}

double tick_step(double max, int ticks) {
  if (!(max > 0) || !std::isfinite(max)) return 1.0;
  const double raw = max / std::max(1, ticks);
  const double power = std::pow(10.0, std::floor(std::log10(raw)));
  for (double m : {1.0, 2.0, 2.5, 5.0, 10.0}) {
    if (m * power >= raw) return m * power;
  }
  return 10 * power;
}

double SvgPlot::Panel::y(double value) const {
  if (!log) return top + height - value / y_max * height;
  const double v = std::clamp(value, y_min, y_max);
  return top + height - (std::log10(v) - std::log10(y_min)) / (std::log10(y_max) - std::log10(y_min)) * height;
}

SvgPlot::SvgPlot(double width, double height, int font_size) : width_(width), height_(height), font_size_(font_size) {}

SvgPlot::Panel SvgPlot::panel(double left, double top, double width, double height, double y_max,
                              const std::string& title, const std::string& unit) {
  Panel p{left, top, width, height, 1.0};
  const double step = tick_step(y_max);
  p.y_max = std::max(step, std::ceil(y_max / step - 1e-9) * step);
  for (double v = 0; v <= p.y_max + step / 2; v += step) {
    const double y = p.y(v);
    if (v > 0) {
      body_ << "<line x1='" << number(left) << "' y1='" << number(y) << "' x2='" << number(left + width) << "' y2='"
            << number(y) << "' stroke='#dddddd'/>\n";
    }
    body_ << "<text x='" << number(left - 5) << "' y='" << number(y + 4) << "' text-anchor='end'>" << number(v) << unit
          << "</text>\n";
  }
  body_ << "<line x1='" << number(left) << "' y1='" << number(p.bottom()) << "' x2='" << number(left + width) << "' y2='"
        << number(p.bottom()) << "' stroke='black'/>\n"
        << "<line x1='" << number(left) << "' y1='" << number(top) << "' x2='" << number(left) << "' y2='"
        << number(p.bottom()) << "' stroke='black'/>\n";
  text(left, top - 10, title);
  return p;
}

SvgPlot::Panel SvgPlot::log_panel(double left, double top, double width, double height, double low, double high,
                                  const std::string& title, const std::string& unit) {
  Panel p{left, top, width, height, 1.0, 0.1, true};
  p.y_min = std::pow(10.0, std::floor(std::log10(low)));
  p.y_max = std::pow(10.0, std::ceil(std::log10(high)));
  if (p.y_max <= p.y_min) p.y_max = p.y_min * 10;
  for (double v = p.y_min; v <= p.y_max * 1.001; v *= 10) {
    const double y = p.y(v);
    if (v > p.y_min) {
      body_ << "<line x1='" << number(left) << "' y1='" << number(y) << "' x2='" << number(left + width) << "' y2='" << number(y)
            << "' stroke='#dddddd'/>\n";
    }
    std::ostringstream label;
    label << v;
    body_ << "<text x='" << number(left - 5) << "' y='" << number(y + 4) << "' text-anchor='end'>" << label.str() << unit << "</text>\n";
  }
  body_ << "<line x1='" << number(left) << "' y1='" << number(p.bottom()) << "' x2='" << number(left + width) << "' y2='"
        << number(p.bottom()) << "' stroke='black'/>\n"
        << "<line x1='" << number(left) << "' y1='" << number(top) << "' x2='" << number(left) << "' y2='" << number(p.bottom())
        << "' stroke='black'/>\n";
  text(left, top - 10, title + " (log scale)");
  return p;
}

SvgPlot::Panel SvgPlot::panel_for(double left, double top, double width, double height, const std::vector<double>& values,
                                  const std::string& title, const std::string& unit) {
  double low = 0, high = 0;
  bool positive = !values.empty();
  for (double v : values) {
    positive = positive && v > 0 && std::isfinite(v);
    low = low == 0 ? v : std::min(low, v);
    high = std::max(high, v);
  }
  if (positive && high / low > 10) return log_panel(left, top, width, height, low, high, title, unit);
  return panel(left, top, width, height, std::max(high, 1e-9), title, unit);
}

void SvgPlot::box(const Panel& p, double x, double width, const std::vector<double>& values, const std::string& colour) {
  if (values.empty()) return;
  std::vector<double> v = values;
  std::sort(v.begin(), v.end());
  auto quantile = [&](double q) {
    const double at = q * double(v.size() - 1);
    const std::size_t i = static_cast<std::size_t>(at);
    return i + 1 < v.size() ? v[i] + (at - double(i)) * (v[i + 1] - v[i]) : v[i];
  };
  const double q1 = p.y(quantile(0.25)), q3 = p.y(quantile(0.75)), med = p.y(quantile(0.5));
  const double lo = p.y(v.front()), hi = p.y(v.back()), left = x - width / 2;
  body_ << "<line x1='" << number(x) << "' y1='" << number(hi) << "' x2='" << number(x) << "' y2='" << number(lo) << "' stroke='"
        << colour << "'/>\n"
        << "<line x1='" << number(x - width / 4) << "' y1='" << number(hi) << "' x2='" << number(x + width / 4) << "' y2='" << number(hi)
        << "' stroke='" << colour << "'/>\n"
        << "<line x1='" << number(x - width / 4) << "' y1='" << number(lo) << "' x2='" << number(x + width / 4) << "' y2='" << number(lo)
        << "' stroke='" << colour << "'/>\n"
        << "<rect x='" << number(left) << "' y='" << number(q3) << "' width='" << number(width) << "' height='"
        << number(std::max(1.0, q1 - q3)) << "' fill='" << colour << "' fill-opacity='0.35' stroke='" << colour << "'/>\n"
        << "<line x1='" << number(left) << "' y1='" << number(med) << "' x2='" << number(left + width) << "' y2='" << number(med)
        << "' stroke='black' stroke-width='2'/>\n";
}

void SvgPlot::diamond(const Panel& p, double x, double value, const std::string& colour) {
  const double y = p.y(value), r = 5;
  body_ << "<polygon points='" << number(x) << "," << number(y - r) << " " << number(x + r) << "," << number(y) << " " << number(x) << ","
        << number(y + r) << " " << number(x - r) << "," << number(y) << "' fill='white' stroke='" << colour << "' stroke-width='1.5'/>\n";
}

void SvgPlot::goal(const Panel& p, double x, double width, double value) {
  const double y = p.y(p.log ? value : std::clamp(value, 0.0, p.y_max));
  body_ << "<line x1='" << number(x - width / 2) << "' y1='" << number(y) << "' x2='" << number(x + width / 2) << "' y2='" << number(y)
        << "' stroke='#d62728' stroke-width='2' stroke-dasharray='5,3'/>\n";
}

void SvgPlot::unsolved(const Panel& p, double x, int count) {
  if (count <= 0) return;
  const double y = p.top + 6, r = 4;
  body_ << "<path d='M" << number(x - r) << "," << number(y - r) << " L" << number(x + r) << "," << number(y + r) << " M" << number(x - r)
        << "," << number(y + r) << " L" << number(x + r) << "," << number(y - r) << "' stroke='#d62728' stroke-width='2'/>\n";
  text(x + r + 2, y + 4, std::to_string(count), "start", "#d62728");
}

void SvgPlot::bar(const Panel& p, double x, double width, double value, const std::string& fill,
                  const std::string& stroke) {
  const double v = std::clamp(value, 0.0, p.y_max);
  if (fill == "hatch") hatched_ = true;
  body_ << "<rect x='" << number(x) << "' y='" << number(p.y(v)) << "' width='" << number(width) << "' height='"
        << number(p.bottom() - p.y(v)) << "' fill='" << (fill == "hatch" ? "url(#hatch)" : fill) << "'"
        << (stroke.empty() ? "" : " stroke='" + stroke + "'") << "/>\n";
}

void SvgPlot::error_bar(const Panel& p, double x, double low, double high) {
  body_ << "<line x1='" << number(x) << "' y1='" << number(p.y(std::clamp(high, 0.0, p.y_max))) << "' x2='" << number(x)
        << "' y2='" << number(p.y(std::clamp(low, 0.0, p.y_max))) << "' stroke='black'/>\n";
}

void SvgPlot::line(const Panel& p, const std::vector<std::pair<double, double>>& points, const std::string& colour) {
  std::ostringstream path;
  for (const auto& [x, v] : points) {
    path << number(x) << ',' << number(p.y(v)) << ' ';
    body_ << "<circle cx='" << number(x) << "' cy='" << number(p.y(v)) << "' r='3' fill='" << colour << "'/>\n";
  }
  body_ << "<polyline fill='none' stroke='" << colour << "' stroke-width='2' points='" << path.str() << "'/>\n";
}

void SvgPlot::text(double x, double y, const std::string& text, const std::string& anchor, const std::string& fill) {
  body_ << "<text x='" << number(x) << "' y='" << number(y) << "'"
        << (anchor == "start" ? "" : " text-anchor='" + anchor + "'") << (fill.empty() ? "" : " fill='" + fill + "'")
        << ">" << escaped(text) << "</text>\n";
}

void SvgPlot::x_label(const Panel& p, double x, const std::string& label) { text(x, p.bottom() + 16, label, "middle"); }

void SvgPlot::legend(double x, double y, const std::string& colour, const std::string& name) {
  if (colour == "diamond") {
    body_ << "<polygon points='" << number(x + 5) << "," << number(y - 9) << " " << number(x + 10) << "," << number(y - 4) << " "
          << number(x + 5) << "," << number(y + 1) << " " << number(x) << "," << number(y - 4)
          << "' fill='white' stroke='black' stroke-width='1.5'/>\n";
  } else if (colour == "cross") {
    body_ << "<path d='M" << number(x + 1) << "," << number(y - 8) << " L" << number(x + 9) << "," << number(y) << " M" << number(x + 1)
          << "," << number(y) << " L" << number(x + 9) << "," << number(y - 8) << "' stroke='#d62728' stroke-width='2'/>\n";
  } else if (colour == "goal") {
    body_ << "<line x1='" << number(x) << "' y1='" << number(y - 4) << "' x2='" << number(x + 12) << "' y2='" << number(y - 4)
          << "' stroke='#d62728' stroke-width='2' stroke-dasharray='5,3'/>\n";
  } else {
    if (colour == "hatch") hatched_ = true;
    body_ << "<rect x='" << number(x) << "' y='" << number(y - 9) << "' width='10' height='10' fill='"
          << (colour == "hatch" ? "url(#hatch)" : colour) << "'" << (colour == "hatch" ? " stroke='grey'" : "") << "/>\n";
  }
  text(x + 14, y, name);
}

void SvgPlot::write(const std::filesystem::path& file) const {
  std::ostringstream out;
  out << "<svg xmlns='http://www.w3.org/2000/svg' width='" << number(width_) << "' height='" << number(height_)
      << "' font-family='sans-serif' font-size='" << font_size_ << "'>\n";
  if (hatched_) {
    out << "<defs><pattern id='hatch' width='6' height='6' patternUnits='userSpaceOnUse' patternTransform='rotate(45)'>"
        << "<line x1='0' y1='0' x2='0' y2='6' stroke='grey' stroke-width='2'/></pattern></defs>\n";
  }
  out << body_.str() << "</svg>\n";
  io::write_text_file(file, out.str(), "SVG file");
}

}  // namespace cluttertamp::bench
