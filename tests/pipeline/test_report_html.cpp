// The offline HTML pages (perclod/report_html.h): a hand-written run report
// in make_lods' shape goes in; the page must show every distance, the
// triangle counts, every judged view with over-limit cells marked, images by
// relative names OutputNames gives, one chart point per distance, and every
// text escaped. The batch index links done models and shows failures.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>

#include "perclod/report_html.h"
#include "test_util.h"

using namespace perclod;
using json = nlohmann::json;

namespace {

using test::has;

size_t occurrences(const std::string& text, const std::string& part) {
  size_t n = 0;
  for (size_t p = text.find(part); p != std::string::npos; p = text.find(part, p + part.size())) ++n;
  return n;
}

// Every value of `attr`="..." in the page.
std::vector<std::string> attributes(const std::string& html, const std::string& attr) {
  std::vector<std::string> out;
  const std::regex re(attr + "=\"([^\"]*)\"");
  for (auto it = std::sregex_iterator(html.begin(), html.end(), re); it != std::sregex_iterator(); ++it)
    out.push_back((*it)[1]);
  return out;
}

std::string name_of(const std::string& path) { return std::filesystem::path(path).filename().string(); }

json view_figures(const std::string& view, const std::string& set, double changed, double ssim, double silhouette) {
  return {{"view", view},
          {"set", set},
          {"drawn_pixels", 40000},
          {"changed_pixels", size_t(changed * 40000)},
          {"changed_fraction", changed},
          {"ssim_covered", ssim},
          {"covered_pixels_original", 38000},
          {"coverage_changed_pixels", size_t(silhouette * 38000)},
          {"silhouette_mismatch", silhouette}};
}

json label_view(const std::string& view) {
  return {{"view", view},
          {"covered_pixels", 31000},
          {"imperceptible_fraction", 0.4},
          {"levels", 5},
          {"labels", {{"perceptible", 800}, {"imperceptible", 600}, {"undisplayable", 11056}}},
          {"seconds", {{"render", 0.01}, {"perceive", 0.02}, {"trace", 0.03}}}};
}

// Two distances; at 56 m the labelling view "front" is tiled in two, and
// held-out view az22.5el15 is over the changed limit.
json small_report(const OutputNames& n) {
  auto lod = [&](double d, size_t after_p, size_t after_i, size_t after_u, double worst_changed) {
    json views = json::array();
    json label_views = json::array();
    json marking = json::array();
    const std::vector<std::string> tiles =
        d == 56 ? std::vector<std::string>{"front_t0", "front_t1", "back"} : std::vector<std::string>{"front", "back"};
    for (const auto& t : tiles) {
      label_views.push_back(label_view(t));
      views.push_back(view_figures(t, "labelling", 0.004, 0.97, 0.002));
    }
    for (const char* v : {"front", "back"}) {
      marking.push_back(n.view(v, d, "_marking.png"));
      marking.push_back(n.view(v, d, "_marking_near.png"));
    }
    views.push_back(view_figures("az22.5el15", "held_out", worst_changed, 0.91, 0.003));
    json over = json::array();
    if (worst_changed > 0.02)
      over.push_back({{"view", "az22.5el15"}, {"set", "held_out"}, {"measure", "changed_fraction"},
                      {"value", worst_changed}, {"limit", 0.02}});
    const size_t after = after_p + after_i + after_u;
    return json{{"distance", d},
                {"tracer", "octree"},
                {"samples_per_pixel", 4},
                {"views", label_views},
                {"labels", {{"perceptible", 800}, {"imperceptible", 600}, {"undisplayable", 11056}}},
                {"outside_views", 0},
                {"labels_file", n.labels(d)},
                {"marking_renders", marking},
                {"pixel_footprint", d * 0.0005},
                {"lod_file", n.lod(d, "obj")},
                {"simplify",
                 {{"triangles_before", {{"perceptible", 800}, {"imperceptible", 600}, {"undisplayable", 11056}}},
                  {"triangles_after", {{"perceptible", after_p}, {"imperceptible", after_i}, {"undisplayable", after_u}}},
                  {"total_before", 12456},
                  {"total_after", after},
                  {"vertices_before", 7000},
                  {"vertices_after", 900},
                  {"stop_reason", "bound"},
                  {"seconds", 1.5}}},
                {"bounds_px", {{"perceptible", 0.5}, {"imperceptible", 0.5}}},
                {"lod_vs_original", views},
                {"fidelity",
                 {{"worst", {{"changed_fraction", worst_changed}, {"ssim_covered", 0.91}, {"silhouette_mismatch", 0.003}}},
                  {"limits", {{"max_changed", 0.02}, {"max_silhouette", 0.01}}},
                  {"over_limits", over}}},
                {"seconds_compare", 0.7},
                {"seconds", 12.25}};
  };
  return {{"triangles", 12456},
          {"components", 3},
          {"display", {{"name", "paper-19in"}, {"ppd", 42.1}, {"f_max", 21.0}}},
          {"tracer", {{"name", "octree"}, {"build_seconds", 0.3}, {"memory_bytes", 1000}}},
          {"simplify_mode", "fidelity"},
          {"judge_views", {"az22.5el15"}},
          {"over_limits", 1},
          {"warnings", {"out/bldg_lod_56m.obj: from view az22.5el15 (held_out) changed_fraction is 5% (limit 2%)"}},
          {"lods", {lod(56, 700, 321, 0, 0.05), lod(132, 410, 97, 0, 0.01)}},
          {"seconds", 30.5}};
}

}  // namespace

TEST(ReportHtml, NamesThePageAfterTheModelBesideTheJsonReport) {
  const OutputNames n{"out", "bldg"};
  EXPECT_EQ(n.report_html(), "out/bldg_report.html");
  EXPECT_EQ(std::filesystem::path(n.report_html()).parent_path(), std::filesystem::path(n.report()).parent_path());
}

TEST(ReportHtml, ShowsEveryDistanceTriangleCountAndView) {
  const OutputNames n{"out", "bldg"};
  const std::string html = model_report_html(small_report(n), n);
  EXPECT_EQ(html.rfind("<!DOCTYPE html>", 0), 0u);
  EXPECT_TRUE(has(html, "<title>perclod report: bldg</title>"));
  for (const char* section : {"<section id=\"d56\">", "<section id=\"d132\">", "<h2>56 m</h2>", "<h2>132 m</h2>"})
    EXPECT_TRUE(has(html, section)) << section;
  // Triangles before and after, per label and in total.
  for (const char* cell : {"<td>12456</td>", "<td>1021</td>", "<td>507</td>", "<td>700</td>", "<td>321</td>",
                           "<td>410</td>", "<td>97</td>", "<td>11056</td>"})
    EXPECT_TRUE(has(html, cell)) << cell;
  for (const char* label : {">perceptible<", ">imperceptible<", ">undisplayable<"}) EXPECT_TRUE(has(html, label));
  // Every judged view, with its set, at both distances.
  EXPECT_EQ(occurrences(html, "<td class=\"l\">az22.5el15</td><td class=\"l\">held_out</td>"), 2u);
  EXPECT_EQ(occurrences(html, "<td class=\"l\">front_t1</td><td class=\"l\">labelling</td>"), 1u);
  EXPECT_EQ(occurrences(html, "<td class=\"l\">front</td><td class=\"l\">labelling</td>"), 1u);
  // The view over the changed limit is marked at 56 m (5 %), not at 132 m (1 %).
  EXPECT_EQ(occurrences(html, "<td class=\"over\">5.00&nbsp;%</td>"), 3u);  // its row, the worst row, the summary
  EXPECT_FALSE(has(html, "<td class=\"over\">1.00&nbsp;%</td>"));
  EXPECT_TRUE(has(html, "<td>1.00&nbsp;%</td>"));
  EXPECT_TRUE(has(html, "0.9100"));  // SSIM
  // Timings and the warning.
  EXPECT_TRUE(has(html, "12.2&nbsp;s") || has(html, "12.3&nbsp;s"));
  EXPECT_TRUE(has(html, "changed_fraction is 5% (limit 2%)"));
  // Self-contained: no script, nothing fetched from elsewhere.
  EXPECT_FALSE(has(html, "<script"));
  EXPECT_FALSE(has(html, "http://") && has(html, "src=\"http"));
  EXPECT_FALSE(has(html, "https://"));
}

// samples: auto shows as "auto" with what the views took; a number as the
// number.
TEST(ReportHtml, ShowsTheSamplesPerPixelAndWhatAutoChose) {
  const OutputNames n{"out", "bldg"};
  nlohmann::json r = small_report(n);
  r["lods"][1]["samples_per_pixel"] = "auto";
  r["lods"][1]["sampling_chosen"] = {{"16 (grid)", 17}, {"4 (mask per sample)", 4}};
  const std::string html = model_report_html(r, n);
  EXPECT_TRUE(has(html, "auto (16 (grid): 17 views, 4 (mask per sample): 4 views)")) << html;
  EXPECT_EQ(occurrences(html, "samples per pixel"), 2u);
  r["lods"][1]["samples_per_pixel"] = "<auto>";
  EXPECT_TRUE(has(model_report_html(r, n), "&lt;auto&gt;"));
}

TEST(ReportHtml, ImagesAreRelativeNamesOfFilesThePipelineWrites) {
  const OutputNames n{"out/sub", "bldg"};
  const std::string html = model_report_html(small_report(n), n);
  std::set<std::string> expected;
  for (double d : {56.0, 132.0}) {
    for (const char* tile : d == 56 ? std::vector<const char*>{"front_t0", "front_t1", "back"}
                                    : std::vector<const char*>{"front", "back"})
      expected.insert(name_of(n.view(tile, d, ".png")));
    for (const char* v : {"front", "back"})
      for (const char* suffix : {"_marking.png", "_marking_near.png"}) expected.insert(name_of(n.view(v, d, suffix)));
  }
  const std::vector<std::string> srcs = attributes(html, "src");
  const std::set<std::string> found(srcs.begin(), srcs.end());
  EXPECT_EQ(found, expected);
  EXPECT_EQ(srcs.size(), expected.size());
  EXPECT_TRUE(found.count("bldg_front_t1_56m.png"));
  EXPECT_TRUE(found.count("bldg_back_132m_marking_near.png"));
  // Links too: the LOD and labels files by their names in the directory.
  const std::vector<std::string> hrefs = attributes(html, "href");
  const std::set<std::string> links(hrefs.begin(), hrefs.end());
  EXPECT_TRUE(links.count("bldg_lod_56m.obj"));
  EXPECT_TRUE(links.count("bldg_labels_132m.txt"));
  EXPECT_TRUE(links.count("bldg_report.json"));
  for (const auto& h : hrefs) {
    EXPECT_EQ(h.find("out/"), std::string::npos) << h;
    EXPECT_NE(h.rfind("/", 0), 0u) << h;
  }
  // No comparison picture in the report: none shown, and the page says so.
  EXPECT_TRUE(has(html, "No LOD-beside-original pictures in this report"));
}

// With debug_images: false the labelling writes no render ("view_images":
// false, no marking): the page links none, and shows no empty view boxes.
TEST(ReportHtml, LinksNoRenderTheLabellingDidNotWrite) {
  const OutputNames n{"out", "bldg"};
  json report = small_report(n);
  for (auto& lod : report["lods"]) {
    lod["view_images"] = false;
    lod["marking_renders"] = json::array();
  }
  const std::string html = model_report_html(report, n);
  EXPECT_TRUE(attributes(html, "src").empty());
  EXPECT_FALSE(has(html, "Labelling views: render and marking"));
  // The markings alone, when they were written, are still shown.
  report["lods"][0]["marking_renders"] = {n.view("front", 56, "_marking.png")};
  const std::vector<std::string> srcs = attributes(model_report_html(report, n), "src");
  EXPECT_EQ(srcs, std::vector<std::string>{"bldg_front_56m_marking.png"});
}

TEST(ReportHtml, ShowsEveryJudgedViewsComparisonPictureBySet) {
  const OutputNames n{"out", "bldg"};
  json report = small_report(n);
  json& views = report["lods"][0]["lod_vs_original"];
  for (auto& v : views) {
    if (v["view"] == "az22.5el15") v["comparison_image"] = "out/bldg_az22.5el15_56m_lod_vs_original.png";
    if (v["view"] == "back") v["comparison_image"] = "out/bldg_back_56m_lod_vs_original.png";
  }
  const std::string html = model_report_html(report, n);
  EXPECT_TRUE(has(html, "<h3>LOD beside the original</h3>"));
  EXPECT_TRUE(has(html, "<h4>Labelling views</h4>"));
  EXPECT_TRUE(has(html, "<h4>Held-out views (never used for labelling)</h4>"));
  // Relative to the page, with the view's figures as the caption.
  EXPECT_TRUE(has(html, "src=\"bldg_az22.5el15_56m_lod_vs_original.png\""));
  EXPECT_TRUE(has(html, "src=\"bldg_back_56m_lod_vs_original.png\""));
  EXPECT_TRUE(has(html, "az22.5el15: "));
  EXPECT_EQ(occurrences(html, "No LOD-beside-original pictures in this report"), 1u);  // 132 m has none
}

TEST(ReportHtml, ChartsHaveOnePointPerDistance) {
  const OutputNames n{"out", "bldg"};
  json report = small_report(n);
  for (size_t k : {1u, 2u, 3u}) {
    json r = report;
    r["lods"] = json::array();
    const double ds[] = {56, 132, 427};
    for (size_t i = 0; i < k; ++i) {
      json l = report["lods"][i % 2];
      l["distance"] = ds[i];
      r["lods"].push_back(l);
    }
    const std::string html = model_report_html(r, n);
    EXPECT_EQ(occurrences(html, "<svg "), 2u);
    for (const char* series : {"triangles", "changed", "ssim", "silhouette"})
      EXPECT_EQ(occurrences(html, std::string("<circle class=\"pt ") + series + "\""), k) << series << " " << k;
    for (size_t i = 0; i < k; ++i)
      EXPECT_EQ(occurrences(html, "class=\"pt triangles\" data-distance=\"" + std::to_string(int(ds[i])) + "\""), 1u);
    EXPECT_TRUE(has(html, "viewing distance (m"));  // x axis label
    EXPECT_TRUE(has(html, ">LOD</text>"));          // legend
    EXPECT_EQ(has(html, "log scale"), k == 3);      // 56..427 spans a factor of 3 or more, 56..132 not
  }
  // A triangle count's point sits higher (smaller y) than a smaller count's.
  const std::string html = model_report_html(report, n);
  const std::regex pt("class=\"pt triangles\" data-distance=\"(\\d+)\" cx=\"([0-9.]+)\" cy=\"([0-9.]+)\"");
  std::map<std::string, double> cy;
  for (auto it = std::sregex_iterator(html.begin(), html.end(), pt); it != std::sregex_iterator(); ++it)
    cy[(*it)[1]] = std::stod((*it)[3]);
  ASSERT_EQ(cy.size(), 2u);
  EXPECT_LT(cy["56"], cy["132"]);  // 1021 triangles above 507
}

// min_ssim marks the SSIM cells below it (view row, worst row, summary row)
// and joins the limits line; a report without the key marks none.
TEST(ReportHtml, MarksSsimBelowMinSsimOnlyWhereALimitIsSet) {
  const OutputNames n{"out", "bldg"};
  nlohmann::json r = small_report(n);
  auto marked = [](const std::string& html) {
    size_t k = 0;
    for (size_t at = html.find("<td class=\"over\">0.9100</td>"); at != std::string::npos;
         at = html.find("<td class=\"over\">0.9100</td>", at + 1))
      ++k;
    return k;
  };
  EXPECT_EQ(marked(model_report_html(r, n)), 0u);
  r["lods"][1]["fidelity"]["limits"]["min_ssim"] = 0.95;  // the held-out view at 132 m has 0.91
  const std::string html = model_report_html(r, n);
  EXPECT_EQ(marked(html), 3u) << html;
  EXPECT_TRUE(has(html, "SSIM &ge; 0.9500"));
  r["lods"][1]["fidelity"]["limits"]["min_ssim"] = 0.9;
  EXPECT_EQ(marked(model_report_html(r, n)), 0u);
}

// The default limit (0.4.0) is the perceptual one: the visible column is
// marked over max_visible, the limits line names it alone, and changed
// pixels over 2% are no longer marked when max_changed is 1 (no limit).
TEST(ReportHtml, MarksTheVisibleRatioOverMaxVisibleAndOnlyTheLimitsSet) {
  const OutputNames n{"out", "bldg"};
  nlohmann::json r = small_report(n);
  for (auto& lod : r["lods"]) {
    lod["fidelity"]["limits"] = {{"max_changed", 1}, {"max_silhouette", 1}, {"min_ssim", 0}, {"max_visible", 1}};
    lod["fidelity"]["over_limits"] = nlohmann::json::array();  // what run finds against these limits
  }
  r["lods"][0]["lod_vs_original"][0]["visible_ratio"] = 1.5;
  r["lods"][0]["fidelity"]["worst"]["visible_ratio"] = 1.5;
  const std::string html = model_report_html(r, n);
  EXPECT_EQ(occurrences(html, "<td class=\"over\">1.50</td>"), 3u) << html;  // its row, the worst row, the summary
  EXPECT_TRUE(has(html, "Limits: visible difference &le; 1.00&times; its floor."));
  EXPECT_FALSE(has(html, "changed &le;"));
  EXPECT_FALSE(has(html, "<td class=\"over\">5.00&nbsp;%</td>"));
  r["lods"][0]["fidelity"]["limits"]["max_visible"] = 0;  // no limit at all
  EXPECT_TRUE(has(model_report_html(r, n), "<p>No limits."));
}

// A fidelity_target search: one row per try, with the bounds it used and
// what it did with undisplayable triangles.
TEST(ReportHtml, ShowsEachFidelitySearchTryWithItsBounds) {
  const OutputNames n{"out", "bldg"};
  nlohmann::json r = small_report(n);
  const nlohmann::json worst = {{"changed_fraction", 0.031}, {"ssim_covered", 0.99}, {"silhouette_mismatch", 0.0}};
  r["lods"][0]["fidelity_search"] = {{{"e_imperceptible", 0.25},
                                      {"e_perceptible", 0.25},
                                      {"undisplayable", "deleted"},
                                      {"triangles", 900},
                                      {"worst", worst},
                                      {"met", false}},
                                     {{"e_imperceptible", 0.125},
                                      {"e_perceptible", 0.125},
                                      {"undisplayable", "collapsed"},
                                      {"e_undisplayable", 0.125},
                                      {"triangles", 1200},
                                      {"worst", worst},
                                      {"met", true},
                                      {"kept", true}}};
  const std::string html = model_report_html(r, n);
  EXPECT_TRUE(has(html, "Fidelity target search"));
  EXPECT_TRUE(has(html, "<th>e_perceptible (px)</th>"));
  EXPECT_TRUE(has(html, "<tr><td>0.125</td><td>0.125</td><td class=\"l\">collapsed within 0.125&nbsp;px</td><td>1200</td>"))
      << html;
  EXPECT_TRUE(has(html, "<tr><td>0.250</td><td>0.250</td><td class=\"l\">deleted</td><td>900</td>")) << html;
  EXPECT_TRUE(has(html, "<th class=\"l\">kept</th>")) << html;
  EXPECT_TRUE(has(html, "<td class=\"l\">yes</td><td class=\"l\">written</td></tr>")) << html;  // the try written
  EXPECT_TRUE(has(html, "<td class=\"l\">no</td><td class=\"l\"></td></tr>")) << html;
  EXPECT_FALSE(has(html, "Tightened to the limits"));
  // tighten_to_limits' tries get the same table under their own title.
  r["lods"][0]["tighten_to_limits"] = r["lods"][0]["fidelity_search"];
  r["lods"][0].erase("fidelity_search");
  const std::string tightened = model_report_html(r, n);
  EXPECT_FALSE(has(tightened, "Fidelity target search"));
  EXPECT_TRUE(has(tightened, "Tightened to the limits (the asked bounds first)"));
  EXPECT_TRUE(has(tightened, "<tr><td>0.250</td><td>0.250</td><td class=\"l\">deleted</td><td>900</td>")) << tightened;
}

// keep_undisplayable: auto: the LOD's facts say what it did with
// undisplayable triangles and the exposure it decided from.
TEST(ReportHtml, ShowsWhatAutoDidWithUndisplayableTriangles) {
  const OutputNames n{"out", "bldg"};
  nlohmann::json r = small_report(n);
  r["lods"][0]["bounds_px"] = {{"perceptible", 0.5}, {"imperceptible", 0.5}, {"undisplayable", "collapsed"},
                               {"e_undisplayable", 4}, {"undisplayable_exposure", 0.00855}};
  const std::string html = model_report_html(r, n);
  EXPECT_TRUE(has(html, "undisplayable collapsed within 4.000&nbsp;px (auto: they are 0.855% of what the views "
                        "between the labelling ones see)"))
      << html;
}

// explain: true: the LOD's facts say why it stopped; without it, nothing.
TEST(ReportHtml, SaysWhyTheLodStoppedWhenExplained) {
  const OutputNames n{"out", "bldg"};
  nlohmann::json r = small_report(n);
  EXPECT_FALSE(has(model_report_html(r, n), "half-edges left"));
  r["lods"][1]["simplify"]["refused"] = {{"bound_or_locked", 11489}, {"valence", 0}, {"topology", 3416},
                                         {"shape", 53},           {"legal", 0},   {"total", 14958}};
  const std::string html = model_report_html(r, n);
  EXPECT_TRUE(has(html, "<td>stopped</td><td class=\"l\">14958 half-edges left: 11489 locked or over their "
                        "bound, 53 refused by shape (normal change, sliver, area), 3416 by topology, 0 by the "
                        "valence cap</td>"))
      << html;
  EXPECT_FALSE(has(html, "legal only after"));
}

TEST(ReportHtml, EscapesEveryText) {
  const OutputNames n{"out", "<a&b>"};
  json report = small_report(n);
  report["model"] = "models/<a&b>.obj";
  report["warnings"] = {"view \"<script>alert(1)</script>\" & co"};
  report["lods"][0]["lod_vs_original"][0]["view"] = "x<y>";
  const std::string html = model_report_html(report, n);
  EXPECT_TRUE(has(html, "<title>perclod report: models/&lt;a&amp;b&gt;.obj</title>"));
  EXPECT_TRUE(has(html, "<h1>perclod report: models/&lt;a&amp;b&gt;.obj</h1>"));
  EXPECT_TRUE(has(html, "&lt;script&gt;alert(1)&lt;/script&gt;"));
  EXPECT_TRUE(has(html, "&quot;"));
  EXPECT_TRUE(has(html, "x&lt;y&gt;"));
  EXPECT_FALSE(has(html, "<a&b>"));
  EXPECT_FALSE(has(html, "<script"));
  EXPECT_FALSE(has(html, "x<y>"));
  // File names in src/href are percent-encoded: the browser finds "<a&b>_back_56m.png".
  EXPECT_TRUE(has(html, "src=\"%3Ca%26b%3E_back_56m.png\""));
  EXPECT_EQ(html_escape("<a&b> \"'"), "&lt;a&amp;b&gt; &quot;&#39;");
  // Without a "model" key the title is the stem, escaped too.
  report.erase("model");
  EXPECT_TRUE(has(model_report_html(report, n), "<title>perclod report: &lt;a&amp;b&gt;</title>"));
}

TEST(ReportHtml, SurvivesAReportWithoutLods) {
  const OutputNames n{"out", "bldg"};
  std::string html;
  ASSERT_NO_THROW(html = model_report_html(json::object(), n));
  EXPECT_TRUE(has(html, "</html>"));
  EXPECT_FALSE(has(html, "<svg"));
  ASSERT_NO_THROW(html = model_report_html(json{{"lods", {{{"distance", "oops"}}}}}, n));
  ASSERT_NO_THROW(html = batch_index_html(json::object()));
  EXPECT_TRUE(has(html, "</html>"));
}

TEST(ReportHtml, WritesThePageAtomicallyNextToTheJsonReport) {
  test::TempDir dir("report-html");
  const OutputNames n{dir.path.string(), "bldg"};
  const json report = small_report(n);
  write_model_report_html(report, n);
  std::ifstream f(dir / "bldg_report.html");
  ASSERT_TRUE(f.good());
  std::stringstream text;
  text << f.rdbuf();
  EXPECT_EQ(text.str(), model_report_html(report, n));
  size_t files = 0;
  for (const auto& e : std::filesystem::directory_iterator(dir.path)) {
    ++files;
    EXPECT_EQ(e.path().filename().string().rfind(".tmp-", 0), std::string::npos);
  }
  EXPECT_EQ(files, 1u);
  // Refs in a page written to an absolute directory are still relative.
  for (const auto& src : attributes(text.str(), "src")) EXPECT_EQ(src.find('/'), std::string::npos) << src;
}

TEST(ReportHtml, BatchIndexLinksDoneModelsAndShowsFailures) {
  const json summary = {
      {"models",
       {{{"name", "bldg_4018215"},
         {"status", "done"},
         {"dir", "bldg_4018215"},
         {"report_html", "bldg_4018215/bldg_4018215_report.html"},
         {"seconds", 95.5},
         {"lods",
          {{{"distance", 56}, {"triangles", 3210},
            {"worst", {{"changed_fraction", 0.012}, {"ssim_covered", 0.93}, {"silhouette_mismatch", 0.004}}}},
           {{"distance", 427}, {"triangles", 640},
            {"worst", {{"changed_fraction", 0.031}, {"ssim_covered", 0.88}, {"silhouette_mismatch", 0.002}}}}}}},
        {{"name", "broken<1>"},
         {"status", "failed"},
         {"error", "models/broken.obj: cannot read: No such file or directory & more"},
         {"dir", "broken"},
         {"seconds", 0.1},
         {"lods", json::array()}},
        {{"name", "old_one"}, {"status", "skipped"}, {"dir", "old_one"}, {"seconds", 0}},
        {{"name", "second"},
         {"status", "done"},
         {"dir", "second"},
         {"report_html", "second/second_report.html"},
         {"seconds", 40},
         {"lods", {{{"distance", 56}, {"triangles", 999}, {"worst", json::object()}}}}}}},
      {"done", 2},
      {"skipped", 1},
      {"failed", 1},
      {"seconds", 135.6}};
  const std::string html = batch_index_html(summary);
  EXPECT_EQ(html.rfind("<!DOCTYPE html>", 0), 0u);
  EXPECT_TRUE(has(html, "<a href=\"bldg_4018215/bldg_4018215_report.html\">bldg_4018215</a>"));
  EXPECT_TRUE(has(html, "<a href=\"second/second_report.html\">second</a>"));
  const std::vector<std::string> hrefs = attributes(html, "href");
  EXPECT_EQ(std::count_if(hrefs.begin(), hrefs.end(), [](const std::string& h) { return has(h, "_report.html"); }), 2);
  // The failure: its row, its (escaped) name and error, no link to a report.
  EXPECT_TRUE(has(html, "<tr class=\"failed\"><td class=\"l\">broken&lt;1&gt;</td><td class=\"l\">failed</td>"));
  EXPECT_TRUE(has(html, "models/broken.obj: cannot read: No such file or directory &amp; more"));
  EXPECT_FALSE(has(html, "broken<1>"));
  EXPECT_TRUE(has(html, "<tr class=\"skipped\"><td class=\"l\">old_one</td>"));
  EXPECT_TRUE(has(html, "2 done, 1 skipped, <span class=\"warn\">1 failed</span>"));
  // Per model its LODs, and the worst over them.
  EXPECT_TRUE(has(html, "56&nbsp;m: 3210<br>427&nbsp;m: 640"));
  EXPECT_TRUE(has(html, "<td>3.10&nbsp;%</td><td>0.8800</td><td>0.40&nbsp;%</td>"));
  // One bar per LOD, two distances in the legend.
  EXPECT_EQ(occurrences(html, "<rect class=\"bar\""), 3u);
  EXPECT_TRUE(has(html, "bldg_4018215 at 427 m: 640 triangles"));
  EXPECT_TRUE(has(html, ">56 m</text>"));
  EXPECT_TRUE(has(html, ">427 m</text>"));
  EXPECT_FALSE(has(html, "<script"));
}
