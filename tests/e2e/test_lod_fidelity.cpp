// A LOD judged from the views it was made for (compare_lod_views), on the
// bundled Ingolstadt building: the measure sees nothing where nothing
// changed and sees a removed part, and the paper-mode LOD at 56 m keeps what
// the views show while holding far fewer triangles than the input.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <tuple>
#include <vector>

#include "perclod/load.h"
#include "perclod/judge.h"
#include "perclod/label.h"
#include "perclod/report_json.h"
#include "cli_util.h"

namespace perclod {
namespace {

using perclod::test::kBuilding;

struct Labelled {
  Scene scene;
  LabelJob job;
  LabelResult result;
};

// All four facades of the building labelled at 56 m; `renderer` holds it.
Labelled label_building(Renderer& renderer) {
  Labelled l;
  l.scene = load_scene(kBuilding);
  l.job.up = UpAxis::Z;
  l.job.views = parse_views("facades", UpAxis::Z);
  l.job.distance = 56;
  OctreeTracer tracer(l.scene);
  l.result = label_scene(renderer, l.scene, tracer, l.job);
  return l;
}

// The building without its perceptible triangles: a change every view sees.
Scene without_perceptible(const Labelled& l) {
  Scene cut = l.scene;
  cut.indices.clear();
  cut.component.clear();
  cut.material.clear();
  for (size_t t = 0; t < l.scene.triangle_count(); ++t) {
    if (l.result.labels[t] == Label::Perceptible) continue;
    for (int k = 0; k < 3; ++k) cut.indices.push_back(l.scene.indices[3 * t + k]);
    if (!l.scene.component.empty()) cut.component.push_back(l.scene.component[t]);
    if (!l.scene.material.empty()) cut.material.push_back(l.scene.material[t]);
  }
  return cut;
}

size_t total(const std::vector<ViewFigures>& views, size_t ViewFigures::*field) {
  size_t n = 0;
  for (const ViewFigures& v : views) n += v.*field;
  return n;
}

// judge_views flags each view over a limit; min_ssim (off by default) flags
// SSIMs below it, and the worst figures are the same either way.
TEST(LodFidelity, JudgeViewsFlagsEachMeasureAgainstItsLimit) {
  auto view = [](const char* name, double changed, double ssim, double silhouette) {
    ViewFigures v;
    v.view = name, v.set = "held_out";
    v.changed_fraction = changed, v.ssim_covered = ssim, v.silhouette_mismatch = silhouette;
    return v;
  };
  const std::vector<ViewFigures> views = {view("a", 0.01, 0.99, 0.0), view("b", 0.03, 0.96, 0.0),
                                          view("c", 0.0, 0.94, 0.02)};
  // By default only the perceptual limit holds: these views see nothing
  // (visible ratio 0), whatever their raw figures.
  EXPECT_TRUE(judge_views(views, FidelityLimits{}).met());
  const FidelityLimits raw{0.02, 0.01, 0, 0};  // limits on changed pixels and silhouette
  const Judgement by_default = judge_views(views, raw);
  ASSERT_EQ(by_default.over_limits.size(), 2u);
  EXPECT_FALSE(by_default.met());
  EXPECT_EQ(by_default.over_limits[0].view, "b");
  EXPECT_EQ(by_default.over_limits[0].measure, "changed_fraction");
  EXPECT_EQ(by_default.over_limits[1].view, "c");
  EXPECT_EQ(by_default.over_limits[1].measure, "silhouette_mismatch");
  EXPECT_EQ(by_default.worst.ssim_covered, 0.94);
  EXPECT_EQ(by_default.worst.changed_fraction, 0.03);
  EXPECT_EQ(by_default.worst.silhouette_mismatch, 0.02);
  EXPECT_EQ(by_default.limits.min_ssim, 0.0);

  FidelityLimits ssim = raw;
  ssim.min_ssim = 0.95;
  const Judgement judged = judge_views(views, ssim);
  EXPECT_EQ(judged.worst.ssim_covered, by_default.worst.ssim_covered);
  EXPECT_EQ(judged.worst.changed_fraction, by_default.worst.changed_fraction);
  const std::vector<OverLimit>& over = judged.over_limits;
  ASSERT_EQ(over.size(), 3u);
  EXPECT_EQ(over[1].view, "c");  // b's 0.96 is within it
  EXPECT_EQ(over[1].measure, "ssim_covered");
  EXPECT_EQ(over[1].value, 0.94);
  EXPECT_EQ(over[1].limit, 0.95);
  EXPECT_TRUE(judge_views({view("d", 0.0, 1.0, 0.0)}, ssim).met());
}

TEST(LodFidelity, SeesNoChangeInTheOriginalAndSeesARemovedPart) {
  Renderer renderer;
  Labelled l = label_building(renderer);
  ASSERT_EQ(l.result.views.size(), 4u);

  std::vector<ViewFigures> same = compare_lod_views(renderer, l.scene, l.result.views, judge_settings_of(l.job));
  ASSERT_EQ(same.size(), 4u);
  EXPECT_GT(total(same, &ViewFigures::drawn_pixels), 100000u);
  EXPECT_EQ(total(same, &ViewFigures::changed_pixels), 0u);
  EXPECT_EQ(total(same, &ViewFigures::coverage_changed_pixels), 0u);

  // Drop every perceptible triangle: the views must notice.
  const Scene cut = without_perceptible(l);
  std::vector<ViewFigures> missing = compare_lod_views(renderer, cut, l.result.views, judge_settings_of(l.job));
  EXPECT_GT(total(missing, &ViewFigures::changed_pixels), total(missing, &ViewFigures::drawn_pixels) / 4);
  EXPECT_GT(total(missing, &ViewFigures::coverage_changed_pixels), 10000u);
}

// The perceptual floor: moving the original a quarter pixel is visible
// (every facade has a floor above 0), the original against itself is 0x it,
// a LOD without its perceptible triangles is many times over it, and
// judge_views flags that only when max_visible is set.
TEST(LodFidelity, VisibleDifferenceIsMeasuredAgainstTheQuarterPixelFloor) {
  Renderer renderer;
  Labelled l = label_building(renderer);
  measure_floors(renderer, l.scene, l.result.views, judge_settings_of(l.job));
  for (const ViewRecord& v : l.result.views) {
    EXPECT_GT(v.visible_floor, 0.5) << v.view;
    EXPECT_GT(v.visible_floor_local, v.visible_floor) << v.view;  // a square at an edge sees the shift in full
  }
  for (const ViewFigures& v : compare_lod_views(renderer, l.scene, l.result.views, judge_settings_of(l.job))) {
    EXPECT_EQ(v.visible_difference, 0.0) << v.view;
    EXPECT_EQ(v.visible_ratio, 0.0) << v.view;
    EXPECT_EQ(v.visible_local_ratio, 0.0) << v.view;
  }
  const Scene cut = without_perceptible(l);
  const std::vector<ViewFigures> missing = compare_lod_views(renderer, cut, l.result.views, judge_settings_of(l.job));
  for (const ViewFigures& v : missing) {
    EXPECT_GT(v.visible_ratio, 2.0) << v.view;
    EXPECT_NEAR(v.visible_ratio, v.visible_difference / v.visible_floor, 1e-9) << v.view;
    EXPECT_NEAR(v.visible_local_ratio, v.visible_local / v.visible_floor_local, 1e-9) << v.view;
    EXPECT_GT(v.visible_local_ratio, 1.0) << v.view;  // a missing part is over the local floor too
  }
  EXPECT_TRUE(judge_views(missing, FidelityLimits{1, 1, 0, 0}).met());  // no visible limit
  const Judgement j = judge_views(missing, FidelityLimits{1, 1, 0, 1.0});
  ASSERT_EQ(j.over_limits.size(), missing.size());
  EXPECT_EQ(j.over_limits[0].measure, "visible_ratio");
  double worst = 0;
  for (const ViewFigures& v : missing) worst = std::max(worst, v.visible_ratio);
  EXPECT_EQ(j.worst.visible_ratio, worst);
  double worst_local = 0;
  for (const ViewFigures& v : missing) worst_local = std::max(worst_local, v.visible_local_ratio);
  EXPECT_EQ(j.worst.visible_local_ratio, worst_local);
  // max_visible_local (off by default) flags the local figure alone.
  const Judgement local = judge_views(missing, FidelityLimits{1, 1, 0, 0, 1.0});
  ASSERT_EQ(local.over_limits.size(), missing.size());
  EXPECT_EQ(local.over_limits[0].measure, "visible_local_ratio");
  EXPECT_EQ(FidelityLimits{}.max_visible_local, 0.0);
}

// Floors and figures do not depend on how many threads work on the views
// (JudgeSettings::workers) or on whether the renders overlap that work.
TEST(LodFidelity, JudgingOnSeveralThreadsGivesTheFiguresOfOne) {
  Renderer renderer;
  Labelled l = label_building(renderer);
  const Scene cut = without_perceptible(l);
  JudgeSettings one = judge_settings_of(l.job);
  one.overlap = false;
  std::vector<ViewRecord> records = l.result.views;
  measure_floors(renderer, l.scene, records, one);
  const std::vector<ViewFigures> expected = compare_lod_views(renderer, cut, records, one);
  for (size_t workers : {1u, 3u}) {  // (every other judging test runs one per CPU)
    SCOPED_TRACE(std::to_string(workers) + " workers");
    JudgeSettings how = one;
    how.overlap = true;
    how.workers = workers;
    std::vector<ViewRecord> again = l.result.views;
    measure_floors(renderer, l.scene, again, how);
    ASSERT_EQ(again.size(), records.size());
    for (size_t k = 0; k < records.size(); ++k) {
      EXPECT_EQ(again[k].visible_floor, records[k].visible_floor) << k;
      EXPECT_EQ(again[k].visible_floor_local, records[k].visible_floor_local) << k;
    }
    std::vector<Rgb8Image> pictures;
    const std::vector<ViewFigures> got = compare_lod_views(renderer, cut, again, how, &pictures);
    ASSERT_EQ(got.size(), expected.size());
    EXPECT_EQ(pictures.size(), expected.size());
    for (size_t k = 0; k < got.size(); ++k) {
      EXPECT_EQ(got[k].view, expected[k].view);
      EXPECT_EQ(got[k].changed_pixels, expected[k].changed_pixels) << k;
      EXPECT_EQ(got[k].visible_difference, expected[k].visible_difference) << k;
      EXPECT_EQ(got[k].visible_ratio, expected[k].visible_ratio) << k;
      EXPECT_EQ(got[k].ssim_covered, expected[k].ssim_covered) << k;
    }
  }
}

// A view where the quarter-pixel shift changes nothing (here: the camera
// turned away, nothing drawn) has no floor of its own; it gets half the
// median floor of the other views, not 0.
TEST(LodFidelity, AViewWithoutAFloorOfItsOwnGetsHalfTheMedian) {
  Renderer renderer;
  Labelled l = label_building(renderer);
  Camera away = l.result.views[0].camera;
  away.forward = -away.forward, away.right = -away.right;
  RenderOutput img;
  renderer.set_scene(l.scene);
  renderer.render(away, img);
  std::vector<uint8_t> background;
  background_of(img, background);
  l.result.views.push_back(view_record("away", away, img.rgb, background, "held_out"));
  measure_floors(renderer, l.scene, l.result.views, judge_settings_of(l.job));
  std::vector<double> floors;
  for (size_t k = 0; k + 1 < l.result.views.size(); ++k) floors.push_back(l.result.views[k].visible_floor);
  std::sort(floors.begin(), floors.end());
  const double median_of_five = floors[1];  // of 0 (the away view's own) and the four facades' floors
  EXPECT_GT(floors[0], 0.5);
  EXPECT_NEAR(l.result.views.back().visible_floor, kFloorOfMedian * median_of_five, 1e-9);
}

TEST(LodFidelity, PaperLodAt56mHoldsAFractionOfTheInputAndLooksAlike) {
  Renderer renderer;
  Labelled l = label_building(renderer);
  SimplifyOptions opt;  // paper: undisplayable triangles deleted, imperceptible ones collapsed
  opt.pixel_footprint = l.result.views[0].camera.pixel_footprint(56);
  SimplifyStats st;
  Scene lod = simplify(l.scene, l.result.labels, opt, &st);
  EXPECT_EQ(st.triangles_after[0], st.triangles_before[0]);
  EXPECT_EQ(st.triangles_after[2], 0u);
  EXPECT_GT(st.undisplayable_faces_deleted, 0u);
  // Measured 3,039 of 12,456 (24%): nothing but perceptible triangles and
  // the imperceptible ones collapses cannot reach.
  EXPECT_LT(lod.triangle_count(), l.scene.triangle_count() / 3);

  std::vector<ViewFigures> views = compare_lod_views(renderer, lod, l.result.views, judge_settings_of(l.job));
  for (const auto& v : views) {
    std::printf("  %s: %zu drawn, %zu changed after vision simulation, %zu coverage\n",
                v.view.c_str(), v.drawn_pixels,
                v.changed_pixels, v.coverage_changed_pixels);
    // Measured 0-2.8% per view; coverage changes under 0.2% of drawn pixels.
    EXPECT_LT(v.changed_fraction, 0.05) << v.view;
    EXPECT_LT(v.coverage_changed_pixels, 0.003 * v.drawn_pixels) << v.view;
  }

  // Plain quadric simplification aimed at the same count, labels ignored,
  // changes far more of what the views show (measured 13,012 changed pixels
  // against 383,057; qem stops short at 10,324 triangles on this model).
  SimplifyOptions qem;
  qem.mode = SimplifyMode::Qem;
  qem.target_triangles = lod.triangle_count();
  SimplifyStats qst;
  Scene plain = simplify(l.scene, l.result.labels, qem, &qst);
  std::vector<ViewFigures> plain_views = compare_lod_views(renderer, plain, l.result.views, judge_settings_of(l.job));
  std::printf("  changed pixels, all views: paper %zu (%zu triangles), qem %zu (%zu triangles)\n",
              total(views, &ViewFigures::changed_pixels), lod.triangle_count(), total(plain_views, &ViewFigures::changed_pixels),
              plain.triangle_count());
  EXPECT_LT(total(views, &ViewFigures::changed_pixels), total(plain_views, &ViewFigures::changed_pixels));
}

// The default job at 56 m: labels from the default view set (the view from
// straight above among them), the fidelity LOD judged from those views and
// the held-out views.
TEST(LodFidelity, DefaultLodAt56mMeetsTheLimitsFromEveryViewIncludingAbove) {
  Renderer renderer;
  Scene scene = load_scene(kBuilding);
  LabelJob job;
  job.up = UpAxis::Z;
  job.views = parse_views(kDefaultViews, UpAxis::Z);
  job.samples = kDefaultSamples;
  job.distance = 56;
  OctreeTracer tracer(scene);
  LabelResult lr = label_scene(renderer, scene, tracer, job);
  std::vector<ViewRecord> judged = lr.views;
  for (auto& r : record_views(renderer, scene, parse_views(kDefaultJudgeViews, UpAxis::Z), framing_of(job)))
    judged.push_back(std::move(r));
  ASSERT_EQ(judged.size(), 21u + 9u);

  SimplifyOptions opt;
  opt.mode = SimplifyMode::Fidelity;
  opt.pixel_footprint = display_pixel_footprint(job.display, 56);
  SimplifyStats st;
  Scene lod = simplify(scene, lr.labels, opt, &st);
  // Measured 4,831 of 12,456 triangles.
  EXPECT_LT(lod.triangle_count(), scene.triangle_count() / 2);
  const std::vector<ViewFigures> views = compare_lod_views(renderer, lod, judged, judge_settings_of(job));
  for (const auto& v : views) {
    std::printf("  %-12s %-9s changed %.3f%%, SSIM %.4f, silhouette %.3f%%\n", v.view.c_str(),
                v.set.c_str(), 100 * v.changed_fraction,
                v.ssim_covered, 100 * v.silhouette_mismatch);
    EXPECT_LE(v.changed_fraction, 0.02) << v.view;
    EXPECT_GE(v.ssim_covered, 0.97) << v.view;
    EXPECT_LE(v.silhouette_mismatch, 0.01) << v.view;
  }
  EXPECT_TRUE(judge_views(views, FidelityLimits{}).met());

  // The paper's setting (four facades, one sample, paper mode) leaves holes
  // in the roof: seen from above, its silhouette differs far more.
  LabelJob paper_job = job;
  paper_job.views = parse_views("facades", UpAxis::Z);
  paper_job.samples = 1;
  LabelResult paper_labels = label_scene(renderer, scene, tracer, paper_job);
  SimplifyOptions paper;
  paper.pixel_footprint = opt.pixel_footprint;
  Scene paper_lod = simplify(scene, paper_labels.labels, paper);
  const auto above = std::find_if(judged.begin(), judged.end(), [](const ViewRecord& r) { return r.view == "top"; });
  ASSERT_NE(above, judged.end());
  std::vector<ViewRecord> top(above, above + 1);
  const double default_top = views[size_t(above - judged.begin())].silhouette_mismatch;
  const double paper_top =
      compare_lod_views(renderer, paper_lod, top, judge_settings_of(job))[0].silhouette_mismatch;
  std::printf("  from above: silhouette mismatch %.3f%% (default) vs %.3f%% (paper)\n", 100 * default_top,
              100 * paper_top);
  EXPECT_GT(paper_top, 0.05);
  EXPECT_LT(default_top, paper_top / 10);
}

// A flat wall of many perceptible triangles: re-tessellated to a few, and
// no pixel of any view changes, but where the outline passes within float
// rounding of a pixel centre (measured: none facing the wall, 4 and 1
// outline pixels from the oblique views, 38 and 8 pixels after vision
// simulation).
TEST(LodFidelity, FlatPerceptibleWallLosesTrianglesNotPixels) {
  Scene wall;
  const int n = 40;  // 40 x 40 quads over 20 m x 10 m in the x-z plane
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) wall.positions.insert(wall.positions.end(), {20.f * i / n, 0.f, 10.f * j / n});
  auto id = [&](int i, int j) { return uint32_t(j * (n + 1) + i); };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      wall.indices.insert(wall.indices.end(), {id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      wall.indices.insert(wall.indices.end(), {id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  Renderer renderer;
  LabelJob job;
  job.up = UpAxis::Z;
  job.views = parse_views("-y,az280el30,az260el15", UpAxis::Z);
  job.samples = kDefaultSamples;
  job.distance = 30;
  OctreeTracer tracer(wall);
  LabelResult lr = label_scene(renderer, wall, tracer, job);
  LabelCounts c = count_labels(lr.labels);
  ASSERT_GT(c.perceptible, wall.triangle_count() / 2);  // the wall is seen
  SimplifyOptions opt;
  opt.mode = SimplifyMode::Fidelity;
  opt.pixel_footprint = display_pixel_footprint(job.display, job.distance);
  Scene lod = simplify(wall, lr.labels, opt);
  EXPECT_LT(lod.triangle_count(), wall.triangle_count() / 20);
  for (const auto& v : compare_lod_views(renderer, lod, lr.views, judge_settings_of(job))) {
    EXPECT_GT(v.drawn_pixels, 10000u) << v.view;
    const size_t drawn = v.drawn_pixels;
    if (v.view == "-y") {
      EXPECT_EQ(v.changed_pixels, 0u);
      EXPECT_EQ(v.coverage_changed_pixels, 0u);
    }
    EXPECT_LE(v.coverage_changed_pixels, drawn / 10000) << v.view;
    EXPECT_LE(v.changed_pixels, drawn / 1000) << v.view;
  }
}

// A record keeps only the rectangle the original draws (its colours), widened by
// kRecordMargin pixels: a LOD drawing farther out (a quad 10 m beside the
// building at 427 m, about 40 px) is a silhouette change and a changed pixel
// there, and the original against itself still changes nothing.
TEST(LodFidelity, ALodDrawingBeyondTheKeptRectangleIsChangedThere) {
  Renderer renderer;
  const Scene scene = load_scene(kBuilding);
  LabelJob job;
  job.up = UpAxis::Z;
  job.distance = 427;
  const std::vector<ViewRecord> rec = record_views(renderer, scene, {"-y"}, framing_of(job));
  ASSERT_EQ(rec.size(), 1u);
  EXPECT_LT(size_t(rec[0].w) * size_t(rec[0].h), size_t(rec[0].camera.width) * size_t(rec[0].camera.height) / 20);
  // The record rebuilds the render it was made from, every byte (the judge
  // perceives that rebuilt render again rather than keep its perception).
  RenderOutput img;
  renderer.set_scene(scene);
  renderer.render(rec[0].camera, img);
  std::vector<uint8_t> rebuilt;
  rec[0].render_into(rebuilt);
  EXPECT_TRUE(rebuilt == img.rgb);
  std::vector<uint8_t> kept;
  rec[0].rgb_into(kept);
  EXPECT_EQ(kept.size(), 3 * size_t(rec[0].w) * size_t(rec[0].h));
  EXPECT_LT(rec[0].packed_rgb.size(), kept.size() / 4);  // packed: a flat-shaded building is mostly runs
  // Without its pixels: the same rectangle and mask, nothing packed, and
  // no render to rebuild.
  std::vector<uint8_t> background;
  background_of(img, background);
  const ViewRecord bare = view_record("-y", rec[0].camera, img.rgb, background, "held_out", false);
  EXPECT_EQ(std::tie(bare.x0, bare.y0, bare.w, bare.h), std::tie(rec[0].x0, rec[0].y0, rec[0].w, rec[0].h));
  EXPECT_EQ(bare.background, rec[0].background);
  EXPECT_TRUE(bare.packed_rgb.empty());
  EXPECT_ANY_THROW(bare.render_into(rebuilt));
  const std::vector<ViewFigures> same = compare_lod_views(renderer, scene, rec, judge_settings_of(job));
  EXPECT_EQ(same[0].changed_pixels, 0u);
  EXPECT_EQ(same[0].coverage_changed_pixels, 0u);
  EXPECT_EQ(same[0].ssim_covered, 1.0);

  Scene more = scene;
  const Bounds b = scene_bounds(scene);
  const float x0 = b.hi[0] + 10, x1 = x0 + 2, y = b.lo[1], z0 = b.lo[2], z1 = z0 + 3;
  const uint32_t v = uint32_t(more.vertex_count());
  more.positions.insert(more.positions.end(), {x0, y, z0, x1, y, z0, x1, y, z1, x0, y, z1});
  more.indices.insert(more.indices.end(), {v, v + 1, v + 2, v, v + 2, v + 3});
  if (!more.component.empty()) more.component.insert(more.component.end(), 2, more.component.back());
  if (!more.material.empty()) more.material.insert(more.material.end(), 2, more.material.back());
  const std::vector<ViewFigures> moved = compare_lod_views(renderer, more, rec, judge_settings_of(job));
  const size_t quad = moved[0].coverage_changed_pixels;
  EXPECT_GT(quad, 40u);  // about 8 x 12 px
  EXPECT_GE(moved[0].changed_pixels, quad);
  EXPECT_EQ(moved[0].drawn_pixels, same[0].drawn_pixels + quad);
}

// The overlapped paths (view k+1 rendered while view k is traced, or
// compared) give what one view after another gives: labels, sample counts,
// every per-view figure but the timings, and the LOD's judged figures.
TEST(LodFidelity, OverlappedViewsGiveTheSequentialResults) {
  Renderer renderer;
  const Scene scene = load_scene(kBuilding);
  OctreeTracer tracer(scene);
  LabelJob job;
  job.up = UpAxis::Z;
  job.views = parse_views(kDefaultViews, UpAxis::Z);
  job.samples = kDefaultSamples;
  job.distance = 132;
  job.verify = true;
  auto without_seconds = [](nlohmann::json views) {
    for (auto& v : views) v.erase("seconds");
    return views;
  };
  LabelJob sequential = job;
  sequential.overlap = false;
  const LabelResult a = label_scene(renderer, scene, tracer, job);
  const LabelResult b = label_scene(renderer, scene, tracer, sequential);
  ASSERT_EQ(a.labels.size(), scene.triangle_count());
  EXPECT_EQ(a.labels, b.labels);
  EXPECT_EQ(a.totals.traced, b.totals.traced);
  EXPECT_EQ(a.totals.imperceptible, b.totals.imperceptible);
  EXPECT_EQ(without_seconds(label_report_json(a.report)["views"]), without_seconds(label_report_json(b.report)["views"]));
  ASSERT_EQ(a.views.size(), b.views.size());
  for (size_t k = 0; k < a.views.size(); ++k) {
    EXPECT_EQ(a.views[k].view, b.views[k].view);
    std::vector<uint8_t> ra, rb;
    a.views[k].rgb_into(ra);
    b.views[k].rgb_into(rb);
    EXPECT_EQ(ra, rb);
  }
  SimplifyOptions opt;
  opt.mode = SimplifyMode::Fidelity;
  opt.pixel_footprint = display_pixel_footprint(job.display, job.distance);
  const Scene lod = simplify(scene, a.labels, opt);
  std::vector<Rgb8Image> pa, pb;
  const std::vector<ViewFigures> ja = compare_lod_views(renderer, lod, a.views, judge_settings_of(job), &pa);
  const std::vector<ViewFigures> jb = compare_lod_views(renderer, lod, a.views, judge_settings_of(sequential), &pb);
  EXPECT_EQ(ja, jb);
  ASSERT_EQ(pa.size(), pb.size());
  for (size_t k = 0; k < pa.size(); ++k) EXPECT_EQ(pa[k].pixels, pb[k].pixels);
}

}  // namespace
}  // namespace perclod
