// Per-building labelling on real city data: six adjacent buildings of the
// Ingolstadt block (../shared/data), labelled at 132 m from the default view
// set with and without views framed on each building. The whole-model views
// stand 132 m from the group's box, so the middle buildings are far from
// their eyes and partly hidden; framed on each building, the eye is 132 m
// from that building and its facades get labelled.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>

#include "perclod/load.h"
#include "perclod/label.h"
#include "perclod/report_json.h"

namespace perclod {
namespace {

// The triangles of the buildings whose index is in `keep`, as a scene of its own.
Scene subset(const Scene& s, const Buildings& b, const std::vector<uint32_t>& keep) {
  Scene out;
  out.component_names = s.component_names;
  out.positions = s.positions;
  for (size_t t = 0; t < s.triangle_count(); ++t) {
    const uint32_t c = s.component_of(t);
    if (std::find(keep.begin(), keep.end(), b.of_component[c]) == keep.end()) continue;
    out.indices.insert(out.indices.end(), s.indices.begin() + 3 * t, s.indices.begin() + 3 * t + 3);
    out.component.push_back(c);
  }
  return out;
}

TEST(PerBuilding, BlockBuildingsAreLabelledFromTheirOwnViews) {
  Scene block = load_scene(std::string(PERCLOD_SHARED_DATA) + "/ingolstadt/ingolstadt_lod3_all53.obj");
  Buildings all = find_buildings(block);
  ASSERT_GE(all.names.size(), 50u);
  // Six buildings nearest the block's centre by their first vertex.
  const Bounds box = scene_bounds(block);
  std::map<uint32_t, double> dist;
  for (size_t t = 0; t < block.triangle_count(); ++t) {
    const uint32_t b = all.of_component[block.component_of(t)];
    if (dist.count(b)) continue;
    const float* p = &block.positions[3 * size_t(block.indices[3 * t])];
    double d = 0;
    for (int k = 0; k < 2; ++k) d += (p[k] - box.center()[k]) * (p[k] - box.center()[k]);
    dist[b] = d;
  }
  std::vector<std::pair<double, uint32_t>> order;
  for (auto [b, d] : dist) order.push_back({d, b});
  std::sort(order.begin(), order.end());
  std::vector<uint32_t> keep;
  for (size_t i = 0; i < 6; ++i) keep.push_back(order[i].second);
  Scene s = subset(block, all, keep);
  ASSERT_GT(s.triangle_count(), 1000u);
  Buildings b = find_buildings(s);

  LabelJob job;
  job.up = UpAxis::Z;
  job.display = DisplayProfile{};
  job.perception = perception_settings_for(job.display);
  job.views = parse_views(kDefaultViews, UpAxis::Z);
  job.samples = 1;
  job.distance = 132;
  job.write_perception_images = false;
  Renderer renderer;
  OctreeTracer tracer(s);
  job.per_building = PerBuilding::Off;
  LabelResult whole = label_scene(renderer, s, tracer, job);
  job.per_building = PerBuilding::Auto;
  LabelResult own = label_scene(renderer, s, tracer, job);  // the default: each building's own views alone
  job.model_views_beside_alone = true;
  LabelResult per = label_scene(renderer, s, tracer, job);
  job.model_views_beside_alone = false;

  // By default each building's own views of it alone make its labels: the
  // whole-model views count nothing (nor are they drawn, with no files to
  // write), so with them the totals are the two labellings' sums.
  EXPECT_FALSE(own.report.model_views_counted);
  EXPECT_TRUE(per.report.model_views_counted);
  EXPECT_TRUE(own.report.views.empty());
  EXPECT_TRUE(own.views.empty());
  EXPECT_EQ(label_report_json(own.report)["model_views_counted"], false);
  size_t seen_only_by_model_views = 0;
  double samples_only = 0, samples_model = 0;
  for (size_t t = 0; t < s.triangle_count(); ++t) {
    ASSERT_EQ(per.totals.traced[t], own.totals.traced[t] + whole.totals.traced[t]) << t;
    ASSERT_EQ(per.totals.imperceptible[t], own.totals.imperceptible[t] + whole.totals.imperceptible[t]) << t;
    samples_model += double(whole.totals.traced[t]);
    if (own.totals.traced[t] == 0 && whole.totals.traced[t] > 0) {
      ++seen_only_by_model_views;
      samples_only += double(whole.totals.traced[t]);
    }
  }
  std::printf("seen only by the whole-model views: %zu triangles, %.0f of their %.0f samples\n",
              seen_only_by_model_views, samples_only, samples_model);
  // What only the whole-model views hit are chance hits on sub-pixel
  // triangles (a few samples each): under 0.1% of their samples.
  EXPECT_LT(samples_only, 1e-3 * samples_model);

  // Per building, every kept building had its own views.
  size_t with_triangles = 0;
  for (const BuildingLabelling& e : per.report.buildings) with_triangles += e.views > 0;
  EXPECT_EQ(with_triangles, 6u);
  // Views only add: labels seen by the whole-model views stay seen, and
  // per-building views see more of the buildings.
  size_t u_whole = 0, u_per = 0, p_whole = 0, p_per = 0;
  for (size_t t = 0; t < s.triangle_count(); ++t) {
    if (whole.labels[t] != Label::Undisplayable) {
      ASSERT_NE(per.labels[t], Label::Undisplayable) << t;
    }
    if (whole.labels[t] == Label::Perceptible) {
      ASSERT_EQ(per.labels[t], Label::Perceptible) << t;
    }
    u_whole += whole.labels[t] == Label::Undisplayable;
    u_per += per.labels[t] == Label::Undisplayable;
    p_whole += whole.labels[t] == Label::Perceptible;
    p_per += per.labels[t] == Label::Perceptible;
  }
  std::printf("6 buildings, %zu triangles at 132 m: undisplayable %zu -> %zu, perceptible %zu -> %zu\n",
              s.triangle_count(), u_whole, u_per, p_whole, p_per);
  EXPECT_LT(u_per, u_whole);
  EXPECT_GT(p_per, p_whole + s.triangle_count() / 100);

  // In groups (group_span 0.5: 66 m across) the six share fewer sets of
  // views. Those views only add to the whole-model ones too, and find more
  // than they do. A group's views clip at the group's box, so where one
  // member hides another the hidden one takes its own view in that
  // direction: the groups leave about as much undisplayable as each
  // building alone (within 1% of the triangles), not the walls only a
  // member hides.
  job.group_span = 0.5;
  LabelResult grouped = label_scene(renderer, s, tracer, job);
  EXPECT_LT(grouped.report.buildings.size(), 6u);
  size_t in_groups = 0, u_grouped = 0, alone = 0;
  for (const BuildingLabelling& e : grouped.report.buildings) in_groups += e.buildings, alone += e.members_alone;
  EXPECT_EQ(in_groups, 6u);
  EXPECT_GT(alone, 0u);
  for (size_t t = 0; t < s.triangle_count(); ++t) {
    if (whole.labels[t] != Label::Undisplayable) {
      ASSERT_NE(grouped.labels[t], Label::Undisplayable) << t;
    }
    u_grouped += grouped.labels[t] == Label::Undisplayable;
  }
  std::printf("in %zu groups (%zu members with views of their own): undisplayable %zu\n",
              grouped.report.buildings.size(), alone, u_grouped);
  EXPECT_LT(u_grouped, u_whole);
  EXPECT_NEAR(double(u_grouped), double(u_per), 0.01 * double(s.triangle_count()));
}

}  // namespace
}  // namespace perclod
