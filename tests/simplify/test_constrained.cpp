// The label-constrained simplifier (Paper and Bounded modes): perceptible
// triangles survive bit for bit, everything else goes where it can.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "fixtures.h"
#include "perclod/simplify.h"

namespace perclod {
namespace {

using test::add_box;
using test::add_grid;
using test::add_tri;
using test::add_vertex;
using test::expect_perceptible_preserved;
using test::expect_valid;

// A bumpy 40x40 grid: a perceptible band in the middle, imperceptible around.
Scene bumpy_grid(std::vector<Label>& labels, double amplitude) {
  Scene s;
  add_grid(s, 40, 6.0, 0, [&](double x, double y) { return amplitude * std::sin(1.3 * x) * std::cos(0.9 * y); });
  labels.assign(s.triangle_count(), Label::Imperceptible);
  for (size_t t = 0; t < s.triangle_count(); ++t) {
    auto p = test::vertex(s, s.indices[3 * t]);
    if (p[0] > 2.5 && p[0] < 3.5) labels[t] = Label::Perceptible;
    if (p[1] < 1.0) labels[t] = Label::Undisplayable;
  }
  return s;
}

TEST(SimplifyPaper, KeepsPerceptibleTrianglesBitIdentical) {
  std::vector<Label> labels;
  Scene in = bumpy_grid(labels, 0.2);
  SimplifyOptions opt;
  opt.mode = SimplifyMode::Paper;
  SimplifyStats st;
  std::vector<uint32_t> src;
  Scene out = simplify(in, labels, opt, &st, &src);
  expect_valid(out);
  expect_perceptible_preserved(in, labels, out, src);
  EXPECT_EQ(st.triangles_after[0], st.triangles_before[0]);
  EXPECT_LT(st.triangles_after[1], st.triangles_before[1] / 4);
  EXPECT_LT(st.triangles_after[2], st.triangles_before[2] / 4);
  EXPECT_GT(st.collapses, 0u);
  EXPECT_EQ(out.offset, in.offset);
}

TEST(SimplifyPaper, FlatWallCollapsesToAFewTriangles) {
  // 200x200 quads = 80,000 triangles, one wall, all imperceptible except one
  // perceptible corner triangle so the wall is not removed as a whole.
  Scene in;
  add_grid(in, 200, 20.0, 0);
  std::vector<Label> labels(in.triangle_count(), Label::Imperceptible);
  labels[0] = Label::Perceptible;
  for (SimplifyMode mode : {SimplifyMode::Paper, SimplifyMode::Bounded}) {
    SimplifyOptions opt;
    opt.mode = mode;
    opt.pixel_footprint = 0.01;
    SimplifyStats st;
    std::vector<uint32_t> src;
    Scene out = simplify(in, labels, opt, &st, &src);
    expect_perceptible_preserved(in, labels, out, src);
    EXPECT_LT(out.triangle_count(), 20u) << simplify_mode_name(mode);
    if (mode == SimplifyMode::Paper) continue;  // Paper may shrink the wall onto its perceptible part
    // Bounded: the boundary quadrics hold the outline: all four corners stay.
    for (auto c : {std::array<float, 3>{0, 0, 0}, {20, 0, 0}, {0, 20, 0}, {20, 20, 0}}) {
      bool found = false;
      for (size_t v = 0; v < out.vertex_count(); ++v)
        found |= out.positions[3 * v] == c[0] && out.positions[3 * v + 1] == c[1] && out.positions[3 * v + 2] == c[2];
      EXPECT_TRUE(found) << "corner " << c[0] << "," << c[1];
    }
    EXPECT_NEAR(test::one_sided_hausdorff(out, in, 2), 0.0, 1e-5);
  }
}

TEST(SimplifyPaper, RemovesIsolatedTriangleAndClosedBoxNobodySees) {
  Scene in;
  add_grid(in, 4, 1.0, 0);  // perceptible
  size_t grid = in.triangle_count();
  uint32_t a = add_vertex(in, 5, 5, 5), b = add_vertex(in, 6, 5, 5), c = add_vertex(in, 5, 6, 5);
  add_tri(in, a, b, c, 1);                            // isolated, undisplayable
  add_box(in, {10, 0, 0}, {11, 1, 1}, 2, 3);          // closed box, undisplayable
  add_box(in, {20, 0, 0}, {21, 1, 1}, 0, 3);          // closed box in the grid's component, imperceptible
  add_tri(in, add_vertex(in, 30, 0, 0), add_vertex(in, 31, 0, 0), add_vertex(in, 30, 1, 0), 0);  // isolated, imperceptible
  std::vector<Label> labels(in.triangle_count(), Label::Undisplayable);
  for (size_t t = 0; t < grid; ++t) labels[t] = Label::Perceptible;
  for (size_t t = grid + 1 + 108; t < in.triangle_count(); ++t) labels[t] = Label::Imperceptible;

  for (SimplifyMode mode : {SimplifyMode::Paper, SimplifyMode::Bounded}) {
    SimplifyOptions opt;
    opt.mode = mode;
    opt.pixel_footprint = 2.0;  // Bounded: pieces up to a 2 m diagonal go
    SimplifyStats st;
    std::vector<uint32_t> src;
    Scene out = simplify(in, labels, opt, &st, &src);
    expect_perceptible_preserved(in, labels, out, src);
    EXPECT_EQ(out.triangle_count(), grid) << simplify_mode_name(mode);
    EXPECT_EQ(st.components_removed, 2u);  // the undisplayable triangle and box
    EXPECT_EQ(st.pieces_removed, 2u);      // the imperceptible box and triangle
    EXPECT_EQ(st.triangles_after[1] + st.triangles_after[2], 0u);
  }
}

TEST(SimplifyBounded, KeepsLargeImperceptiblePiecesThatAreFarFromFlat) {
  // Bounded must not delete a piece bigger than its tolerance.
  Scene in;
  add_grid(in, 2, 1.0, 0);
  add_box(in, {10, 0, 0}, {15, 5, 5}, 0, 2);
  std::vector<Label> labels(in.triangle_count(), Label::Imperceptible);
  for (size_t t = 0; t < 8; ++t) labels[t] = Label::Perceptible;
  SimplifyOptions opt;
  opt.mode = SimplifyMode::Bounded;
  opt.pixel_footprint = 0.01;
  SimplifyStats st;
  Scene out = simplify(in, labels, opt, &st);
  EXPECT_EQ(st.pieces_removed, 0u);
  EXPECT_GT(st.triangles_after[1], 0u);
  EXPECT_LE(st.max_error, 0.01);
}

TEST(SimplifyBounded, NeverExceedsItsTolerance) {
  std::vector<Label> labels;
  Scene in = bumpy_grid(labels, 0.3);
  for (double tol : {0.002, 0.01, 0.05}) {
    SimplifyOptions opt;
    opt.mode = SimplifyMode::Bounded;
    opt.pixel_footprint = tol / 2;
    opt.k = 2.0;
    SimplifyStats st;
    std::vector<uint32_t> src;
    Scene out = simplify(in, labels, opt, &st, &src);
    expect_perceptible_preserved(in, labels, out, src);
    EXPECT_NEAR(st.tolerance, tol, 1e-12);
    EXPECT_LE(st.max_error, tol);
    EXPECT_LT(out.triangle_count(), in.triangle_count());
    // Measured independently: sampled Hausdorff distance both ways.
    double to_input = test::one_sided_hausdorff(out, in, 3);
    double to_output = test::one_sided_hausdorff(in, out, 1);
    EXPECT_LE(to_input, tol * 1.0001) << "tolerance " << tol;
    EXPECT_LE(to_output, tol * 1.0001) << "tolerance " << tol;
  }
}

TEST(SimplifyBounded, LargerToleranceRemovesMore) {
  std::vector<Label> labels;
  Scene in = bumpy_grid(labels, 0.3);
  size_t prev = in.triangle_count() + 1;
  for (double tol : {0.001, 0.01, 0.1}) {
    SimplifyOptions opt;
    opt.mode = SimplifyMode::Bounded;
    opt.pixel_footprint = tol;
    Scene out = simplify(in, labels, opt);
    EXPECT_LT(out.triangle_count(), prev) << tol;
    prev = out.triangle_count();
  }
}

TEST(SimplifyPaper, NonManifoldInputKeepsEveryPerceptibleFace) {
  Scene in;
  add_grid(in, 6, 3.0, 0);
  // A fin: three extra triangles on one interior edge of the grid (an edge
  // with up to five faces), and a bow-tie pair touching a grid vertex only.
  uint32_t e0 = add_vertex(in, 1.0, 1.0, 0), e1 = add_vertex(in, 1.5, 1.5, 0);  // == grid vertices
  for (int k = 1; k <= 3; ++k) add_tri(in, e0, e1, add_vertex(in, 1.2, 1.3, 0.3 * k), 1);
  uint32_t c = add_vertex(in, 3.0, 3.0, 0);
  add_tri(in, c, add_vertex(in, 3.0, 3.5, 1.0), add_vertex(in, 3.5, 3.0, 1.0), 2);
  add_tri(in, c, add_vertex(in, 3.5, 3.5, -1.0), add_vertex(in, 3.2, 3.8, -1.0), 2);
  std::vector<Label> labels(in.triangle_count(), Label::Imperceptible);
  for (size_t t = 0; t < in.triangle_count(); t += 3) labels[t] = Label::Perceptible;
  SimplifyStats st;
  std::vector<uint32_t> src;
  Scene out = simplify(in, labels, SimplifyOptions{}, &st, &src);
  expect_valid(out);
  expect_perceptible_preserved(in, labels, out, src);
  EXPECT_GT(st.nonmanifold_faces_duplicated, 0u);
  EXPECT_LT(st.triangles_after[1], st.triangles_before[1]);
}

TEST(SimplifyPaper, DeletesUndisplayableTrianglesWhoseVerticesAreAllPerceptible) {
  // A grid where every vertex belongs to a perceptible triangle (the first
  // of each quad, and the second of the quad at the corner (0, n) only that
  // one reaches): no collapse is possible. Paper deletes the undisplayable
  // triangles (no pixel reaches them); the imperceptible ones cover pixels
  // and stay. Bounded keeps both: deleting would break its distance bound.
  Scene in;
  const int n = 4;
  add_grid(in, n, 2.0, 0);
  std::vector<Label> labels(in.triangle_count(), Label::Perceptible);
  for (size_t q = 0; q < size_t(n * n); ++q)
    if (q != size_t(n * (n - 1))) labels[2 * q + 1] = q % 2 ? Label::Imperceptible : Label::Undisplayable;
  for (SimplifyMode mode : {SimplifyMode::Paper, SimplifyMode::Bounded}) {
    SimplifyOptions opt;
    opt.mode = mode;
    opt.pixel_footprint = 0.01;
    SimplifyStats st;
    std::vector<uint32_t> src;
    Scene out = simplify(in, labels, opt, &st, &src);
    expect_valid(out);
    expect_perceptible_preserved(in, labels, out, src);
    EXPECT_EQ(st.collapses, 0u) << simplify_mode_name(mode);
    EXPECT_EQ(st.triangles_after[1], st.triangles_before[1]);
    if (mode == SimplifyMode::Paper) {
      EXPECT_EQ(st.triangles_after[2], 0u);
      EXPECT_EQ(st.undisplayable_faces_deleted, st.triangles_before[2]);
    } else {
      EXPECT_EQ(out.triangle_count(), in.triangle_count());
    }
  }
  SimplifyOptions keep;  // Paper, told to keep the surface closed
  keep.delete_undisplayable = false;
  SimplifyStats st;
  std::vector<uint32_t> src;
  Scene out = simplify(in, labels, keep, &st, &src);
  expect_perceptible_preserved(in, labels, out, src);
  EXPECT_EQ(out.triangle_count(), in.triangle_count());
  EXPECT_EQ(st.undisplayable_faces_deleted, 0u);
}

TEST(SimplifyPaper, JoinsNeighboursWoundTheOtherWayAndKeepsTheirWinding) {
  // Every other triangle of a flat grid is wound the other way (as in many
  // CityGML exports). The simplifier still sees one surface (no face is cut
  // loose), simplifies it, and every output triangle faces where its input
  // triangle faced.
  Scene in;
  add_grid(in, 10, 2.0, 0);
  for (size_t t = 1; t < in.triangle_count(); t += 2) std::swap(in.indices[3 * t + 1], in.indices[3 * t + 2]);
  std::vector<Label> labels(in.triangle_count(), Label::Imperceptible);
  labels[0] = Label::Perceptible;
  auto normal_z = [](const Scene& s, size_t t) {
    auto a = test::vertex(s, s.indices[3 * t]), b = test::vertex(s, s.indices[3 * t + 1]),
         c = test::vertex(s, s.indices[3 * t + 2]);
    return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
  };
  for (SimplifyMode mode : {SimplifyMode::Paper, SimplifyMode::Qem}) {
    SimplifyOptions opt;
    opt.mode = mode;
    opt.target_triangles = 20;
    SimplifyStats st;
    std::vector<uint32_t> src;
    Scene out = simplify(in, labels, opt, &st, &src);
    expect_valid(out);
    EXPECT_EQ(st.nonmanifold_faces_duplicated, 0u) << simplify_mode_name(mode);
    EXPECT_LE(out.triangle_count(), 20u);
    for (size_t t = 0; t < out.triangle_count(); ++t) {
      double z = normal_z(out, t);
      if (z == 0) continue;  // degenerate output would be caught by the count above
      EXPECT_EQ(z > 0, normal_z(in, src[t]) > 0) << simplify_mode_name(mode) << " output triangle " << t;
    }
  }
}

TEST(SimplifyPaper, DegenerateAndSoupInputIsWeldedAndKept) {
  // The same grid as a triangle soup (no shared vertices) simplifies like
  // the indexed one: welding joins the corners.
  Scene grid;
  add_grid(grid, 20, 2.0, 0);
  Scene soup;
  for (size_t t = 0; t < grid.triangle_count(); ++t) {
    uint32_t v[3];
    for (int k = 0; k < 3; ++k) {
      auto p = test::vertex(grid, grid.indices[3 * t + k]);
      v[k] = add_vertex(soup, p[0], p[1], p[2]);
    }
    add_tri(soup, v[0], v[1], v[2], 0);
  }
  uint32_t d = add_vertex(soup, 0.5, 0.5, 0.0);
  add_tri(soup, d, d, add_vertex(soup, 0.7, 0.5, 0.0), 0);  // repeated corner, perceptible
  std::vector<Label> labels(soup.triangle_count(), Label::Imperceptible);
  labels[0] = labels.back() = Label::Perceptible;
  SimplifyStats st;
  std::vector<uint32_t> src;
  Scene out = simplify(soup, labels, SimplifyOptions{}, &st, &src);
  expect_perceptible_preserved(soup, labels, out, src);
  EXPECT_EQ(st.degenerate_faces, 1u);
  EXPECT_LT(out.triangle_count(), soup.triangle_count() / 10);
}

TEST(SimplifyPaper, ConstraintLinesKeepSharpEdges) {
  // A finely gridded imperceptible box with one perceptible triangle: with
  // constraint lines every vertex on a box edge survives; without, they go.
  Scene in;
  add_box(in, {0, 0, 0}, {2, 2, 2}, 0, 8);
  std::vector<Label> labels(in.triangle_count(), Label::Imperceptible);
  labels[0] = Label::Perceptible;
  auto on_edge = [](const float* p) {
    int extreme = 0;
    for (int a = 0; a < 3; ++a) extreme += p[a] == 0.0f || p[a] == 2.0f;
    return extreme >= 2;
  };
  size_t edge_vertices = 0;
  for (size_t v = 0; v < in.vertex_count(); ++v) edge_vertices += on_edge(&in.positions[3 * v]);
  ASSERT_GT(edge_vertices, 0u);
  for (bool lines : {true, false}) {
    SimplifyOptions opt;
    opt.constraint_lines = lines;
    Scene out = simplify(in, labels, opt);
    std::set<std::array<float, 3>> kept;
    for (size_t v = 0; v < out.vertex_count(); ++v)
      if (on_edge(&out.positions[3 * v])) kept.insert({out.positions[3 * v], out.positions[3 * v + 1], out.positions[3 * v + 2]});
    // 12 edges x 7 inner points + 8 corners distinct positions
    if (lines)
      EXPECT_EQ(kept.size(), 12u * 7u + 8u);
    else
      EXPECT_LT(kept.size(), 12u * 7u + 8u);
  }
}

TEST(SimplifyPaper, ReportsDisplacementRelativeToTheBox) {
  std::vector<Label> labels;
  Scene in = bumpy_grid(labels, 0.2);
  SimplifyStats st;
  simplify(in, labels, SimplifyOptions{}, &st);
  EXPECT_GT(st.max_displacement_rel, 0.0);
  EXPECT_LE(st.max_displacement_rel, 1.0);
  EXPECT_GT(st.mean_displacement_rel, 0.0);
  EXPECT_LE(st.mean_displacement_rel, st.max_displacement_rel);
  EXPECT_NEAR(st.bbox_diagonal, scene_bounds(in).diagonal(), 1e-6);
}

}  // namespace
}  // namespace perclod
