// The index page of a batch of runs (perclod/report_html.h).
#include "perclod/report_html.h"

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

#include "html.h"

namespace perclod {
using namespace html;

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
