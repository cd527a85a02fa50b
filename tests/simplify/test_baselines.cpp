// The baselines: plain quadric simplification to a count (Qem) and
// Rossignac-Borrel vertex clustering (Cluster), and input checking.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "fixtures.h"
#include "perclod/simplify.h"

namespace perclod {
namespace {

using test::add_box;
using test::add_grid;
using test::add_sphere;
using test::add_tri;
using test::add_vertex;

Scene sphere_scene() {
  Scene s;
  add_sphere(s, 1.0, 80, 120, 0);  // 18,960 triangles
  return s;
}

void expect_within_one_percent(size_t got, size_t target) {
  EXPECT_LE(std::abs(double(got) - double(target)), 0.01 * double(target)) << got << " for " << target;
}

TEST(SimplifyQem, ReachesTargetOnASphere) {
  Scene in = sphere_scene();
  std::vector<Label> labels(in.triangle_count(), Label::Perceptible);  // ignored by qem
  for (size_t target : {5000u, 1000u, 200u}) {
    SimplifyOptions opt;
    opt.mode = SimplifyMode::Qem;
    opt.target_triangles = target;
    SimplifyStats st;
    Scene out = simplify(in, labels, opt, &st);
    expect_within_one_percent(out.triangle_count(), target);
    for (float x : out.positions) ASSERT_TRUE(std::isfinite(x));
    // Half-edge collapses keep vertices where they are: all on the sphere.
    for (size_t v = 0; v < out.vertex_count(); ++v) {
      auto p = test::vertex(out, uint32_t(v));
      EXPECT_NEAR(std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]), 1.0, 1e-5);
    }
    // And the surface stays close to the sphere.
    EXPECT_LT(st.max_displacement_rel, 0.5);
  }
}

TEST(SimplifyQem, ReachesTargetOnABuildingLikeScene) {
  // Facade stand-in: a wall grid with many boxes (windows, sills) on it.
  Scene in;
  add_grid(in, 60, 30.0, 0);
  uint32_t comp = 1;
  for (int i = 0; i < 8; ++i)
    for (int j = 0; j < 8; ++j)
      add_box(in, {1.0 + 3.5 * i, 1.0 + 3.5 * j, 0}, {2.5 + 3.5 * i, 3.0 + 3.5 * j, 0.3}, comp++, 4);
  std::vector<Label> labels(in.triangle_count(), Label::Imperceptible);
  size_t target = in.triangle_count() / 5;
  SimplifyOptions opt;
  opt.mode = SimplifyMode::Qem;
  opt.target_triangles = target;
  SimplifyStats st;
  std::vector<uint32_t> src;
  Scene out = simplify(in, labels, opt, &st, &src);
  expect_within_one_percent(out.triangle_count(), target);
  ASSERT_EQ(src.size(), out.triangle_count());
  for (size_t t = 0; t < out.triangle_count(); ++t) EXPECT_EQ(out.component[t], in.component[src[t]]);
}

TEST(SimplifyCluster, OutputShrinksAsTheCellGrows) {
  Scene in = sphere_scene();
  add_box(in, {2, 2, 2}, {3, 4, 5}, 1, 6);
  std::vector<Label> labels(in.triangle_count(), Label::Perceptible);
  size_t prev = in.triangle_count() + 1;
  for (double cell : {0.02, 0.05, 0.1, 0.3, 1.0}) {
    SimplifyOptions opt;
    opt.mode = SimplifyMode::Cluster;
    opt.pixel_footprint = cell;
    SimplifyStats st;
    Scene out = simplify(in, labels, opt, &st);
    EXPECT_LT(out.triangle_count(), prev) << "cell " << cell;
    prev = out.triangle_count();
    for (float x : out.positions) ASSERT_TRUE(std::isfinite(x));
    // Each vertex moves at most to its cell's representative: within a cell diagonal.
    EXPECT_LE(st.max_displacement_rel * st.bbox_diagonal, cell * std::sqrt(3.0) * 1.0001);
  }
}

TEST(SimplifyCluster, DropsDuplicatesAndCountsDanglingEdges) {
  // A box much smaller than one cell collapses to a point; a thin sliver
  // of triangles to dangling edges.
  Scene in;
  add_box(in, {0.01, 0.01, 0.01}, {0.02, 0.02, 0.02}, 0, 2);
  add_grid(in, 10, 10.0, 1);
  std::vector<Label> labels(in.triangle_count(), Label::Perceptible);
  SimplifyOptions opt;
  opt.mode = SimplifyMode::Cluster;
  opt.pixel_footprint = 1.0;
  SimplifyStats st;
  Scene out = simplify(in, labels, opt, &st);
  // The grid's cells line up with the grid itself: nothing merges but the
  // little box, which becomes one point sharing the grid's corner cell.
  EXPECT_EQ(out.triangle_count(), 200u);
  opt.pixel_footprint = 4.0;
  Scene coarse = simplify(in, labels, opt, &st);
  EXPECT_LT(coarse.triangle_count(), 200u);
  EXPECT_GT(coarse.triangle_count(), 0u);
}

TEST(SimplifyCluster, PreservingTheBoundingBoxKeepsEveryComponentsBox) {
  Scene in;
  add_sphere(in, 1.0, 30, 40, 0);
  add_box(in, {1.3, 0.2, 0.1}, {2.9, 1.7, 1.3}, 1, 5);
  std::vector<Label> labels(in.triangle_count(), Label::Perceptible);
  SimplifyOptions opt;
  opt.mode = SimplifyMode::Cluster;
  opt.pixel_footprint = 0.37;  // cells do not line up with the boxes
  opt.preserve_bbox = true;
  Scene out = simplify(in, labels, opt);
  for (uint32_t comp : {0u, 1u}) {
    Bounds want, got;
    auto box = [&](const Scene& s, Bounds& b) {
      b.lo = {INFINITY, INFINITY, INFINITY};
      b.hi = {-INFINITY, -INFINITY, -INFINITY};
      for (size_t t = 0; t < s.triangle_count(); ++t)
        if (s.component[t] == comp)
          for (int k = 0; k < 3; ++k)
            for (int a = 0; a < 3; ++a) {
              float v = s.positions[3 * size_t(s.indices[3 * t + k]) + a];
              b.lo[a] = std::min(b.lo[a], v);
              b.hi[a] = std::max(b.hi[a], v);
            }
    };
    box(in, want);
    box(out, got);
    for (int a = 0; a < 3; ++a) {
      EXPECT_FLOAT_EQ(got.lo[a], want.lo[a]) << "component " << comp << " axis " << a;
      EXPECT_FLOAT_EQ(got.hi[a], want.hi[a]) << "component " << comp << " axis " << a;
    }
  }
  // Without the option the sphere's box shrinks (representatives are centres of mass).
  opt.preserve_bbox = false;
  Scene loose = simplify(in, labels, opt);
  EXPECT_GT(scene_bounds(loose).lo[0], scene_bounds(in).lo[0]);
}

TEST(SimplifyInput, BadInputIsRefusedWithAMessage) {
  Scene s;
  add_grid(s, 2, 1.0, 0);
  std::vector<Label> labels(s.triangle_count(), Label::Imperceptible);
  auto message = [&](const Scene& sc, const std::vector<Label>& l, const SimplifyOptions& o) -> std::string {
    try {
      simplify(sc, l, o);
    } catch (const std::invalid_argument& e) {
      return e.what();
    }
    return "";
  };
  std::vector<Label> short_labels(labels.begin(), labels.end() - 1);
  EXPECT_NE(message(s, short_labels, {}).find("labels"), std::string::npos);
  Scene bad_index = s;
  bad_index.indices[4] = 999;
  EXPECT_NE(message(bad_index, labels, {}).find("vertex 999"), std::string::npos);
  Scene nan = s;
  nan.positions[7] = NAN;
  EXPECT_NE(message(nan, labels, {}).find("not finite"), std::string::npos);
  SimplifyOptions bounded;
  bounded.mode = SimplifyMode::Bounded;
  EXPECT_NE(message(s, labels, bounded).find("pixel footprint"), std::string::npos);
  SimplifyOptions qem;
  qem.mode = SimplifyMode::Qem;
  EXPECT_NE(message(s, labels, qem).find("target"), std::string::npos);
  Scene bad_comp = s;
  bad_comp.component.pop_back();
  EXPECT_NE(message(bad_comp, labels, {}).find("component"), std::string::npos);
  EXPECT_THROW(parse_simplify_mode("fast"), std::invalid_argument);
  EXPECT_EQ(parse_simplify_mode("bounded"), SimplifyMode::Bounded);
}

TEST(SimplifyInput, EmptySceneGivesEmptyScene) {
  Scene s;
  Scene out = simplify(s, {}, SimplifyOptions{});
  EXPECT_EQ(out.triangle_count(), 0u);
}

}  // namespace
}  // namespace perclod
