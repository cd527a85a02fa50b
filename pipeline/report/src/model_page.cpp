// The page of one model's run report (perclod/report_html.h).
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
#include "perclod/simplify.h"

namespace perclod {
using namespace html;
namespace {

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

// The limits in force, in words ("visible difference <= 1x its floor, ...").
// Reports from before a key carry none (NaN): no limit.
std::string limits_text(double max_visible, double max_changed, double max_sil, double min_ssim) {
  std::vector<std::string> parts;
  if (max_visible > 0) parts.push_back("visible difference &le; " + fixed(max_visible, 2) + "&times; its floor");
  if (max_changed < 1) parts.push_back("changed &le; " + percent(max_changed));
  if (max_sil < 1) parts.push_back("silhouette mismatch &le; " + percent(max_sil));
  if (min_ssim > 0) parts.push_back("SSIM &ge; " + fixed(min_ssim, 4));
  if (parts.empty()) return "<p>No limits.";
  std::string s = "<p>Limits: ";
  for (size_t i = 0; i < parts.size(); ++i) s += (i ? ", " : "") + parts[i];
  return s + ".";
}

std::string fidelity_table(const json& lod) {
  const json& fid = sub(lod, "fidelity");
  const json& limits = sub(fid, "limits");
  const auto over = over_limits(fid);
  const double max_changed = num(limits, "max_changed"), max_sil = num(limits, "max_silhouette");
  const double min_ssim = num(limits, "min_ssim");  // NaN in reports from before the key: no limit
  const double max_visible = num(limits, "max_visible");
  std::ostringstream s;
  s << limits_text(max_visible, max_changed, max_sil, min_ssim)
    << " Cells over a limit are <span style=\"background:#ffd7d5;color:#a40e26;font-weight:600\">marked</span>.</p>\n";
  s << "<table class=\"fidelity\"><tr><th class=\"l\">view</th><th class=\"l\">set</th>"
       "<th>visible (&times; floor)</th><th>changed</th><th>SSIM (covered)</th><th>silhouette mismatch</th>"
       "<th>drawn px</th></tr>\n";
  for (const auto& v : list(lod, "lod_vs_original")) {
    const std::string view = str(v, "view");
    auto cell = [&](const char* measure, const std::string& text, bool over_here) {
      return std::string(over_here || over.count({view, measure}) ? "<td class=\"over\">" : "<td>") + text + "</td>";
    };
    const double changed = num(v, "changed_fraction"), sil = num(v, "silhouette_mismatch");
    const double q = num(v, "ssim_covered"), vis = num(v, "visible_ratio");
    s << "<tr><td class=\"l\">" << html_escape(view) << "</td><td class=\"l\">" << html_escape(str(v, "set"))
      << "</td>" << cell("visible_ratio", fixed(vis, 2), max_visible > 0 && vis > max_visible)
      << cell("changed_fraction", percent(changed), changed > max_changed)
      << cell("ssim_covered", fixed(q, 4), q < min_ssim)
      << cell("silhouette_mismatch", percent(sil), sil > max_sil) << "<td>" << count(num(v, "drawn_pixels"))
      << "</td></tr>\n";
  }
  const json& worst = sub(fid, "worst");
  const double wc = num(worst, "changed_fraction"), ws = num(worst, "silhouette_mismatch");
  const double wv = num(worst, "visible_ratio");
  auto open = [](bool over_here) { return over_here ? "<td class=\"over\">" : "<td>"; };
  s << "<tr><th class=\"l\" colspan=\"2\">worst</th>" << open(max_visible > 0 && wv > max_visible) << fixed(wv, 2)
    << "</td>" << open(wc > max_changed) << percent(wc) << "</td>" << open(num(worst, "ssim_covered") < min_ssim)
    << fixed(num(worst, "ssim_covered"), 4) << "</td>" << open(ws > max_sil) << percent(ws)
    << "</td><td></td></tr>\n</table>\n";
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
  // The renders were written unless the labelling says not (reports from
  // before the key have them).
  const json* written = member(lod, "view_images");
  const bool renders = !written || !written->is_boolean() || written->get<bool>();
  std::vector<std::string> order;
  std::map<std::string, std::vector<std::string>> tiles;
  for (const auto& v : list(lod, "views")) {
    const std::string view = str(v, "view"), base = untiled(view);
    if (!tiles.count(base)) order.push_back(base);
    tiles[base].push_back(view);
  }
  if (!renders && marking.empty()) order.clear();  // debug_images: false: no picture of a labelling view
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
      if (renders) s << image(relative(names.view(tile, d, ".png"), names), tile + " render");
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

namespace {

// The run as a whole: the facts table (model, display, tracer, mode, views,
// distances, limits, time), the warnings and the charts.
void write_run_overview(std::ostringstream& s, const json& report, const json& lods) {
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
}

// The summary over distances: one row per LOD, its worst figures against the limits.
void write_lod_summary(std::ostringstream& s, const json& lods, const OutputNames& names) {
  s << "<h2>LODs</h2>\n<table class=\"summary\"><tr><th>distance</th><th>pixel footprint</th><th>triangles</th>"
       "<th>kept</th><th>worst visible (&times; floor)</th><th>worst changed</th><th>lowest SSIM</th><th>worst silhouette</th><th>over limits</th>"
       "<th>time</th><th class=\"l\">LOD file</th></tr>\n";
  for (const auto& l : lods) {
    const json& simp = sub(l, "simplify");
    const json& fid = sub(l, "fidelity");
    const json& worst = sub(fid, "worst");
    const json& limits = sub(fid, "limits");
    const double b = num(simp, "total_before"), a = num(simp, "total_after");
    const double wc = num(worst, "changed_fraction"), ws = num(worst, "silhouette_mismatch");
    const double wv = num(worst, "visible_ratio"), max_visible = num(limits, "max_visible");
    const std::string lod_file = str(l, "lod_file");
    const std::string d = short_number(num(l, "distance"));
    s << "<tr><td><a href=\"#d" << url(d) << "\">" << d << "&nbsp;m</a></td><td>" << fixed(num(l, "pixel_footprint"), 4)
      << "&nbsp;m</td><td>" << count(a) << "</td><td>" << (b > 0 ? percent(a / b, 1) : "&ndash;") << "</td>"
      << (max_visible > 0 && wv > max_visible ? "<td class=\"over\">" : "<td>") << fixed(wv, 2) << "</td>"
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
}

// The facts of one LOD: footprint, samples, vertices, why it stopped, the
// bounds, the times and its files.
std::vector<std::pair<std::string, std::string>> lod_facts(const json& l, const OutputNames& names) {
  const json& simp = sub(l, "simplify");
  const json& bounds = sub(l, "bounds_px");
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
  if (const json* j = member(l, "judged_alone")) {
    std::string text = count(num(*j, "buildings")) + " buildings from " + count(num(*j, "views")) + " views, " +
                       count(num(*j, "within_limits")) + " within the limits";
    if (num(*j, "unchanged") > 0) text += ", " + count(num(*j, "unchanged")) + " of them unchanged (not rendered)";
    if (num(*j, "tightened") > 0) text += ", " + count(num(*j, "tightened")) + " of them made at tighter bounds";
    facts.push_back({"judged alone", text + " (the table lists each building's worst view)"});
    if (const json* searched = member(*j, "searched")) {
      std::string steps;
      for (const json& st : (*searched)["steps"])
        steps += (steps.empty() ? "" : ", ") + count(num(st, "buildings")) + " at " +
                 [](double e) { std::ostringstream o; o << e; return o.str(); }(num(st, "e_imperceptible")) + " px" +
                 (st.value("keep_undisplayable", false) ? " (undisplayable kept)" : "");
      if (num(*searched, "unmet") > 0) steps += "; " + count(num(*searched, "unmet")) + " within the target at none";
      facts.push_back({"bounds per building", steps});
    }
  }
  facts.push_back({"time: total", seconds(num(l, "seconds"))});
  if (const json* stages = member(l, "stage_seconds")) {
    const json& st = *stages;
    std::string label = seconds(num(st, "label"));
    if (num(st, "label_buildings") > 0) label += " (own views of buildings " + seconds(num(st, "label_buildings")) + ")";
    facts.push_back({"time: labelling", label});
    facts.push_back({"time: export", seconds(num(st, "export"))});
  }
  facts.push_back({"time: simplify", seconds(num(simp, "seconds"))});
  facts.push_back({"time: judging", seconds(num(l, "seconds_compare"))});
  for (const char* key : {"lod_file", "labels_file"}) {
    const std::string f = str(l, key);
    if (!f.empty())
      facts.push_back({key == std::string("lod_file") ? "LOD file" : "labels file",
                       "<a href=\"" + url(relative(f, names)) + "\">" + html_escape(file_name(f)) + "</a>"});
  }
  return facts;
}

// One distance's section: its facts, triangles, fidelity, searches,
// labelling and images.
void write_distance_section(std::ostringstream& s, const json& l, const OutputNames& names) {
  const double d = num(l, "distance");
  const json& simp = sub(l, "simplify");
  const std::string tag = short_number(d);
  s << "<section id=\"d" << url(tag) << "\">\n<h2>" << tag << " m</h2>\n";
  if (const json* e = member(l, "empty"); e && e->is_boolean() && e->get<bool>())
    s << "<p class=\"warn\">This LOD is empty: no triangle of the model is displayable at " << tag << " m.</p>\n";
  const std::vector<std::pair<std::string, std::string>> facts = lod_facts(l, names);
  s << "<h3>Triangles</h3>\n" << triangles_table(simp) << facts_table(facts);
  s << "<h3>Fidelity: the LOD against the original, per judged view</h3>\n" << fidelity_table(l);
  s << tries_table(l, "fidelity_search", "Fidelity target search");
  s << tries_table(l, "tighten_to_limits", "Tightened to the limits (the asked bounds first)");
  s << "<h3>Labelling</h3>\n";
  // Labels of buildings alone come from their own views: the whole-model
  // views (if any are listed) were drawn for their pictures only.
  if (const json* c = member(l, "model_views_counted"); c && c->is_boolean() && !c->get<bool>()) {
    size_t views = 0;
    for (const auto& b : list(l, "per_building")) views += size_t(num(b, "views"));
    s << "<p class=\"muted\">Each of the " << list(l, "per_building").size()
      << " buildings was labelled from its own views of it alone (" << views
      << " views in all); the whole-model views count nothing"
      << (list(l, "views").empty() ? "." : " and are listed for their pictures only.") << "</p>\n";
  }
  if (!list(l, "views").empty()) s << label_views_table(l);
  s << images_section(l, d, names);
  s << "</section>\n";
}

}  // namespace

std::string model_report_html(const json& report, const OutputNames& names) {
  const std::string model = str(report, "model").empty() ? names.stem : str(report, "model");
  const json& lods = list(report, "lods");
  std::ostringstream s;
  s << page_head("perclod report: " + model);
  s << "<h1>perclod report: " << html_escape(model) << "</h1>\n";
  s << "<p class=\"muted\">Files of <code>" << html_escape(names.stem) << "</code>; the full figures are in <a href=\""
    << url(relative(names.report(), names)) << "\">" << html_escape(file_name(names.report())) << "</a>.</p>\n";
  write_run_overview(s, report, lods);
  write_lod_summary(s, lods, names);
  for (const auto& l : lods) write_distance_section(s, l, names);
  s << "<p class=\"muted\">Written by perclod.</p>\n</body>\n</html>\n";
  return s.str();
}

void write_model_report_html(const json& report, const OutputNames& names) {
  write_text_atomic(names.report_html(), model_report_html(report, names));
}

}  // namespace perclod
