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

// Squared distance from point p to triangle (a, b, c) (Ericson's closest point).
inline double point_triangle_dist2(const std::array<double, 3>& p, const std::array<double, 3>& a,
                                   const std::array<double, 3>& b, const std::array<double, 3>& c) {
  auto sub = [](auto x, auto y) { return std::array<double, 3>{x[0] - y[0], x[1] - y[1], x[2] - y[2]}; };
  auto dot = [](auto x, auto y) { return x[0] * y[0] + x[1] * y[1] + x[2] * y[2]; };
  auto at = [&](const std::array<double, 3>& q) { auto d = sub(p, q); return dot(d, d); };
  auto ab = sub(b, a), ac = sub(c, a), ap = sub(p, a);
  double d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return at(a);
  auto bp = sub(p, b);
  double d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return at(b);
  double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) {
    double v = d1 / (d1 - d3);
    return at({a[0] + v * ab[0], a[1] + v * ab[1], a[2] + v * ab[2]});
  }
  auto cp = sub(p, c);
  double d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return at(c);
  double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) {
    double w = d2 / (d2 - d6);
    return at({a[0] + w * ac[0], a[1] + w * ac[1], a[2] + w * ac[2]});
  }
  double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return at({b[0] + w * (c[0] - b[0]), b[1] + w * (c[1] - b[1]), b[2] + w * (c[2] - b[2])});
  }
  double denom = 1.0 / (va + vb + vc);
  double v = vb * denom, w = vc * denom;
  return at({a[0] + ab[0] * v + ac[0] * w, a[1] + ab[1] * v + ac[1] * w, a[2] + ab[2] * v + ac[2] * w});
}

inline std::array<double, 3> vertex(const Scene& s, uint32_t i) {
  return {s.positions[3 * size_t(i)], s.positions[3 * size_t(i) + 1], s.positions[3 * size_t(i) + 2]};
}

inline double distance_to_surface(const std::array<double, 3>& p, const Scene& s) {
  double best = INFINITY;
  for (size_t t = 0; t < s.triangle_count(); ++t)
    best = std::min(best, point_triangle_dist2(p, vertex(s, s.indices[3 * t]), vertex(s, s.indices[3 * t + 1]),
                                               vertex(s, s.indices[3 * t + 2])));
  return std::sqrt(best);
}

// Symmetric sampled Hausdorff distance: barycentric samples of each
// triangle of one mesh (corners included) against the other surface.
inline double one_sided_hausdorff(const Scene& from, const Scene& to, int samples_per_edge = 4) {
  double worst = 0;
  for (size_t t = 0; t < from.triangle_count(); ++t) {
    auto a = vertex(from, from.indices[3 * t]), b = vertex(from, from.indices[3 * t + 1]),
         c = vertex(from, from.indices[3 * t + 2]);
    for (int i = 0; i <= samples_per_edge; ++i)
      for (int j = 0; i + j <= samples_per_edge; ++j) {
        double u = double(i) / samples_per_edge, v = double(j) / samples_per_edge, w = 1 - u - v;
        std::array<double, 3> p = {u * a[0] + v * b[0] + w * c[0], u * a[1] + v * b[1] + w * c[1],
                                   u * a[2] + v * b[2] + w * c[2]};
        worst = std::max(worst, distance_to_surface(p, to));
      }
  }
  return worst;
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
