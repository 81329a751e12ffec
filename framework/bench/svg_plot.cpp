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

double tick_step(double max, int ticks) {
  if (!(max > 0) || !std::isfinite(max)) return 1.0;
  const double raw = max / std::max(1, ticks);
  const double power = std::pow(10.0, std::floor(std::log10(raw)));
  for (double m : {1.0, 2.0, 2.5, 5.0, 10.0}) {
    if (m * power >= raw) return m * power;
  }
  return 10 * power;
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
  body_ << "<rect x='" << number(x) << "' y='" << number(y - 9) << "' width='10' height='10' fill='" << colour << "'/>\n";
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
