// Known-answer scenes, each traced by the octree, by Embree (verify mode) and
// by the brute-force oracle. The octree must equal the oracle bit for bit
// (same rays, same watertight test, same tie rule); Embree's robust test is a
// different formulation, so against it we ask for zero real disagreements.
#include <cmath>
#include <random>
#include <set>

#include "pixel_rays.h"
#include "raycast_fixtures.h"
#include "watertight.h"

namespace perclod::test {
namespace {

void expect_octree_equals_oracle(const Scene& s, const Camera& c) {
  OctreeTracer oct(s);
  BruteForceTracer brute(s);
  const size_t n = size_t(c.width) * size_t(c.height);
  std::vector<uint32_t> a(n), b(n);
  std::vector<float> ta(n), tb(n);
  oct.trace(c, a.data(), ta.data());
  brute.trace(c, b.data(), tb.data());
  size_t diff = 0, tdiff = 0;
  for (size_t i = 0; i < n; ++i) {
    diff += a[i] != b[i];
    tdiff += a[i] == b[i] && ta[i] != tb[i];
  }
  EXPECT_EQ(diff, 0u) << "octree differs from the brute-force oracle";
  EXPECT_EQ(tdiff, 0u) << "octree t differs from the oracle's";
}

// min_identical: scenes built to put pixel centres exactly on shared edges
// legitimately differ there (each watertight test includes the edge in a
// different triangle); those mismatches must all be ties.
void expect_embree_agrees(const Scene& s, const Camera& c, const std::vector<uint32_t>& octree,
                          double min_identical = 0.999) {
  const auto e = EmbreeTracer(s, EmbreeMode::Verify).trace(c);
  const Agreement g = compare_traced(s, c, octree.data(), e.data());
  EXPECT_EQ(g.real_disagreements, 0u);
  EXPECT_GE(g.identical_rate(), min_identical);
  EXPECT_EQ(g.identical + g.ties + g.edge_grazes + g.real_disagreements, g.covered);
}

// Signed distance (pixels) of p from the directed edge a->b in image space.
double edge_distance(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& p) {
  const Eigen::Vector2d e = b - a, q = p - a;
  return (e.x() * q.y() - e.y() * q.x()) / e.norm();
}

TEST(RaycastScenes, SingleLargeQuadExactPixelSet) {
  const Camera cam = front_camera(64, 48);
  const double pts[4][2] = {{5.3, 4.7}, {57.2, 6.1}, {55.8, 41.35}, {8.15, 40.6}};
  V3 p[4];
  for (int i = 0; i < 4; ++i) p[i] = at_pixel(cam, pts[i][0], pts[i][1], 10.0);
  Scene s;
  add_quad(s, p[0], p[1], p[2], p[3], 0);

  // Expected set from Camera::project of the (float-rounded) corners.
  Eigen::Vector2d img[4];
  for (int i = 0; i < 4; ++i) {
    V3 q(s.positions[3 * i], s.positions[3 * i + 1], s.positions[3 * i + 2]);
    double px, py, depth;
    ASSERT_TRUE(cam.project(q, px, py, depth));
    img[i] = {px, py};
  }
  std::vector<uint8_t> inside(64 * 48, 0);
  size_t expected = 0;
  for (int y = 0; y < 48; ++y)
    for (int x = 0; x < 64; ++x) {
      const Eigen::Vector2d c(x + 0.5, y + 0.5);
      double dmin = INFINITY;
      bool in = true;
      for (int k = 0; k < 4; ++k) {
        const double d = edge_distance(img[k], img[(k + 1) % 4], c);
        dmin = std::min(dmin, std::fabs(d));
        in &= d > 0;  // clockwise on screen (y down) = positive here
      }
      ASSERT_GT(dmin, 1e-3) << "test corners put a pixel centre on an edge";
      inside[y * 64 + x] = in;
      expected += in;
    }
  ASSERT_GT(expected, 1500u);

  const Traced r = trace_all(s, cam);
  for (const auto* buf : {&r.octree, &r.embree, &r.brute}) {
    size_t hits = 0, wrong = 0;
    for (int i = 0; i < 64 * 48; ++i) {
      hits += (*buf)[i] != 0;
      wrong += ((*buf)[i] != 0) != (inside[i] != 0);
      EXPECT_LE((*buf)[i], 2u);
    }
    EXPECT_EQ(hits, expected);
    EXPECT_EQ(wrong, 0u);
  }
  expect_octree_equals_oracle(s, cam);
}

// A height field whose vertices sit on pixel centres (so edges run through
// pixel centres in exact arithmetic, not in float), some jittered, with
// alternating diagonals: every pixel centre inside the outer border is hit
// exactly once, by a triangle of the mesh.
TEST(RaycastScenes, SharedEdgesThroughPixelCentresLeaveNoHoles) {
  const int W = 72, H = 56;
  const Camera cam = front_camera(W, H, 0.9);
  const int nx = 9, ny = 7;
  auto image_x = [&](int i) { return i == 0 ? 2.25 : i == nx ? 2.25 + 7.0 * nx : 2.5 + 7.0 * i + (i % 2 ? 0.37 : 0.0); };
  auto image_y = [&](int j) { return j == 0 ? 3.75 : j == ny ? 3.75 + 7.0 * ny : 3.5 + 7.0 * j + (j % 3 == 1 ? 0.21 : 0.0); };
  Scene s;
  std::vector<uint32_t> vid((nx + 1) * (ny + 1));
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i)
      vid[j * (nx + 1) + i] = add_vertex(s, at_pixel(cam, image_x(i), image_y(j), 10.0 + 0.7 * std::sin(1.3 * i + 0.7 * j)));
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const uint32_t a = vid[j * (nx + 1) + i], b = vid[j * (nx + 1) + i + 1];
      const uint32_t c = vid[(j + 1) * (nx + 1) + i + 1], d = vid[(j + 1) * (nx + 1) + i];
      const uint32_t comp = uint32_t(j);  // one component per row: shared edges across components too
      if ((i + j) % 2) {
        add_triangle(s, a, b, c, comp);
        add_triangle(s, a, c, d, comp);
      } else {
        add_triangle(s, a, b, d, comp);
        add_triangle(s, b, c, d, comp);
      }
    }
  size_t expected = 0;
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x)
      expected += (x + 0.5 > image_x(0) && x + 0.5 < image_x(nx) && y + 0.5 > image_y(0) && y + 0.5 < image_y(ny));
  const Traced r = trace_all(s, cam);
  for (const auto* buf : {&r.octree, &r.embree, &r.brute}) {
    size_t hits = 0;
    for (int y = 0; y < H; ++y)
      for (int x = 0; x < W; ++x) {
        const bool in = x + 0.5 > image_x(0) && x + 0.5 < image_x(nx) && y + 0.5 > image_y(0) && y + 0.5 < image_y(ny);
        const bool hit = (*buf)[y * W + x] != 0;
        EXPECT_EQ(hit, in) << "pixel " << x << "," << y;
        hits += hit;
      }
    EXPECT_EQ(hits, expected);  // one triangle per covered pixel: no holes, no double counts
    const TriangleCounts counts = count_triangles(buf->data(), nullptr, buf->size(), s.triangle_count());
    size_t sum = 0;
    for (uint32_t t : counts.traced) sum += t;
    EXPECT_EQ(sum, expected);
  }
  expect_octree_equals_oracle(s, cam);
  expect_embree_agrees(s, cam, r.octree, 0.9);
}

// Cells of 4x4 pixels whose corners sit on pixel corners: each cell's two
// triangles together own exactly its 16 pixels.
TEST(RaycastScenes, PixelAlignedGridOwnsExactCells) {
  const int W = 40, H = 32, cell = 4;
  const Camera cam = front_camera(W, H, 0.7);
  Scene s;
  for (int cy = 0; cy < H / cell; ++cy)
    for (int cx = 0; cx < W / cell; ++cx) {
      const double x0 = cx * cell, y0 = cy * cell;
      add_quad(s, at_pixel(cam, x0, y0, 5), at_pixel(cam, x0 + cell, y0, 5), at_pixel(cam, x0 + cell, y0 + cell, 5),
               at_pixel(cam, x0, y0 + cell, 5), uint32_t(cy * (W / cell) + cx));
    }
  const Traced r = trace_all(s, cam);
  for (const auto* buf : {&r.octree, &r.embree, &r.brute}) {
    const TriangleCounts counts = count_triangles(buf->data(), nullptr, buf->size(), s.triangle_count());
    for (size_t q = 0; q < s.triangle_count() / 2; ++q)
      EXPECT_EQ(counts.traced[2 * q] + counts.traced[2 * q + 1], uint32_t(cell * cell)) << "cell " << q;
    // The pixel (x, y) belongs to the cell that contains it.
    for (int y = 0; y < H; ++y)
      for (int x = 0; x < W; ++x) {
        const uint32_t id = (*buf)[y * W + x];
        ASSERT_NE(id, 0u);
        EXPECT_EQ((id - 1) / 2, uint32_t((y / cell) * (W / cell) + x / cell));
      }
  }
  expect_octree_equals_oracle(s, cam);
}

// Two coplanar quads overlap; the one with the lower triangle indices wins
// the overlap although its component id is higher.
TEST(RaycastScenes, CoplanarOverlapGoesToLowestIndex) {
  const int W = 48, H = 40;
  const Camera cam = front_camera(W, H);
  Scene s;
  add_quad(s, at_pixel(cam, 4.3, 5.2, 7), at_pixel(cam, 30.1, 5.2, 7), at_pixel(cam, 30.1, 30.3, 7),
           at_pixel(cam, 4.3, 30.3, 7), 5);  // triangles 0, 1
  add_quad(s, at_pixel(cam, 16.2, 12.4, 7), at_pixel(cam, 44.6, 12.4, 7), at_pixel(cam, 44.6, 36.7, 7),
           at_pixel(cam, 16.2, 36.7, 7), 0);  // triangles 2, 3
  const Traced r = trace_all(s, cam);
  for (const auto* buf : {&r.octree, &r.embree, &r.brute}) {
    size_t overlap = 0;
    for (int y = 13; y < 30; ++y)
      for (int x = 17; x < 30; ++x) {
        EXPECT_LE((*buf)[y * W + x], 2u) << "pixel " << x << "," << y;
        ++overlap;
      }
    EXPECT_GT(overlap, 200u);
    EXPECT_GE((*buf)[35 * W + 40], 3u);  // quad B alone
  }
  expect_octree_equals_oracle(s, cam);
  const Agreement g = compare_traced(s, cam, r.octree.data(), r.embree.data());
  EXPECT_EQ(g.identical, g.covered);
}

// Stacks of nearly coplanar quads whose depths differ by fractions of the
// tie window (1e-6 relative), some tilted so that a box nearer the eye holds
// a hit farther away: a pixel's window then holds up to eight hits, found in
// every order, nearer hits arriving after farther ones and pushing some out
// of the window. The octree remembers a few hits per pixel and walks a tile
// again only when more pile up; either way it must equal the oracle, for one
// sample per pixel and for four traced in one walk.
TEST(RaycastScenes, StackedNearTiesEqualTheOracle) {
  const int W = 40, H = 36;
  const Camera cam = front_camera(W, H);
  std::mt19937 rng(20261202);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  size_t stacked = 0;
  for (int round = 0; round < 12; ++round) {
    Scene s;
    const int quads = 3 + round % 6;
    for (int q = 0; q < quads; ++q) {
      const double d = 7.0 * (1.0 + 3e-6 * unit(rng));
      // Tilt: depth gradient across the quad, from none to 40 windows.
      const double tilt = (round % 3 == 0 ? 0.0 : 4e-5 * (unit(rng) - 0.5)) * 7.0;
      const double x0 = 3 + 6 * unit(rng), y0 = 3 + 5 * unit(rng), x1 = 30 + 7 * unit(rng), y1 = 26 + 7 * unit(rng);
      add_quad(s, at_pixel(cam, x0, y0, d - tilt), at_pixel(cam, x1, y0, d), at_pixel(cam, x1, y1, d + tilt),
               at_pixel(cam, x0, y1, d), uint32_t(rng() % 4));
    }
    // How many pixels see more hits than the octree remembers (at least 5).
    for (int y = 0; y < H; ++y)
      for (int x = 0; x < W; ++x) {
        int hits = 0;
        double t;
        for (size_t tri = 0; tri < s.triangle_count(); ++tri)
          hits += intersect_pixel_double(s, cam, x, y, tri, t) != DoubleHit::Miss;
        stacked += hits >= 5;
      }
    expect_octree_equals_oracle(s, cam);
    const auto offsets = sample_offsets(4);
    const auto a = trace_samples(OctreeTracer(s), cam, offsets), b = trace_samples(BruteForceTracer(s), cam, offsets);
    for (size_t k = 0; k < offsets.size(); ++k) EXPECT_EQ(a[k], b[k]) << "round " << round << ", sample " << k;
  }
  EXPECT_GT(stacked, 1000u) << "the stacks must overfill the remembered ties";
}

// The double re-test's three answers, with a pixel centre placed inside or
// outside a triangle's edge by d (in barycentric units along that edge's
// altitude): Inside only beyond the float rounding (about 4e-6 here: 1e-6 of
// the 10 m reach over the triangle's 2.5 m size), Edge within it on either
// side (the vertices' float rounding is 5e-7), Miss beyond it outside.
TEST(RaycastScenes, DoubleRetestCallsTheRoundingBandAroundAnEdgeAGraze) {
  const Camera cam = front_camera(64, 48);
  const double cx = 32.5, cy = 24.5;  // centre of pixel (32, 24)
  struct Case {
    double d;
    DoubleHit want;
  };
  for (const Case c : {Case{1e-2, DoubleHit::Inside}, Case{2e-6, DoubleHit::Edge}, Case{-2e-6, DoubleHit::Edge},
                       Case{-1e-2, DoubleHit::Miss}}) {
    // Apex 10 px above the centre; the base edge 10 d px below it (inside
    // by d of the 10 px altitude), 20 px wide.
    const double base_y = cy + 10.0 * c.d;
    Scene s;
    add_triangle(s, add_vertex(s, at_pixel(cam, cx - 10, base_y, 10.0)), add_vertex(s, at_pixel(cam, cx + 10, base_y, 10.0)),
                 add_vertex(s, at_pixel(cam, cx, cy - 10, 10.0)), 0);
    double t = 0;
    EXPECT_EQ(intersect_pixel_double(s, cam, 32, 24, 0, t), c.want) << "d = " << c.d;
  }
}

bool hits_floor(const Scene& s, const Camera& c, int x, int y, double& t) {
  return intersect_pixel_double(s, c, x, y, 4, t) != DoubleHit::Miss ||
         intersect_pixel_double(s, c, x, y, 5, t) != DoubleHit::Miss;
}

// A wall in front of the near plane is clipped away; a floor crossing the
// near plane is seen only beyond it.
TEST(RaycastScenes, NearPlaneCutsGeometry) {
  const int W = 40, H = 40;
  const Camera cam = front_camera(W, H, 1.0, /*znear=*/1.0, /*zfar=*/100.0);
  Scene s;
  add_quad(s, V3(-5, -5, -0.5), V3(5, -5, -0.5), V3(5, 5, -0.5), V3(-5, 5, -0.5), 0);  // before znear
  add_quad(s, V3(-5, -5, -3), V3(5, -5, -3), V3(5, 5, -3), V3(-5, 5, -3), 1);          // back wall
  add_quad(s, V3(-5, -0.4, -0.2), V3(5, -0.4, -0.2), V3(5, -0.4, -3.0), V3(-5, -0.4, -3.0), 2);  // floor
  const Traced r = trace_all(s, cam);
  for (const auto* buf : {&r.octree, &r.embree, &r.brute}) {
    size_t floor_px = 0, far_floor = 0, maybe_floor = 0;
    for (int y = 0; y < H; ++y)
      for (int x = 0; x < W; ++x) {
        const uint32_t id = (*buf)[y * W + x];
        ASSERT_NE(id, 0u);
        EXPECT_GT(id, 2u) << "the wall before znear must be clipped";
        double tf;
        const bool floor_hit = hits_floor(s, cam, x, y, tf);
        if (id >= 5) ++floor_px;
        if (floor_hit && tf >= 0.99) ++maybe_floor;
        if (floor_hit && tf > 1.01) {
          ++far_floor;
          EXPECT_GE(id, 5u) << "floor beyond znear at " << x << "," << y;
        }
        // Rays that meet the floor before znear continue to the back wall.
        Camera unclipped = cam;
        unclipped.znear = 0.01;
        double tu;
        const bool near_floor = hits_floor(s, unclipped, x, y, tu);
        if (near_floor && tu < 0.99) {
          EXPECT_LE(id, 4u) << "pixel " << x << "," << y;
        }
      }
    EXPECT_GT(floor_px, 50u);
    EXPECT_GE(floor_px, far_floor);
    EXPECT_LE(floor_px, maybe_floor);
  }
  expect_octree_equals_oracle(s, cam);
}

// 20,000 triangles of 0.2 m at 500 m: a few pixel centres land on the patch,
// nearly every triangle is undisplayable.
TEST(RaycastScenes, DistantSubPixelTrianglesAreUndisplayable) {
  const Camera cam = front_camera(64, 48, 0.8, 1.0, 2000.0);
  Scene s;
  const int n = 100;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const double x = -10 + 0.2 * i + 0.013, y = -10 + 0.2 * j + 0.007;
      add_quad(s, V3(x, y, -500), V3(x + 0.2, y, -500), V3(x + 0.2, y + 0.2, -500), V3(x, y + 0.2, -500),
               uint32_t(j / 10 * 10 + i / 10));
    }
  const double footprint = cam.pixel_footprint(500);
  ASSERT_GT(footprint, 5.0);
  const Traced r = trace_all(s, cam);
  for (const auto* buf : {&r.octree, &r.embree, &r.brute}) {
    const size_t covered = count_nonzero(*buf);
    EXPECT_GE(covered, 4u);
    EXPECT_LE(covered, 16u);
    const auto labels = label_triangles(count_triangles(buf->data(), nullptr, buf->size(), s.triangle_count()));
    const LabelCounts lc = count_labels(labels);
    EXPECT_EQ(lc.perceptible, covered);  // one pixel each, no two pixels on one tiny triangle
    EXPECT_EQ(lc.undisplayable, s.triangle_count() - covered);
  }
  expect_octree_equals_oracle(s, cam);
}

// A quad seen from behind (its winding turned away from the eye) is hit like
// a front face: no culling.
TEST(RaycastScenes, BackFacesAreHit) {
  const Camera cam = front_camera(32, 32);
  const V3 a(-1, -1, -4), b(1, -1, -4), c(1, 1, -4), d(-1, 1, -4);
  Scene front, back;
  add_quad(front, a, b, c, d, 0);  // counter-clockwise from the eye
  add_quad(back, a, d, c, b, 0);   // clockwise: its normal points away
  const Traced rf = trace_all(front, cam), rb = trace_all(back, cam);
  const size_t nf = count_nonzero(rf.octree);
  EXPECT_GT(nf, 100u);
  EXPECT_EQ(count_nonzero(rb.octree), nf);
  EXPECT_EQ(count_nonzero(rb.embree), nf);
  EXPECT_EQ(count_nonzero(rb.brute), nf);
  expect_octree_equals_oracle(back, cam);
}

// A closed box hides a smaller component inside it.
TEST(RaycastScenes, HiddenInteriorComponentIsUndisplayable) {
  const Camera cam = look_at(V3(3, 4, 10), V3(0, 0, 0), V3(0, 1, 0), 0.8, 64, 48, 0.1, 100);
  Scene s;
  add_box(s, V3(-2, -2, -2), V3(2, 2, 2), 0);
  add_box(s, V3(-1, -1, -1), V3(1, 1, 1), 1);  // triangles 12..23
  const Traced r = trace_all(s, cam);
  for (const auto* buf : {&r.octree, &r.embree, &r.brute}) {
    const auto labels = label_triangles(count_triangles(buf->data(), nullptr, buf->size(), s.triangle_count()));
    for (size_t t = 12; t < 24; ++t) EXPECT_EQ(labels[t], Label::Undisplayable) << "inner triangle " << t;
    size_t outer_seen = 0;
    for (size_t t = 0; t < 12; ++t) outer_seen += labels[t] != Label::Undisplayable;
    EXPECT_EQ(outer_seen, 6u);  // three faces of the box are visible, two triangles each
  }
  expect_octree_equals_oracle(s, cam);
}

// 6 x 6 x 3 boxes, each its own component: enough for the octree to split.
Scene box_lattice() {
  Scene s;
  uint32_t comp = 0;
  for (int k = 0; k < 3; ++k)
    for (int j = 0; j < 6; ++j)
      for (int i = 0; i < 6; ++i) {
        const V3 lo(-6 + 2 * i + 0.3, -6 + 2 * j + 0.3, -3 + 2 * k + 0.3);
        add_box(s, lo, lo + V3(1.2 + 0.05 * i, 1.1, 1.3), comp++);
      }
  return s;
}

TEST(RaycastScenes, RayParallelToOctreeSlab) {
  const Scene s = box_lattice();
  OctreeTracer oct(s);
  ASSERT_GE(oct.stats().depth_reached, 1);
  // Axis-aligned camera, odd image: the centre column's rays have x = 0
  // exactly and the centre row's y = 0, parallel to the x and y slabs;
  // the eye's x and y are those of the root's splitting planes.
  const Bounds b = scene_bounds(s);
  Camera cam = front_camera(63, 47, 1.2, 0.1, 100);
  cam.eye = V3(0.5f * (b.lo[0] + b.hi[0]), 0.5f * (b.lo[1] + b.hi[1]), 9);
  EXPECT_EQ(cam.ray_direction(31.5, 23.5).x(), 0.0);
  EXPECT_EQ(cam.ray_direction(31.5, 23.5).y(), 0.0);
  const auto oc = oct.trace(cam);
  EXPECT_GT(count_nonzero(oc), 1000u);
  expect_octree_equals_oracle(s, cam);
  expect_embree_agrees(s, cam, oc);
  // Sideways: rays along -x graze the z slabs of the lattice.
  Camera side = look_at(V3(20, 0.5f * (b.lo[1] + b.hi[1]), 0.5f * (b.lo[2] + b.hi[2])), V3(0, 0.5f * (b.lo[1] + b.hi[1]), 0.5f * (b.lo[2] + b.hi[2])),
                        V3(0, 0, 1), 1.2, 63, 47, 0.1, 100);
  expect_octree_equals_oracle(s, side);
}

TEST(RaycastScenes, EyeExactlyOnSlabPlanes) {
  const Scene s = box_lattice();
  const Bounds b = scene_bounds(s);
  // The root's centre, computed the way the octree splits (float midpoint):
  // the eye sits on all three first-level splitting planes, inside the scene.
  const V3 centre(0.5f * (b.lo[0] + b.hi[0]), 0.5f * (b.lo[1] + b.hi[1]), 0.5f * (b.lo[2] + b.hi[2]));
  const V3 dirs[] = {V3(1, 0, 0), V3(-1, 0, 0), V3(0, 1, 0), V3(0, -1, 0), V3(0.3, 0.4, -0.8), V3(-1, -1, 1)};
  for (const V3& d : dirs) {
    const V3 up = std::fabs(d.z()) > 0.9 ? V3(0, 1, 0) : V3(0, 0, 1);
    const Camera cam = look_at(centre, centre + d, up, 1.4, 40, 30, 0.01, 100);
    const auto oc = OctreeTracer(s).trace(cam);
    EXPECT_GT(count_nonzero(oc), 100u);
    expect_octree_equals_oracle(s, cam);
    expect_embree_agrees(s, cam, oc);
  }
}

TEST(RaycastScenes, EmptySceneAndMisses) {
  Scene s;
  const Camera cam = front_camera(16, 16);
  for (const auto& buf : {OctreeTracer(s).trace(cam), EmbreeTracer(s).trace(cam), EmbreeTracer(s, EmbreeMode::Fast).trace(cam)})
    EXPECT_EQ(count_nonzero(buf), 0u);
  Scene behind;
  add_quad(behind, V3(-1, -1, 4), V3(1, -1, 4), V3(1, 1, 4), V3(-1, 1, 4), 0);  // behind the eye
  EXPECT_EQ(count_nonzero(OctreeTracer(behind).trace(cam)), 0u);
  EXPECT_EQ(count_nonzero(EmbreeTracer(behind).trace(cam)), 0u);
}

TEST(RaycastScenes, BadInputThrows) {
  Scene s;
  add_quad(s, V3(-1, -1, -4), V3(1, -1, -4), V3(1, 1, -4), V3(-1, 1, -4), 0);
  Scene bad = s;
  bad.indices[4] = 99;
  EXPECT_THROW(OctreeTracer{bad}, std::invalid_argument);
  EXPECT_THROW(EmbreeTracer{bad}, std::invalid_argument);
  bad = s;
  bad.positions[2] = NAN;
  EXPECT_THROW(OctreeTracer{bad}, std::invalid_argument);
  bad = s;
  bad.component.pop_back();
  EXPECT_THROW(OctreeTracer{bad}, std::invalid_argument);
  OctreeOptions o;
  o.max_components_per_leaf = 0;
  EXPECT_THROW(OctreeTracer(s, o), std::invalid_argument);
  OctreeTracer oct(s);
  Camera cam = front_camera(0, 10);
  EXPECT_THROW(oct.trace(cam), std::invalid_argument);
  cam = front_camera(10, 10, 0.8, 5.0, 1.0);
  EXPECT_THROW(oct.trace(cam), std::invalid_argument);
}

TEST(RaycastScenes, FastEmbreeAndTBufferMatchOctree) {
  const Scene s = box_lattice();
  const Camera cam = look_at(V3(9, 7, 15), V3(0, 0, 0), V3(0, 0, 1), 0.9, 90, 70, 0.1, 100);
  const size_t n = 90 * 70;
  std::vector<uint32_t> a(n), b(n);
  std::vector<float> ta(n), tb(n);
  OctreeTracer(s).trace(cam, a.data(), ta.data());
  const EmbreeTracer fast(s, EmbreeMode::Fast);
  EXPECT_GT(fast.memory_bytes(), s.triangle_count() * 12);  // at least its copy of the geometry
  EXPECT_STREQ(fast.name(), "embree-fast");
  fast.trace(cam, b.data(), tb.data());
  const Agreement g = compare_traced(s, cam, a.data(), b.data());
  EXPECT_EQ(g.real_disagreements, 0u);
  EXPECT_GT(g.covered, 2000u);
  for (size_t i = 0; i < n; ++i)
    if (a[i] && a[i] == b[i]) {
      EXPECT_NEAR(ta[i], tb[i], 1e-4 * ta[i]);
    }
}

}  // namespace
}  // namespace perclod::test

namespace perclod::test {
namespace {

// The structure's settings change speed, never the answer: every variant
// reproduces the brute-force oracle, and the octree really splits when asked.
TEST(RaycastScenes, OctreeSettingsDoNotChangeResults) {
  Scene s = box_lattice();
  for (int j = 0; j < 30; ++j)  // plus one 1,800-triangle component: a deep BVH
    for (int i = 0; i < 30; ++i)
      add_quad(s, V3(-7 + 0.4 * i, -7 + 0.4 * j, -4.5), V3(-6.6 + 0.4 * i, -7 + 0.4 * j, -4.5),
               V3(-6.6 + 0.4 * i, -6.6 + 0.4 * j, -4.4), V3(-7 + 0.4 * i, -6.6 + 0.4 * j, -4.5), 200);
  const Camera cam = look_at(V3(4, -6, 14), V3(0, 0, -2), V3(0, 0, 1), 1.0, 80, 60, 0.1, 100);
  const auto expected = BruteForceTracer(s).trace(cam);
  ASSERT_GT(count_nonzero(expected), 2000u);
  OctreeOptions flat;
  flat.max_depth = 0;
  OctreeOptions deep;
  deep.max_components_per_leaf = 1;
  OctreeOptions tiny_leaves;
  tiny_leaves.max_triangles_per_bvh_leaf = 1;
  OctreeOptions huge_leaves;
  huge_leaves.max_triangles_per_bvh_leaf = 4096;
  for (const OctreeOptions& o : {OctreeOptions{}, flat, deep, tiny_leaves, huge_leaves}) {
    const OctreeTracer oct(s, o);
    EXPECT_EQ(oct.trace(cam), expected) << "depth " << o.max_depth << " per leaf " << o.max_components_per_leaf
                                        << " bvh leaf " << o.max_triangles_per_bvh_leaf;
    EXPECT_GT(oct.memory_bytes(), 40 * s.triangle_count());
    EXPECT_GE(oct.build_seconds(), 0.0);
  }
  EXPECT_EQ(OctreeTracer(s, flat).stats().octree_nodes, 1u);
  const auto st = OctreeTracer(s, deep).stats();
  EXPECT_GE(st.depth_reached, 2);
  EXPECT_LE(st.depth_reached, 9);
  EXPECT_GT(OctreeTracer(s, tiny_leaves).stats().bvh_nodes, OctreeTracer(s).stats().bvh_nodes);
}

// At the deepest octree OctreeOptions allows (20 levels) a walk keeps 7
// siblings waiting at every level: boxes along the diagonal at 2^-k (k = 0
// .. 24), each split from the ones nearer the origin at level k, seen from
// just beyond the origin, where every level's cell is wider than a pixel, so
// the walk descends the whole chain first. It finds the oracle's hits and
// its stack holds (128 entries overflowed here; the ASan stage checks the
// bounds).
TEST(RaycastScenes, TheDeepestOctreeIsWalkedWhole) {
  Scene s;
  add_box(s, V3(0, 0, 0), V3(1e-9, 1e-9, 1e-9), 0);
  for (int k = 0; k <= 24; ++k) {
    const double a = std::ldexp(1.0, -k);
    add_box(s, V3(a, a, a), V3(1.5 * a, 1.5 * a, 1.5 * a), uint32_t(k + 1));
  }
  OctreeOptions deepest;
  deepest.max_depth = 20;
  deepest.max_components_per_leaf = 1;
  const OctreeTracer oct(s, deepest);
  ASSERT_EQ(oct.stats().depth_reached, 20);
  const Camera cam = look_at(V3(-1e-7, -1e-7, -1e-7), V3(1, 1, 1), V3(0, 0, 1), 0.3, 32, 32, 1e-9, 10);
  const auto expected = BruteForceTracer(s).trace(cam);
  ASSERT_GT(count_nonzero(expected), 20u);
  EXPECT_EQ(oct.trace(cam), expected);
}

}  // namespace
}  // namespace perclod::test

namespace perclod::test {
namespace {

// Zero-area triangles (repeated index, collinear vertices) are valid input,
// never hit, and do not disturb their neighbours.
TEST(RaycastScenes, DegenerateTrianglesAreNeverHit) {
  const Camera cam = front_camera(40, 30);
  Scene s;
  const uint32_t a = add_vertex(s, V3(-1, -1, -5)), b = add_vertex(s, V3(1, -1, -5));
  const uint32_t c = add_vertex(s, V3(1, 1, -5)), m = add_vertex(s, V3(0, 0, -5));
  add_triangle(s, a, a, c, 0);  // repeated index
  add_triangle(s, a, m, c, 0);  // collinear: the diagonal
  add_triangle(s, a, b, c, 1);  // a real triangle behind both
  const Traced r = trace_all(s, cam);
  for (const auto* buf : {&r.octree, &r.embree, &r.brute}) {
    const TriangleCounts counts = count_triangles(buf->data(), nullptr, buf->size(), s.triangle_count());
    EXPECT_EQ(counts.traced[0], 0u);
    EXPECT_EQ(counts.traced[1], 0u);
    EXPECT_GT(counts.traced[2], 50u);
  }
  expect_octree_equals_oracle(s, cam);
}

// The octree's four-lane exact test serves tiles whose rays share one axis
// permutation; a tile where the dominant axis of the rays changes is traced
// ray by ray. A wide view along a diagonal has both kinds (and tiles cut
// short at the image's right and bottom edges): each must equal the oracle.
TEST(RaycastScenes, DiagonalViewWithMixedAxisTilesEqualsTheOracle) {
  const Scene s = box_lattice();
  const Camera cam = look_at(V3(-6.5, -6, 2.5), V3(0, 0, 0), V3(0, 0, 1), 1.6, 200, 150, 0.1, 100);
  // Count tiles (32 x 32, as the octree cuts them) by their rays' permutations.
  int uniform = 0, mixed = 0;
  for (int ty = 0; ty < cam.height; ty += 32)
    for (int tx = 0; tx < cam.width; tx += 32) {
      std::set<int> axes;
      for (int y = ty; y < std::min(ty + 32, cam.height); ++y)
        for (int x = tx; x < std::min(tx + 32, cam.width); ++x) {
          float d[3];
          detail::pixel_direction(cam, x, y, d);
          const detail::ShearedRay r = detail::shear_ray(d);
          axes.insert(r.kx | r.ky << 2 | r.kz << 4);
        }
      (axes.size() == 1 ? uniform : mixed) += 1;
    }
  EXPECT_GE(uniform, 5) << mixed << " tiles mixed";
  EXPECT_GE(mixed, 5) << uniform << " tiles uniform";
  const auto oc = OctreeTracer(s).trace(cam);
  EXPECT_GT(count_nonzero(oc), size_t(cam.width) * size_t(cam.height) / 4);
  expect_octree_equals_oracle(s, cam);
}

}  // namespace
}  // namespace perclod::test
