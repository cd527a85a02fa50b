// Fidelity mode: every collapse bounded by the labels of the faces it moves,
// and qem's report of a target it cannot reach.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <utility>

#include "fixtures.h"
#include "perclod/simplify.h"

using namespace perclod;
using namespace perclod::test;

namespace {

SimplifyOptions fidelity(double p, double e_p, double e_i) {
  SimplifyOptions o;
  o.mode = SimplifyMode::Fidelity;
  o.pixel_footprint = p;
  o.bound_perceptible_px = e_p;
  o.bound_imperceptible_px = e_i;
  return o;
}

double total_area(const Scene& s) {
  double sum = 0;
  for (size_t t = 0; t < s.triangle_count(); ++t) {
    double a = 0;
    normal_of(s, t, &a);
    sum += a;
  }
  return sum;
}

// The triangles of s for which keep(t) holds, on the same vertices.
template <class Keep>
Scene triangles_where(const Scene& s, Keep keep) {
  Scene out = s;
  out.indices.clear();
  out.component.clear();
  out.material.clear();
  for (size_t t = 0; t < s.triangle_count(); ++t) {
    if (!keep(t)) continue;
    out.indices.insert(out.indices.end(), s.indices.begin() + 3 * t, s.indices.begin() + 3 * t + 3);
    if (!s.component.empty()) out.component.push_back(s.component[t]);
    if (!s.material.empty()) out.material.push_back(s.material[t]);
  }
  return out;
}

// The number of distinct undirected edges of s's triangles.
size_t edge_count(const Scene& s) {
  std::set<std::pair<uint32_t, uint32_t>> edges;
  for (size_t t = 0; t < s.triangle_count(); ++t)
    for (int k = 0; k < 3; ++k) {
      const uint32_t a = s.indices[3 * t + k], b = s.indices[3 * t + (k + 1) % 3];
      edges.insert({std::min(a, b), std::max(a, b)});
    }
  return edges.size();
}

}  // namespace

TEST(SimplifyFidelity, ParsesItsName) {
  EXPECT_EQ(parse_simplify_mode("fidelity"), SimplifyMode::Fidelity);
  EXPECT_TRUE(simplify_mode_uses_labels(SimplifyMode::Fidelity));
  EXPECT_FALSE(simplify_mode_keeps_perceptible(SimplifyMode::Fidelity));
  EXPECT_THROW(parse_simplify_mode("fidelty"), std::invalid_argument);
}

TEST(SimplifyFidelity, FlatPerceptibleWallIsRetessellatedWithoutMovingIt) {
  Scene in;
  add_grid(in, 30, 6.0, 0);  // 1800 perceptible triangles in the plane z = 0
  std::vector<Label> labels(in.triangle_count(), Label::Perceptible);
  SimplifyStats st;
  Scene out = simplify(in, labels, fidelity(0.01, 0.5, 2.0), &st);
  EXPECT_LT(out.triangle_count(), in.triangle_count() / 20);
  EXPECT_NEAR(total_area(out), 36.0, 1e-3);  // the same square, no hole, no overlap
  for (size_t i = 0; i < out.vertex_count(); ++i) EXPECT_EQ(out.positions[3 * i + 2], 0.0f);
  EXPECT_LE(test::one_sided_hausdorff(in, out, 1), 1e-5);
  // Paper keeps every one of them.
  SimplifyOptions paper;
  paper.mode = SimplifyMode::Paper;
  EXPECT_EQ(simplify(in, labels, paper).triangle_count(), in.triangle_count());
}

TEST(SimplifyFidelity, EachLabelKeepsItsOwnBound) {
  // A bumpy grid: perceptible in one band, imperceptible elsewhere. Every
  // output point stays within e_I * p of the input, and the perceptible band
  // within e_P * p.
  Scene in;
  add_grid(in, 40, 6.0, 0, [](double x, double y) { return 0.3 * std::sin(1.3 * x) * std::cos(0.9 * y); });
  std::vector<Label> labels(in.triangle_count(), Label::Imperceptible);
  for (size_t t = 0; t < in.triangle_count(); ++t)
    if (vertex(in, in.indices[3 * t])[0] > 2.5 && vertex(in, in.indices[3 * t])[0] < 3.5)
      labels[t] = Label::Perceptible;
  const double p = 0.01, e_p = 0.5, e_i = 4.0;
  SimplifyStats st;
  std::vector<uint32_t> src;
  Scene out = simplify(in, labels, fidelity(p, e_p, e_i), &st, &src);
  EXPECT_NEAR(st.tolerance, e_i * p, 1e-12);
  EXPECT_NEAR(st.tolerance_perceptible, e_p * p, 1e-12);
  EXPECT_LE(st.max_error, e_i * p);
  EXPECT_LT(out.triangle_count(), in.triangle_count() / 2);
  EXPECT_LE(test::one_sided_hausdorff(out, in, 3), e_i * p * 1.0001);
  EXPECT_LE(test::one_sided_hausdorff(in, out, 1), e_i * p * 1.0001);
  // The perceptible band both ways: its input surface within e_P * p of the
  // output, and the output triangles made from it within e_P * p of the
  // input (measured at 0.24 px of e_P = 0.5; with the band given 2 px, 0.77
  // and 0.52).
  const Scene band_in = triangles_where(in, [&](size_t t) { return labels[t] == Label::Perceptible; });
  const Scene band_out = triangles_where(out, [&](size_t t) { return labels[src[t]] == Label::Perceptible; });
  EXPECT_GT(band_out.triangle_count(), 0u);
  EXPECT_LE(test::one_sided_hausdorff(band_in, out, 3), e_p * p * 1.0001);
  EXPECT_LE(test::one_sided_hausdorff(band_out, in, 3), e_p * p * 1.0001);
  // A looser perceptible bound removes more; zero bounds remove only what is exactly flat.
  Scene tighter = simplify(in, labels, fidelity(p, 0.0, 0.0));
  EXPECT_GT(tighter.triangle_count(), out.triangle_count());
}

TEST(SimplifyFidelity, SmallImperceptiblePiecesGoLargeOnesStay) {
  // A perceptible wall with two imperceptible boxes: one smaller than
  // e_I * p (removed), one larger (kept, within its bound).
  Scene in;
  add_grid(in, 4, 4.0, 0);
  const size_t wall = in.triangle_count();
  add_box(in, {1, 1, 0}, {1.01, 1.01, 0.01}, 1);  // diagonal 0.017
  add_box(in, {2, 2, 0}, {2.5, 2.5, 0.5}, 2, 3);  // diagonal 0.87
  std::vector<Label> labels(in.triangle_count(), Label::Imperceptible);
  for (size_t t = 0; t < wall; ++t) labels[t] = Label::Perceptible;
  SimplifyStats st;
  Scene out = simplify(in, labels, fidelity(0.01, 0.5, 4.0), &st);  // e_I * p = 0.04
  EXPECT_EQ(st.pieces_removed, 1u);
  EXPECT_EQ(st.pieces_triangles_removed, 12u);
  EXPECT_GE(st.triangles_after[1], 12u);  // the big box keeps its shape: at least its 6 faces
  EXPECT_LE(test::one_sided_hausdorff(in, out, 1), 0.017 + 1e-6);  // only the small box is missing
}

TEST(SimplifyFidelity, DeletesUndisplayableTrianglesAndKeepsTheVisibleOnesInPlace) {
  // A closed box seen from +z only: its top is perceptible, the rest is
  // undisplayable and deleted; the top does not move.
  Scene in;
  add_box(in, {0, 0, 0}, {1, 1, 1}, 0, 4);
  std::vector<Label> labels(in.triangle_count(), Label::Undisplayable);
  for (size_t t = 0; t < in.triangle_count(); ++t)
    if (normal_of(in, t)[2] > 0.5) labels[t] = Label::Perceptible;
  SimplifyStats st;
  Scene out = simplify(in, labels, fidelity(0.01, 0.5, 2.0), &st);
  EXPECT_EQ(st.undisplayable_faces_deleted, st.triangles_before[2]);
  EXPECT_EQ(st.triangles_after[2], 0u);
  EXPECT_NEAR(total_area(out), 1.0, 1e-5);
  for (size_t i = 0; i < out.vertex_count(); ++i) EXPECT_EQ(out.positions[3 * i + 2], 1.0f);
  // Kept and collapsed instead when asked (unbounded: they may all go).
  SimplifyOptions keep = fidelity(0.01, 0.5, 2.0);
  keep.delete_undisplayable = false;
  SimplifyStats kst;
  std::vector<uint32_t> src;
  Scene kept = simplify(in, labels, keep, &kst, &src);
  EXPECT_EQ(kst.undisplayable_faces_deleted, 0u);
  EXPECT_LT(kst.triangles_after[2], kst.triangles_before[2] / 2);
  EXPECT_GT(kst.triangles_after[0], 0u);
  for (size_t t = 0; t < kept.triangle_count(); ++t) {
    if (labels[src[t]] != Label::Perceptible) continue;
    for (int k = 0; k < 3; ++k) EXPECT_EQ(kept.positions[3 * size_t(kept.indices[3 * t + k]) + 2], 1.0f);
  }
}

// A 3 m strip, 1 cm wide (a mullion; component 1, imperceptible) of 30
// quads, 5 cm in front of a 4 m perceptible wall (component 0).
struct Mullion {
  Scene in;
  std::vector<Label> labels;
  Mullion() {
    add_grid(in, 4, 4.0, 0);
    const size_t wall = in.triangle_count();
    for (int i = 0; i < 30; ++i) {
      const double x0 = 0.5 + 0.1 * i, x1 = x0 + 0.1;
      uint32_t a = add_vertex(in, x0, 2.0, 0.05), b = add_vertex(in, x1, 2.0, 0.05),
               c = add_vertex(in, x1, 2.01, 0.05), d = add_vertex(in, x0, 2.01, 0.05);
      add_tri(in, a, b, c, 1);
      add_tri(in, a, c, d, 1);
    }
    labels.assign(in.triangle_count(), Label::Imperceptible);
    for (size_t t = 0; t < wall; ++t) labels[t] = Label::Perceptible;
  }
  // The strip's surface area in `s` (m^2).
  static double area(const Scene& s) {
    double a = 0;
    for (size_t t = 0; t < s.triangle_count(); ++t)
      if (s.component[t] == 1) {
        double at = 0;
        normal_of(s, t, &at);
        a += at;
      }
    return a;
  }
  double simplified_area(const SimplifyOptions& o) const { return area(simplify(in, labels, o)); }
};

TEST(SimplifyFidelity, AreaRuleKeepsALongPartThinnerThanTheBound) {
  // A 3 m strip, 1 cm wide (a mullion), in front of a perceptible wall:
  // every move across it is within e_I * p = 2 cm, so the distance bound
  // alone lets collapses across its width eat into it; the area budget
  // (1 px^2 = 1 cm^2 here) keeps its surface.
  const Mullion m;
  const double before = Mullion::area(m.in);
  SimplifyOptions with_area = fidelity(0.01, 0.5, 2.0);
  SimplifyOptions without = with_area;
  without.bound_area_px2 = INFINITY;
  const double kept = m.simplified_area(with_area);
  const double folded = m.simplified_area(without);
  std::printf("  bar area %.5f m^2: %.5f with the area rule, %.5f without\n", before, kept, folded);
  EXPECT_NEAR(kept, before, 1e-4 * 4);  // at most the budgets of the bar's few kept vertices
  // Without it, more than ten times the 1 px^2 budget goes (measured 0.0280
  // of 0.0300 m^2: 20 px^2 gone).
  EXPECT_LT(folded, before - 10 * 1e-4);
}

// The budget is bound_area_px2 at bounds up to 1 px and grows with the
// bound squared above: the mullion of the test above keeps its area at 1 px
// bounds, and at 8 px (a move eight times its width allowed) loses more than
// a budget of 1 px^2 lets go, and no more than no area rule would.
TEST(SimplifyFidelity, AreaBudgetGrowsWithTheSquareOfTheBound) {
  const Mullion m;
  const double before = Mullion::area(m.in), px2 = 1e-4;  // p = 1 cm: a square pixel is 1 cm^2
  const double at1 = m.simplified_area(fidelity(0.01, 0.5, 1.0));
  const double at8 = m.simplified_area(fidelity(0.01, 0.5, 8.0));
  // bound_area_px2 = 1/64 at 8 px: the 1 px^2 a budget that did not grow gave.
  SimplifyOptions fixed_budget = fidelity(0.01, 0.5, 8.0);
  fixed_budget.bound_area_px2 = 1.0 / 64;
  const double at8_fixed = m.simplified_area(fixed_budget);
  SimplifyOptions no_rule = fidelity(0.01, 0.5, 8.0);
  no_rule.bound_area_px2 = INFINITY;
  const double at8_free = m.simplified_area(no_rule);
  std::printf("  bar area %.5f m^2: %.5f at 1 px, %.5f at 8 px (%.5f with 1 px^2 budgets, %.5f without the rule)\n",
              before, at1, at8, at8_fixed, at8_free);
  EXPECT_NEAR(at1, before, 4 * px2);
  EXPECT_NEAR(at8_fixed, before, 4 * px2);  // the fixed budget refused what 8 px allows
  EXPECT_LT(at8, before - 10 * px2);        // measured: 20 px^2 of the 300 go
  EXPECT_GE(at8, at8_free - 1e-9);          // never more than without the rule
}

// bound_scale tightens some triangles' bounds and leaves the others' as
// asked: two bumpy grids (components apart, never welded together) at e_I 4
// px, the second scaled by 1/8, simplify as each does alone at 4 and at 0.5
// px; a small imperceptible box the first's bound removes stays at its
// scale 0.1. All ones is no scale; a scale per triangle or none.
TEST(SimplifyFidelity, BoundScaleTightensOnlyItsTriangles) {
  auto bumps = [](double x, double y) { return 0.3 * std::sin(1.3 * x) * std::cos(0.9 * y); };
  Scene in;
  add_grid(in, 30, 6.0, 0, bumps);
  const size_t first = in.triangle_count();
  add_grid(in, 30, 6.0, 1, bumps, 10, 0);
  const size_t grids = in.triangle_count();
  add_box(in, {20, 0, 0}, {20.01, 0.01, 0.01}, 2);  // diagonal 0.017 < 0.04
  std::vector<Label> labels(in.triangle_count(), Label::Imperceptible);
  const SimplifyOptions loose = fidelity(0.01, 4.0, 4.0), tight = fidelity(0.01, 0.5, 0.5);
  // How many of a LOD's triangles come from input triangles lo .. hi - 1.
  auto count_of = [](const std::vector<uint32_t>& src, size_t lo, size_t hi) {
    return size_t(std::count_if(src.begin(), src.end(), [&](uint32_t t) { return t >= lo && t < hi; }));
  };
  std::vector<uint32_t> src_loose, src_tight, src_scaled;
  const Scene all_loose = simplify(in, labels, loose, nullptr, &src_loose);
  simplify(in, labels, tight, nullptr, &src_tight);
  SimplifyOptions scaled = loose;
  scaled.bound_scale.assign(in.triangle_count(), 1.f);
  std::fill(scaled.bound_scale.begin() + long(first), scaled.bound_scale.begin() + long(grids), 0.125f);
  std::fill(scaled.bound_scale.begin() + long(grids), scaled.bound_scale.end(), 0.1f);
  SimplifyStats st;
  simplify(in, labels, scaled, &st, &src_scaled);
  EXPECT_EQ(count_of(src_scaled, 0, first), count_of(src_loose, 0, first));
  EXPECT_EQ(count_of(src_scaled, first, grids), count_of(src_tight, first, grids));
  EXPECT_LT(count_of(src_loose, 0, first), count_of(src_tight, first, grids));
  EXPECT_EQ(count_of(src_loose, grids, in.triangle_count()), 0u);  // the box goes at 4 px
  EXPECT_EQ(count_of(src_scaled, grids, in.triangle_count()), 12u);      // and stays at 0.4
  EXPECT_EQ(st.pieces_removed, 0u);

  SimplifyOptions ones = loose;
  ones.bound_scale.assign(in.triangle_count(), 1.f);
  const Scene same = simplify(in, labels, ones);
  EXPECT_EQ(same.indices, all_loose.indices);
  EXPECT_EQ(same.positions, all_loose.positions);

  ones.bound_scale.pop_back();
  EXPECT_THROW(simplify(in, labels, ones), std::invalid_argument);
  ones.bound_scale.push_back(-1.f);
  EXPECT_THROW(simplify(in, labels, ones), std::invalid_argument);
}

// keep_undisplayable_of keeps the undisplayable triangles it flags while
// the others are deleted: two boxes seen from +z only, the second's flagged;
// its sides stay, within their bound (0: none moves), the first's go.
TEST(SimplifyFidelity, FlaggedUndisplayableTrianglesAreKeptTheOthersDeleted) {
  Scene in;
  add_box(in, {0, 0, 0}, {1, 1, 1}, 0, 2);
  const size_t first = in.triangle_count();
  add_box(in, {3, 0, 0}, {4, 1, 1}, 1, 2);
  std::vector<Label> labels(in.triangle_count(), Label::Undisplayable);
  for (size_t t = 0; t < in.triangle_count(); ++t)
    if (normal_of(in, t)[2] > 0.5) labels[t] = Label::Perceptible;
  SimplifyOptions o = fidelity(0.01, 0.5, 0.5);
  o.bound_undisplayable_px = 0;
  o.keep_undisplayable_of.assign(in.triangle_count(), 0);
  std::fill(o.keep_undisplayable_of.begin() + long(first), o.keep_undisplayable_of.end(), 1);
  SimplifyStats st;
  std::vector<uint32_t> src;
  const Scene out = simplify(in, labels, o, &st, &src);
  size_t first_u = 0, second_u = 0;
  for (uint32_t t : src)
    if (labels[t] == Label::Undisplayable) (t < first ? first_u : second_u)++;
  EXPECT_EQ(first_u, 0u);
  EXPECT_EQ(st.undisplayable_faces_deleted, first - 8);  // the first box's all but its top
  EXPECT_GT(second_u, 0u);
  EXPECT_EQ(st.triangles_after[2], second_u);
  o.keep_undisplayable_of.pop_back();
  EXPECT_THROW(simplify(in, labels, o), std::invalid_argument);
}

TEST(SimplifyFidelity, RefusesBadBounds) {
  Scene in;
  add_grid(in, 2, 1.0, 0);
  std::vector<Label> labels(in.triangle_count(), Label::Perceptible);
  EXPECT_THROW(simplify(in, labels, fidelity(0.01, -1, 2)), std::invalid_argument);
  EXPECT_THROW(simplify(in, labels, fidelity(0.01, 0.5, NAN)), std::invalid_argument);
  EXPECT_THROW(simplify(in, labels, fidelity(0.01, 0.5, INFINITY)), std::invalid_argument);
  EXPECT_THROW(simplify(in, labels, fidelity(0.0, 0.5, 2)), std::invalid_argument);
}

TEST(SimplifyFidelity, ExplainsWhyItStopped) {
  // A bumpy grid under a tight bound: nearly every half-edge left is over it.
  Scene grid;
  add_grid(grid, 30, 6.0, 0, [](double x, double y) { return 0.3 * std::sin(1.3 * x) * std::cos(0.9 * y); });
  std::vector<Label> labels(grid.triangle_count(), Label::Imperceptible);
  SimplifyStats plain, told;
  const Scene a = simplify(grid, labels, fidelity(0.01, 0.5, 0.5), &plain);
  EXPECT_FALSE(plain.refused_counted);  // only when asked
  EXPECT_EQ(plain.refused.total(), 0u);
  SimplifyOptions o = fidelity(0.01, 0.5, 0.5);
  o.explain_stop = true;
  const Scene b = simplify(grid, labels, o, &told);
  EXPECT_EQ(b.indices, a.indices);  // counting changes nothing
  EXPECT_EQ(b.positions, a.positions);
  ASSERT_TRUE(told.refused_counted);
  EXPECT_EQ(told.refused.total(), 2 * edge_count(b));  // both directions of every edge left
  EXPECT_GT(told.refused.bound_or_locked, told.refused.total() / 2);
  EXPECT_EQ(told.refused.legal, 0u);  // the last pass found nothing to collapse
  // A sphere with no bound stops where the shape and topology rules do.
  Scene ball;
  add_sphere(ball, 1.0, 12, 24, 0);
  std::vector<Label> ball_labels(ball.triangle_count(), Label::Perceptible);  // kept as a piece
  SimplifyOptions loose = fidelity(0.01, 1e9, 1e9);
  loose.bound_area_px2 = INFINITY;
  loose.explain_stop = true;
  loose.free_topology = false;  // the half-edge loop's rules (past them it goes on to nothing)
  SimplifyStats bs;
  const Scene small = simplify(ball, ball_labels, loose, &bs);
  EXPECT_LT(small.triangle_count(), ball.triangle_count() / 4);
  EXPECT_EQ(bs.refused.bound_or_locked, 0u);
  EXPECT_GT(bs.refused.shape + bs.refused.topology, 0u);
  EXPECT_EQ(bs.refused.total(), 2 * edge_count(small)) << small.triangle_count();
}

// Where the half-edge loop stops for topology alone, free_topology goes on
// within the same bounds. Two cases the half-edge mesh cannot simplify:
// three flat sheets meeting on one line (a wall, its continuation and a fin:
// the fin's faces on that non-manifold line get vertices of their own and
// never collapse), and a lace left by deleting every other triangle of a
// fine bumpy grid (triangles touching only at corners, each on its own in
// the mesh, and perceptible, so no piece rule removes them).
TEST(SimplifyFidelity, FreeTopologyGoesOnWhereTheHalfEdgeRulesStop) {
  const double p = 0.01, e = 2.0, tol = e * p;
  SimplifyOptions manifold = fidelity(p, e, e), free = manifold;
  manifold.free_topology = false;
  manifold.explain_stop = free.explain_stop = true;
  {
    Scene book;
    add_grid(book, 10, 1.0, 0);                          // z = 0, y in [0, 1]
    add_grid(book, 10, 1.0, 0, nullptr, 0.0, -1.0);      // z = 0, y in [-1, 0]
    Scene fin;
    add_grid(fin, 10, 1.0, 0);
    for (size_t v = 0; v < fin.vertex_count(); ++v) {  // (x, y, 0) -> (x, 0, y)
      fin.positions[3 * v + 2] = fin.positions[3 * v + 1];
      fin.positions[3 * v + 1] = 0;
    }
    const uint32_t base = uint32_t(book.vertex_count());
    book.positions.insert(book.positions.end(), fin.positions.begin(), fin.positions.end());
    for (size_t t = 0; t < fin.triangle_count(); ++t)
      add_tri(book, base + fin.indices[3 * t], base + fin.indices[3 * t + 1], base + fin.indices[3 * t + 2], 0);
    std::vector<Label> labels(book.triangle_count(), Label::Imperceptible);
    SimplifyStats ms, fs;
    const Scene m = simplify(book, labels, manifold, &ms), f = simplify(book, labels, free, &fs);
    EXPECT_GT(ms.nonmanifold_faces_duplicated, 0u);
    EXPECT_EQ(ms.free_collapses, 0u);
    EXPECT_GT(fs.free_collapses, 0u);
    EXPECT_EQ(fs.refused.topology, 0u);  // no rule of the kind is left
    EXPECT_LT(f.triangle_count(), m.triangle_count() / 2) << m.triangle_count();
    for (const Scene* out : {&m, &f}) {  // the same three square metres, not moved
      EXPECT_NEAR(total_area(*out), 3.0, 1e-4);
      EXPECT_LE(test::one_sided_hausdorff(*out, book, 3), 1e-5);
      EXPECT_LE(test::one_sided_hausdorff(book, *out, 1), 1e-5);
    }
  }
  {
    // Cells half the bound wide: removing any one triangle is within it.
    Scene grid;
    add_grid(grid, 30, 0.3, 0, [](double x, double y) { return 0.004 * std::sin(21 * x) * std::cos(17 * y); });
    std::vector<Label> labels(grid.triangle_count(), Label::Perceptible);
    for (size_t t = 1; t < labels.size(); t += 2) labels[t] = Label::Undisplayable;  // deleted
    const Scene kept = triangles_where(grid, [&](size_t t) { return labels[t] == Label::Perceptible; });
    SimplifyStats ms, fs;
    const Scene m = simplify(grid, labels, manifold, &ms), f = simplify(grid, labels, free, &fs);
    EXPECT_GT(ms.refused.topology, ms.refused.bound_or_locked) << "the lace stops for topology";
    EXPECT_LT(f.triangle_count(), m.triangle_count() / 2) << m.triangle_count() << " " << fs.refused.shape << " " << fs.refused.bound_or_locked;
    EXPECT_LE(fs.max_error, tol);
    EXPECT_LE(test::one_sided_hausdorff(f, grid, 3), tol * 1.0001);
    EXPECT_LE(test::one_sided_hausdorff(kept, f, 1), tol * 1.0001);
  }
}

TEST(SimplifyQem, ReportsATargetItCannotReach) {
  // 50 separate triangles: no edge can collapse, so a target of 10 is missed.
  Scene in;
  for (int i = 0; i < 50; ++i) {
    uint32_t a = add_vertex(in, 2 * i, 0, 0), b = add_vertex(in, 2 * i + 1, 0, 0), c = add_vertex(in, 2 * i, 1, 0);
    add_tri(in, a, b, c, 0);
  }
  std::vector<Label> labels(in.triangle_count(), Label::Perceptible);
  SimplifyOptions o;
  o.mode = SimplifyMode::Qem;
  o.target_triangles = 10;
  SimplifyStats st;
  Scene out = simplify(in, labels, o, &st);
  EXPECT_EQ(out.triangle_count(), 50u);
  EXPECT_FALSE(st.target_reached);
  EXPECT_NE(st.stop_reason.find("every remaining collapse is refused"), std::string::npos) << st.stop_reason;
  EXPECT_NE(st.stop_reason.find("by topology"), std::string::npos) << st.stop_reason;
  EXPECT_TRUE(st.refused_counted);  // the counts behind the words: 50 x 3 boundary edges, both ways
  EXPECT_EQ(st.refused.total(), 300u);
  EXPECT_NE(st.stop_reason.find(std::to_string(st.refused.topology) + " half-edges by topology"), std::string::npos);
  // A reachable target is reported as reached.
  Scene grid;
  add_grid(grid, 10, 1.0, 0);
  std::vector<Label> gl(grid.triangle_count(), Label::Perceptible);
  o.target_triangles = 20;
  SimplifyStats gs;
  Scene g = simplify(grid, gl, o, &gs);
  EXPECT_LE(g.triangle_count(), 20u);
  EXPECT_TRUE(gs.target_reached);
  EXPECT_TRUE(gs.stop_reason.empty());
}
