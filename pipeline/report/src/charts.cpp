// SVG line charts for the report pages (html.h).
#include "html.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <string_view>
#include <vector>

namespace perclod::html {

std::vector<double> ticks(double lo, double hi, int want) {
  if (!(hi > lo)) return {lo};
  const double raw = (hi - lo) / want, mag = std::pow(10, std::floor(std::log10(raw)));
  double step = mag;
  for (double m : {1.0, 2.0, 2.5, 5.0, 10.0})
    if (m * mag >= raw) {
      step = m * mag;
      break;
    }
  std::vector<double> out;
  for (double v = std::ceil(lo / step - 1e-9) * step; v <= hi + step * 1e-9; v += step)
    out.push_back(std::abs(v) < step * 1e-9 ? 0 : v);
  return out;
}

double nice_max(double v) {
  if (!(v > 0) || !std::isfinite(v)) return 1;
  const std::vector<double> t = ticks(0, v);
  const double step = t.size() > 1 ? t[1] - t[0] : v;
  return std::ceil(v / step - 1e-9) * step;
}

std::string tick_label(double v, double step) {
  if (std::abs(v) >= 1e6 && step >= 1e5) return short_number(v / 1e6) + "M";
  if (std::abs(v) >= 1e4 && step >= 1e3) return short_number(v / 1e3) + "k";
  std::ostringstream ss;
  ss.precision(6);
  ss << v;
  return ss.str();
}

namespace {

// A chart's plot area within its 600 x 350 frame, and where a distance and
// a value fall in it (x on a log scale when the distances span 3x or more).
struct ChartFrame {
  double W = 600, H = 350, ml = 74, mr = 24, mt = 54, mb = 52;
  double pw = 0, ph = 0, xmin = INFINITY, xmax = -INFINITY;
  bool log_x = false;
  ChartFrame(const std::vector<double>& x, bool right_axis) {
    if (right_axis) mr = 74;
    pw = W - ml - mr, ph = H - mt - mb;
    for (double v : x)
      if (std::isfinite(v)) xmin = std::min(xmin, v), xmax = std::max(xmax, v);
    log_x = xmin > 0 && xmax / xmin >= 3;
  }
  double fx(double v) const {
    if (!(xmax > xmin)) return ml + pw / 2;
    const double t = log_x ? std::log(v / xmin) / std::log(xmax / xmin) : (v - xmin) / (xmax - xmin);
    return ml + pw * (0.04 + 0.92 * t);
  }
  double fy(const Axis& a, double v) const { return mt + ph * (1 - (v - a.lo) / (a.hi - a.lo)); }
};

// The left axis's grid and ticks, the right axis's ticks.
void chart_ticks(std::ostringstream& s, const ChartFrame& f, const Axis& left, const Axis* right) {
  const std::vector<double> lt = ticks(left.lo, left.hi);
  const double lstep = lt.size() > 1 ? lt[1] - lt[0] : 1;
  for (double v : lt) {
    const double y = f.fy(left, v);
    s << "<line class=\"grid\" x1=\"" << f.ml << "\" x2=\"" << f.ml + f.pw << "\" y1=\"" << y << "\" y2=\"" << y
      << "\"/><text x=\"" << f.ml - 6 << "\" y=\"" << y + 4 << "\" text-anchor=\"end\">"
      << html_escape(tick_label(v * left.scale, lstep * left.scale) + left.suffix) << "</text>\n";
  }
  if (!right) return;
  const std::vector<double> rt = ticks(right->lo, right->hi);
  const double rstep = rt.size() > 1 ? rt[1] - rt[0] : 1;
  for (double v : rt)
    s << "<text x=\"" << f.ml + f.pw + 6 << "\" y=\"" << f.fy(*right, v) + 4 << "\">"
      << html_escape(tick_label(v * right->scale, rstep * right->scale) + right->suffix) << "</text>\n";
}

// The axes, a tick per distance, and the axis labels.
void chart_axes(std::ostringstream& s, const ChartFrame& f, const std::vector<double>& x, const Axis& left,
                const Axis* right) {
  const double ml = f.ml, mt = f.mt, pw = f.pw, ph = f.ph;
  s << "<line class=\"axis\" x1=\"" << ml << "\" x2=\"" << ml << "\" y1=\"" << mt << "\" y2=\"" << mt + ph
    << "\"/><line class=\"axis\" x1=\"" << ml << "\" x2=\"" << ml + pw << "\" y1=\"" << mt + ph << "\" y2=\""
    << mt + ph << "\"/>\n";
  if (right)
    s << "<line class=\"axis\" x1=\"" << ml + pw << "\" x2=\"" << ml + pw << "\" y1=\"" << mt << "\" y2=\""
      << mt + ph << "\"/>\n";
  for (double v : x) {
    if (!std::isfinite(v)) continue;
    const double px = f.fx(v);
    s << "<line class=\"axis\" x1=\"" << px << "\" x2=\"" << px << "\" y1=\"" << mt + ph << "\" y2=\"" << mt + ph + 5
      << "\"/><text x=\"" << px << "\" y=\"" << mt + ph + 18 << "\" text-anchor=\"middle\">" << short_number(v)
      << "</text>\n";
  }
  s << "<text x=\"" << ml + pw / 2 << "\" y=\"" << f.H - 10 << "\" text-anchor=\"middle\">viewing distance (m"
    << (f.log_x ? ", log scale" : "") << ")</text>\n";
  s << "<text transform=\"translate(16," << mt + ph / 2 << ") rotate(-90)\" text-anchor=\"middle\">"
    << html_escape(left.label) << "</text>\n";
  if (right)
    s << "<text transform=\"translate(" << f.W - 14 << "," << mt + ph / 2 << ") rotate(90)\" text-anchor=\"middle\">"
      << html_escape(right->label) << "</text>\n";
}

// Limit rules on the left axis.
void chart_rules(std::ostringstream& s, const ChartFrame& f, const Axis& left,
                 const std::vector<std::pair<std::string, double>>& rules) {
  for (const auto& [name, v] : rules) {
    if (!(v >= left.lo && v <= left.hi)) continue;
    const double y = f.fy(left, v);
    s << "<line x1=\"" << f.ml << "\" x2=\"" << f.ml + f.pw << "\" y1=\"" << y << "\" y2=\"" << y
      << "\" stroke=\"#cf222e\" stroke-dasharray=\"2,3\"/><text x=\"" << f.ml + f.pw - 4 << "\" y=\"" << y - 4
      << "\" text-anchor=\"end\" style=\"fill:#cf222e;font-size:11px\">" << html_escape(name) << "</text>\n";
  }
}

// One series: a polyline through consecutive points, and the points.
void chart_series(std::ostringstream& s, const ChartFrame& f, const std::vector<double>& x, const Series& ser,
                  const Axis& a) {
  std::ostringstream pts;
  size_t n = 0;
  for (size_t i = 0; i < x.size() && i < ser.y.size(); ++i)
    if (std::isfinite(x[i]) && std::isfinite(ser.y[i])) pts << (n++ ? " " : "") << f.fx(x[i]) << "," << f.fy(a, ser.y[i]);
  if (n > 1)
    s << "<polyline class=\"line " << ser.css << "\" fill=\"none\" stroke=\"" << ser.colour
      << "\" stroke-width=\"2\"" << (ser.dashed ? " stroke-dasharray=\"6,4\"" : "") << " points=\"" << pts.str()
      << "\"/>\n";
  for (size_t i = 0; i < x.size() && i < ser.y.size(); ++i) {
    if (!std::isfinite(x[i]) || !std::isfinite(ser.y[i])) continue;
    std::ostringstream value;
    value.precision(4);
    value << ser.y[i] * a.scale;
    s << "<circle class=\"pt " << ser.css << "\" data-distance=\"" << short_number(x[i]) << "\" cx=\""
      << f.fx(x[i]) << "\" cy=\"" << f.fy(a, ser.y[i]) << "\" r=\"4\" fill=\"" << ser.colour << "\"><title>"
      << html_escape(ser.name) << " at " << short_number(x[i]) << " m: " << value.str() << html_escape(a.suffix)
      << "</title></circle>\n";
  }
}

// The legend: one row between the title and the plot.
void chart_legend(std::ostringstream& s, const ChartFrame& f, const std::vector<Series>& series, bool right_axis) {
  double lx = f.ml;
  const double ly = 38;
  for (const Series& ser : series) {
    const bool right = ser.right && right_axis;
    s << "<line x1=\"" << lx << "\" x2=\"" << lx + 22 << "\" y1=\"" << ly << "\" y2=\"" << ly << "\" stroke=\""
      << ser.colour << "\" stroke-width=\"2\"" << (ser.dashed ? " stroke-dasharray=\"6,4\"" : "")
      << "/><circle cx=\"" << lx + 11 << "\" cy=\"" << ly << "\" r=\"3\" fill=\"" << ser.colour << "\"/><text x=\""
      << lx + 28 << "\" y=\"" << ly + 4 << "\">" << html_escape(ser.name) << (right ? " (right)" : "")
      << "</text>\n";
    lx += 40 + 7 * double(ser.name.size() + (right ? 8 : 0));
  }
}

}  // namespace

std::string line_chart(const std::string& id, const std::string& title, const std::vector<double>& x,
                       const std::vector<Series>& series, const Axis& left, const Axis* right,
                       const std::vector<std::pair<std::string, double>>& left_rules) {
  const ChartFrame f(x, right != nullptr);
  std::ostringstream s;
  s << "<svg id=\"" << html_escape(id) << "\" xmlns=\"http://www.w3.org/2000/svg\" width=\"" << f.W
    << "\" height=\"" << f.H << "\" viewBox=\"0 0 " << f.W << " " << f.H << "\" role=\"img\" aria-label=\""
    << html_escape(title) << "\">\n";
  s << "<text x=\"" << f.ml << "\" y=\"20\" style=\"font-weight:600;font-size:14px\">" << html_escape(title)
    << "</text>\n";
  chart_ticks(s, f, left, right);
  chart_axes(s, f, x, left, right);
  chart_rules(s, f, left, left_rules);
  for (const Series& ser : series) chart_series(s, f, x, ser, ser.right && right ? *right : left);
  chart_legend(s, f, series, right != nullptr);
  s << "</svg>\n";
  return s.str();
}

}  // namespace perclod::html
