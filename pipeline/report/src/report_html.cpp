// Offline HTML pages of run reports (perclod/report_html.h): plain strings
// built here, inline CSS and SVG, no script.
#include "perclod/report_html.h"

#include "perclod/simplify.h"

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


namespace perclod {
namespace {

using json = nlohmann::json;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// ---- reading the report: a missing or mistyped key is a blank, not a throw --

const json* member(const json& j, const char* key) {
  if (!j.is_object()) return nullptr;
  auto it = j.find(key);
  return it == j.end() || it->is_null() ? nullptr : &*it;
}

double num(const json& j, const char* key) {
  const json* v = member(j, key);
  return v && v->is_number() ? v->get<double>() : kNaN;
}

std::string str(const json& j, const char* key) {
  const json* v = member(j, key);
  if (!v) return "";
  return v->is_string() ? v->get<std::string>() : v->dump();
}

const json& sub(const json& j, const char* key) {
  static const json empty = json::object();
  const json* v = member(j, key);
  return v ? *v : empty;
}

const json& list(const json& j, const char* key) {
  static const json empty = json::array();
  const json* v = member(j, key);
  return v && v->is_array() ? *v : empty;
}

// ---- formatting -----------------------------------------------------------

std::string fixed(double v, int decimals) {
  if (!std::isfinite(v)) return "&ndash;";
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  return buf;
}

std::string count(double v) {
  if (!std::isfinite(v)) return "&ndash;";
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.0f", v);
  return buf;
}

std::string percent(double fraction, int decimals = 2) {
  return std::isfinite(fraction) ? fixed(100 * fraction, decimals) + "&nbsp;%" : "&ndash;";
}

// The labelling's samples per pixel: the number, or "auto" with what the
// views took, e.g. "auto (16 (grid): 21 views)".
std::string samples_text(const json& lod) {
  const json* v = member(lod, "samples_per_pixel");
  if (!v) return "&ndash;";
  if (v->is_number()) return count(v->get<double>());
  std::string text = html_escape(str(lod, "samples_per_pixel"));
  const json* chosen = member(lod, "sampling_chosen");
  if (chosen && chosen->is_object() && !chosen->empty()) {
    std::string parts;
    for (const auto& [name, n] : chosen->items())
      parts += (parts.empty() ? "" : ", ") + html_escape(name) + ": " + (n.is_number() ? count(n.get<double>()) : "?") + " views";
    text += " (" + parts + ")";
  }
  return text;
}

// Shortest form, as in file names: 56, 12.5.
std::string short_number(double v) {
  std::ostringstream ss;
  ss << v;
  return ss.str();
}

std::string seconds(double s) { return std::isfinite(s) ? fixed(s, s < 10 ? 2 : 1) + "&nbsp;s" : "&ndash;"; }

// A path for an href/src: bytes outside a safe set percent-encoded (so '#',
// '?', '%', spaces and non-ASCII survive), then HTML-escaped.
std::string url(const std::string& path) {
  static const char* hex = "0123456789ABCDEF";
  std::string out;
  for (unsigned char c : path) {
    if (std::isalnum(c) || std::string_view("-._~/+,=@").find(char(c)) != std::string_view::npos) {
      out += char(c);
    } else {
      out += '%';
      out += hex[c >> 4];
      out += hex[c & 15];
    }
  }
  return html_escape(out);
}

std::string file_name(const std::string& path) { return std::filesystem::path(path).filename().string(); }

// A file the pipeline wrote under names.dir, relative to a page in names.dir:
// the path below the directory, else its file name (outputs are flat).
std::string relative(const std::string& path, const OutputNames& names) {
  const std::string prefix = names.dir + "/";
  if (!names.dir.empty() && path.rfind(prefix, 0) == 0 && path.find("..") == std::string::npos)
    return path.substr(prefix.size());
  return file_name(path);
}

// "front_t3" -> "front": a view's tiles are shown together, beside the
// view's near marking.
std::string untiled(const std::string& view) {
  const size_t p = view.rfind("_t");
  if (p == std::string::npos || p + 2 == view.size()) return view;
  for (size_t i = p + 2; i < view.size(); ++i)
    if (!std::isdigit(static_cast<unsigned char>(view[i]))) return view;
  return view.substr(0, p);
}

const char* kStyle = R"(
body{font-family:system-ui,-apple-system,"Segoe UI",Roboto,"DejaVu Sans",sans-serif;margin:24px;color:#1d1d1f;background:#fff;max-width:1240px}
h1{font-size:1.6em;margin:0 0 4px}h2{font-size:1.3em;margin:32px 0 8px;border-bottom:2px solid #d0d7de;padding-bottom:4px}
h3{font-size:1.05em;margin:18px 0 6px}
table{border-collapse:collapse;margin:6px 0 12px;font-size:0.9em}
th,td{border:1px solid #d0d7de;padding:3px 8px;text-align:right}
th{background:#f3f5f7}td.l,th.l{text-align:left}
td.over{background:#ffd7d5;color:#a40e26;font-weight:600}
tr.failed td{background:#fff0ef}tr.skipped td{color:#6e7781}
.muted{color:#6e7781}.warn{color:#a40e26}
.facts td:first-child{text-align:left;font-weight:600;background:#f8f9fa}
figure{display:inline-block;margin:4px 8px 12px 0;vertical-align:top}
figure img{display:block;max-width:200px;max-height:200px;border:1px solid #d0d7de;background:#eee}
figcaption{font-size:0.8em;color:#444;max-width:200px;word-break:break-all}
.pair{display:inline-block;border:1px solid #d0d7de;padding:6px;margin:0 8px 8px 0}
.swatch{display:inline-block;width:12px;height:12px;vertical-align:middle;margin-right:4px;border:1px solid #888}
svg{background:#fff;border:1px solid #d0d7de;margin:4px 8px 8px 0}
svg text{font-family:inherit;font-size:12px;fill:#1d1d1f}
svg .grid{stroke:#e6e9ec}svg .axis{stroke:#57606a}
)";

std::string page_head(const std::string& title) {
  return "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
         "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n<title>" +
         html_escape(title) + "</title>\n<style>" + kStyle + "</style>\n</head>\n<body>\n";
}

// ---- charts -----------------------------------------------------------------

// A few round tick values from lo to hi.
std::vector<double> ticks(double lo, double hi, int want = 5) {
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

// Upper end of an axis from 0: the next tick above `v`.
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

struct Series {
  std::string name, css, colour;
  std::vector<double> y;   // one per x (NaN: no point)
  bool right = false;      // against the right axis
  bool dashed = false;
};

struct Axis {
  std::string label;
  double lo = 0, hi = 1;
  std::string suffix;  // tick label suffix, e.g. "%"
  double scale = 1;    // tick label = value * scale
};

// An SVG line chart of `series` against x (distances in metres): x on a log
// scale when the distances span a factor of 3 or more, one tick per
// distance; each point a <circle class="pt CSS"> with a tooltip.
std::string line_chart(const std::string& id, const std::string& title, const std::vector<double>& x,
                       const std::vector<Series>& series, const Axis& left, const Axis* right,
                       const std::vector<std::pair<std::string, double>>& left_rules = {}) {
  const double W = 600, H = 350, ml = 74, mr = right ? 74 : 24, mt = 54, mb = 52;
  const double pw = W - ml - mr, ph = H - mt - mb;
  double xmin = INFINITY, xmax = -INFINITY;
  for (double v : x)
    if (std::isfinite(v)) xmin = std::min(xmin, v), xmax = std::max(xmax, v);
  const bool log_x = xmin > 0 && xmax / xmin >= 3;
  auto fx = [&](double v) {
    if (!(xmax > xmin)) return ml + pw / 2;
    const double t = log_x ? std::log(v / xmin) / std::log(xmax / xmin) : (v - xmin) / (xmax - xmin);
    return ml + pw * (0.04 + 0.92 * t);
  };
  auto fy = [&](const Axis& a, double v) { return mt + ph * (1 - (v - a.lo) / (a.hi - a.lo)); };
  std::ostringstream s;
  s << "<svg id=\"" << html_escape(id) << "\" xmlns=\"http://www.w3.org/2000/svg\" width=\"" << W << "\" height=\""
    << H << "\" viewBox=\"0 0 " << W << " " << H << "\" role=\"img\" aria-label=\"" << html_escape(title) << "\">\n";
  s << "<text x=\"" << ml << "\" y=\"20\" style=\"font-weight:600;font-size:14px\">" << html_escape(title)
    << "</text>\n";
  // Left axis grid and ticks.
  const std::vector<double> lt = ticks(left.lo, left.hi);
  const double lstep = lt.size() > 1 ? lt[1] - lt[0] : 1;
  for (double v : lt) {
    const double y = fy(left, v);
    s << "<line class=\"grid\" x1=\"" << ml << "\" x2=\"" << ml + pw << "\" y1=\"" << y << "\" y2=\"" << y
      << "\"/><text x=\"" << ml - 6 << "\" y=\"" << y + 4 << "\" text-anchor=\"end\">"
      << html_escape(tick_label(v * left.scale, lstep * left.scale) + left.suffix) << "</text>\n";
  }
  if (right) {
    const std::vector<double> rt = ticks(right->lo, right->hi);
    const double rstep = rt.size() > 1 ? rt[1] - rt[0] : 1;
    for (double v : rt)
      s << "<text x=\"" << ml + pw + 6 << "\" y=\"" << fy(*right, v) + 4 << "\">"
        << html_escape(tick_label(v * right->scale, rstep * right->scale) + right->suffix) << "</text>\n";
  }
  // Axes.
  s << "<line class=\"axis\" x1=\"" << ml << "\" x2=\"" << ml << "\" y1=\"" << mt << "\" y2=\"" << mt + ph
    << "\"/><line class=\"axis\" x1=\"" << ml << "\" x2=\"" << ml + pw << "\" y1=\"" << mt + ph << "\" y2=\""
    << mt + ph << "\"/>\n";
  if (right)
    s << "<line class=\"axis\" x1=\"" << ml + pw << "\" x2=\"" << ml + pw << "\" y1=\"" << mt << "\" y2=\""
      << mt + ph << "\"/>\n";
  for (double v : x) {
    if (!std::isfinite(v)) continue;
    const double px = fx(v);
    s << "<line class=\"axis\" x1=\"" << px << "\" x2=\"" << px << "\" y1=\"" << mt + ph << "\" y2=\"" << mt + ph + 5
      << "\"/><text x=\"" << px << "\" y=\"" << mt + ph + 18 << "\" text-anchor=\"middle\">" << short_number(v)
      << "</text>\n";
  }
  s << "<text x=\"" << ml + pw / 2 << "\" y=\"" << H - 10 << "\" text-anchor=\"middle\">viewing distance (m"
    << (log_x ? ", log scale" : "") << ")</text>\n";
  s << "<text transform=\"translate(16," << mt + ph / 2 << ") rotate(-90)\" text-anchor=\"middle\">"
    << html_escape(left.label) << "</text>\n";
  if (right)
    s << "<text transform=\"translate(" << W - 14 << "," << mt + ph / 2 << ") rotate(90)\" text-anchor=\"middle\">"
      << html_escape(right->label) << "</text>\n";
  // Limit rules on the left axis.
  for (const auto& [name, v] : left_rules) {
    if (!(v >= left.lo && v <= left.hi)) continue;
    const double y = fy(left, v);
    s << "<line x1=\"" << ml << "\" x2=\"" << ml + pw << "\" y1=\"" << y << "\" y2=\"" << y
      << "\" stroke=\"#cf222e\" stroke-dasharray=\"2,3\"/><text x=\"" << ml + pw - 4 << "\" y=\"" << y - 4
      << "\" text-anchor=\"end\" style=\"fill:#cf222e;font-size:11px\">" << html_escape(name) << "</text>\n";
  }
  // Series: a polyline through consecutive points, and the points.
  for (const Series& ser : series) {
    const Axis& a = ser.right && right ? *right : left;
    std::ostringstream pts;
    size_t n = 0;
    for (size_t i = 0; i < x.size() && i < ser.y.size(); ++i)
      if (std::isfinite(x[i]) && std::isfinite(ser.y[i])) pts << (n++ ? " " : "") << fx(x[i]) << "," << fy(a, ser.y[i]);
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
        << fx(x[i]) << "\" cy=\"" << fy(a, ser.y[i]) << "\" r=\"4\" fill=\"" << ser.colour << "\"><title>"
        << html_escape(ser.name) << " at " << short_number(x[i]) << " m: " << value.str() << html_escape(a.suffix)
        << "</title></circle>\n";
    }
  }
  // Legend: one row between the title and the plot.
  double lx = ml;
  const double ly = 38;
  for (const Series& ser : series) {
    s << "<line x1=\"" << lx << "\" x2=\"" << lx + 22 << "\" y1=\"" << ly << "\" y2=\"" << ly << "\" stroke=\""
      << ser.colour << "\" stroke-width=\"2\"" << (ser.dashed ? " stroke-dasharray=\"6,4\"" : "")
      << "/><circle cx=\"" << lx + 11 << "\" cy=\"" << ly << "\" r=\"3\" fill=\"" << ser.colour << "\"/><text x=\""
      << lx + 28 << "\" y=\"" << ly + 4 << "\">" << html_escape(ser.name) << (ser.right && right ? " (right)" : "")
      << "</text>\n";
    lx += 40 + 7 * double(ser.name.size() + (ser.right && right ? 8 : 0));
  }
  s << "</svg>\n";
  return s.str();
}

// ---- the model page ---------------------------------------------------------

const char* kLabels[] = {"perceptible", "imperceptible", "undisplayable"};

std::string image(const std::string& file, const std::string& caption) {
  return "<figure><a href=\"" + url(file) + "\"><img src=\"" + url(file) + "\" alt=\"" + html_escape(caption) +
         "\" loading=\"lazy\"></a><figcaption>" + html_escape(caption) + "</figcaption></figure>";
}

std::string triangles_table(const json& simplify) {
  const json& before = sub(simplify, "triangles_before");
  const json& after = sub(simplify, "triangles_after");
  std::ostringstream s;
  s << "<table class=\"triangles\"><tr><th class=\"l\">label</th><th>before</th><th>after</th><th>kept</th></tr>\n";
  auto row = [&](const std::string& name, double b, double a) {
    s << "<tr><td class=\"l\">" << name << "</td><td>" << count(b) << "</td><td>" << count(a) << "</td><td>"
      << (b > 0 ? percent(a / b, 1) : "&ndash;") << "</td></tr>\n";
  };
  for (const char* l : kLabels) row(l, num(before, l), num(after, l));
  row("<b>total</b>", num(simplify, "total_before"), num(simplify, "total_after"));
  s << "</table>\n";
  return s.str();
}

std::string facts_table(const std::vector<std::pair<std::string, std::string>>& rows) {
  std::ostringstream s;
  s << "<table class=\"facts\">";
  for (const auto& [k, v] : rows) s << "<tr><td>" << k << "</td><td class=\"l\">" << v << "</td></tr>";
  s << "</table>\n";
  return s.str();
}

// Over-limit (view, measure) pairs of a LOD's fidelity summary.
std::set<std::pair<std::string, std::string>> over_limits(const json& fidelity) {
  std::set<std::pair<std::string, std::string>> over;
  for (const auto& o : list(fidelity, "over_limits")) over.insert({str(o, "view"), str(o, "measure")});
  return over;
}

std::string fidelity_table(const json& lod) {
  const json& fid = sub(lod, "fidelity");
  const json& limits = sub(fid, "limits");
  const auto over = over_limits(fid);
  const double max_changed = num(limits, "max_changed"), max_sil = num(limits, "max_silhouette");
  const double min_ssim = num(limits, "min_ssim");  // NaN in reports from before the key: no limit
  std::ostringstream s;
  s << "<p>Limits: changed &le; " << percent(max_changed) << ", silhouette mismatch &le; " << percent(max_sil);
  if (min_ssim > 0) s << ", SSIM &ge; " << fixed(min_ssim, 4);
  s << ". Cells over a limit are <span style=\"background:#ffd7d5;color:#a40e26;font-weight:600\">marked</span>.</p>\n";
  s << "<table class=\"fidelity\"><tr><th class=\"l\">view</th><th class=\"l\">set</th><th>changed</th>"
       "<th>SSIM (covered)</th><th>silhouette mismatch</th><th>drawn px</th></tr>\n";
  for (const auto& v : list(lod, "lod_vs_original")) {
    const std::string view = str(v, "view");
    auto cell = [&](const char* measure, const std::string& text, bool over_here) {
      return std::string(over_here || over.count({view, measure}) ? "<td class=\"over\">" : "<td>") + text + "</td>";
    };
    const double changed = num(v, "changed_fraction"), sil = num(v, "silhouette_mismatch");
    const double q = num(v, "ssim_covered");
    s << "<tr><td class=\"l\">" << html_escape(view) << "</td><td class=\"l\">" << html_escape(str(v, "set"))
      << "</td>" << cell("changed_fraction", percent(changed), changed > max_changed)
      << cell("ssim_covered", fixed(q, 4), q < min_ssim)
      << cell("silhouette_mismatch", percent(sil), sil > max_sil) << "<td>" << count(num(v, "drawn_pixels"))
      << "</td></tr>\n";
  }
  const json& worst = sub(fid, "worst");
  const double wc = num(worst, "changed_fraction"), ws = num(worst, "silhouette_mismatch");
  s << "<tr><th class=\"l\" colspan=\"2\">worst</th>" << (wc > max_changed ? "<td class=\"over\">" : "<td>")
    << percent(wc) << "</td>" << (num(worst, "ssim_covered") < min_ssim ? "<td class=\"over\">" : "<td>")
    << fixed(num(worst, "ssim_covered"), 4) << "</td>" << (ws > max_sil ? "<td class=\"over\">" : "<td>")
    << percent(ws) << "</td><td></td></tr>\n</table>\n";
  return s.str();
}

std::string label_views_table(const json& lod) {
  std::ostringstream s;
  s << "<table class=\"label-views\"><tr><th class=\"l\">labelling view</th><th>covered px</th>"
       "<th>imperceptible px</th><th>perceptible tri.</th><th>imperceptible tri.</th><th>undisplayable tri.</th>"
       "<th>render</th><th>perceive</th><th>trace</th></tr>\n";
  for (const auto& v : list(lod, "views")) {
    const json& l = sub(v, "labels");
    const json& t = sub(v, "seconds");
    s << "<tr><td class=\"l\">" << html_escape(str(v, "view")) << "</td><td>" << count(num(v, "covered_pixels"))
      << "</td><td>" << percent(num(v, "imperceptible_fraction"), 1) << "</td><td>" << count(num(l, "perceptible"))
      << "</td><td>" << count(num(l, "imperceptible")) << "</td><td>" << count(num(l, "undisplayable")) << "</td><td>"
      << seconds(num(t, "render")) << "</td><td>" << seconds(num(t, "perceive")) << "</td><td>"
      << seconds(num(t, "trace")) << "</td></tr>\n";
  }
  s << "</table>\n";
  return s.str();
}

// Per labelling view: the render of each of its tiles and its marking renders
// (as listed in the report); then every judged view's comparison picture.
std::string images_section(const json& lod, double d, const OutputNames& names) {
  std::ostringstream s;
  std::map<std::string, std::string> marking;  // file name -> path in the report
  for (const auto& m : list(lod, "marking_renders"))
    if (m.is_string()) marking[file_name(m.get<std::string>())] = m.get<std::string>();
  std::vector<std::string> order;
  std::map<std::string, std::vector<std::string>> tiles;
  for (const auto& v : list(lod, "views")) {
    const std::string view = str(v, "view"), base = untiled(view);
    if (!tiles.count(base)) order.push_back(base);
    tiles[base].push_back(view);
  }
  if (!order.empty()) {
    s << "<h3>Labelling views: render and marking</h3>\n<p class=\"muted\">Marking colours: "
         "<span class=\"swatch\" style=\"background:#0f0\"></span>perceptible "
         "<span class=\"swatch\" style=\"background:#f00\"></span>imperceptible "
         "<span class=\"swatch\" style=\"background:#00f\"></span>undisplayable. "
         "Near (with marking_near): the marking from a quarter of the distance (closer_factor).</p>\n";
  }
  for (const std::string& base : order) {
    s << "<div class=\"pair\">";
    auto marking_of = [&](const std::string& view, const char* suffix, const std::string& caption) {
      auto it = marking.find(file_name(names.view(view, d, suffix)));
      if (it != marking.end()) s << image(relative(it->second, names), caption);
    };
    for (const std::string& tile : tiles[base]) {
      s << image(relative(names.view(tile, d, ".png"), names), tile + " render");
      if (tile != base) marking_of(tile, "_marking.png", tile + " marking");  // a tile's own marking
    }
    marking_of(base, "_marking.png", base + " marking");
    marking_of(base, "_marking_near.png", base + " marking, near");
    s << "</div>\n";
  }
  // LOD beside the original, from every judged view (labelling and held-out):
  // compare_lod_views' pictures, original | LOD | changes.
  std::ostringstream labelling, held_out;
  for (const auto& v : list(lod, "lod_vs_original")) {
    const std::string picture = str(v, "comparison_image");
    if (picture.empty()) continue;
    std::ostringstream caption;
    caption.precision(3);
    caption << str(v, "view") << ": " << 100 * num(v, "changed_fraction") << "% changed, SSIM "
            << num(v, "ssim_covered") << ", silhouette " << 100 * num(v, "silhouette_mismatch") << "%";
    (str(v, "set") == "held_out" ? held_out : labelling) << image(relative(picture, names), caption.str());
  }
  if (!labelling.str().empty() || !held_out.str().empty()) {
    s << "<h3>LOD beside the original</h3>\n<p class=\"muted\">Each picture: the original | the LOD | the LOD "
         "with perceptibly changed pixels red and pixels drawn by only one of the two blue (luminance, "
         "cropped to the drawn region).</p>\n";
    if (!labelling.str().empty()) s << "<h4>Labelling views</h4>\n<div class=\"pair\">" << labelling.str() << "</div>\n";
    if (!held_out.str().empty())
      s << "<h4>Held-out views (never used for labelling)</h4>\n<div class=\"pair\">" << held_out.str() << "</div>\n";
  } else {
    s << "<p class=\"muted\">No LOD-beside-original pictures in this report.</p>\n";
  }
  return s.str();
}

// "deleted", "collapsed" or "collapsed within E px" (a LOD's bounds_px or a
// search try), and what keep_undisplayable: auto decided from, when it did.
std::string undisplayable_rule(const json& j) {
  std::string rule = html_escape(str(j, "undisplayable"));
  if (member(j, "e_undisplayable")) rule += " within " + fixed(num(j, "e_undisplayable"), 3) + "&nbsp;px";
  if (member(j, "undisplayable_exposure"))
    rule += " (auto: they are " + fixed(100 * num(j, "undisplayable_exposure"), 3) +
            "% of what the views between the labelling ones see)";
  return rule;
}

// The tries of a fidelity_target search ("fidelity_search") or of
// tighten_to_limits ("tighten_to_limits": the asked bounds first), one row each.
std::string tries_table(const json& lod, const char* key, const char* title) {
  const json& search = list(lod, key);
  if (search.empty()) return "";
  std::ostringstream s;
  s << "<h3>" << title << "</h3>\n<table class=\"search\"><tr><th>e_imperceptible (px)</th>"
       "<th>e_perceptible (px)</th><th class=\"l\">undisplayable</th><th>triangles</th>"
       "<th>worst changed</th><th>lowest SSIM</th><th>worst silhouette</th><th class=\"l\">met</th>"
       "<th class=\"l\">kept</th></tr>\n";
  for (const auto& t : search) {
    const json& w = sub(t, "worst");
    const json* met = member(t, "met");
    const json* kept = member(t, "kept");  // the try whose LOD was written
    s << "<tr><td>" << fixed(num(t, "e_imperceptible"), 3) << "</td><td>" << fixed(num(t, "e_perceptible"), 3)
      << "</td><td class=\"l\">" << undisplayable_rule(t) << "</td><td>" << count(num(t, "triangles")) << "</td><td>"
      << percent(num(w, "changed_fraction")) << "</td><td>" << fixed(num(w, "ssim_covered"), 4) << "</td><td>"
      << percent(num(w, "silhouette_mismatch")) << "</td><td class=\"l\">"
      << (met && met->is_boolean() ? (met->get<bool>() ? "yes" : "no") : "") << "</td><td class=\"l\">"
      << (kept && kept->is_boolean() && kept->get<bool>() ? "written" : "") << "</td></tr>\n";
  }
  s << "</table>\n";
  return s.str();
}

std::string charts(const json& lods) {
  std::vector<double> x, before, after, perceptible, changed, silhouette, ssim;
  double limit_changed = kNaN, limit_sil = kNaN;
  for (const auto& l : lods) {
    const json& simp = sub(l, "simplify");
    const json& worst = sub(sub(l, "fidelity"), "worst");
    const json& limits = sub(sub(l, "fidelity"), "limits");
    x.push_back(num(l, "distance"));
    before.push_back(num(simp, "total_before"));
    after.push_back(num(simp, "total_after"));
    perceptible.push_back(num(sub(simp, "triangles_after"), "perceptible"));
    changed.push_back(num(worst, "changed_fraction"));
    silhouette.push_back(num(worst, "silhouette_mismatch"));
    ssim.push_back(num(worst, "ssim_covered"));
    if (std::isnan(limit_changed)) limit_changed = num(limits, "max_changed");
    if (std::isnan(limit_sil)) limit_sil = num(limits, "max_silhouette");
  }
  if (x.empty()) return "";
  auto max_of = [](std::initializer_list<const std::vector<double>*> vs) {
    double m = 0;
    for (auto* v : vs)
      for (double y : *v)
        if (std::isfinite(y)) m = std::max(m, y);
    return m;
  };
  Axis tri{"triangles", 0, nice_max(max_of({&before, &after})), "", 1};
  std::string out = line_chart("chart-triangles", "Triangles against distance", x,
                               {{"original", "before", "#8c959f", before, false, true},
                                {"LOD", "triangles", "#0969da", after, false, false},
                                {"LOD perceptible", "perceptible", "#1a7f37", perceptible, false, false}},
                               tri, nullptr);
  double top = max_of({&changed, &silhouette});
  if (std::isfinite(limit_changed)) top = std::max(top, limit_changed);
  if (std::isfinite(limit_sil)) top = std::max(top, limit_sil);
  Axis pct{"worst view, %", 0, nice_max(top), "%", 100};
  double ssim_lo = 1;
  for (double v : ssim)
    if (std::isfinite(v)) ssim_lo = std::min(ssim_lo, v);
  Axis ssim_axis{"lowest SSIM", std::min(0.9, std::floor(ssim_lo * 10) / 10), 1, "", 1};
  std::vector<std::pair<std::string, double>> rules;
  if (std::isfinite(limit_changed)) rules.push_back({"changed limit", limit_changed});
  if (std::isfinite(limit_sil) && limit_sil != limit_changed) rules.push_back({"silhouette limit", limit_sil});
  out += line_chart("chart-fidelity", "Worst fidelity against distance", x,
                    {{"changed pixels", "changed", "#cf222e", changed, false, false},
                     {"silhouette mismatch", "silhouette", "#bf8700", silhouette, false, false},
                     {"SSIM", "ssim", "#8250df", ssim, true, true}},
                    pct, &ssim_axis, rules);
  return out;
}

}  // namespace

std::string html_escape(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&#39;"; break;
      default: out += c;
    }
  }
  return out;
}

std::string model_report_html(const json& report, const OutputNames& names) {
  const std::string model = str(report, "model").empty() ? names.stem : str(report, "model");
  const json& lods = list(report, "lods");
  std::ostringstream s;
  s << page_head("perclod report: " + model);
  s << "<h1>perclod report: " << html_escape(model) << "</h1>\n";
  s << "<p class=\"muted\">Files of <code>" << html_escape(names.stem) << "</code>; the full figures are in <a href=\""
    << url(relative(names.report(), names)) << "\">" << html_escape(file_name(names.report())) << "</a>.</p>\n";

  // The run as a whole.
  const json& display = sub(report, "display");
  const json& tracer = sub(report, "tracer");
  std::string judge;
  for (const auto& v : list(report, "judge_views")) judge += (judge.empty() ? "" : ", ") + html_escape(v.is_string() ? v.get<std::string>() : v.dump());
  std::string dist;
  for (const auto& l : lods) {
    const std::string d = short_number(num(l, "distance"));
    dist += (dist.empty() ? "" : ", ") + std::string("<a href=\"#d") + url(d) + "\">" + d + "&nbsp;m</a>";
  }
  const double over = num(report, "over_limits");
  s << facts_table({{"model triangles", count(num(report, "triangles"))},
                    {"components", count(num(report, "components"))},
                    {"display", html_escape(str(display, "name")) + " (" + fixed(num(display, "ppd"), 1) +
                                    " px/degree, f_max " + fixed(num(display, "f_max"), 1) + " cpd)"},
                    {"tracer", html_escape(str(tracer, "name")) + ", built in " + seconds(num(tracer, "build_seconds"))},
                    {"simplify mode", html_escape(str(report, "simplify_mode"))},
                    {"held-out views", judge.empty() ? "none (labelling views only)" : judge},
                    {"distances", dist},
                    {"figures over limits", over > 0 ? "<span class=\"warn\">" + count(over) + "</span>" : count(over)},
                    {"total time", seconds(num(report, "seconds"))}});
  const json& warnings = list(report, "warnings");
  if (!warnings.empty()) {
    s << "<h3 class=\"warn\">Warnings</h3>\n<ul class=\"warnings\">\n";
    for (const auto& w : warnings) s << "<li>" << html_escape(w.is_string() ? w.get<std::string>() : w.dump()) << "</li>\n";
    s << "</ul>\n";
  }
  s << "<div class=\"charts\">\n" << charts(lods) << "</div>\n";

  // Summary over distances.
  s << "<h2>LODs</h2>\n<table class=\"summary\"><tr><th>distance</th><th>pixel footprint</th><th>triangles</th>"
       "<th>kept</th><th>worst changed</th><th>lowest SSIM</th><th>worst silhouette</th><th>over limits</th>"
       "<th>time</th><th class=\"l\">LOD file</th></tr>\n";
  for (const auto& l : lods) {
    const json& simp = sub(l, "simplify");
    const json& fid = sub(l, "fidelity");
    const json& worst = sub(fid, "worst");
    const json& limits = sub(fid, "limits");
    const double b = num(simp, "total_before"), a = num(simp, "total_after");
    const double wc = num(worst, "changed_fraction"), ws = num(worst, "silhouette_mismatch");
    const std::string lod_file = str(l, "lod_file");
    const std::string d = short_number(num(l, "distance"));
    s << "<tr><td><a href=\"#d" << url(d) << "\">" << d << "&nbsp;m</a></td><td>" << fixed(num(l, "pixel_footprint"), 4)
      << "&nbsp;m</td><td>" << count(a) << "</td><td>" << (b > 0 ? percent(a / b, 1) : "&ndash;") << "</td>"
      << (wc > num(limits, "max_changed") ? "<td class=\"over\">" : "<td>") << percent(wc) << "</td>"
      << (num(worst, "ssim_covered") < num(limits, "min_ssim") ? "<td class=\"over\">" : "<td>")
      << fixed(num(worst, "ssim_covered"), 4) << "</td>"
      << (ws > num(limits, "max_silhouette") ? "<td class=\"over\">" : "<td>") << percent(ws) << "</td><td>"
      << list(fid, "over_limits").size() << "</td><td>" << seconds(num(l, "seconds")) << "</td><td class=\"l\">"
      << (lod_file.empty() ? "" : "<a href=\"" + url(relative(lod_file, names)) + "\">" +
                                      html_escape(file_name(lod_file)) + "</a>")
      << "</td></tr>\n";
  }
  s << "</table>\n";

  // One section per distance.
  for (const auto& l : lods) {
    const double d = num(l, "distance");
    const json& simp = sub(l, "simplify");
    const json& bounds = sub(l, "bounds_px");
    const std::string tag = short_number(d);
    s << "<section id=\"d" << url(tag) << "\">\n<h2>" << tag << " m</h2>\n";
    if (const json* e = member(l, "empty"); e && e->is_boolean() && e->get<bool>())
      s << "<p class=\"warn\">This LOD is empty: no triangle of the model is displayable at " << tag << " m.</p>\n";
    std::vector<std::pair<std::string, std::string>> facts = {
        {"pixel footprint", fixed(num(l, "pixel_footprint"), 4) + "&nbsp;m"},
        {"samples per pixel", samples_text(l)},
        {"views combined", str(l, "combine_views").empty() ? "any" : html_escape(str(l, "combine_views"))},
        {"vertices", count(num(simp, "vertices_before")) + " &rarr; " + count(num(simp, "vertices_after"))}};
    if (!str(simp, "stop_reason").empty()) facts.push_back({"stop reason", html_escape(str(simp, "stop_reason"))});
    if (const json* why = member(simp, "refused")) {  // explain: true: in refused_text's words
      auto n = [&](const char* rule) { return size_t(std::max(0.0, num(*why, rule))); };
      facts.push_back({"stopped", refused_text({n("bound_or_locked"), n("valence"), n("topology"), n("shape"),
                                                n("legal")})});
    }
    if (member(l, "bounds_px"))
      facts.push_back({"bounds (px)", "perceptible " + fixed(num(bounds, "perceptible"), 2) + ", imperceptible " +
                                          fixed(num(bounds, "imperceptible"), 2) + "; undisplayable " +
                                          undisplayable_rule(bounds)});
    facts.push_back({"outside every view", count(num(l, "outside_views")) + " triangles"});
    facts.push_back({"time: total", seconds(num(l, "seconds"))});
    facts.push_back({"time: simplify", seconds(num(simp, "seconds"))});
    facts.push_back({"time: judging", seconds(num(l, "seconds_compare"))});
    for (const char* key : {"lod_file", "labels_file"}) {
      const std::string f = str(l, key);
      if (!f.empty())
        facts.push_back({key == std::string("lod_file") ? "LOD file" : "labels file",
                         "<a href=\"" + url(relative(f, names)) + "\">" + html_escape(file_name(f)) + "</a>"});
    }
    s << "<h3>Triangles</h3>\n" << triangles_table(simp) << facts_table(facts);
    s << "<h3>Fidelity: the LOD against the original, per judged view</h3>\n" << fidelity_table(l);
    s << tries_table(l, "fidelity_search", "Fidelity target search");
    s << tries_table(l, "tighten_to_limits", "Tightened to the limits (the asked bounds first)");
    s << "<h3>Labelling</h3>\n" << label_views_table(l);
    s << images_section(l, d, names);
    s << "</section>\n";
  }
  s << "<p class=\"muted\">Written by perclod.</p>\n</body>\n</html>\n";
  return s.str();
}

void write_model_report_html(const json& report, const OutputNames& names) {
  write_text_atomic(names.report_html(), model_report_html(report, names));
}

// ---- the batch index --------------------------------------------------------

namespace {

const char* kPalette[] = {"#0969da", "#1a7f37", "#bf8700", "#8250df", "#cf222e", "#1b7c83", "#953800", "#57606a"};

// Grouped bars: per model, one bar per LOD (triangles), coloured by distance.
std::string batch_chart(const json& models) {
  std::vector<double> distances;
  double top = 0;
  size_t bars = 0, groups = 0;
  for (const auto& m : models) {
    const json& lods = list(m, "lods");
    if (lods.empty()) continue;
    ++groups;
    for (const auto& l : lods) {
      const double d = num(l, "distance"), t = num(l, "triangles");
      if (std::isfinite(d) && std::find(distances.begin(), distances.end(), d) == distances.end())
        distances.push_back(d);
      if (std::isfinite(t)) top = std::max(top, t);
      ++bars;
    }
  }
  if (!bars) return "";
  std::sort(distances.begin(), distances.end());
  const double bw = 16, gap = 18, ml = 70, mr = 150, mt = 34, mb = 70, ph = 220;
  const double pw = std::max(300.0, bars * bw + groups * gap + gap);
  const double W = ml + pw + mr, H = mt + ph + mb;
  const Axis axis{"triangles", 0, nice_max(top), "", 1};
  auto fy = [&](double v) { return mt + ph * (1 - v / axis.hi); };
  std::ostringstream s;
  s << "<svg id=\"chart-batch\" xmlns=\"http://www.w3.org/2000/svg\" width=\"" << W << "\" height=\"" << H
    << "\" viewBox=\"0 0 " << W << " " << H << "\" role=\"img\" aria-label=\"LOD triangles per model\">\n"
    << "<text x=\"" << ml << "\" y=\"20\" style=\"font-weight:600;font-size:14px\">LOD triangles per model</text>\n";
  const std::vector<double> t = ticks(0, axis.hi);
  const double step = t.size() > 1 ? t[1] - t[0] : 1;
  for (double v : t)
    s << "<line class=\"grid\" x1=\"" << ml << "\" x2=\"" << ml + pw << "\" y1=\"" << fy(v) << "\" y2=\"" << fy(v)
      << "\"/><text x=\"" << ml - 6 << "\" y=\"" << fy(v) + 4 << "\" text-anchor=\"end\">" << tick_label(v, step)
      << "</text>\n";
  s << "<line class=\"axis\" x1=\"" << ml << "\" x2=\"" << ml << "\" y1=\"" << mt << "\" y2=\"" << mt + ph
    << "\"/><line class=\"axis\" x1=\"" << ml << "\" x2=\"" << ml + pw << "\" y1=\"" << mt + ph << "\" y2=\""
    << mt + ph << "\"/>\n<text transform=\"translate(16," << mt + ph / 2
    << ") rotate(-90)\" text-anchor=\"middle\">triangles</text>\n";
  double x = ml + gap;
  for (const auto& m : models) {
    const json& lods = list(m, "lods");
    if (lods.empty()) continue;
    const double x0 = x;
    for (const auto& l : lods) {
      const double d = num(l, "distance"), tri = num(l, "triangles");
      const size_t k = std::find(distances.begin(), distances.end(), d) - distances.begin();
      const char* colour = kPalette[k % std::size(kPalette)];
      if (std::isfinite(tri))
        s << "<rect class=\"bar\" x=\"" << x << "\" y=\"" << fy(tri) << "\" width=\"" << bw - 2 << "\" height=\""
          << mt + ph - fy(tri) << "\" fill=\"" << colour << "\"><title>" << html_escape(str(m, "name")) << " at "
          << short_number(d) << " m: " << count(tri) << " triangles</title></rect>\n";
      x += bw;
    }
    const std::string name = str(m, "name");
    const std::string shown = name.size() > 18 ? name.substr(0, 17) + "\u2026" : name;
    s << "<text transform=\"translate(" << (x0 + x) / 2 << "," << mt + ph + 12
      << ") rotate(30)\" text-anchor=\"start\">" << html_escape(shown) << "</text>\n";
    x += gap;
  }
  double ly = mt + 8;
  for (size_t k = 0; k < distances.size(); ++k) {
    s << "<rect x=\"" << ml + pw + 16 << "\" y=\"" << ly - 6 << "\" width=\"12\" height=\"12\" fill=\""
      << kPalette[k % std::size(kPalette)] << "\"/><text x=\"" << ml + pw + 34 << "\" y=\"" << ly + 4 << "\">"
      << short_number(distances[k]) << " m</text>\n";
    ly += 18;
  }
  s << "</svg>\n";
  return s.str();
}

}  // namespace

std::string batch_index_html(const json& summary) {
  const json& models = list(summary, "models");
  std::ostringstream s;
  s << page_head("perclod batch");
  s << "<h1>perclod batch</h1>\n<p>" << count(num(summary, "done")) << " done, " << count(num(summary, "skipped"))
    << " skipped, " << (num(summary, "failed") > 0 ? "<span class=\"warn\">" : "<span>") << count(num(summary, "failed"))
    << " failed</span>; " << models.size() << " models in " << seconds(num(summary, "seconds")) << ".</p>\n";
  s << "<table class=\"models\"><tr><th class=\"l\">model</th><th class=\"l\">status</th><th class=\"l\">LODs: "
       "triangles at distance</th><th>worst changed</th><th>lowest SSIM</th><th>worst silhouette</th><th>time</th>"
       "<th class=\"l\">outputs / error</th></tr>\n";
  for (const auto& m : models) {
    const std::string name = str(m, "name"), status = str(m, "status"), report = str(m, "report_html");
    const std::string dir = str(m, "dir");
    std::string lods;
    double changed = kNaN, ssim = kNaN, sil = kNaN;
    for (const auto& l : list(m, "lods")) {
      lods += (lods.empty() ? "" : "<br>") + short_number(num(l, "distance")) + "&nbsp;m: " + count(num(l, "triangles"));
      const json& w = sub(l, "worst");
      auto worse = [](double& acc, double v, bool high) {
        if (std::isfinite(v) && (std::isnan(acc) || (high ? v > acc : v < acc))) acc = v;
      };
      worse(changed, num(w, "changed_fraction"), true);
      worse(ssim, num(w, "ssim_covered"), false);
      worse(sil, num(w, "silhouette_mismatch"), true);
    }
    const std::string status_class = status == "failed" ? "failed" : status == "skipped" ? "skipped" : "done";
    s << "<tr class=\"" << status_class << "\"><td class=\"l\">"
      << (report.empty() ? html_escape(name) : "<a href=\"" + url(report) + "\">" + html_escape(name) + "</a>")
      << "</td><td class=\"l\">" << html_escape(status) << "</td><td class=\"l\">" << lods << "</td><td>"
      << percent(changed) << "</td><td>" << fixed(ssim, 4) << "</td><td>" << percent(sil) << "</td><td>"
      << seconds(num(m, "seconds")) << "</td><td class=\"l\">";
    if (status == "failed")
      s << "<span class=\"error warn\">" << html_escape(str(m, "error")) << "</span>";
    else if (!dir.empty())
      s << "<a href=\"" << url(dir) << "/\">" << html_escape(dir) << "/</a>";
    s << "</td></tr>\n";
  }
  s << "</table>\n" << batch_chart(models) << "<p class=\"muted\">Written by perclod.</p>\n</body>\n</html>\n";
  return s.str();
}

}  // namespace perclod
