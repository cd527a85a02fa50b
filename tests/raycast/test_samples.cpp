// Several samples per pixel (Camera::shift_x/shift_y, sample_offsets) and the
// frustum test that keeps unframed triangles from being called undisplayable.
#include <gtest/gtest.h>

#include <set>

#include "perclod/raycast.h"

namespace perclod {
namespace {

// A 64 x 64 camera at the origin looking down -z, 1 unit per pixel at depth 64
// (fov chosen so that the image plane at z = -64 spans [-32, 32]).
Camera unit_camera() {
  Camera c;
  c.width = c.height = 64;
  c.fov_y = 2 * std::atan(0.5);
  c.znear = 1;
  c.zfar = 100;
  return c;
}

// A triangle in the plane z = -64 covering the image points in `px` x `py`
// (pixel coordinates, row 0 at the top) as a right triangle's square part.
Scene square_at(double x0, double x1, double y0, double y1) {
  // Image x -> world x = x - 32; image y -> world y = 32 - y (at depth 64).
  Scene s;
  const float X0 = float(x0 - 32), X1 = float(x1 - 32), Y0 = float(32 - y1), Y1 = float(32 - y0);
  s.positions = {X0, Y0, -64, X1, Y0, -64, X1, Y1, -64, X0, Y1, -64};
  s.indices = {0, 1, 2, 0, 2, 3};
  return s;
}

TEST(Samples, PatternsHaveOneSamplePerRowAndColumnInsideThePixel) {
  for (int n : {1, 2, 4, 8}) {
    auto s = sample_offsets(n);
    ASSERT_EQ(s.size(), size_t(n));
    std::set<double> xs, ys;
    for (auto [x, y] : s) {
      EXPECT_GT(x, -0.5);
      EXPECT_LT(x, 0.5);
      EXPECT_GT(y, -0.5);
      EXPECT_LT(y, 0.5);
      xs.insert(x);
      ys.insert(y);
    }
    EXPECT_EQ(xs.size(), size_t(n)) << n;
    EXPECT_EQ(ys.size(), size_t(n)) << n;
  }
  EXPECT_THROW(sample_offsets(3), std::invalid_argument);
  EXPECT_THROW(sample_offsets(0), std::invalid_argument);
}

// 9 and 16 are the ordered grids: one sample in each cell of an s x s
// sub-grid, at its centre, and the pixel centres of a camera refined s times.
TEST(Samples, GridPatternsAreTheCentresOfARefinedCamera) {
  for (int s : {3, 4}) {
    const auto g = sample_offsets(s * s);
    ASSERT_EQ(g, grid_offsets(s));
    EXPECT_EQ(sample_grid(s * s), s);
    std::set<std::pair<int, int>> cells;
    for (auto [x, y] : g) cells.insert({int(std::floor((x + 0.5) * s)), int(std::floor((y + 0.5) * s))});
    EXPECT_EQ(cells.size(), size_t(s * s));
    Camera c = unit_camera();
    c.shift_x = 0.3, c.shift_y = -0.2;  // a refined camera keeps the shift
    const Camera f = refined(c, s);
    for (int k = 0; k < s * s; ++k) {  // fine pixel (s x + a, s y + b) = pixel (x, y) at offset k = b s + a
      const int a = k % s, b = k / s, x = 5, y = 7;
      Camera shifted = c;
      shifted.shift_x += g[k][0], shifted.shift_y += g[k][1];
      const Eigen::Vector3d d1 = f.ray_direction(s * x + a + 0.5, s * y + b + 0.5);
      const Eigen::Vector3d d2 = shifted.ray_direction(x + 0.5, y + 0.5);
      EXPECT_LT((d1 - d2).norm(), 1e-12) << s << " " << k;
    }
  }
  EXPECT_EQ(sample_grid(8), 0);
  EXPECT_THROW(grid_offsets(5), std::invalid_argument);
  EXPECT_THROW(grid_offsets(0), std::invalid_argument);
}

TEST(Samples, ShiftMovesTheSamplingPointInsideThePixel) {
  Camera c = unit_camera();
  double px, py, depth;
  ASSERT_TRUE(c.project(Eigen::Vector3d(0.25, -0.125, -64), px, py, depth));
  EXPECT_NEAR(px, 32.25, 1e-9);
  EXPECT_NEAR(py, 32.125, 1e-9);
  c.shift_x = 0.25;
  c.shift_y = 0.125;
  // The shifted camera's pixel centre (32.5, 32.5) samples what was at (32.75, 32.625).
  ASSERT_TRUE(c.project(Eigen::Vector3d(0.75, -0.625, -64), px, py, depth));
  EXPECT_NEAR(px, 32.5, 1e-9);
  EXPECT_NEAR(py, 32.5, 1e-9);
  Eigen::Vector3d d = c.ray_direction(32.5, 32.5) * 64;
  EXPECT_NEAR(d.x(), 0.75, 1e-9);
  EXPECT_NEAR(d.y(), -0.625, 1e-9);
  // The projection matrix agrees with project(): the renderer sees the same shift.
  Eigen::Vector4d clip = c.projection() * c.view() * Eigen::Vector4d(0.75, -0.625, -64, 1);
  EXPECT_NEAR((clip.x() / clip.w() + 1) * 0.5 * c.width, 32.5, 1e-9);
  EXPECT_NEAR((1 - clip.y() / clip.w()) * 0.5 * c.height, 32.5, 1e-9);
}

// A triangle pair of 0.3 x 0.3 px that holds no pixel centre: one sample per
// pixel misses it (undisplayable), four samples find it, and the octree and
// the brute-force oracle agree on every shifted sample.
TEST(Samples, SubPixelSquareMissedByTheCentreIsFoundByFourSamples) {
  // Pixel (10, 20): centre (10.5, 20.5); the 4-sample offset (0.375, -0.125)
  // lands at (10.875, 20.375).
  Scene s = square_at(10.7, 11.0, 20.2, 20.5 - 1e-3);
  const Camera c = unit_camera();
  OctreeTracer octree(s);
  BruteForceTracer brute(s);
  TriangleCounts one = count_triangles(octree.trace(c).data(), nullptr, 64 * 64, 2);
  EXPECT_EQ(one.traced[0] + one.traced[1], 0u);
  EXPECT_EQ(label_triangles(one)[0], Label::Undisplayable);

  std::vector<uint8_t> mask(64 * 64, 0);
  mask[20 * 64 + 10] = 1;  // the pixel is imperceptible: its samples carry that
  TriangleCounts four;
  four.traced.assign(2, 0);
  four.imperceptible.assign(2, 0);
  for (auto o : sample_offsets(4)) {
    Camera sc = c;
    sc.shift_x = o[0];
    sc.shift_y = o[1];
    std::vector<uint32_t> a = octree.trace(sc), b = brute.trace(sc);
    EXPECT_EQ(a, b);
    add_counts(four, a.data(), mask.data(), a.size());
  }
  EXPECT_EQ(four.traced[0] + four.traced[1], 1u);  // exactly the one sample at (10.875, 20.375)
  EXPECT_EQ(four.imperceptible[0] + four.imperceptible[1], 1u);
  auto labels = label_triangles(four);
  EXPECT_TRUE(labels[0] == Label::Imperceptible || labels[1] == Label::Imperceptible);
}

// cropped(): a window of the image as a camera of its own samples exactly
// what the whole camera samples there, shifted or not, so a render or trace
// of the window is the whole image's over it (mask_per_sample renders only
// the window where the model lies).
TEST(Samples, CroppedCameraSamplesTheSamePointsAsTheWholeImage) {
  // A fan of thin triangles across the frame at several depths: many edges
  // pass close to pixel centres, so any error in the window's rays shows.
  Scene s;
  for (int i = 0; i < 40; ++i) {
    const float x = -30.0f + 1.53f * float(i), z = -40.0f - 0.7f * float(i);
    const uint32_t v = uint32_t(s.positions.size() / 3);
    s.positions.insert(s.positions.end(), {x, -25.0f, z, x + 0.61f, 27.0f, z, x + 1.9f, -20.0f, z});
    s.indices.insert(s.indices.end(), {v, v + 1, v + 2});
  }
  OctreeTracer octree(s);
  for (std::array<double, 2> shift : {std::array<double, 2>{0, 0}, std::array<double, 2>{0.375, -0.125}}) {
    Camera whole = unit_camera();
    whole.width = 80;  // not square: the window's pitch must follow the height's
    whole.shift_x = shift[0];
    whole.shift_y = shift[1];
    const std::vector<uint32_t> all = octree.trace(whole);
    const int x0 = 13, y0 = 6, w = 37, h = 29;
    const Camera win = cropped(whole, x0, y0, w, h);
    ASSERT_EQ(win.width, w);
    ASSERT_EQ(win.height, h);
    EXPECT_NEAR(win.pixel_footprint(64), whole.pixel_footprint(64), 1e-12);
    const std::vector<uint32_t> part = octree.trace(win);
    size_t differ = 0, hits = 0;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        differ += part[size_t(y) * w + x] != all[size_t(y + y0) * whole.width + x + x0];
        hits += part[size_t(y) * w + x] != 0;  // 0: a miss
      }
    EXPECT_EQ(differ, 0u) << shift[0];
    EXPECT_GT(hits, size_t(w * h / 4));
    // A world point lands on the window's pixel less the window's origin.
    double ax, ay, bx, by, depth;
    ASSERT_TRUE(whole.project(Eigen::Vector3d(3.3, -7.1, -50), ax, ay, depth));
    ASSERT_TRUE(win.project(Eigen::Vector3d(3.3, -7.1, -50), bx, by, depth));
    EXPECT_NEAR(bx, ax - x0, 1e-9);
    EXPECT_NEAR(by, ay - y0, 1e-9);
  }
}

TEST(Frustum, MarksTrianglesInsideAndLeavesThoseBesideOrBehind) {
  const Camera c = unit_camera();
  Scene s;
  // 0: in view; 1: far right of the frame; 2: behind the eye; 3: crosses the
  // left edge (a corner inside); 4: beyond zfar.
  s.positions = {0, 0, -10, 1, 0, -10, 0, 1, -10,     //
                 50, 0, -10, 51, 0, -10, 50, 1, -10,  //
                 0, 0, 10, 1, 0, 10, 0, 1, 10,        //
                 -6, 0, -10, -4, 0, -10, -6, 1, -10,  //
                 0, 0, -200, 1, 0, -200, 0, 1, -200};
  for (uint32_t i = 0; i < 15; ++i) s.indices.push_back(i);
  std::vector<uint8_t> in(5, 0);
  mark_in_frustum(s, c, in);
  EXPECT_EQ(in, (std::vector<uint8_t>{1, 0, 0, 1, 0}));
  std::vector<uint8_t> wrong(4, 0);
  EXPECT_THROW(mark_in_frustum(s, c, wrong), std::invalid_argument);
}

}  // namespace
}  // namespace perclod
