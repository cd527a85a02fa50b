// The simplifier on generated facades (perclod/facade.h), labelled with the
// synthetic rule of fixtures.h: the viewer stands in front of wall 0 (which
// faces -y) looking along +y; back faces are undisplayable, front faces of at
// least `min_area` perceptible, smaller front faces imperceptible; and the
// hidden interior (components named interior_*) is undisplayable, as no ray
// from outside reaches it.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <set>
#include <utility>

#include "fixtures.h"
#include "perclod/facade.h"
#include "perclod/simplify.h"

namespace perclod {
namespace {

Scene small_facade() {
  FacadeParams p;
  p.floors = 2;
  p.bays = 3;
  p.hidden_interior = true;
  p.subpixel_ornaments = true;
  return generate_facade(p);
}

TEST(SimplifyFacade, PerceptibleTrianglesSurviveBitIdentical) {
  Scene in = small_facade();
  auto labels = test::synthetic_labels(in, {0, 1, 0}, 0.02);
  for (size_t t = 0; t < in.triangle_count(); ++t)
    if (in.component_names[in.component[t]].rfind("interior_", 0) == 0) labels[t] = Label::Undisplayable;
  for (SimplifyMode mode : {SimplifyMode::Paper, SimplifyMode::Bounded}) {
    SimplifyOptions opt;
    opt.mode = mode;
    opt.pixel_footprint = 0.03;
    SimplifyStats st;
    std::vector<uint32_t> src;
    Scene out = simplify(in, labels, opt, &st, &src);
    for (float x : out.positions) ASSERT_TRUE(std::isfinite(x));
    std::multiset<test::Tri> want, got;
    for (size_t t = 0; t < in.triangle_count(); ++t)
      if (labels[t] == Label::Perceptible) want.insert(test::canonical(test::tri_of(in, t)));
    for (size_t t = 0; t < out.triangle_count(); ++t)
      if (labels[src[t]] == Label::Perceptible) got.insert(test::canonical(test::tri_of(out, t)));
    ASSERT_GT(want.size(), 100u);
    EXPECT_TRUE(want == got) << simplify_mode_name(mode);
    EXPECT_EQ(st.triangles_after[0], st.triangles_before[0]);
    EXPECT_LT(st.triangles_after[1], st.triangles_before[1]) << simplify_mode_name(mode);
    EXPECT_LT(st.triangles_after[2], st.triangles_before[2]) << simplify_mode_name(mode);
    EXPECT_GT(st.components_removed, 0u);  // the hidden interior
    EXPECT_EQ(out.component_names, in.component_names);
    EXPECT_EQ(out.offset, in.offset);
    if (mode == SimplifyMode::Bounded) {
      EXPECT_LE(st.max_error, 0.03);
    }
  }
}

TEST(SimplifyFacade, QemReachesTarget) {
  Scene in = small_facade();
  std::vector<Label> labels(in.triangle_count(), Label::Imperceptible);
  size_t target = in.triangle_count() / 4;
  SimplifyOptions opt;
  opt.mode = SimplifyMode::Qem;
  opt.target_triangles = target;
  Scene out = simplify(in, labels, opt);
  EXPECT_LE(std::abs(double(out.triangle_count()) - double(target)), 0.01 * double(target))
      << out.triangle_count() << " for " << target << " of " << in.triangle_count();
}

TEST(SimplifyFacade, ClusterShrinksAsTheCellGrows) {
  Scene in = small_facade();
  std::vector<Label> labels(in.triangle_count(), Label::Perceptible);
  size_t prev = in.triangle_count() + 1;
  for (double cell : {0.02, 0.1, 0.5}) {
    SimplifyOptions opt;
    opt.mode = SimplifyMode::Cluster;
    opt.pixel_footprint = cell;
    Scene out = simplify(in, labels, opt);
    EXPECT_LT(out.triangle_count(), prev) << cell;
    prev = out.triangle_count();
  }
}

// Output triangles with the input triangle each came from, in a canonical
// order: equal when two runs produce the same LOD in any triangle order.
std::multiset<std::pair<test::Tri, uint32_t>> triangles_with_source(const Scene& out, const std::vector<uint32_t>& src) {
  std::multiset<std::pair<test::Tri, uint32_t>> r;
  for (size_t t = 0; t < out.triangle_count(); ++t) r.insert({test::canonical(test::tri_of(out, t)), src[t]});
  return r;
}

// Pieces are simplified in chunks, in parallel: neither the chunk size nor
// the thread count may change which triangles come out. The scene has many
// pieces (facade parts) and flat grids whose collapses all tie at cost 0.
TEST(SimplifyFacade, ChunksAndThreadsDoNotChangeTheResult) {
  Scene in = small_facade();
  const size_t facade_triangles = in.triangle_count();
  for (int g = 0; g < 6; ++g)
    test::add_grid(in, 12, 2.0, uint32_t(in.component_names.size()), nullptr, 3.0 * g, -5.0);
  auto labels = test::synthetic_labels(in, {0, 1, 0}, 0.02);
  // Each grid imperceptible but for one perceptible corner, so that Paper
  // keeps the grid and collapses the rest of it.
  for (size_t t = facade_triangles; t < in.triangle_count(); ++t)
    labels[t] = (t - facade_triangles) % 288 == 0 ? Label::Perceptible : Label::Imperceptible;
  for (SimplifyMode mode : {SimplifyMode::Paper, SimplifyMode::Bounded, SimplifyMode::Fidelity}) {
    SimplifyOptions opt;
    opt.mode = mode;
    opt.pixel_footprint = 0.03;
    struct Run {
      Scene out;
      std::vector<uint32_t> src;
      SimplifyStats st;
    };
    auto run = [&](size_t chunk_faces, int threads) {
      tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
      SimplifyOptions o = opt;
      o.chunk_faces = chunk_faces;
      Run r;
      r.out = simplify(in, labels, o, &r.st, &r.src);
      return r;
    };
    const Run whole = run(0, 1), chunked = run(64, 1), parallel = run(64, 2);
    const char* name = simplify_mode_name(mode);
    ASSERT_GT(whole.st.collapses, 100u) << name;
    EXPECT_EQ(whole.st.chunks, 1u) << name;
    EXPECT_GT(chunked.st.chunks, 4u) << name;
    EXPECT_TRUE(triangles_with_source(whole.out, whole.src) == triangles_with_source(chunked.out, chunked.src)) << name;
    for (const Run* r : {&chunked, &parallel}) {
      EXPECT_EQ(r->st.collapses, whole.st.collapses) << name;
      EXPECT_EQ(r->st.triangles_after, whole.st.triangles_after) << name;
      EXPECT_EQ(r->st.vertices_before, whole.st.vertices_before) << name;
      EXPECT_EQ(r->st.vertices_after, whole.st.vertices_after) << name;
      EXPECT_EQ(r->st.pieces_removed, whole.st.pieces_removed) << name;
      EXPECT_EQ(r->st.undisplayable_faces_deleted, whole.st.undisplayable_faces_deleted) << name;
      EXPECT_EQ(r->st.max_error, whole.st.max_error) << name;
      EXPECT_EQ(r->st.max_displacement_rel, whole.st.max_displacement_rel) << name;
      EXPECT_NEAR(r->st.mean_displacement_rel, whole.st.mean_displacement_rel, 1e-12) << name;
    }
    // Same chunks on one or two threads: the same file, byte for byte.
    EXPECT_EQ(parallel.out.positions, chunked.out.positions) << name;
    EXPECT_EQ(parallel.out.indices, chunked.out.indices) << name;
    EXPECT_EQ(parallel.src, chunked.src) << name;
  }
}

}  // namespace
}  // namespace perclod
