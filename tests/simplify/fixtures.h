// Test meshes, a tiny OBJ reader, the synthetic label rule and geometric
// checks shared by the simplify tests (and by e2e/test_simplify_building.cpp,
// which includes this file by path).
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <functional>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "perclod/scene.h"

namespace perclod::test {

using Tri = std::array<std::array<float, 3>, 3>;

inline uint32_t add_vertex(Scene& s, double x, double y, double z) {
  s.positions.insert(s.positions.end(), {float(x), float(y), float(z)});
  return uint32_t(s.vertex_count() - 1);
}

inline void add_tri(Scene& s, uint32_t a, uint32_t b, uint32_t c, uint32_t comp, uint32_t mat = 0) {
  s.indices.insert(s.indices.end(), {a, b, c});
  s.component.push_back(comp);
  s.material.push_back(mat);
  while (s.component_names.size() <= comp) s.component_names.push_back(std::to_string(s.component_names.size()));
  while (s.materials.size() <= mat) s.materials.push_back(Material{std::to_string(s.materials.size())});
}

// n x n quads over [x0, x0+size] x [y0, y0+size], z = height(x, y), shared vertices.
inline void add_grid(Scene& s, int n, double size, uint32_t comp,
                     const std::function<double(double, double)>& height = nullptr,
                     double x0 = 0, double y0 = 0) {
  uint32_t base = uint32_t(s.vertex_count());
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      double x = x0 + size * i / n, y = y0 + size * j / n;
      add_vertex(s, x, y, height ? height(x, y) : 0.0);
    }
  auto id = [&](int i, int j) { return base + uint32_t(j * (n + 1) + i); };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      add_tri(s, id(i, j), id(i + 1, j), id(i + 1, j + 1), comp);
      add_tri(s, id(i, j), id(i + 1, j + 1), id(i, j + 1), comp);
    }
}

// Closed, outward-oriented axis-aligned box, each face an n x n grid.
inline void add_box(Scene& s, std::array<double, 3> lo, std::array<double, 3> hi, uint32_t comp, int n = 1) {
  // face: fixed axis a, side (0 lo, 1 hi); u, v the other axes in right-handed order
  for (int a = 0; a < 3; ++a)
    for (int side = 0; side < 2; ++side) {
      int u = (a + 1) % 3, v = (a + 2) % 3;
      uint32_t base = uint32_t(s.vertex_count());
      for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) {
          std::array<double, 3> p;
          p[a] = side ? hi[a] : lo[a];
          p[u] = lo[u] + (hi[u] - lo[u]) * i / n;
          p[v] = lo[v] + (hi[v] - lo[v]) * j / n;
          add_vertex(s, p[0], p[1], p[2]);
        }
      auto id = [&](int i, int j) { return base + uint32_t(j * (n + 1) + i); };
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
          if (side) {  // normal +a: u x v = +a
            add_tri(s, id(i, j), id(i + 1, j), id(i + 1, j + 1), comp);
            add_tri(s, id(i, j), id(i + 1, j + 1), id(i, j + 1), comp);
          } else {
            add_tri(s, id(i, j), id(i + 1, j + 1), id(i + 1, j), comp);
            add_tri(s, id(i, j), id(i, j + 1), id(i + 1, j + 1), comp);
          }
        }
    }
}

// UV sphere: 2 * segments * (rings - 1) triangles (the poles are fans).
inline void add_sphere(Scene& s, double r, int rings, int segments, uint32_t comp) {
  uint32_t top = add_vertex(s, 0, 0, r);
  uint32_t first = uint32_t(s.vertex_count());
  for (int i = 1; i < rings; ++i) {
    double th = M_PI * i / rings;
    for (int j = 0; j < segments; ++j) {
      double ph = 2 * M_PI * j / segments;
      add_vertex(s, r * std::sin(th) * std::cos(ph), r * std::sin(th) * std::sin(ph), r * std::cos(th));
    }
  }
  uint32_t bottom = add_vertex(s, 0, 0, -r);
  auto id = [&](int ring, int seg) { return first + uint32_t((ring - 1) * segments + (seg % segments)); };
  for (int j = 0; j < segments; ++j) add_tri(s, top, id(1, j), id(1, j + 1), comp);
  for (int i = 1; i < rings - 1; ++i)
    for (int j = 0; j < segments; ++j) {
      add_tri(s, id(i, j), id(i + 1, j), id(i + 1, j + 1), comp);
      add_tri(s, id(i, j), id(i + 1, j + 1), id(i, j + 1), comp);
    }
  for (int j = 0; j < segments; ++j) add_tri(s, bottom, id(rings - 1, j + 1), id(rings - 1, j), comp);
}

inline std::array<double, 3> normal_of(const Scene& s, size_t t, double* area = nullptr) {
  const float* p[3];
  for (int k = 0; k < 3; ++k) p[k] = &s.positions[3 * size_t(s.indices[3 * t + k])];
  double e1[3], e2[3];
  for (int a = 0; a < 3; ++a) {
    e1[a] = p[1][a] - p[0][a];
    e2[a] = p[2][a] - p[0][a];
  }
  std::array<double, 3> n = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                             e1[0] * e2[1] - e1[1] * e2[0]};
  double l = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  if (area) *area = 0.5 * l;
  if (l > 0)
    for (double& x : n) x /= l;
  return n;
}

// The fixed synthetic label rule (stands in for rendering + ray casting): a
// viewer looks along `view` (unit, towards the model).
//   normal . view >= 0 (facing away or edge-on) -> Undisplayable
//   facing the viewer and area >= min_area      -> Perceptible
//   facing the viewer and smaller               -> Imperceptible
inline std::vector<Label> synthetic_labels(const Scene& s, std::array<double, 3> view, double min_area) {
  std::vector<Label> l(s.triangle_count());
  for (size_t t = 0; t < l.size(); ++t) {
    double area;
    auto n = normal_of(s, t, &area);
    double d = n[0] * view[0] + n[1] * view[1] + n[2] * view[2];
    l[t] = d >= 0 ? Label::Undisplayable : area >= min_area ? Label::Perceptible : Label::Imperceptible;
  }
  return l;
}

inline Tri tri_of(const Scene& s, size_t t) {
  Tri r;
  for (int k = 0; k < 3; ++k)
    for (int a = 0; a < 3; ++a) r[k][a] = s.positions[3 * size_t(s.indices[3 * t + k]) + a];
  return r;
}

// Rotation to a canonical first corner (lexicographically smallest), keeping
// the cyclic order: equal after canonicalisation == equal up to rotation.
inline Tri canonical(Tri t) {
  int best = 0;
  for (int k = 1; k < 3; ++k)
    if (t[k] < t[best]) best = k;
  return {t[best], t[(best + 1) % 3], t[(best + 2) % 3]};
}

// The brute-force distance checks below are test code, O(points x
// triangles), and they are left out of the sanitized build's instrumentation:
// with it they ran some 40x slower than in Release (SimplifyFidelity.
// EachLabelKeepsItsOwnBound: 0.4 s Release, 17.8 s ASan), without checking
// any more of perclod's code. What they read is checked first instead, by
// the Scene contract's validate() (every index names a vertex), so the
// unsanitized loops stay in bounds. The simplifier that made the scenes runs
// instrumented as before.
#if defined(__clang__) || defined(__GNUC__)
#define PERCLOD_TEST_UNSANITIZED __attribute__((no_sanitize("address", "undefined")))
#else
#define PERCLOD_TEST_UNSANITIZED
#endif

namespace oracle {
struct P3 {
  double x, y, z;
};
PERCLOD_TEST_UNSANITIZED inline P3 sub(P3 a, P3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
PERCLOD_TEST_UNSANITIZED inline double dot(P3 a, P3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
PERCLOD_TEST_UNSANITIZED inline double dist2(P3 a, P3 b) { return dot(sub(a, b), sub(a, b)); }
PERCLOD_TEST_UNSANITIZED inline P3 at(const Scene& s, uint32_t i) {
  const float* v = s.positions.data() + 3 * size_t(i);
  return {v[0], v[1], v[2]};
}

// Squared distance from point p to triangle (a, b, c) (Ericson's closest point).
PERCLOD_TEST_UNSANITIZED inline double point_triangle_dist2(P3 p, P3 a, P3 b, P3 c) {
  const P3 ab = sub(b, a), ac = sub(c, a), ap = sub(p, a);
  const double d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return dist2(p, a);
  const P3 bp = sub(p, b);
  const double d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return dist2(p, b);
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) {
    const double v = d1 / (d1 - d3);
    return dist2(p, {a.x + v * ab.x, a.y + v * ab.y, a.z + v * ab.z});
  }
  const P3 cp = sub(p, c);
  const double d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return dist2(p, c);
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) {
    const double w = d2 / (d2 - d6);
    return dist2(p, {a.x + w * ac.x, a.y + w * ac.y, a.z + w * ac.z});
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return dist2(p, {b.x + w * (c.x - b.x), b.y + w * (c.y - b.y), b.z + w * (c.z - b.z)});
  }
  const double denom = 1.0 / (va + vb + vc);
  const double v = vb * denom, w = vc * denom;
  return dist2(p, {a.x + ab.x * v + ac.x * w, a.y + ab.y * v + ac.y * w, a.z + ab.z * v + ac.z * w});
}

// Distance from p to the nearest triangle of s; s's indices are in range.
PERCLOD_TEST_UNSANITIZED inline double distance_to_surface(P3 p, const Scene& s) {
  double best = INFINITY;
  const uint32_t* idx = s.indices.data();
  for (size_t t = 0, n = s.indices.size() / 3; t < n; ++t) {
    const double d2 = point_triangle_dist2(p, at(s, idx[3 * t]), at(s, idx[3 * t + 1]), at(s, idx[3 * t + 2]));
    if (d2 < best) best = d2;
  }
  return std::sqrt(best);
}

// The largest distance from a barycentric sample of a triangle of `from` to `to`.
PERCLOD_TEST_UNSANITIZED inline double one_sided_hausdorff(const Scene& from, const Scene& to, int samples_per_edge) {
  double worst = 0;
  const uint32_t* idx = from.indices.data();
  for (size_t t = 0, n = from.indices.size() / 3; t < n; ++t) {
    const P3 a = at(from, idx[3 * t]), b = at(from, idx[3 * t + 1]), c = at(from, idx[3 * t + 2]);
    for (int i = 0; i <= samples_per_edge; ++i)
      for (int j = 0; i + j <= samples_per_edge; ++j) {
        const double u = double(i) / samples_per_edge, v = double(j) / samples_per_edge, w = 1 - u - v;
        const P3 p = {u * a.x + v * b.x + w * c.x, u * a.y + v * b.y + w * c.y, u * a.z + v * b.z + w * c.z};
        const double d = distance_to_surface(p, to);
        if (d > worst) worst = d;
      }
  }
  return worst;
}
}  // namespace oracle

inline std::array<double, 3> vertex(const Scene& s, uint32_t i) {
  return {s.positions[3 * size_t(i)], s.positions[3 * size_t(i) + 1], s.positions[3 * size_t(i) + 2]};
}

// One side of the sampled Hausdorff distance: barycentric samples of each
// triangle of one mesh (corners included) against the other surface
// (validate() throws, failing the test, if either breaks the Scene contract).
inline double one_sided_hausdorff(const Scene& from, const Scene& to, int samples_per_edge = 4) {
  validate(from);
  validate(to);
  if (samples_per_edge < 1) return INFINITY;
  return oracle::one_sided_hausdorff(from, to, samples_per_edge);
}

// Every perceptible input triangle appears in the output exactly as it was
// (positions bit-identical, same cyclic order), and nothing else changed label.
inline void expect_perceptible_preserved(const Scene& in, const std::vector<Label>& labels, const Scene& out,
                                         const std::vector<uint32_t>& source) {
  ASSERT_EQ(source.size(), out.triangle_count());
  std::multiset<Tri> want, got;
  for (size_t t = 0; t < in.triangle_count(); ++t)
    if (labels[t] == Label::Perceptible) want.insert(canonical(tri_of(in, t)));
  for (size_t t = 0; t < out.triangle_count(); ++t) {
    if (labels[source[t]] != Label::Perceptible) continue;
    auto tri = canonical(tri_of(out, t));
    EXPECT_EQ(tri, canonical(tri_of(in, source[t]))) << "output triangle " << t;
    got.insert(tri);
  }
  EXPECT_EQ(want.size(), got.size());
  EXPECT_TRUE(want == got) << "perceptible triangles differ";
}

inline void expect_valid(const Scene& s) {
  for (float x : s.positions) ASSERT_TRUE(std::isfinite(x));
  for (uint32_t i : s.indices) ASSERT_LT(i, s.vertex_count());
  EXPECT_EQ(s.component.size(), s.triangle_count());
  EXPECT_EQ(s.material.size(), s.triangle_count());
}

}  // namespace perclod::test
