// Labels from view sets (issue 10): framed views leave nothing of a near
// side undisplayable, a roof seen only from above is labelled with the
// default views, triangles outside every frustum are never undisplayable,
// per-building views label each building at its own distance, the samples
// rule reaches sub-pixel parts, and keep_unsampled_surface finds sub-pixel
// triangles between the samples of a drawn surface.
#include <gtest/gtest.h>

#include <cmath>

#include "perclod/fidelity_search.h"
#include "perclod/judge.h"
#include "perclod/label.h"
#include "perclod/report_json.h"
#include "perclod/undisplayable.h"
#include "test_util.h"

namespace perclod {
namespace {

// Adds an axis-aligned box [lo, hi] as 12 triangles in component `comp`.
void add_box(Scene& s, std::array<float, 3> lo, std::array<float, 3> hi, uint32_t comp) {
  const uint32_t v0 = uint32_t(s.positions.size() / 3);
  for (int i = 0; i < 8; ++i)
    s.positions.insert(s.positions.end(), {i & 1 ? hi[0] : lo[0], i & 2 ? hi[1] : lo[1], i & 4 ? hi[2] : lo[2]});
  const uint32_t quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (auto& q : quads) {
    s.indices.insert(s.indices.end(), {v0 + q[0], v0 + q[1], v0 + q[2], v0 + q[0], v0 + q[2], v0 + q[3]});
    s.component.insert(s.component.end(), {comp, comp});
  }
}

// A wall facing -y (Z up), `w` x `h` metres at y = 0, of 1 m squares, with a
// 0.5 m thick body behind it.
Scene wall(int w, int h) {
  Scene s;
  s.component_names = {"wall"};
  for (int i = 0; i <= w; ++i)
    for (int k = 0; k <= h; ++k) s.positions.insert(s.positions.end(), {float(i), 0.0f, float(k)});
  auto v = [&](int i, int k) { return uint32_t(i * (h + 1) + k); };
  for (int i = 0; i < w; ++i)
    for (int k = 0; k < h; ++k) {
      s.indices.insert(s.indices.end(), {v(i, k), v(i + 1, k), v(i + 1, k + 1), v(i, k), v(i + 1, k + 1), v(i, k + 1)});
      s.component.insert(s.component.end(), {0, 0});
    }
  add_box(s, {0, 0.01f, 0}, {float(w), 0.5f, float(h)}, 0);
  return s;
}

LabelJob job_for(const std::string& views, double d, int samples = 1) {
  LabelJob job;
  job.up = UpAxis::Z;
  job.display.width = 320;
  job.display.height = 256;
  job.perception = perception_settings_for(job.display);
  job.views = parse_views(views, UpAxis::Z);
  job.distance = d;
  job.samples = samples;
  return job;
}

// Two labellings that must agree: the labels and every triangle's counts.
void expect_same_labelling(const LabelResult& a, const LabelResult& b) {
  EXPECT_EQ(a.labels, b.labels);
  EXPECT_EQ(a.totals.traced, b.totals.traced);
  EXPECT_EQ(a.totals.imperceptible, b.totals.imperceptible);
}

LabelResult label(const Scene& s, const LabelJob& job) {
  Renderer r;
  OctreeTracer t(s);
  return label_scene(r, s, t, job);
}

// At 5 m a 30 x 12 m wall overfills the frame: tiles frame every square.
TEST(ViewSets, TilingLeavesNoTriangleOfTheNearSideUndisplayable) {
  Scene s = wall(30, 12);
  const size_t front = 2 * 30 * 12;
  LabelResult r = label(s, job_for("-y", 5));
  EXPECT_GT(r.views.size(), 4u);
  for (size_t t = 0; t < front; ++t) ASSERT_NE(r.labels[t], Label::Undisplayable) << "square triangle " << t;
  EXPECT_EQ(label_report_json(r.report)["views"].size(), r.views.size());
  // Without tiling (one camera) most of the wall would be out of the frame.
  Camera one = view_camera(scene_bounds(s), UpAxis::Z, "-y", 5, job_for("-y", 5).display);
  std::vector<uint8_t> in(s.triangle_count(), 0);
  mark_in_frustum(s, one, in);
  size_t outside = 0;
  for (size_t t = 0; t < front; ++t) outside += !in[t];
  EXPECT_GT(outside, front / 2);
}

// Triangles no view can contain (the back of the wall for a single -y view
// is in the frustum but hidden: undisplayable; a part far to the side of a
// +x-only view set is outside every frustum: imperceptible and counted).
TEST(ViewSets, TriangleOutsideEveryFrustumIsNeverUndisplayable) {
  Scene s = wall(4, 3);
  LabelJob job = job_for("-y", 20);
  LabelResult r = label(s, job);
  EXPECT_EQ(r.outside_views, 0u);  // framed: everything is in the frustum
  size_t hidden = 0;
  for (Label l : r.labels) hidden += l == Label::Undisplayable;
  EXPECT_GT(hidden, 0u);  // the body's back face
  // A camera that frames nothing of the model: every triangle is outside.
  Scene far = s;
  std::vector<uint8_t> in(far.triangle_count(), 0);
  Camera c = view_camera(scene_bounds(s), UpAxis::Z, "-y", 20, job.display);
  c.forward = -c.forward;  // looking away
  c.right = -c.right;
  mark_in_frustum(far, c, in);
  for (uint8_t v : in) EXPECT_EQ(v, 0);
}

// A flat roof is edge-on to horizontal views at the box's mid-height and
// below eye level of nothing: undisplayable from the facades, labelled with
// the default views.
TEST(ViewSets, RoofSeenOnlyFromAboveIsLabelledWithTheDefaultViews) {
  Scene s;
  s.component_names = {"house"};
  add_box(s, {0, 0, 0}, {10, 8, 6}, 0);
  const size_t roof[2] = {2, 3};  // the z = hi quad of add_box
  LabelResult paper = label(s, job_for("facades", 56));
  for (size_t t : roof) EXPECT_EQ(paper.labels[t], Label::Undisplayable);
  LabelResult def = label(s, job_for(kDefaultViews, 56, kDefaultSamples));
  for (size_t t : roof) EXPECT_NE(def.labels[t], Label::Undisplayable);
}

// Two buildings 300 m apart, each with a 1.5 cm plaque on its +y face. From
// az90el30 the whole-model view stands ~170 m away (the plaque is a tenth of
// a pixel and no sample finds it); framed on each building the eye is 20 m
// outside that building and the plaque is about a pixel.
TEST(ViewSets, PerBuildingViewsLabelEachBuildingAtItsOwnDistance) {
  Scene s;
  s.component_names = {"a/Building/1", "a/Window/2", "b/Building/1", "b/Window/2"};
  add_box(s, {0, 0, 0}, {10, 10, 10}, 0);
  add_box(s, {5, 10.01f, 5}, {5.015f, 10.02f, 5.015f}, 1);
  add_box(s, {300, 0, 0}, {310, 10, 10}, 2);
  add_box(s, {305, 10.01f, 5}, {305.015f, 10.02f, 5.015f}, 3);
  Buildings b = find_buildings(s);
  ASSERT_EQ(b.names, (std::vector<std::string>{"a", "b"}));
  EXPECT_EQ(b.of_component, (std::vector<uint32_t>{0, 0, 1, 1}));
  EXPECT_EQ(b.named, 2u);

  auto plaque_front = [](const LabelResult& r, size_t first) {  // the plaque's +y quad
    return r.labels[first + 6] != Label::Undisplayable || r.labels[first + 7] != Label::Undisplayable;
  };
  LabelJob job = job_for("az90el30", 20, 4);
  LabelResult whole = label(s, job);
  EXPECT_FALSE(plaque_front(whole, 12));
  EXPECT_FALSE(plaque_front(whole, 36));
  job.per_building = PerBuilding::Auto;
  LabelResult per = label(s, job);
  EXPECT_TRUE(plaque_front(per, 12));
  EXPECT_TRUE(plaque_front(per, 36));
  EXPECT_EQ(label_report_json(per.report)["per_building"].size(), 2u);
  // The same groups without "<building>/" names are parts of one model:
  // auto leaves them to the whole-model views.
  Scene parts = s;
  parts.component_names = {"Building_1", "Window_2", "Building_3", "Window_4"};
  EXPECT_EQ(find_buildings(parts).names.size(), 4u);
  EXPECT_EQ(find_buildings(parts).named, 0u);
  LabelResult auto_parts = label(parts, job);
  EXPECT_FALSE(label_report_json(auto_parts.report).contains("per_building"));
  EXPECT_EQ(auto_parts.labels, whole.labels);
  // Per-building views only add: nothing labelled by the whole-model views is lost.
  for (size_t t = 0; t < s.triangle_count(); ++t)
    if (whole.labels[t] == Label::Perceptible) {
      EXPECT_EQ(per.labels[t], Label::Perceptible);
    }
}

// Boxes 10 m wide every 12 m along x (Z up): each group's boxes span at
// most the span across, every box is in exactly one group, a group holds
// neighbours, and boxes stacked along the up axis span nothing across.
TEST(ViewSets, GroupBoxesSplitUntilEachGroupFitsTheSpan) {
  std::vector<Bounds> boxes;
  for (int i = 0; i < 12; ++i) boxes.push_back({{12.0f * i, 0, 0}, {12.0f * i + 10, 10, 30}});
  boxes.push_back(Bounds::empty());  // a building without triangles: in no group
  const auto singles = group_boxes(boxes, UpAxis::Z, 0);
  ASSERT_EQ(singles.size(), 12u);
  for (uint32_t i = 0; i < 12; ++i) EXPECT_EQ(singles[i], std::vector<uint32_t>{i});
  const auto groups = group_boxes(boxes, UpAxis::Z, 40);
  EXPECT_GE(groups.size(), 4u);  // 142 m of row in parts of at most 40 m
  EXPECT_LE(groups.size(), 6u);
  std::vector<int> seen(boxes.size(), 0);
  for (const auto& g : groups) {
    float lo = INFINITY, hi = -INFINITY;
    for (uint32_t b : g) ++seen[b], lo = std::min(lo, boxes[b].lo[0]), hi = std::max(hi, boxes[b].hi[0]);
    EXPECT_LE(hi - lo, 40.0f);
    EXPECT_EQ(g.back() - g.front() + 1, g.size());  // neighbours, not every other box
  }
  for (int i = 0; i < 12; ++i) EXPECT_EQ(seen[i], 1) << i;
  EXPECT_EQ(seen[12], 0);
  EXPECT_EQ(group_boxes(boxes, UpAxis::Z, 1000).size(), 1u);
  // With Y up their 30 m of z lies across too: no box fits 25 m, while with
  // Z up they pair up.
  EXPECT_EQ(group_boxes(boxes, UpAxis::Y, 25).size(), 12u);
  EXPECT_LE(group_boxes(boxes, UpAxis::Z, 25).size(), 8u);  // halving 12 into 34 m threes, then a pair and one
  std::vector<Bounds> stack;  // ten floors of a 10 m tower, Y up
  for (int i = 0; i < 10; ++i) stack.push_back({{0, 4.0f * i, 0}, {10, 4.0f * i + 4, 10}});
  EXPECT_EQ(group_boxes(stack, UpAxis::Y, 12).size(), 1u);
  EXPECT_EQ(group_boxes(stack, UpAxis::Z, 12).size(), 4u);  // with Z up the 40 m lie across: 12 m at most
  // Span 0 keeps boxes without extent across apart too (two posts, Z up).
  const std::vector<Bounds> posts = {{{0, 0, 0}, {0, 0, 5}}, {{0, 0, 6}, {0, 0, 9}}};
  EXPECT_EQ(group_boxes(posts, UpAxis::Z, 0).size(), 2u);
  EXPECT_EQ(group_boxes(posts, UpAxis::Z, 1).size(), 1u);
}

// Two 10 m buildings 6 m apart, each with a 1.5 cm plaque on its +y face,
// and a third 300 m away. With group_span 1 at 20 m the near two share one
// set of views (the report names the group by its first building and counts
// two), the far one keeps its own; each plaque is still found, as it is
// from each building's own views.
TEST(ViewSets, GroupsLabelNeighboursFromSharedViews) {
  Scene s;
  s.component_names = {"a/Building/1", "a/Window/2", "b/Building/1", "b/Window/2", "c/Building/1", "c/Window/2"};
  const float x[3] = {0, 16, 300};
  for (uint32_t k = 0; k < 3; ++k) {
    add_box(s, {x[k], 0, 0}, {x[k] + 10, 10, 10}, 2 * k);
    add_box(s, {x[k] + 5, 10.01f, 5}, {x[k] + 5.015f, 10.02f, 5.015f}, 2 * k + 1);
  }
  auto plaque_front = [](const LabelResult& r, size_t first) {
    return r.labels[first + 6] != Label::Undisplayable || r.labels[first + 7] != Label::Undisplayable;
  };
  LabelJob job = job_for("az90el30", 20, 4);
  job.per_building = PerBuilding::On;
  job.model_views_beside_alone = true;  // the whole-model views count, as they do with groups
  LabelResult alone = label(s, job);
  ASSERT_EQ(alone.report.buildings.size(), 3u);
  job.group_span = 1.5;  // 30 m at 20 m: a and b (26 m across), not c
  LabelResult grouped = label(s, job);
  ASSERT_EQ(grouped.report.buildings.size(), 2u);
  EXPECT_EQ(grouped.report.buildings[0].building, "a");
  EXPECT_EQ(grouped.report.buildings[0].buildings, 2u);
  EXPECT_EQ(grouped.report.buildings[1].building, "c");
  EXPECT_EQ(grouped.report.buildings[1].buildings, 1u);
  const nlohmann::json per_json = label_report_json(grouped.report)["per_building"];
  EXPECT_EQ(per_json[0]["buildings"], 2);
  EXPECT_FALSE(per_json[1].contains("buildings"));
  for (size_t first : {12u, 36u, 60u}) {
    EXPECT_TRUE(plaque_front(alone, first)) << first;
    EXPECT_TRUE(plaque_front(grouped, first)) << first;
  }
  // The lone building is framed as before: its labels do not change.
  for (size_t t = 48; t < 72; ++t) EXPECT_EQ(grouped.labels[t], alone.labels[t]) << t;
}

// Buildings a (a 10 m cube at the origin) and b (10 m along x from b_x,
// 10 m deep, b_height high), Z up, labelled per building.
Scene two_buildings(float b_x, float b_height) {
  Scene s;
  s.component_names = {"a/Building/1", "b/Building/1"};
  add_box(s, {0, 0, 0}, {10, 10, 10}, 0);
  add_box(s, {b_x, 0, 0}, {b_x + 10, 10, b_height}, 1);
  return s;
}
LabelJob per_building_job(const std::string& views, double d) {
  LabelJob job = job_for(views, d);
  job.per_building = PerBuilding::On;
  return job;
}

// Two 10 m buildings in a row along x, b (16-26 m) in front of a from +x.
// In one group at 300 m, the group's +x view sees b where a's own view,
// clipped at a's box, would see a's +x face: a takes its own +x view, and
// that face is labelled as building by building. From -y nothing stands
// in front of either, so the group's -y view serves both.
TEST(ViewSets, AGroupMemberHiddenByAnotherTakesItsOwnViewInThatDirection) {
  const Scene s = two_buildings(16, 10);
  for (bool own_views_alone : {false, true}) {  // a's own +x view in place, or of a alone
    SCOPED_TRACE(own_views_alone ? "own views alone" : "own views in place");
    LabelJob job = per_building_job("+x,-y", 300);
    job.own_views_alone = own_views_alone;
    LabelResult alone = label(s, job);
    job.group_span = 0.1;  // 30 m at 300 m
    LabelResult grouped = label(s, job);
    ASSERT_EQ(grouped.report.buildings.size(), 1u);
    const BuildingLabelling& g = grouped.report.buildings[0];
    EXPECT_EQ(g.buildings, 2u);
    EXPECT_EQ(g.members_alone, 1u);  // a
    EXPECT_EQ(g.own_views, 1u);      // a from +x
    EXPECT_EQ(g.views, 3u);          // the group's two (one frame each) and a's
    const nlohmann::json j = label_report_json(grouped.report)["per_building"][0];
    EXPECT_EQ(j["own_views"], 1);
    EXPECT_EQ(j["members_alone"], 1);
    for (size_t t : {10u, 11u}) {  // a's +x face (from -y a grazing sliver between the two)
      EXPECT_EQ(alone.labels[t], Label::Perceptible) << t;
      EXPECT_EQ(grouped.labels[t], Label::Perceptible) << t;
    }
    for (size_t t : {4u, 5u, 16u, 17u}) {  // both -y faces, seen from the group's -y view
      EXPECT_NE(grouped.labels[t], Label::Undisplayable) << t;
    }
  }
}

// A house (a, 0-10 m) against a taller one (b, from 10.1 m, 20 m high):
// a's +x wall is a party wall. b's -x wall stands 0.1 m in front of it,
// beyond the near plane of a's own views (1% of a's diagonal before a), so
// in place (own_views_alone false) b hides that wall from every view. With
// own_views_alone (the default) each building's own views show it alone:
// the wall is seen and kept.
TEST(ViewSets, OwnViewsAloneSeeThePartyWallANeighbourHides) {
  const Scene s = two_buildings(10.1f, 20);
  LabelJob job = per_building_job("+x,-y", 300);
  job.own_views_alone = false;
  LabelResult in_place = label(s, job);
  job.own_views_alone = true;
  LabelResult alone = label(s, job);
  for (size_t t : {10u, 11u}) {  // a's +x face
    EXPECT_NE(in_place.labels[t], Label::Perceptible) << t;
    EXPECT_EQ(alone.labels[t], Label::Perceptible) << t;
  }
  ASSERT_EQ(alone.report.buildings.size(), 2u);
  for (const BuildingLabelling& b : alone.report.buildings) EXPECT_EQ(b.views, 2u) << b.building;
  // Faces nothing hides are labelled alike either way.
  for (size_t t : {4u, 5u, 16u, 17u, 22u, 23u}) EXPECT_EQ(alone.labels[t], in_place.labels[t]) << t;
}

// A kiosk 36 m in front of a hall: framed on the kiosk at 56 m, the +x view
// stands inside the hall's box. With the neighbours in place the report
// counts such views per building; the hall's own views all stand outside
// the kiosk. Own views of each building alone draw no neighbour to stand in.
TEST(ViewSets, PerBuildingReportCountsViewsWhoseEyeIsInsideANeighbour) {
  Scene s;
  s.component_names = {"kiosk/Building/1", "hall/Building/1"};
  add_box(s, {0, 0, 0}, {4, 4, 4}, 0);
  add_box(s, {40, -30, 0}, {120, 30, 40}, 1);
  LabelJob job = job_for("+x,-x", 56);
  job.per_building = PerBuilding::On;
  job.own_views_alone = false;
  LabelResult r = label(s, job);
  const std::vector<BuildingLabelling>& per = r.report.buildings;
  ASSERT_TRUE(r.report.per_building);
  ASSERT_EQ(per.size(), 2u);
  EXPECT_EQ(per[0].building, "kiosk");
  EXPECT_EQ(per[0].eyes_inside_other_buildings, 1u);  // +x; -x stands in the open
  EXPECT_EQ(per[1].building, "hall");
  EXPECT_EQ(per[1].eyes_inside_other_buildings, 0u);
  const nlohmann::json per_json = label_report_json(r.report)["per_building"];
  EXPECT_EQ(per_json[0]["eyes_inside_other_buildings"], 1);
  // The kiosk's -x face, seen from its -x view in the open, is labelled.
  size_t visible = 0;
  for (size_t t = 0; t < 12; ++t) visible += r.labels[t] != Label::Undisplayable;
  EXPECT_GT(visible, 0u);
  job.own_views_alone = true;
  const LabelResult alone = label(s, job);
  ASSERT_EQ(alone.report.buildings.size(), 2u);
  for (const BuildingLabelling& b : alone.report.buildings) EXPECT_EQ(b.eyes_inside_other_buildings, 0u) << b.building;
}

// One sample per pixel of the default labelling reproduces the paper's
// single-sample counts exactly; four samples count in quarter pixels.
TEST(ViewSets, SampleCountsScaleWithSamplesPerPixel) {
  Scene s = test::box();
  for (float& p : s.positions) p *= 10;
  LabelResult one = label(s, job_for("facades", 30, 1));
  LabelResult four = label(s, job_for("facades", 30, 4));
  uint64_t a = 0, b = 0;
  for (size_t t = 0; t < s.triangle_count(); ++t) a += one.totals.traced[t], b += four.totals.traced[t];
  EXPECT_GT(a, 1000u);
  EXPECT_NEAR(double(b) / double(a), 4.0, 0.1);
  EXPECT_EQ(label_report_json(four.report)["samples_per_pixel"], 4);
  EXPECT_THROW(label(s, job_for("facades", 30, 3)), std::invalid_argument);
}

// combine_views: pooled decides P and I from every view's samples together.
// It leaves the undisplayable set as it is, it can only turn a triangle
// perceptible in some view imperceptible (if every view's fraction reaches
// the ratio, so does their sum), and on a wall of small boxes seen from the
// side and from above it does: a box perceptible only in the views that hold
// few of its samples.
TEST(ViewSets, PooledViewsDecideFromEveryViewsSamplesTogether) {
  Scene s = wall(30, 12);
  for (int i = 0; i < 30; ++i)
    for (int k = 0; k < 12; ++k)
      add_box(s, {i + 0.3f, -0.3f, k + 0.3f}, {i + 0.6f, 0.0f, k + 0.6f}, 0);
  LabelJob job = job_for("facades,ring8el30", 60, 4);
  LabelResult any = label(s, job);
  job.combine = CombineViews::Pooled;
  LabelResult pooled = label(s, job);
  ASSERT_EQ(any.totals.traced, pooled.totals.traced);  // the same samples, combined otherwise
  EXPECT_EQ(pooled.labels, label_triangles(pooled.totals, job.ratio));
  size_t turned = 0;
  for (size_t t = 0; t < s.triangle_count(); ++t) {
    ASSERT_EQ(any.labels[t] == Label::Undisplayable, pooled.labels[t] == Label::Undisplayable) << t;
    if (pooled.labels[t] == Label::Perceptible) {
      ASSERT_EQ(any.labels[t], Label::Perceptible) << t;
    }
    turned += any.labels[t] == Label::Perceptible && pooled.labels[t] == Label::Imperceptible;
  }
  EXPECT_GT(turned, 0u);
  EXPECT_EQ(label_report_json(any.report)["combine_views"], "any");
  EXPECT_EQ(label_report_json(pooled.report)["combine_views"], "pooled");
  EXPECT_EQ(parse_combine_views("pooled"), CombineViews::Pooled);
  EXPECT_THROW(parse_combine_views("all"), std::invalid_argument);
}

// mask_per_sample: each sample offset gets a render of its own, cropped to
// the model, traced at its pixel centres. The samples are the ones a single
// render would trace, so the traced counts match sample for sample; the
// report keeps one entry per view, naming its passes. With one sample it is
// the plain labelling exactly, and it refuses keep_unsampled_surface.
TEST(ViewSets, MaskPerSampleTracesTheSameSamplesFromARenderEach) {
  Scene s = wall(30, 12);
  LabelJob job = job_for("facades,az30el30", 60, 4);
  const LabelResult plain = label(s, job);
  job.mask_per_sample = true;
  const LabelResult mps = label(s, job);
  uint64_t a = 0, b = 0;
  size_t same = 0;
  for (size_t t = 0; t < s.triangle_count(); ++t) {
    a += plain.totals.traced[t], b += mps.totals.traced[t];
    same += plain.totals.traced[t] == mps.totals.traced[t];
    EXPECT_EQ(plain.labels[t] == Label::Undisplayable, mps.labels[t] == Label::Undisplayable) << t;
  }
  EXPECT_GT(a, 10000u);
  EXPECT_NEAR(double(b) / double(a), 1.0, 1e-3);
  EXPECT_GE(same, s.triangle_count() * 99 / 100);  // 729 of 732 measured, the others one sample apart
  ASSERT_EQ(label_report_json(mps.report)["views"].size(), label_report_json(plain.report)["views"].size());
  for (const ViewLabelling& v : mps.report.views) EXPECT_EQ(v.passes, 4u);
  EXPECT_EQ(label_report_json(mps.report)["mask_per_sample"], true);
  EXPECT_FALSE(label_report_json(plain.report).contains("mask_per_sample"));

  LabelJob one = job_for("facades", 60, 1);
  const LabelResult one_plain = label(s, one);
  one.mask_per_sample = true;
  const LabelResult one_mps = label(s, one);
  expect_same_labelling(one_mps, one_plain);

  job.keep_unsampled_surface = true;
  EXPECT_THROW(label(s, job), std::invalid_argument);
}

// samples: 16 is the 4 x 4 ordered grid, each sample read from its own
// picture, all 16 pictures from one render of the view's window at 4x the
// resolution: one report entry and one render per view, four times the
// traced samples of 4 samples per pixel on the same triangles, and the
// view's record drawn from sample 0's camera.
TEST(ViewSets, AGridOfSamplesComesFromOneRefinedRender) {
  Scene s = wall(30, 12);
  LabelJob job = job_for("facades,az30el30", 60, 4);
  const LabelResult plain = label(s, job);
  job.samples = 16;
  const LabelResult grid = label(s, job);
  uint64_t a = 0, b = 0;
  size_t seen_differently = 0;  // a sliver on the box's edge that one pattern hits and the other misses
  for (size_t t = 0; t < s.triangle_count(); ++t) {
    a += plain.totals.traced[t], b += grid.totals.traced[t];
    seen_differently += (plain.labels[t] == Label::Undisplayable) != (grid.labels[t] == Label::Undisplayable);
  }
  EXPECT_LE(seen_differently, 2u);  // 1 of 732 measured
  EXPECT_GT(a, 10000u);
  EXPECT_NEAR(double(b) / double(4 * a), 1.0, 2e-3);
  EXPECT_EQ(label_report_json(grid.report)["sample_grid"], 4);
  EXPECT_EQ(label_report_json(grid.report)["mask_per_sample"], true);
  ASSERT_EQ(label_report_json(grid.report)["views"].size(), label_report_json(plain.report)["views"].size());
  const nlohmann::json grid_views = label_report_json(grid.report)["views"];
  for (size_t v = 0; v < grid_views.size(); ++v) {
    const auto& g = grid_views[v];
    EXPECT_FALSE(g.contains("passes"));
    const Camera c = grid.views[v].camera;
    EXPECT_EQ(g["rendered_pixels"].get<size_t>(), 16 * size_t(c.width) * c.height);
    EXPECT_LT(c.width * c.height, 1280 * 1024);  // the model's window, not the frame
  }
  // The record's camera is sample 0's: the record's picture is what that camera draws.
  Renderer r;
  r.set_scene(s);
  RenderOutput o;
  r.render(grid.views[0].camera, o, {});
  std::vector<uint8_t> kept;
  grid.views[0].render_into(kept);
  ASSERT_EQ(kept.size(), o.rgb.size());
  size_t differ = 0, covered = 0;
  for (size_t i = 0; i < o.ids.size(); ++i) covered += o.ids[i] != 0;
  for (size_t i = 0; i < o.rgb.size(); ++i) differ += o.rgb[i] != kept[i];
  EXPECT_GT(covered, 1000u);
  EXPECT_LE(differ, o.rgb.size() / 1000);

  job.keep_unsampled_surface = true;
  EXPECT_THROW(label(s, job), std::invalid_argument);
}

// wall(30, 12) with a 0.3 m box standing out of each square: small parts
// for the perception to resolve or not.
Scene studded_wall() {
  Scene s = wall(30, 12);
  for (int i = 0; i < 30; ++i)
    for (int k = 0; k < 12; ++k) add_box(s, {i + 0.3f, -0.3f, k + 0.3f}, {i + 0.6f, 0.0f, k + 0.6f}, 0);
  return s;
}

// The window a mask-per-sample pass renders perceives as the whole frame
// does over the model: the same mask on every pixel the model covers. So
// does the narrower window of a model alone (nothing drawn beyond its box).
TEST(ViewSets, PerceptionWindowPerceivesAsTheWholeFrameOverTheModel) {
  for (bool alone : {false, true}) {
    SCOPED_TRACE(alone ? "alone" : "in place");
    const Scene s = studded_wall();
    const LabelJob job = job_for("az30el30", 120, 1);
    const Camera whole = frame_view(scene_bounds(s), UpAxis::Z, "az30el30", job.distance, job.display)[0].camera;
    const Camera win = perception_window(whole, scene_bounds(s), job.perception, alone);
    ASSERT_LT(win.width * win.height, whole.width * whole.height);  // the model leaves part of the frame
    if (alone) {  // half the margin on either side (the wall fills the frame's height)
      const Camera wide = perception_window(whole, scene_bounds(s), job.perception);
      const int align = 1 << default_levels(0.5 * job.display.pixels_per_degree(), job.perception.k);
      EXPECT_NEAR(wide.width - win.width, 12 * align, align);
      EXPECT_LE(win.height, wide.height);
    }
    const int x0 = int(std::lround(win.shift_x - 0.5 * (win.width - whole.width)));
    const int y0 = int(std::lround(win.shift_y - 0.5 * (win.height - whole.height)));
    Renderer r;
    r.set_scene(s);
    RenderOutput a, b;
    r.render(whole, a, {});
    r.render(win, b, {});
    const PerceptionResult pa = perceive(a.rgb.data(), a.width, a.height, job.perception);
    const PerceptionResult pb = perceive(b.rgb.data(), b.width, b.height, job.perception);
    size_t covered = 0, differ = 0, ids_differ = 0;
    for (int y = 0; y < win.height; ++y)
      for (int x = 0; x < win.width; ++x) {
        const size_t i = size_t(y) * win.width + x, j = size_t(y + y0) * whole.width + x + x0;
        ids_differ += a.ids[j] != b.ids[i];
        if (!a.ids[j]) continue;
        ++covered;
        differ += pa.mask[j] != pb.mask[i];
      }
    EXPECT_GT(covered, 1000u);
    EXPECT_EQ(ids_differ, 0u);
    EXPECT_EQ(differ, 0u) << "of " << covered;
  }
}

// One render at s times the resolution holds the s x s renders at
// grid_offsets(s): every fine pixel (s x + a, s y + b) shows what pixel (x, y)
// of the render shifted by offset b s + a shows, and their perception masks
// agree over the model.
TEST(ViewSets, ARefinedRenderHoldsTheGridOfShiftedRenders) {
  const Scene s = studded_wall();
  const LabelJob job = job_for("az30el30", 120, 1);
  const Camera whole = frame_view(scene_bounds(s), UpAxis::Z, "az30el30", job.distance, job.display)[0].camera;
  const Camera win = perception_window(whole, scene_bounds(s), job.perception);
  Renderer r;
  r.set_scene(s);
  for (int g : {2, 3}) {
    RenderOutput fine;
    r.render(refined(win, g), fine, {});
    ASSERT_EQ(fine.width, g * win.width);
    const auto offsets = grid_offsets(g);
    for (int k = 0; k < g * g; ++k) {
      Camera c = win;
      c.shift_x += offsets[k][0], c.shift_y += offsets[k][1];
      RenderOutput one;
      r.render(c, one, {});
      RenderOutput part = one;
      const int a = k % g, b = k / g;
      for (int y = 0; y < win.height; ++y)
        for (int x = 0; x < win.width; ++x) {
          const size_t i = size_t(y) * win.width + x, f = size_t(g * y + b) * fine.width + size_t(g * x + a);
          part.ids[i] = fine.ids[f];
          for (int ch = 0; ch < 3; ++ch) part.rgb[3 * i + ch] = fine.rgb[3 * f + ch];
        }
      size_t covered = 0, ids_differ = 0, differ = 0;
      const PerceptionResult p1 = perceive(one.rgb.data(), one.width, one.height, job.perception);
      const PerceptionResult p2 = perceive(part.rgb.data(), part.width, part.height, job.perception);
      for (size_t i = 0; i < one.ids.size(); ++i) {
        ids_differ += one.ids[i] != part.ids[i];
        if (!one.ids[i]) continue;
        ++covered;
        differ += p1.mask[i] != p2.mask[i];
      }
      EXPECT_GT(covered, 1000u);
      EXPECT_LE(ids_differ, covered / 1000) << "grid " << g << " sample " << k;
      EXPECT_LE(differ, covered / 1000) << "grid " << g << " sample " << k;
    }
  }
}

// A 1 m square in the plane y = `y`, facing -y, tessellated in squares of
// `cell` metres (two triangles each); returns its first triangle.
size_t add_fine_grid(Scene& s, float y, float cell, uint32_t comp) {
  const size_t first = s.triangle_count();
  const int n = int(std::lround(1.0 / cell));
  const uint32_t v0 = uint32_t(s.positions.size() / 3);
  for (int i = 0; i <= n; ++i)
    for (int k = 0; k <= n; ++k) s.positions.insert(s.positions.end(), {i * cell, y, k * cell});
  auto v = [&](int i, int k) { return v0 + uint32_t(i * (n + 1) + k); };
  for (int i = 0; i < n; ++i)
    for (int k = 0; k < n; ++k) {
      s.indices.insert(s.indices.end(), {v(i, k), v(i + 1, k), v(i + 1, k + 1), v(i, k), v(i + 1, k + 1), v(i, k + 1)});
      s.component.insert(s.component.end(), {comp, comp});
    }
  return first;
}

// samples auto picks a view's sampling from the triangles it draws
// (choose_sampling): a neighbour of 20,000 triangles puts the scene over a
// sixteenth of the 320 x 256 frame's pixels, so every view of it in place
// is one render at 4 samples, while a's own views of a alone (12
// triangles, a box of over kSparseViewPixels pixels each at 300 m) take one
// sample.
TEST(ViewSets, OwnViewsAloneSampleAsTheBuildingsOwnTrianglesAsk) {
  Scene s = two_buildings(16, 10);
  add_fine_grid(s, 11.0f, 0.01f, 1);  // b's, behind a
  ASSERT_GT(16 * s.triangle_count(), size_t(320 * 256));
  LabelJob job = per_building_job("+x,-y", 300);
  job.samples = kAutoSamples;
  job.own_views_alone = false;
  const LabelResult in_place = label(s, job);
  job.own_views_alone = true;
  const LabelResult alone = label(s, job);
  ASSERT_EQ(in_place.report.buildings.size(), 2u);
  ASSERT_EQ(alone.report.buildings.size(), 2u);
  EXPECT_EQ(in_place.report.buildings[0].sampling_chosen, (std::map<std::string, size_t>{{"4", 2}}));
  // (a's box covers over kSparseViewPixels pixels per triangle of its 12:
  // a sparse view, one sample.)
  EXPECT_EQ(alone.report.buildings[0].sampling_chosen, (std::map<std::string, size_t>{{"1", 2}}));
  // b alone still draws its 20,012 triangles: one render at 4 samples.
  EXPECT_EQ(alone.report.buildings[1].sampling_chosen, (std::map<std::string, size_t>{{"4", 2}}));
  // a's faces that some view sees are labelled from its own views either way.
  for (size_t t : {4u, 5u, 10u, 11u}) EXPECT_NE(alone.labels[t], Label::Undisplayable) << t;
}

// Buildings alone are labelled on one thread per CPU
// (building_threads 0), each with its own OpenGL context: the labels, the
// counts and the report's per-building entries (in model order) are those
// of one thread, with or without the render overlapping the trace.
TEST(ViewSets, BuildingsAloneOnSeveralThreadsLabelAsOnOne) {
  Scene s = two_buildings(16, 14);
  add_box(s, {-14, 2, 0}, {-4, 8, 6}, 2);
  add_box(s, {30, 0, 0}, {34, 4, 20}, 3);
  s.component_names = {"a/Building/1", "b/Building/1", "c/Building/1", "d/Building/1"};
  LabelJob job = per_building_job("facades,top", 80);
  job.samples = kAutoSamples;
  job.building_threads = 1;
  const LabelResult one = label(s, job);
  ASSERT_EQ(one.report.buildings.size(), 4u);
  for (const auto& [threads, overlap] : {std::pair{2, true}, std::pair{3, false}}) {
    SCOPED_TRACE(std::to_string(threads) + " threads, overlap " + std::to_string(overlap));
    job.building_threads = threads;
    job.overlap = overlap;
    const LabelResult many = label(s, job);
    expect_same_labelling(many, one);
    ASSERT_EQ(many.report.buildings.size(), 4u);
    for (size_t b = 0; b < 4; ++b) {
      EXPECT_EQ(many.report.buildings[b].building, one.report.buildings[b].building);
      EXPECT_EQ(many.report.buildings[b].views, one.report.buildings[b].views);
      EXPECT_EQ(many.report.buildings[b].sampling_chosen, one.report.buildings[b].sampling_chosen);
    }
    EXPECT_EQ(many.report.step_seconds.count("render"), 1u);
  }
  EXPECT_EQ(building_lanes(job), 3u);
  job.building_threads = 0;
  EXPECT_GE(building_lanes(job), 1u);
}

// Each building's LOD judged alone (judge_buildings_alone): b (16-26 m)
// loses a plaque on its -x face, which a (0-10 m, 10 m high) hides from a
// view of the model from -x. Framed on b alone, the -x view sees the plaque
// go; a's figures stay 0; the model's -x view sees nothing. Two lanes give
// one lane's figures, in building order.
TEST(ViewSets, EachBuildingIsJudgedAloneFromViewsFramedOnIt) {
  Scene s = two_buildings(16, 14);
  const size_t whole = s.triangle_count();
  add_box(s, {15.5f, 3, 2}, {16, 7, 4}, 1);  // b's plaque, behind a from -x
  // A dark plaque: a flat one the walls' colour would look the same head on.
  s.materials = {Material{"wall", {0.8f, 0.8f, 0.8f}, true}, Material{"plaque", {0.1f, 0.1f, 0.1f}, true}};
  s.material.assign(s.triangle_count(), 0);
  std::fill(s.material.begin() + long(whole), s.material.end(), 1u);
  Scene lod = s;
  lod.indices.resize(3 * whole);
  lod.component.resize(whole);
  lod.material.resize(whole);
  LabelJob job = job_for("-x,+y", 100);
  const Framing framing = framing_of(job);
  const JudgeSettings how{job.perception, true, 1};

  // The window: each camera is cropped around its building, not the frame.
  Bounds a = Bounds::empty();
  for (const float p : {0.f, 10.f}) a.grow(std::array<float, 3>{p, p, p}.data());
  const std::vector<ViewTile> tiles = framed_windows(a, job.views, framing, job.perception);
  ASSERT_EQ(tiles.size(), 2u);
  EXPECT_LT(tiles[0].camera.width, job.display.width);

  const std::vector<BuildingJudged> one = judge_buildings_alone(s, lod, job.views, framing, how, 1);
  ASSERT_EQ(one.size(), 2u);
  EXPECT_EQ(one[0].building, "a");
  EXPECT_EQ(one[1].building, "b");
  EXPECT_EQ(one[1].triangles, 24u);
  EXPECT_EQ(one[1].lod_triangles, 12u);
  ASSERT_EQ(one[1].views.size(), 2u);
  EXPECT_FALSE(one[1].unchanged);
  // a's LOD is its original: settled without a render.
  EXPECT_TRUE(one[0].unchanged);
  EXPECT_TRUE(one[0].views.empty());
  // The same triangles in another order are judged, and nothing changes.
  Scene reordered = lod;
  std::swap_ranges(reordered.indices.begin(), reordered.indices.begin() + 3, reordered.indices.begin() + 3);
  const std::vector<BuildingJudged> swapped = judge_buildings_alone(s, reordered, job.views, framing, how, 1);
  ASSERT_EQ(swapped.size(), 2u);
  EXPECT_FALSE(swapped[0].unchanged);
  ASSERT_EQ(swapped[0].views.size(), 2u);
  for (const ViewFigures& v : swapped[0].views) {
    EXPECT_EQ(v.building, "a");
    EXPECT_EQ(v.changed_pixels, 0u) << v.view;
    EXPECT_EQ(v.visible_ratio, 0.0) << v.view;
  }
  EXPECT_EQ(swapped[1].views, one[1].views);
  const ViewFigures& minus_x = one[1].views[0];
  EXPECT_EQ(minus_x.view, "b/-x");
  EXPECT_GT(minus_x.changed_pixels, 0u);
  EXPECT_GT(minus_x.visible_ratio, 1.0);
  EXPECT_FALSE(judge_views(one[1].views, FidelityLimits{}).met());
  EXPECT_TRUE(judge_views(one[0].views, FidelityLimits{}).met());

  const std::vector<BuildingJudged> two = judge_buildings_alone(s, lod, job.views, framing, how, 2);
  ASSERT_EQ(two.size(), 2u);
  for (size_t b = 0; b < 2; ++b) EXPECT_EQ(two[b].views, one[b].views) << b;

  // Floors kept between calls: measured once per building (none for a,
  // unchanged), then taken as they are.
  BuildingFloors floors;
  const std::vector<BuildingJudged> cached = judge_buildings_alone(s, lod, job.views, framing, how, 2, nullptr,
                                                                   nullptr, &floors);
  ASSERT_EQ(floors.size(), 2u);
  EXPECT_TRUE(floors[0].empty());
  ASSERT_EQ(floors[1].size(), 2u);
  for (size_t b = 0; b < 2; ++b) EXPECT_EQ(cached[b].views, one[b].views) << b;
  EXPECT_EQ(judge_buildings_alone(s, lod, job.views, framing, how, 1, nullptr, nullptr, &floors)[1].views,
            one[1].views);
  floors[1][0] = {123.0, 456.0};
  const ViewFigures taken = judge_buildings_alone(s, lod, job.views, framing, how, 1, nullptr, nullptr, &floors)[1].views[0];
  EXPECT_EQ(taken.visible_floor, 123.0);
  EXPECT_EQ(taken.visible_floor_local, 456.0);
  EXPECT_EQ(taken.visible_difference, one[1].views[0].visible_difference);

  // The window judges as b's whole frame does, up to the rounding of a
  // cropped camera at the rasteriser's edges.
  Renderer r;
  std::vector<uint32_t> of_b, lod_of_b, vertex;
  for (uint32_t t = 0; t < s.triangle_count(); ++t)
    if (s.component[t] == 1) of_b.push_back(t);
  for (uint32_t t = 0; t < lod.triangle_count(); ++t)
    if (lod.component[t] == 1) lod_of_b.push_back(t);
  const Scene b_alone = subset_scene(s, of_b, vertex), b_lod = subset_scene(lod, lod_of_b, vertex);
  // View by view, the figures of recording, measuring the floors and
  // comparing each in turn over b's windows.
  std::vector<ViewRecord> windows =
      record_views(r, b_alone, framed_windows(scene_bounds(b_alone), job.views, framing, job.perception), "held_out");
  measure_floors(r, b_alone, windows, how);
  const std::vector<ViewFigures> in_turn = compare_lod_views(r, b_lod, windows, how);
  ASSERT_EQ(in_turn.size(), 2u);
  for (size_t v = 0; v < 2; ++v) {
    ViewFigures f = in_turn[v];
    f.building = "b";
    f.view = "b/" + f.view;
    EXPECT_EQ(one[1].views[v], f) << v;
  }
  std::vector<ViewRecord> frames = record_views(r, b_alone, job.views, framing);
  measure_floors(r, b_alone, frames, how);
  const std::vector<ViewFigures> whole_frame = compare_lod_views(r, b_lod, frames, how);
  ASSERT_EQ(whole_frame.size(), 2u);
  for (size_t v = 0; v < 2; ++v) {
    EXPECT_NEAR(one[1].views[v].visible_ratio, whole_frame[v].visible_ratio, 0.1 * whole_frame[v].visible_ratio + 1e-9)
        << v;
    EXPECT_NEAR(double(one[1].views[v].changed_pixels), double(whole_frame[v].changed_pixels),
                0.1 * double(whole_frame[v].changed_pixels))
        << v;
  }

  // The model's -x view: a hides the plaque, nothing changes.
  const std::vector<ViewRecord> model = record_views(r, s, {"-x"}, framing);
  const std::vector<ViewFigures> seen = compare_lod_views(r, lod, model, how);
  ASSERT_EQ(seen.size(), 1u);
  EXPECT_EQ(seen[0].changed_pixels, 0u);

  // A LOD without any of b's triangles: b judged against nothing.
  Scene without_b = lod;
  without_b.indices.resize(3 * 12);
  without_b.component.resize(12);
  without_b.material.resize(12);
  const std::vector<BuildingJudged> gone = judge_buildings_alone(s, without_b, job.views, framing, how, 1);
  ASSERT_EQ(gone.size(), 2u);
  EXPECT_EQ(gone[1].lod_triangles, 0u);
  for (const ViewFigures& v : gone[1].views) EXPECT_EQ(v.silhouette_mismatch, 1.0) << v.view;

  Scene renamed = lod;
  renamed.component_names[1] = "c/Building/1";
  EXPECT_THROW(judge_buildings_alone(s, renamed, job.views, framing, how, 1), std::invalid_argument);
}

// A building's own views draw and read only their window on it: the labels
// and counts are those of drawing the whole frame, alone and in place (with
// the unsampled-surface rule, which reads the render's depth at projected
// pixels). A mask per sample's passes drew only their window before.
TEST(ViewSets, OwnViewsDrawnInTheirWindowLabelAsTheWholeFrame) {
  Scene s = two_buildings(16, 14);
  add_box(s, {-14, 2, 0}, {-4, 8, 6}, 2);
  // A square metre of 2 cm cells in front of a: triangles a fortieth of a
  // pixel at 150 m, which the unsampled-surface rule keeps.
  const size_t grid = add_fine_grid(s, -3.0f, 0.02f, 3);
  s.component_names = {"a/Building/1", "b/Building/1", "c/Building/1", "d/Building/1"};
  for (const bool alone : {true, false}) {
    SCOPED_TRACE(alone ? "alone" : "in place, unsampled surface");
    LabelJob job = per_building_job("facades,az30el30", 150);
    job.display.width = 768;  // a frame the windows (the DWT's reach around a building) leave part of
    job.display.height = 640;
    job.perception = perception_settings_for(job.display);
    job.samples = 4;
    job.own_views_alone = alone;
    job.keep_unsampled_surface = !alone;
    job.own_views_window_only = false;
    const LabelResult whole = label(s, job);
    job.own_views_window_only = true;
    const LabelResult window = label(s, job);
    expect_same_labelling(window, whole);
    if (!alone) {  // the rule found the grid's unsampled triangles in the parts drawn
      size_t kept = 0;
      for (size_t t = grid; t < s.triangle_count(); ++t) kept += window.labels[t] != Label::Undisplayable;
      EXPECT_GT(kept, (s.triangle_count() - grid) / 2);
    }
    // Each building's views drew a part of their frames.
    ASSERT_EQ(window.report.buildings.size(), 4u);
    for (size_t b = 0; b < 4; ++b) {
      const size_t frames = whole.report.buildings[b].rendered_pixels, parts = window.report.buildings[b].rendered_pixels;
      EXPECT_GT(parts, 0u);
      EXPECT_LT(parts, frames) << whole.report.buildings[b].building;
    }
  }
}

// A surface of triangles a fifth of a pixel across: the four samples and the
// centre of a pixel hit at most five of its 50 triangles, so the paper's rule
// calls nine in ten undisplayable, and a LOD without them is perforated.
// keep_unsampled_surface finds them on the drawn surface; the same grid
// hidden 0.25 m behind it, or lying under a coplanar quad, stays
// undisplayable, and with one sample per pixel the option changes nothing.
TEST(ViewSets, UnsampledTrianglesOfADrawnSurfaceAreKeptOnRequest) {
  LabelJob job = job_for("-y", 1, 4);
  const double p1 = display_pixel_footprint(job.display, 1.0);
  job.distance = 0.05 / p1;  // a pixel is 5 cm, a cell 1 cm
  Scene s;
  s.component_names = {"front", "hidden", "body"};
  const size_t front = add_fine_grid(s, 0.0f, 0.01f, 0);
  const size_t hidden = add_fine_grid(s, 0.25f, 0.01f, 1);
  const size_t n = hidden - front;
  add_box(s, {0, 0.5f, 0}, {1, 0.6f, 1}, 2);
  auto undisplayable = [&](const LabelResult& r, size_t first) {
    size_t u = 0;
    for (size_t t = first; t < first + n; ++t) u += r.labels[t] == Label::Undisplayable;
    return double(u) / double(n);
  };
  LabelResult paper_rule = label(s, job);
  EXPECT_GT(undisplayable(paper_rule, front), 0.8);
  EXPECT_EQ(undisplayable(paper_rule, hidden), 1.0);
  EXPECT_EQ(label_report_json(paper_rule.report)["keep_unsampled_surface"], false);

  job.keep_unsampled_surface = true;
  LabelResult kept = label(s, job);
  EXPECT_LT(undisplayable(kept, front), 0.1);  // 0 measured; border pixels may keep a few
  EXPECT_EQ(undisplayable(kept, hidden), 1.0);
  EXPECT_EQ(label_report_json(kept.report)["keep_unsampled_surface"], true);
  size_t counted = 0;
  for (const ViewLabelling& v : kept.report.views) counted += v.unsampled_surface;
  EXPECT_GT(counted, size_t(0.8 * double(n)));
  // Only triangles no sample hit change; the sampled ones keep their counts.
  for (size_t t = 0; t < s.triangle_count(); ++t)
    if (paper_rule.totals.traced[t]) {
      EXPECT_EQ(kept.totals.traced[t], paper_rule.totals.traced[t]);
    }

  // The same fine grid lying in the plane of a wall quad drawn before it (a
  // window polygon in its wall, a coplanar copy): the quad is drawn and
  // traced there, the grid is hidden and stays undisplayable.
  Scene coplanar;
  coplanar.component_names = {"wall", "window"};
  coplanar.positions = {0, 0, 0, 1, 0, 0, 1, 0, 1, 0, 0, 1};
  coplanar.indices = {0, 1, 2, 0, 2, 3};
  coplanar.component = {0, 0};
  const size_t window = add_fine_grid(coplanar, 0.0f, 0.01f, 1);
  EXPECT_GT(undisplayable(label(coplanar, job), window), 0.9);

  job.samples = 1;
  LabelResult one = label(s, job);
  job.keep_unsampled_surface = false;
  EXPECT_EQ(one.labels, label(s, job).labels);
}

// samples: auto picks per view, from the window's share of the frame and
// the scene's triangles (choose_sampling): a view far away takes the
// 16-sample grid, one whose window is up to half the frame 4 samples with a
// mask per sample, a larger one (or any view of a scene with more triangles
// than frame pixels / 16) one render with 4 samples; a box covering at
// least kSparseViewPixels per triangle one sample, however wide its window.
TEST(ViewSets, AutoSamplesRuleWeighsWindowFrameAndTriangles) {
  const size_t frame = 1280 * 1024;
  const size_t dense = 25000;  // kSparseViewPixels x 25,000 is more than the frame
  ASSERT_GT(kSparseViewPixels * dense, frame);
  EXPECT_EQ(choose_sampling(frame / 16, frame, dense, frame / 16), (ViewSampling{16, true}));
  EXPECT_EQ(choose_sampling(frame / 16 + 1, frame, dense, frame / 16), (ViewSampling{4, true}));
  EXPECT_EQ(choose_sampling(frame / 2, frame, dense, frame / 2), (ViewSampling{4, true}));
  EXPECT_EQ(choose_sampling(frame / 2 + 1, frame, dense, frame / 2), (ViewSampling{4, false}));
  EXPECT_EQ(choose_sampling(frame, frame, dense, frame), (ViewSampling{4, false}));
  EXPECT_EQ(choose_sampling(frame / 16, frame, frame / 16, frame / 16), (ViewSampling{16, true}));
  EXPECT_EQ(choose_sampling(100, frame, frame / 16 + 1, 100), (ViewSampling{4, false}));  // triangle-bound
  // Sparse: 1,000 triangles whose box covers kSparseViewPixels x 1,000 pixels or more.
  const size_t sparse = kSparseViewPixels * 1000;
  EXPECT_EQ(choose_sampling(frame / 2, frame, 1000, sparse), (ViewSampling{1, false}));
  EXPECT_EQ(choose_sampling(frame, frame, 1000, frame), (ViewSampling{1, false}));
  EXPECT_EQ(choose_sampling(frame / 2, frame, 1000, sparse - 1), (ViewSampling{4, true}));
  // The window's margin does not count: a small box in a wide window.
  EXPECT_EQ(choose_sampling(frame / 16, frame, 100, kSparseViewPixels * 100 - 1), (ViewSampling{16, true}));
  EXPECT_EQ(choose_sampling(frame / 16, frame, 100, kSparseViewPixels * 100), (ViewSampling{1, false}));
  EXPECT_EQ(choose_sampling(frame / 16, frame, 0, 0), (ViewSampling{1, false}));  // nothing to draw
  EXPECT_EQ(parse_samples("auto"), kAutoSamples);
  EXPECT_EQ(parse_samples("16"), 16);
  for (const char* bad : {"3", "", "4x", "sixteen", "-4", "5"}) {
    try {
      parse_samples(bad);
      ADD_FAILURE() << "'" << bad << "' accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("auto, 1, 2, 4, 8, 9 or 16"), std::string::npos) << e.what();
    }
  }
}

// Each view labelled with samples auto is labelled exactly as its chosen
// setting labels it, and the totals count sixteenths of a pixel: far away
// every view takes the grid (the totals of samples 16 bit for bit), a
// broad side at 100 m a mask per sample (4 x the totals of 4 samples so
// made), and a scene of more triangles than frame pixels / 16 one render
// (4 x the totals of 4 samples).
TEST(ViewSets, AutoSamplesLabelEachViewAsItsChoice) {
  auto full_frame = [](LabelJob job) {
    job.display = DisplayProfile{};
    job.perception = perception_settings_for(job.display);
    return job;
  };
  auto same_as = [](const LabelResult& a, const LabelResult& b, uint32_t weight, const char* what) {
    ASSERT_EQ(a.labels.size(), b.labels.size());
    EXPECT_EQ(a.labels, b.labels) << what;
    size_t traced = 0;
    for (size_t t = 0; t < a.labels.size(); ++t) {
      ASSERT_EQ(a.totals.traced[t], weight * b.totals.traced[t]) << what << " triangle " << t;
      ASSERT_EQ(a.totals.imperceptible[t], weight * b.totals.imperceptible[t]) << what << " triangle " << t;
      traced += b.totals.traced[t] > 0;
    }
    EXPECT_GT(traced, a.labels.size() / 4) << what;
  };
  const Scene s = wall(30, 12);
  {
    const LabelResult autos = label(s, full_frame(job_for("facades,az30el30,top", 200, kAutoSamples)));
    EXPECT_EQ(label_report_json(autos.report)["samples_per_pixel"], "auto");
    EXPECT_EQ(label_report_json(autos.report)["sampling_chosen"], (nlohmann::json{{"16 (grid)", 6}}));
    for (const ViewLabelling& v : autos.report.views) EXPECT_EQ(v.sampling, "16 (grid)");
    same_as(autos, label(s, full_frame(job_for("facades,az30el30,top", 200, 16))), 1, "grid at 200 m");
  }
  {
    // Twice the size at twice the distance, with four times the triangles:
    // the same window as the 30 x 12 wall's at 100 m, too dense to be sparse.
    const Scene dense = wall(60, 24);
    const LabelResult autos = label(dense, full_frame(job_for("-y,+y", 200, kAutoSamples)));
    EXPECT_EQ(label_report_json(autos.report)["sampling_chosen"], (nlohmann::json{{"4 (mask per sample)", 2}}));
    LabelJob mps = full_frame(job_for("-y,+y", 200, 4));
    mps.mask_per_sample = true;
    same_as(autos, label(dense, mps), 4, "mask per sample at 200 m");
    // The 30 x 12 wall at 100 m: its box covers over kSparseViewPixels per triangle.
    const LabelResult sparse = label(s, full_frame(job_for("-y,+y", 100, kAutoSamples)));
    EXPECT_EQ(label_report_json(sparse.report)["sampling_chosen"], (nlohmann::json{{"1", 2}}));
  }
  {
    const Scene fine = wall(80, 40);  // 6,412 triangles > 320 x 256 / 16
    const LabelResult autos = label(fine, job_for("facades,top", 400, kAutoSamples));
    EXPECT_EQ(label_report_json(autos.report)["sampling_chosen"], (nlohmann::json{{"4", label_report_json(autos.report)["views"].size()}}));  // tiles too
    same_as(autos, label(fine, job_for("facades,top", 400, 4)), 4, "one render, triangle-bound");
  }
  {
    const Scene coarse = wall(2, 1);  // 16 triangles, a box of over 16 x kSparseViewPixels pixels at 25 m
    const LabelResult autos = label(coarse, full_frame(job_for("-y,+y", 25, kAutoSamples)));
    EXPECT_EQ(label_report_json(autos.report)["sampling_chosen"], (nlohmann::json{{"1", 2}}));
    same_as(autos, label(coarse, full_frame(job_for("-y,+y", 25, 1))), 16, "one sample, sparse");
    // At 200 m its box covers less than kSparseViewPixels per triangle (its
    // window, widened by the perception's margin, would cover more).
    const LabelResult far = label(coarse, full_frame(job_for("-y,+y", 200, kAutoSamples)));
    EXPECT_EQ(label_report_json(far.report)["sampling_chosen"], (nlohmann::json{{"16 (grid)", 2}}));
  }
  // With mask_per_sample or keep_unsampled_surface, auto means 4 samples.
  LabelJob keep = job_for("-y", 100, kAutoSamples);
  keep.keep_unsampled_surface = true;
  EXPECT_EQ(effective_samples(keep), 4);
  EXPECT_EQ(label_report_json(label(s, keep).report)["samples_per_pixel"], 4);
}

// keep_undisplayable: auto keeps undisplayable triangles only when the
// exposure views see more than kKeepUndisplayableExposure of their pixels on
// them, and then within kAutoUndisplayableBoundPx; anything but the fidelity
// mode deleting them is left as asked.
TEST(UndisplayableAuto, KeepsOnlyWhatTheViewsBetweenWouldSeeOpen) {
  SimplifyOptions so;
  so.mode = SimplifyMode::Fidelity;
  ASSERT_TRUE(so.delete_undisplayable);
  EXPECT_TRUE(choose_undisplayable(so, 0).delete_undisplayable);
  EXPECT_TRUE(choose_undisplayable(so, kKeepUndisplayableExposure).delete_undisplayable);
  const SimplifyOptions kept = choose_undisplayable(so, 2 * kKeepUndisplayableExposure);
  EXPECT_FALSE(kept.delete_undisplayable);
  EXPECT_EQ(kept.bound_undisplayable_px, kAutoUndisplayableBoundPx);
  SimplifyOptions paper = so;
  paper.mode = SimplifyMode::Paper;  // the paper's rule stays exact
  EXPECT_TRUE(choose_undisplayable(paper, 1).delete_undisplayable);
  SimplifyOptions asked = so;
  asked.delete_undisplayable = false;
  asked.bound_undisplayable_px = 1;  // an asked bound is not loosened
  EXPECT_EQ(choose_undisplayable(asked, 1).bound_undisplayable_px, 1);
  for (const std::string& v : exposure_views())  // none is a labelling or held-out view of the defaults
    for (const char* preset : {kDefaultViews, "held_out"}) {
      const std::vector<std::string> set = parse_views(preset, UpAxis::Z);
      EXPECT_EQ(std::find(set.begin(), set.end(), v), set.end()) << v << " in " << preset;
    }
}

// tighten_to_limits tries the steps of kTightenSteps that tighten the asked
// bounds (none that would change nothing), and only for a LOD over a limit
// by no more than kTightenReach times it.
TEST(TightenToLimits, StepsAreTheTighterOnesAndReachIsBounded) {
  SimplifyOptions so;
  so.mode = SimplifyMode::Fidelity;  // undisplayable deleted
  so.bound_imperceptible_px = 0.5;   // the default until 0.8
  const std::vector<FidelitySearchStep> steps = tighten_steps(so);
  ASSERT_EQ(steps.size(), std::size(kTightenSteps));
  const SimplifyOptions first = fidelity_bounds(so, steps[0]);
  EXPECT_EQ(first.bound_imperceptible_px, 0.25);
  EXPECT_EQ(first.bound_perceptible_px, 0.25);
  EXPECT_TRUE(first.delete_undisplayable);
  const SimplifyOptions second = fidelity_bounds(so, steps[1]);
  EXPECT_FALSE(second.delete_undisplayable);
  EXPECT_EQ(second.bound_undisplayable_px, kAutoUndisplayableBoundPx);
  const SimplifyOptions last = fidelity_bounds(so, steps.back());
  EXPECT_EQ(last.bound_imperceptible_px, 0.125);
  EXPECT_EQ(last.bound_undisplayable_px, 0.125);
  // Each step is at least as tight as the one before, and none is e = 0.
  SimplifyOptions before = so;
  for (const FidelitySearchStep& step : steps) {
    const SimplifyOptions t = fidelity_bounds(so, step);
    EXPECT_LE(t.bound_imperceptible_px, before.bound_imperceptible_px);
    EXPECT_LE(t.bound_perceptible_px, before.bound_perceptible_px);
    if (!before.delete_undisplayable) {
      EXPECT_LE(t.bound_undisplayable_px, before.bound_undisplayable_px);
    }
    EXPECT_GT(t.bound_imperceptible_px, 0);
    before = t;
  }
  // keep_undisplayable: auto kept them within 4 px: the 0.25 px step with
  // them kept within 4 px would repeat the first, and is left out.
  const SimplifyOptions kept = choose_undisplayable(so, 1.0);
  const std::vector<FidelitySearchStep> kept_steps = tighten_steps(kept);
  ASSERT_EQ(kept_steps.size(), 3u);
  EXPECT_EQ(fidelity_bounds(kept, kept_steps[0]).bound_undisplayable_px, kAutoUndisplayableBoundPx);
  EXPECT_EQ(fidelity_bounds(kept, kept_steps[1]).bound_imperceptible_px, 0.125);
  EXPECT_EQ(fidelity_bounds(kept, kept_steps[2]).bound_undisplayable_px, 0.125);
  SimplifyOptions tight = so;  // asked at 0.125 px: only keeping what was deleted remains
  tight.bound_imperceptible_px = 0.125;
  ASSERT_EQ(tighten_steps(tight).size(), 2u);
  for (const FidelitySearchStep& step : tighten_steps(tight)) EXPECT_TRUE(step.keep_undisplayable);
  tight.delete_undisplayable = false;
  tight.bound_undisplayable_px = 0.1;
  tight.bound_perceptible_px = 0.125;
  EXPECT_TRUE(tighten_steps(tight).empty());  // nothing tighter to try
  SimplifyOptions paper = so;
  paper.mode = SimplifyMode::Paper;
  EXPECT_TRUE(tighten_steps(paper).empty());

  const FidelityLimits limits{0.02, 0.01, 0, 0};  // 2% changed, 1% silhouette, no SSIM or visible limit
  auto judged = [](double changed, double silhouette, double ssim,
                   const FidelityLimits& against = FidelityLimits{0.02, 0.01, 0, 0}) {
    ViewFigures v;
    v.view = "v", v.set = "held_out";
    v.changed_fraction = changed, v.silhouette_mismatch = silhouette, v.ssim_covered = ssim;
    return judge_views({v}, against);
  };
  EXPECT_FALSE(worth_tightening(judged(0.02, 0.01, 0.9), limits));  // within: nothing to do
  EXPECT_TRUE(worth_tightening(judged(0.0329, 0.0001, 0.99), limits));
  EXPECT_TRUE(worth_tightening(judged(kTightenReach * 0.02, 0, 0.99), limits));
  EXPECT_FALSE(worth_tightening(judged(0.12, 0.001, 0.91), limits));  // the demo at 427 m: out of reach
  EXPECT_FALSE(worth_tightening(judged(0.03, 0.04, 0.99), limits));   // silhouette out of reach
  FidelityLimits ssim = limits;
  ssim.min_ssim = 0.97;
  EXPECT_TRUE(worth_tightening(judged(0.01, 0, 0.95, ssim), ssim));   // 0.05 short of 1 <= 3 x 0.03
  EXPECT_FALSE(worth_tightening(judged(0.01, 0, 0.90, ssim), ssim));  // 0.10 > 0.09
}

// Asked looser than kTightenHalvingsTo (the default, 8 px): e halves down to
// it first, then kTightenSteps; no step loosens e_P, and only the steps
// below kTightenHalvingsTo need the LOD within reach of its limits.
TEST(TightenToLimits, LooseBoundsHalveDownToHalfAPixelFirst) {
  SimplifyOptions so;
  so.mode = SimplifyMode::Fidelity;
  ASSERT_EQ(so.bound_imperceptible_px, kDefaultBoundImperceptiblePx);
  ASSERT_EQ(so.bound_imperceptible_px, 8.0);
  ASSERT_EQ(so.bound_perceptible_px, 0.5);
  const std::vector<FidelitySearchStep> steps = tighten_steps(so);
  std::vector<double> e;
  for (const FidelitySearchStep& step : steps) e.push_back(step.e);
  EXPECT_EQ(e, (std::vector<double>{4, 2, 1, 0.5, 0.25, 0.25, 0.125, 0.125}));
  for (size_t i = 0; i < steps.size(); ++i) {
    const SimplifyOptions t = tightened_bounds(so, steps[i]);
    EXPECT_EQ(t.bound_imperceptible_px, steps[i].e);
    // fidelity_bounds alone would loosen e_P to a quarter of 4 px (1 px).
    EXPECT_EQ(t.bound_perceptible_px, std::min(0.5, steps[i].e)) << steps[i].e;
    EXPECT_EQ(tighten_step_needs_reach(steps[i]), steps[i].e < 0.5) << i;
    EXPECT_EQ(t.delete_undisplayable, !steps[i].keep_undisplayable) << i;
  }
  EXPECT_EQ(fidelity_bounds(so, steps[0]).bound_perceptible_px, 1.0);
  // Not a power of two: halvings while above 0.5 px, then 0.5 px itself.
  so.bound_imperceptible_px = 6;
  e.clear();
  for (const FidelitySearchStep& step : tighten_steps(so)) e.push_back(step.e);
  EXPECT_EQ(e, (std::vector<double>{3, 1.5, 0.75, 0.5, 0.25, 0.25, 0.125, 0.125}));
  so.bound_imperceptible_px = 0.7;
  EXPECT_EQ(tighten_steps(so).front().e, 0.5);
  // Once a halving meets the limits, the step midway to the try before it.
  so.bound_imperceptible_px = 8;
  ASSERT_TRUE(tighten_midway(so, 4).has_value());
  EXPECT_DOUBLE_EQ(tighten_midway(so, 4)->e, std::sqrt(32.0));  // the asked 8 px before it
  EXPECT_DOUBLE_EQ(tighten_midway(so, 2)->e, std::sqrt(8.0));
  EXPECT_DOUBLE_EQ(tighten_midway(so, 0.5)->e, std::sqrt(0.5));
  EXPECT_FALSE(tighten_midway(so, 4)->keep_undisplayable);
  EXPECT_FALSE(tighten_midway(so, 0.25).has_value());  // a sub-pixel step
  EXPECT_FALSE(tighten_midway(so, 3).has_value());     // not a step of these bounds
  so.bound_imperceptible_px = 0.5;
  EXPECT_FALSE(tighten_midway(so, 0.25).has_value());
}

// The driver run and the benchmarks share: tries the steps in order, stops
// at the first within the limits (then tries midway after a halving), keeps
// the tightest when none is within, and tries nothing when the asked LOD is
// within its limits or out of reach.
TEST(TightenToLimits, TriesTheStepsInOrderUntilOneIsWithin) {
  SimplifyOptions so;
  so.mode = SimplifyMode::Fidelity;
  so.bound_imperceptible_px = 0.5;  // the default until 0.8: every step needs reach
  const FidelityLimits limits{0.02, 0.01, 0, 0};  // changed pixels and silhouette only
  auto judged = [&](double changed) {
    ViewFigures v;
    v.view = "v", v.set = "held_out";
    v.changed_fraction = changed, v.silhouette_mismatch = 0.0, v.ssim_covered = 0.99;
    return judge_views({v}, limits);
  };
  std::vector<double> tried;  // e_imperceptible of each try
  std::vector<bool> midways;  // whether each try was the midway one
  // The n-th try (from 1) is within, and so is every midway try; 0: none
  // is. A try's triangles: 1000 / e, or `midway_triangles` for a midway try.
  size_t midway_triangles = 0;
  auto within_at = [&](size_t n) {
    return [&, n](const SimplifyOptions& o, bool midway) {
      tried.push_back(o.bound_imperceptible_px);
      midways.push_back(midway);
      if (midway) return std::pair<bool, size_t>(true, midway_triangles);
      return std::pair<bool, size_t>(tried.size() == n, size_t(1000 / o.bound_imperceptible_px));
    };
  };
  auto clear = [&] { tried.clear(), midways.clear(); };
  TighteningResult t = tighten_to_limits(so, judged(0.01), limits, within_at(1));
  EXPECT_EQ(t.outcome, Tightening::NotTried);
  EXPECT_EQ(t.kept.bound_imperceptible_px, 0.5);
  EXPECT_EQ(tighten_to_limits(so, judged(0.2), limits, within_at(1)).outcome, Tightening::NotTried);  // out of reach
  EXPECT_TRUE(tried.empty());
  t = tighten_to_limits(so, judged(0.03), limits, within_at(2));
  EXPECT_EQ(t.outcome, Tightening::Met);
  EXPECT_EQ(tried, (std::vector<double>{0.25, 0.25}));  // no midway below half a pixel
  EXPECT_EQ(t.tries, 2u);
  EXPECT_EQ(t.kept_try, 1u);
  EXPECT_FALSE(t.kept.delete_undisplayable);  // the second 0.25 px step keeps them
  EXPECT_FALSE(t.remake);
  clear();
  // None within: every step, and the tightest (the last) is kept.
  t = tighten_to_limits(so, judged(0.03), limits, within_at(0));
  EXPECT_EQ(t.outcome, Tightening::NoneWithin);
  ASSERT_EQ(tried.size(), tighten_steps(so).size());
  for (size_t i = 0; i < tried.size(); ++i)
    EXPECT_EQ(tried[i], fidelity_bounds(so, tighten_steps(so)[i]).bound_imperceptible_px);
  EXPECT_EQ(t.kept_try, tried.size() - 1);
  EXPECT_EQ(t.kept.bound_imperceptible_px, 0.125);
  EXPECT_FALSE(t.remake);
  // Asked 8 px (the default): out of reach, the halvings down to 0.5 px are
  // tried all the same, and no step below; within reach, every step.
  so.bound_imperceptible_px = 8;
  clear();
  t = tighten_to_limits(so, judged(0.2), limits, within_at(0));
  EXPECT_EQ(t.outcome, Tightening::NoneWithin);
  EXPECT_EQ(tried, (std::vector<double>{4, 2, 1, 0.5}));
  EXPECT_EQ(t.kept.bound_imperceptible_px, 0.5);
  EXPECT_EQ(t.kept.bound_perceptible_px, 0.5);
  // Within at 1 px: then midway between it and 2 px, kept when it has no
  // more triangles than the LOD at 1 px (1000), made again otherwise.
  clear();
  midway_triangles = 900;
  t = tighten_to_limits(so, judged(0.2), limits, within_at(3));
  EXPECT_EQ(t.outcome, Tightening::Met);
  ASSERT_EQ(tried.size(), 4u);
  EXPECT_EQ((std::vector<double>(tried.begin(), tried.begin() + 3)), (std::vector<double>{4, 2, 1}));
  EXPECT_DOUBLE_EQ(tried[3], std::sqrt(2.0));
  EXPECT_EQ(midways, (std::vector<bool>{false, false, false, true}));
  EXPECT_EQ(t.kept_try, 3u);
  EXPECT_DOUBLE_EQ(t.kept.bound_imperceptible_px, std::sqrt(2.0));
  EXPECT_FALSE(t.remake);
  clear();
  midway_triangles = 1001;
  t = tighten_to_limits(so, judged(0.2), limits, within_at(3));
  EXPECT_EQ(t.kept_try, 2u);
  EXPECT_EQ(t.kept.bound_imperceptible_px, 1.0);
  EXPECT_TRUE(t.remake);  // the midway LOD was the last made
  clear();
  t = tighten_to_limits(so, judged(0.03), limits, within_at(0));
  EXPECT_EQ(t.outcome, Tightening::NoneWithin);
  EXPECT_EQ(tried.size(), 8u);
  EXPECT_EQ(t.kept.bound_imperceptible_px, 0.125);
  clear();
  EXPECT_EQ(tighten_to_limits(so, judged(0.01), limits, within_at(1)).outcome, Tightening::NotTried);  // within
  EXPECT_TRUE(tried.empty());
}

// The looser half of a fidelity_target search, on scripted tries (met,
// triangles) for e = 32, 64, ... px: kept while met with fewer triangles;
// met with as many ends it there; a failure or more triangles goes back to
// the last kept step, which is made again.
// A search step's bounds: e_I = e; e_P follows e down where e is tighter
// than the asked e_P, and kPerceptibleShare of e up where that is looser.
TEST(FidelitySearch, PerceptibleBoundFollowsAShareOfTheStep) {
  SimplifyOptions so;
  so.mode = SimplifyMode::Fidelity;  // e_P = e_I = 0.5 px
  auto at = [&](double e) { return fidelity_bounds(so, FidelitySearchStep{e, false}); };
  EXPECT_EQ(at(16).bound_imperceptible_px, 16.0);
  EXPECT_EQ(at(16).bound_perceptible_px, 16 * kPerceptibleShare);
  EXPECT_EQ(at(4).bound_perceptible_px, 4 * kPerceptibleShare);
  EXPECT_EQ(at(1).bound_perceptible_px, 0.5);    // a quarter of 1 px is tighter than asked: the asked 0.5
  EXPECT_EQ(at(0.25).bound_perceptible_px, 0.25);  // tighter than asked: follows e
  so.bound_perceptible_px = 8;                   // an asked e_P looser than a quarter stays
  EXPECT_EQ(at(16).bound_perceptible_px, 8.0);
}

TEST(FidelitySearch, LooserBoundsAreKeptWhileTheyMeetTheTargetAndRemoveTriangles) {
  using Try = std::pair<bool, size_t>;
  std::vector<double> tried;
  auto run = [&](size_t triangles, std::vector<Try> script) {
    tried.clear();
    return search_looser(triangles, [&tried, script](const FidelitySearchStep& step) {
      EXPECT_FALSE(step.keep_undisplayable);
      tried.push_back(step.e);
      return tried.size() <= script.size() ? script[tried.size() - 1] : Try{false, 0};
    });
  };
  // Han at 56 m with a 5% target: 32 and 64 px meet it, 128 px does not,
  // and nor does the midway step (64 sqrt 2 px).
  LooserSearch l = run(13044, {{true, 12701}, {true, 10298}, {false, 9323}});
  EXPECT_EQ(tried, (std::vector<double>{32, 64, 128, 64 * std::sqrt(2.0)}));
  EXPECT_EQ(l.step.e, 64);
  EXPECT_EQ(l.tries, 4);
  EXPECT_EQ(l.kept, 1);
  EXPECT_TRUE(l.remake);
  // The midway step meets it with fewer triangles: it is written as it is.
  l = run(13044, {{true, 12701}, {true, 10298}, {false, 9323}, {true, 9900}});
  EXPECT_EQ(l.step.e, 64 * std::sqrt(2.0));
  EXPECT_FALSE(l.step.keep_undisplayable);
  EXPECT_EQ(l.kept, 3);
  EXPECT_FALSE(l.remake);
  // It meets it with more triangles than 64 px: 64 px stays.
  l = run(13044, {{true, 12701}, {true, 10298}, {false, 9323}, {true, 10299}});
  EXPECT_EQ(l.step.e, 64);
  EXPECT_TRUE(l.remake);
  // The demo at 56 m: 256 px removes none more than 128 px, and is written.
  l = run(7745, {{true, 7709}, {true, 7708}, {true, 7704}, {true, 7704}});
  EXPECT_EQ(tried, (std::vector<double>{32, 64, 128, 256}));
  EXPECT_EQ(l.step.e, 256);
  EXPECT_EQ(l.kept, 3);
  EXPECT_FALSE(l.remake);
  // Met, but with more triangles than the step before: back to that step,
  // no midway try (looser bounds did not help).
  l = run(1000, {{true, 900}, {true, 950}});
  EXPECT_EQ(tried, (std::vector<double>{32, 64}));
  EXPECT_EQ(l.step.e, 32);
  EXPECT_EQ(l.kept, 0);
  EXPECT_TRUE(l.remake);
  // The first looser try fails, and the midway one: back to kFidelitySearch[0].
  l = run(1000, {{false, 500}});
  EXPECT_EQ(tried, (std::vector<double>{32, 16 * std::sqrt(2.0)}));
  EXPECT_EQ(l.step.e, kFidelitySearch[0].e);
  EXPECT_EQ(l.tries, 2);
  EXPECT_EQ(l.kept, -1);
  EXPECT_TRUE(l.remake);
  // Met with more triangles at once: the same.
  l = run(1000, {{true, 1001}});
  EXPECT_EQ(l.kept, -1);
  EXPECT_TRUE(l.remake);
  // Every try met with fewer triangles: up to the cap, the last one written.
  std::vector<Try> fewer;
  for (size_t n = 999; n > 900; --n) fewer.push_back({true, n});
  l = run(1000, fewer);
  EXPECT_EQ(tried.back(), kFidelitySearchLoosestPx);
  EXPECT_EQ(tried, (std::vector<double>{32, 64, 128, 256, 512, 1024}));
  EXPECT_EQ(l.step.e, kFidelitySearchLoosestPx);
  EXPECT_EQ(l.kept, l.tries - 1);
  EXPECT_FALSE(l.remake);
}

// The whole search on scripted tries: down the steps to the first within
// the target, then once midway between it and the step before; the midway
// LOD is written when it meets the target with no more triangles, else the
// step's is made again. No midway try between steps that keep undisplayable
// triangles.
TEST(FidelitySearch, TheStepWithinTheTargetIsFollowedByOneMidwayTowardsTheLastThatFailed) {
  using Try = std::pair<bool, size_t>;
  std::vector<FidelitySearchStep> tried;
  auto run = [&](std::vector<Try> script) {
    tried.clear();
    return search_fidelity_target([&tried, script](const FidelitySearchStep& step, bool looser) {
      EXPECT_FALSE(looser);
      tried.push_back(step);
      return tried.size() <= script.size() ? script[tried.size() - 1] : Try{false, 0};
    });
  };
  // 16 px over the target, 8 px within, 8 sqrt 2 px within with fewer: kept.
  TargetSearch s = run({{false, 3000}, {true, 3592}, {true, 3300}});
  ASSERT_EQ(tried.size(), 3u);
  EXPECT_EQ(tried[2].e, 8 * std::sqrt(2.0));
  EXPECT_FALSE(tried[2].keep_undisplayable);
  EXPECT_TRUE(s.met);
  EXPECT_EQ(s.step.e, 8 * std::sqrt(2.0));
  EXPECT_EQ(s.kept, 2u);
  EXPECT_FALSE(s.remake);
  // The midway try over the target: 8 px, made again.
  s = run({{false, 3000}, {true, 3592}, {false, 3300}});
  EXPECT_EQ(s.step.e, 8);
  EXPECT_EQ(s.kept, 1u);
  EXPECT_EQ(s.tries, 3u);
  EXPECT_TRUE(s.remake);
  // Within, but with more triangles: 8 px too.
  s = run({{false, 3000}, {true, 3592}, {true, 3593}});
  EXPECT_EQ(s.step.e, 8);
  EXPECT_TRUE(s.remake);
  // Met only at the first step that keeps undisplayable triangles: no midway.
  std::vector<Try> script;
  size_t first_keep = 0;
  while (!kFidelitySearch[first_keep].keep_undisplayable) ++first_keep, script.push_back({false, 100});
  script.push_back({true, 200});
  s = run(script);
  EXPECT_EQ(tried.size(), first_keep + 1);
  EXPECT_EQ(s.step.e, kFidelitySearch[first_keep].e);
  EXPECT_FALSE(s.remake);
  // No step within: every one tried, no midway, the tightest written.
  s = run({});
  EXPECT_EQ(tried.size(), std::size(kFidelitySearch));
  EXPECT_FALSE(s.met);
}

// The exposure is the share of the exposure views' hits on undisplayable
// triangles: none of them 0, all of them 1, and a ground whose half x < 4 is
// undisplayable one half (the views stand symmetric about x = 4), a
// quarter of it (x < 2) less than a half and more than nothing.
TEST(UndisplayableAuto, ExposureIsTheShareOfHitsOnUndisplayableTriangles) {
  Scene s;  // 8 x 8 m of ground at z = 0, 1 m squares facing up
  s.component_names = {"ground"};
  for (int i = 0; i <= 8; ++i)
    for (int k = 0; k <= 8; ++k) s.positions.insert(s.positions.end(), {float(i), float(k), 0.0f});
  for (uint32_t i = 0; i < 8; ++i)
    for (uint32_t k = 0; k < 8; ++k) {
      const uint32_t v = i * 9 + k;
      s.indices.insert(s.indices.end(), {v, v + 9, v + 10, v, v + 10, v + 1});
      s.component.insert(s.component.end(), {0, 0});
    }
  OctreeTracer tracer(s);
  const Framing job = framing_of(job_for("top", 20));
  std::vector<Label> labels(s.triangle_count(), Label::Perceptible);
  EXPECT_EQ(undisplayable_exposure(s, tracer, labels, job), 0);
  std::fill(labels.begin(), labels.end(), Label::Undisplayable);
  EXPECT_EQ(undisplayable_exposure(s, tracer, labels, job), 1);
  auto left_of = [&](int x) {
    std::fill(labels.begin(), labels.end(), Label::Perceptible);
    for (size_t t = 0; t < size_t(2 * 8 * x); ++t) labels[t] = Label::Undisplayable;  // squares i < x
    return undisplayable_exposure(s, tracer, labels, job);
  };
  EXPECT_NEAR(left_of(4), 0.5, 0.02);
  const double quarter = left_of(2);
  EXPECT_GT(quarter, 0.1);
  EXPECT_LT(quarter, 0.4);
  EXPECT_THROW(undisplayable_exposure(s, tracer, std::vector<Label>(3), job), std::invalid_argument);
}

}  // namespace
}  // namespace perclod
