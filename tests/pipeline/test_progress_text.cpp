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
  l.progress.lod_made(r);
  ASSERT_EQ(l.got.size(), 1u);
  EXPECT_EQ(l.got[0], "  LOD 56 m: 100 -> 40 triangles (40%); worst of 3 views: 1.25% changed, SSIM 0.99, "
                      "silhouette 0.1%, visible 0.75x the floor; out/m_lod_56m.obj");
  r.simplify.refused_counted = true;
  r.simplify.refused.shape = 2;
  l.progress.lod_made(r);
  ASSERT_EQ(l.got.size(), 3u);
  EXPECT_EQ(l.got[2].rfind("  LOD 56 m stopped: 2 half-edges left:", 0), 0u) << l.got[2];
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
