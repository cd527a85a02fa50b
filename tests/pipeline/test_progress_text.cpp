// The progress lines perclod prints (perclod/progress_text.h): one line per
// event, worded from the typed results the stages report.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "perclod/progress_text.h"

using namespace perclod;

namespace {

struct Lines {
  std::vector<std::string> got;
  TextProgress progress{[this](const std::string& s) { got.push_back(s); }};
};

TEST(ProgressText, ALodLineGivesCountsWorstFiguresAndWhyItStopped) {
  Lines l;
  LodResult r;
  r.distance = 56;
  r.lod_file = "out/m_lod_56m.obj";
  r.simplify.triangles_before = {10, 70, 20};
  r.simplify.triangles_after = {10, 30, 0};
  r.views.resize(3);
  r.fidelity.worst = {0.0125, 0.99, 0.001, 0.75};
  r.seconds = 12.5, r.seconds_label = 9, r.seconds_simplify = 0.25, r.seconds_compare = 3, r.seconds_export = 0.125;
  r.labelling.per_building = true;
  r.labelling.seconds_buildings = 6;
  l.progress.lod_made(r);
  ASSERT_EQ(l.got.size(), 2u);
  EXPECT_EQ(l.got[0], "  LOD 56 m: 100 -> 40 triangles (40%); worst of 3 views: 1.25% changed, SSIM 0.99, "
                      "silhouette 0.1%, visible 0.75x the floor; out/m_lod_56m.obj");
  EXPECT_EQ(l.got[1], "  LOD 56 m took 12.5 s: label 9 s (own views 6 s), simplify 0.25 s, judge 3 s, export 0.125 s");
  r.simplify.refused_counted = true;
  r.simplify.refused.shape = 2;
  l.progress.lod_made(r);
  ASSERT_EQ(l.got.size(), 5u);
  EXPECT_EQ(l.got[3].rfind("  LOD 56 m stopped: 2 half-edges left:", 0), 0u) << l.got[3];
  EXPECT_EQ(l.got[4], l.got[1]);
}

// A building's line, and a group's, with the time left once the pace is known.
TEST(ProgressText, BuildingAndGroupLinesSayWhatIsLeft) {
  Lines l;
  BuildingLabelling b{"NL.1", 1, 21, 2, 0.5, {}};
  l.progress.building_labelled(0, 3, b);
  BuildingLabelling g{"NL.2", 4, 34, 0, 1.25, {}};
  l.progress.building_labelled(1, 3, g);
  l.progress.building_labelled(2, 3, b);
  ASSERT_EQ(l.got.size(), 3u);
  EXPECT_EQ(l.got[0], "  building 1/3 NL.1: 21 views, 0.5 s; 2 with the eye inside another building's box");
  EXPECT_EQ(l.got[1].rfind("  group 2/3 (4 buildings from NL.2): 34 views, 1.25 s (about ", 0), 0u) << l.got[1];
  EXPECT_NE(l.got[1].find(" left)"), std::string::npos) << l.got[1];
  EXPECT_EQ(l.got[2].find("left"), std::string::npos) << "nothing is left after the last";
}

TEST(ProgressText, ATryNamesItsBoundsAndWhetherItMet) {
  Lines l;
  LodTry t;
  t.e_imperceptible = 8, t.e_perceptible = 0.5, t.triangles = 1234;
  t.undisplayable = {false, 4, -1};
  t.worst = {0.02, 0.98, 0.005, 1.5};
  t.met = true;
  l.progress.lod_tried("fidelity target", 132, t);
  ASSERT_EQ(l.got.size(), 1u);
  EXPECT_EQ(l.got[0], "  fidelity target at 132 m: e_imperceptible 8 px, e_perceptible 0.5 px, undisplayable "
                      "collapsed within 4 px -> 1234 triangles, worst 2% changed, SSIM 0.98, silhouette 0.5%, visible 1.5x "
                      "the floor (met)");
}

TEST(ProgressText, AViewLineSumsItsPassesAndNamesAutosChoice) {
  Lines l;
  ViewLabelling v;
  v.covered_pixels = 5000;
  v.imperceptible_fraction = 0.25;
  v.seconds = {{"render", 0.010}, {"perceive", 0.020}, {"trace", 0.0305}};
  v.passes = 4;
  v.sampling = "4 (mask per sample)";
  l.progress.view_labelled("+x", 56, v);
  ASSERT_EQ(l.got.size(), 1u);
  EXPECT_EQ(l.got[0], "  +x at 56 m: 5000 px, 25% imperceptible in the first of 4 passes; all passes: render 10 ms, "
                      "perceive 20 ms, trace 30.5 ms (samples 4 (mask per sample))");
}

TEST(ProgressText, BatchLinesCarryTheTimeLeftOnlyWhenKnown) {
  EXPECT_EQ(batch_line(0, 3, "a", "start: a.obj", -1), "[1/3 a] start: a.obj");
  EXPECT_EQ(batch_line(2, 3, "c", "done", 125), "[3/3 c] done  (about 2m05s left)");
  EXPECT_EQ(format_seconds(89), "89s");
  EXPECT_EQ(format_seconds(90), "1m30s");
  EXPECT_EQ(format_seconds(5400), "1h30m");
}

}  // namespace
