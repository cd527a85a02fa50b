// Small scene builders and oracles shared by the raycast tests (and by
// e2e/test_raycast_building.cpp, which includes this file by path).
#pragma once

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <array>
#include <memory>
#include <string>
#include <vector>

#include "perclod/camera.h"
#include "perclod/raycast.h"
#include "perclod/scene.h"

namespace perclod::test {

using V3 = Eigen::Vector3d;

inline uint32_t add_vertex(Scene& s, const V3& p) {
  s.positions.push_back(float(p.x()));
  s.positions.push_back(float(p.y()));
  s.positions.push_back(float(p.z()));
  return uint32_t(s.vertex_count() - 1);
}

inline void ensure_component(Scene& s, uint32_t component) {
  while (s.component_names.size() <= component) {
    std::string name = std::to_string(s.component_names.size());
    name.insert(name.begin(), 'c');
    s.component_names.push_back(std::move(name));
  }
  if (s.materials.empty()) s.materials.push_back({});
}

inline void add_triangle(Scene& s, uint32_t a, uint32_t b, uint32_t c, uint32_t component) {
  ensure_component(s, component);
  s.indices.insert(s.indices.end(), {a, b, c});
  s.component.push_back(component);
  s.material.push_back(0);
}

// Quad p0 p1 p2 p3 (in order around it) as triangles (p0 p1 p2), (p0 p2 p3)
// sharing the diagonal p0-p2.
inline void add_quad(Scene& s, const V3& p0, const V3& p1, const V3& p2, const V3& p3, uint32_t component) {
  const uint32_t a = add_vertex(s, p0), b = add_vertex(s, p1), c = add_vertex(s, p2), d = add_vertex(s, p3);
  add_triangle(s, a, b, c, component);
  add_triangle(s, a, c, d, component);
}

// Axis-aligned closed box, 12 triangles, outward facing.
inline void add_box(Scene& s, const V3& lo, const V3& hi, uint32_t component) {
  V3 c[8];
  for (int i = 0; i < 8; ++i)
    c[i] = V3((i & 1) ? hi.x() : lo.x(), (i & 2) ? hi.y() : lo.y(), (i & 4) ? hi.z() : lo.z());
  const int faces[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& f : faces) add_quad(s, c[f[0]], c[f[1]], c[f[2]], c[f[3]], component);
}

// Camera at the origin looking down -z.
inline Camera front_camera(int w, int h, double fov_y = 0.8, double znear = 0.1, double zfar = 1000.0) {
  return look_at(V3(0, 0, 0), V3(0, 0, -1), V3(0, 1, 0), fov_y, w, h, znear, zfar);
}

// World point on the ray through image point (px, py) at eye depth d.
inline V3 at_pixel(const Camera& c, double px, double py, double d) {
  return c.eye + d * c.ray_direction(px, py);
}

// The three tracers every scene is run through.
struct Traced {
  std::vector<uint32_t> octree, embree, brute;
};

inline Traced trace_all(const Scene& s, const Camera& c, bool with_brute = true) {
  Traced r;
  r.octree = OctreeTracer(s).trace(c);
  r.embree = EmbreeTracer(s, EmbreeMode::Verify).trace(c);
  if (with_brute) r.brute = BruteForceTracer(s).trace(c);
  return r;
}

// Tracer::trace_samples into one buffer per sample, each filled with `fill`
// first (so a test can tell that every pixel was written).
inline std::vector<std::vector<uint32_t>> trace_samples(const Tracer& tracer, const Camera& c,
                                                        const std::vector<std::array<double, 2>>& offsets,
                                                        uint32_t fill = 0) {
  std::vector<std::vector<uint32_t>> out(offsets.size(), std::vector<uint32_t>(size_t(c.width) * size_t(c.height), fill));
  std::vector<uint32_t*> buffers;
  for (auto& b : out) buffers.push_back(b.data());
  tracer.trace_samples(c, offsets, buffers.data());
  return out;
}

inline size_t count_nonzero(const std::vector<uint32_t>& v) {
  size_t n = 0;
  for (uint32_t x : v) n += x != 0;
  return n;
}

// Z-up facade view: eye `distance` in front of the bounding box's -y face.
inline Camera facade_view(const Scene& s, double distance, double sideways, int w, int h) {
  const Bounds b = scene_bounds(s);
  const auto c = b.center();
  const double diag = b.diagonal();
  const V3 eye(c[0] + sideways, b.lo[1] - distance, c[2]);
  return look_at(eye, V3(c[0], c[1], c[2]), V3(0, 0, 1), 0.585, w, h, 0.05, distance + 2 * diag);
}

// Octree against Embree on one view: identical on >= 99.99% of covered
// pixels, no real disagreement.
inline void expect_agreement(const Scene& s, const Camera& cam, const OctreeTracer& oct, const EmbreeTracer& emb) {
  const auto a = oct.trace(cam);
  const auto e = emb.trace(cam);
  const Agreement g = compare_traced(s, cam, a.data(), e.data());
  EXPECT_GT(g.covered, g.pixels / 50);
  EXPECT_EQ(g.real_disagreements, 0u);
  EXPECT_GE(g.identical_rate(), 0.9999) << "identical " << g.identical << " of " << g.covered << ", ties "
                                        << g.ties << ", edge grazes " << g.edge_grazes;
  ::testing::Test::RecordProperty("identical_rate", std::to_string(g.identical_rate()));
}

}  // namespace perclod::test
