// The four-lane exact test (watertight_hit4, shear_rays4) against the scalar
// one it must equal: the same permutation and shear constants, and for every
// lane it calls sure, the same decision and the same t, bit for bit. Rays are
// aimed at edges and vertices, where edge_function recomputes in double and
// a wrong bound would show.
#include <gtest/gtest.h>

#include <cstring>
#include <limits>
#include <random>

#include "float_bounds.h"
#include "watertight.h"

namespace perclod::detail {
namespace {

uint32_t bits(float v) {
  uint32_t b;
  std::memcpy(&b, &v, sizeof b);
  return b;
}

// The rounding helpers step by one float as nextafter does, without libm.
TEST(Watertight, FloatStepsEqualNextafter) {
  const float specials[] = {0.0f, -0.0f, 1.0f, -1.0f, std::numeric_limits<float>::denorm_min(),
                            -std::numeric_limits<float>::denorm_min(), std::numeric_limits<float>::min(),
                            std::numeric_limits<float>::max(), -std::numeric_limits<float>::max(), INFINITY,
                            -INFINITY, 3.5e-39f, -3.5e-39f, 123.456f, -0.001f};
  for (float f : specials) {
    EXPECT_EQ(bits(float_step_up(f)), bits(std::nextafter(f, INFINITY))) << f;
  }
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> mag(-40.0, 40.0);
  for (int i = 0; i < 100000; ++i) {
    const double v = (i % 2 ? -1.0 : 1.0) * std::pow(10.0, mag(rng));
    const float up = float_at_or_above(v), down = float_at_or_below(v);
    EXPECT_GE(double(up), v);
    EXPECT_LE(double(down), v);
    EXPECT_EQ(bits(up), bits(double(float(v)) < v ? std::nextafter(float(v), INFINITY) : float(v)));
    EXPECT_EQ(bits(down), bits(double(float(v)) > v ? std::nextafter(float(v), -INFINITY) : float(v)));
  }
}

TEST(Watertight, FourLanesEqualTheScalarTest) {
  std::mt19937 rng(20261203);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f), pos(0.0f, 1.0f);
  long lanes = 0, sure = 0, hits = 0, edge_rays = 0, off_edge = 0, off_edge_sure = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    // A triangle 5-200 units in front of the origin (the eye), 0.01-10 units wide.
    const float depth = 5.0f + 195.0f * pos(rng), size = 0.01f + 10.0f * pos(rng) * pos(rng);
    const float cx = 0.3f * depth * unit(rng), cy = 0.3f * depth * unit(rng);
    float V[3][3];
    for (auto& v : V) {
      v[0] = cx + size * unit(rng);
      v[1] = cy + size * unit(rng);
      v[2] = -depth + size * unit(rng);
    }
    // Four rays through points of the triangle's plane: on an edge, at a
    // vertex, inside or outside, each nudged or not.
    float d[3][4 + 3] = {};
    int kinds[4];
    for (int l = 0; l < 4; ++l) {
      const int kind = kinds[l] = int(pos(rng) * 4.0f);
      float a = pos(rng), b = pos(rng);
      if (kind == 0) b = 0.0f, ++edge_rays;                   // on edge AB
      if (kind == 1) a = 1.0f, b = 0.0f, ++edge_rays;         // at vertex B
      if (kind == 2 && a + b > 1.0f) a = 1.0f - a, b = 1.0f - b;  // inside
      if (kind == 3) a *= 2.0f, b *= 2.0f;                    // often outside
      // Relative nudge 0 or +-2^-24 .. 2^-8: from on the edge, through the
      // band where the float edge value is within its rounding error, to
      // clearly off it.
      for (int k = 0; k < 3; ++k) {
        const float p = V[0][k] + a * (V[1][k] - V[0][k]) + b * (V[2][k] - V[0][k]);
        const int e = int(pos(rng) * 18.0f);
        const float nudge = e == 0 ? 0.0f : std::ldexp(unit(rng) < 0 ? -1.0f : 1.0f, e - 25);
        d[k][l] = p * (1.0f + nudge);
      }
    }
    const float d0[3] = {d[0][0], d[1][0], d[2][0]};
    const ShearedRay r0 = shear_ray(d0);
    alignas(16) float sx[4 + 3], sy[4 + 3], sz[4 + 3], tmax[4 + 3];
    const int same = shear_rays4(d[0], d[1], d[2], r0.kx, r0.ky, r0.kz, sx, sy, sz);
    ASSERT_EQ(same & 1, 1);  // lane 0 picked the permutation it was given
    float sx_max = 0.0f, sy_max = 0.0f;
    int live = 0;
    for (int l = 0; l < 4; ++l) {
      const float dl[3] = {d[0][l], d[1][l], d[2][l]};
      const ShearedRay r = shear_ray(dl);
      const bool picked = r.kx == r0.kx && r.ky == r0.ky && r.kz == r0.kz;
      ASSERT_EQ(picked, bool(same >> l & 1)) << "trial " << trial << " lane " << l;
      if (!picked) continue;
      EXPECT_EQ(bits(sx[l]), bits(r.sx));
      EXPECT_EQ(bits(sy[l]), bits(r.sy));
      EXPECT_EQ(bits(sz[l]), bits(r.sz));
      sx_max = std::max(sx_max, std::fabs(r.sx));
      sy_max = std::max(sy_max, std::fabs(r.sy));
      tmax[l] = pos(rng) < 0.2f ? 0.5f : 2.0f;  // some windows end before the triangle
      live |= 1 << l;
    }
    const PermutedTriangle tri = permute_triangle(V[0], V[1], V[2], r0.kx, r0.ky, r0.kz, sx_max, sy_max);
    const Hits4 h = watertight_hit4(tri, sx, sy, sz, 1e-3f, tmax, live);
    EXPECT_EQ(h.hit & ~live, 0);
    EXPECT_EQ(h.hit & h.unsure, 0);
    for (int l = 0; l < 4; ++l) {
      if (!(live >> l & 1)) continue;
      ++lanes;
      off_edge += kinds[l] >= 2;
      if (h.unsure >> l & 1) continue;
      ++sure;
      off_edge_sure += kinds[l] >= 2;
      const ShearedRay r{r0.kx, r0.ky, r0.kz, sx[l], sy[l], sz[l]};
      float t = -1.0f;
      const bool hit = watertight_hit(r, V[0], V[1], V[2], 1e-3f, tmax[l], t);
      ASSERT_EQ(hit, bool(h.hit >> l & 1)) << "trial " << trial << " lane " << l;
      if (hit) {
        EXPECT_EQ(bits(h.t[l]), bits(t)) << "trial " << trial << " lane " << l;
        ++hits;
      }
    }
  }
  // The comparison is not vacuous: nearly every lane that does not aim at an
  // edge or a vertex is decided in four lanes, many lanes are hits, and many
  // rays aim exactly at edges and vertices (where the scalar test may
  // recompute in double, and unsure lanes are expected).
  EXPECT_GT(off_edge_sure, off_edge * 95 / 100);
  EXPECT_GT(hits, lanes / 5);
  EXPECT_GT(edge_rays, 20000);
  std::printf("lanes %ld (sure %ld, hits %ld); off edges %ld (sure %ld); rays at edges or vertices %ld\n", lanes,
              sure, hits, off_edge, off_edge_sure, edge_rays);
}

}  // namespace
}  // namespace perclod::detail
