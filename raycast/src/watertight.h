// watertight.h - the watertight ray/triangle test of Woop, Benthin and Wald
// (JCGT 2(1), 2013), float, no back-face culling (private).
//
// The ray is prepared once (ShearedRay: the axis permutation that makes the
// largest direction component z, and the shear constants); the triangle is
// given by its vertices relative to the ray origin (A, B, C). A pixel centre
// that falls exactly on an edge shared by two triangles is inside both (the
// edge functions are evaluated identically for both and zero counts as
// inside), never in neither: no holes. Compile without FP contraction.
#pragma once

#include <emmintrin.h>  // SSE2: part of every x86-64 target

#include <cmath>
#include <cstdint>
#include <limits>

#include "float_bounds.h"

namespace perclod::detail {

struct ShearedRay {
  uint8_t kx, ky, kz;
  float sx, sy, sz;
};

inline ShearedRay shear_ray(const float d[3]) {
  const float ax = std::fabs(d[0]), ay = std::fabs(d[1]), az = std::fabs(d[2]);
  int kz = 2;
  if (ax > ay && ax > az) kz = 0;
  else if (ay > az) kz = 1;
  int kx = kz + 1 == 3 ? 0 : kz + 1;
  int ky = kx + 1 == 3 ? 0 : kx + 1;
  if (d[kz] < 0.0f) std::swap(kx, ky);  // keep the winding of the projected triangle
  ShearedRay r;
  r.kx = uint8_t(kx);
  r.ky = uint8_t(ky);
  r.kz = uint8_t(kz);
  r.sz = 1.0f / d[kz];  // one division; every tracer shares this setup
  r.sx = d[kx] * r.sz;
  r.sy = d[ky] * r.sz;
  return r;
}

// When an edge value is below kEdgeRecomputeRel times its magnitude sum M
// (edge_function's `mag`), edge_function() recomputes it in double.
// Derivation (rounding model of float_bounds.h): each sheared coordinate,
// px = P[kx] - sx P[kz], is off by gamma(2) of |P[kx]| + |sx P[kz]|, which the
// products carry into e = qx py - qy px as at most gamma(2) M; the two
// products and the difference add gamma(2) of |qx py| + |qy px| <= M. So the
// float value errs by at most 2 gamma(2) M, about 4 u M, and one above
// 32 u M (16 float epsilons) has the right sign with 8x headroom for the
// second-order terms and for M itself being summed in float.
constexpr float kEdgeRecomputeRel = 16 * std::numeric_limits<float>::epsilon();
static_assert(kEdgeRecomputeRel >= 2 * float_gamma(2));

// One edge function, P x Q in the sheared 2D frame. When the float value is
// within its rounding error (shear and product), it is re-evaluated from the
// vertices in double: the sign of a small value is then right (grazing rays
// at thin, nearly edge-on triangles), and the decision depends only on this
// edge's two vertices, so a neighbour sharing the edge decides identically.
inline float edge_function(const ShearedRay& r, const float P[3], const float Q[3], float px, float py,
                           float qx, float qy) {
  const float e = qx * py - qy * px;
  // Magnitude sum M: the shear (|P| scale) times the other point's sheared size, both ways.
  const float mag = (std::fabs(P[r.kx]) + std::fabs(r.sx * P[r.kz]) + std::fabs(P[r.ky]) +
                     std::fabs(r.sy * P[r.kz])) * (std::fabs(qx) + std::fabs(qy)) +
                    (std::fabs(Q[r.kx]) + std::fabs(r.sx * Q[r.kz]) + std::fabs(Q[r.ky]) +
                     std::fabs(r.sy * Q[r.kz])) * (std::fabs(px) + std::fabs(py));
  if (std::fabs(e) > kEdgeRecomputeRel * mag) return e;
  const double dpx = double(P[r.kx]) - double(r.sx) * double(P[r.kz]);
  const double dpy = double(P[r.ky]) - double(r.sy) * double(P[r.kz]);
  const double dqx = double(Q[r.kx]) - double(r.sx) * double(Q[r.kz]);
  const double dqy = double(Q[r.ky]) - double(r.sy) * double(Q[r.kz]);
  return float(dqx * dpy - dqy * dpx);
}

// Hit with t in [tmin, tmax] (inclusive): returns true and sets t.
inline bool watertight_hit(const ShearedRay& r, const float A[3], const float B[3],
                           const float C[3], float tmin, float tmax, float& t) {
  const float ax = A[r.kx] - r.sx * A[r.kz], ay = A[r.ky] - r.sy * A[r.kz];
  const float bx = B[r.kx] - r.sx * B[r.kz], by = B[r.ky] - r.sy * B[r.kz];
  const float cx = C[r.kx] - r.sx * C[r.kz], cy = C[r.ky] - r.sy * C[r.kz];
  const float u = edge_function(r, B, C, bx, by, cx, cy);  // cx * by - cy * bx
  const float v = edge_function(r, C, A, cx, cy, ax, ay);  // ax * cy - ay * cx
  const float w = edge_function(r, A, B, ax, ay, bx, by);  // bx * ay - by * ax
  if ((u < 0.0f || v < 0.0f || w < 0.0f) && (u > 0.0f || v > 0.0f || w > 0.0f)) return false;
  const float det = u + v + w;
  if (det == 0.0f) return false;
  const float az = r.sz * A[r.kz], bz = r.sz * B[r.kz], cz = r.sz * C[r.kz];
  const float tt = (u * az + v * bz + w * cz) / det;
  if (!(tt >= tmin && tt <= tmax)) return false;
  t = tt;
  return true;
}

// ---- four rays at once

// Four rays' shear constants (sx, sy, sz, each written as four floats) for
// the axis permutation (kx, ky, kz), with the same operations as shear_ray.
// Returns the lanes (a bit mask) for which shear_ray picks that permutation;
// the other lanes' constants are not theirs.
inline int shear_rays4(const float* dx, const float* dy, const float* dz, int kx, int ky, int kz, float* sx,
                       float* sy, float* sz) {
  const __m128 d[3] = {_mm_loadu_ps(dx), _mm_loadu_ps(dy), _mm_loadu_ps(dz)};
  const __m128 abs_mask = _mm_castsi128_ps(_mm_set1_epi32(0x7fffffff));
  const __m128 ax = _mm_and_ps(d[0], abs_mask), ay = _mm_and_ps(d[1], abs_mask), az = _mm_and_ps(d[2], abs_mask);
  // shear_ray's choice of kz: 0 if ax > ay && ax > az, else 1 if ay > az, else 2.
  const __m128 z0 = _mm_and_ps(_mm_cmpgt_ps(ax, ay), _mm_cmpgt_ps(ax, az));
  const __m128 y_over_z = _mm_cmpgt_ps(ay, az);
  const int picked = _mm_movemask_ps(z0);
  const int picked1 = _mm_movemask_ps(_mm_andnot_ps(z0, y_over_z));
  const int is_kz = kz == 0 ? picked : kz == 1 ? picked1 : ~(picked | picked1) & 15;
  // ... and it swaps kx and ky when d[kz] < 0.
  const int negative = _mm_movemask_ps(_mm_cmplt_ps(d[kz], _mm_setzero_ps()));
  const bool swapped = kx != (kz == 2 ? 0 : kz + 1);
  const __m128 SZ = _mm_div_ps(_mm_set1_ps(1.0f), d[kz]);
  _mm_storeu_ps(sz, SZ);
  _mm_storeu_ps(sx, _mm_mul_ps(d[kx], SZ));
  _mm_storeu_ps(sy, _mm_mul_ps(d[ky], SZ));
  return is_kz & (swapped ? negative : ~negative & 15);
}

// Four rays that share one axis permutation (kx, ky, kz), against one
// triangle, with SSE: the same float operations in the same order as
// watertight_hit, so a lane's decision and t are bit-identical to it. Only
// edge_function's magnitude check is done differently: a lane whose edge
// value is above a bound of edge_function's threshold would have kept the
// float value there too; a lane where it is not is "unsure" and must be
// decided by watertight_hit (and its double recomputation).
//
// The bound: edge_function's threshold is kEdgeRecomputeRel (SP (|qx| +
// |qy|) + SQ (|px| + |py|)) in float, SP the float sum |P[kx]| +
// |sx P[kz]| + |P[ky]| + |sy P[kz]|. For every ray with |sx| <= sx_max and
// |sy| <= sy_max, SP <= MP (1 + u)^4 with MP = |P[kx]| + |P[ky]| + (sx_max +
// sy_max) |P[kz]| (one rounding per sum and product). The four-lane test
// evaluates the same expression, in the same order, with SP and SQ replaced
// by m = MP (1 + 2^-16) rounded up to a float (PermutedTriangle::m), which
// is at least SP; |qx| + |qy| and |px| + |py| are the lane's own, computed
// as edge_function computes them. Float rounding is monotone (flushing
// denormals to zero too), so each operation's result is at or above its
// counterpart in edge_function, and so is the bound.
struct PermutedTriangle {
  float a[3], b[3], c[3];  // vertex k in the permuted frame: {P[kx], P[ky], P[kz]}
  float m[3];              // m of A, B and C (see above)
};

inline PermutedTriangle permute_triangle(const float A[3], const float B[3], const float C[3], int kx, int ky,
                                         int kz, float sx_max, float sy_max) {
  PermutedTriangle p;
  const float* src[3] = {A, B, C};
  float* dst[3] = {p.a, p.b, p.c};
  for (int i = 0; i < 3; ++i) {
    dst[i][0] = src[i][kx];
    dst[i][1] = src[i][ky];
    dst[i][2] = src[i][kz];
    const double m = std::fabs(double(dst[i][0])) + std::fabs(double(dst[i][1])) +
                     (double(sx_max) + double(sy_max)) * std::fabs(double(dst[i][2]));
    p.m[i] = float_at_or_above(m * (1.0 + 0x1p-16));
  }
  return p;
}

struct Hits4 {
  int hit;     // lanes with a hit in [tmin, tmax[lane]]
  int unsure;  // lanes watertight_hit must decide
  alignas(16) float t[4];
};

// The lanes of `live` (a bit mask) of the rays (sx, sy, sz) and windows
// tmax, each array read as four floats from its pointer (they must extend
// three past the last live lane).
inline Hits4 watertight_hit4(const PermutedTriangle& tri, const float* sx, const float* sy, const float* sz,
                             float tmin, const float* tmax, int live) {
  const __m128 SX = _mm_loadu_ps(sx), SY = _mm_loadu_ps(sy), SZ = _mm_loadu_ps(sz);
  const __m128 TMAX = _mm_loadu_ps(tmax);
  auto shear = [&](const float P[3], __m128& x, __m128& y) {
    const __m128 pz = _mm_set1_ps(P[2]);
    x = _mm_sub_ps(_mm_set1_ps(P[0]), _mm_mul_ps(SX, pz));
    y = _mm_sub_ps(_mm_set1_ps(P[1]), _mm_mul_ps(SY, pz));
  };
  __m128 ax, ay, bx, by, cx, cy;
  shear(tri.a, ax, ay);
  shear(tri.b, bx, by);
  shear(tri.c, cx, cy);
  const __m128 u = _mm_sub_ps(_mm_mul_ps(cx, by), _mm_mul_ps(cy, bx));
  const __m128 v = _mm_sub_ps(_mm_mul_ps(ax, cy), _mm_mul_ps(ay, cx));
  const __m128 w = _mm_sub_ps(_mm_mul_ps(bx, ay), _mm_mul_ps(by, ax));
  const __m128 abs_mask = _mm_castsi128_ps(_mm_set1_epi32(0x7fffffff));
  auto abs = [&](__m128 x) { return _mm_and_ps(x, abs_mask); };
  const __m128 sa = _mm_add_ps(abs(ax), abs(ay)), sb = _mm_add_ps(abs(bx), abs(by)),
               sc = _mm_add_ps(abs(cx), abs(cy));
  const __m128 ma = _mm_set1_ps(tri.m[0]), mb = _mm_set1_ps(tri.m[1]), mc = _mm_set1_ps(tri.m[2]);
  const __m128 rel = _mm_set1_ps(kEdgeRecomputeRel);
  // Edge (P, Q): above kEdgeRecomputeRel (MP SQq + MQ SPp).
  auto above = [&](__m128 e, __m128 mp, __m128 sq, __m128 mq, __m128 sp) {
    return _mm_cmpgt_ps(abs(e), _mm_mul_ps(rel, _mm_add_ps(_mm_mul_ps(mp, sq), _mm_mul_ps(mq, sp))));
  };
  const __m128 sure =
      _mm_and_ps(_mm_and_ps(above(u, mb, sc, mc, sb), above(v, mc, sa, ma, sc)), above(w, ma, sb, mb, sa));
  const __m128 zero = _mm_setzero_ps();
  const __m128 neg = _mm_or_ps(_mm_or_ps(_mm_cmplt_ps(u, zero), _mm_cmplt_ps(v, zero)), _mm_cmplt_ps(w, zero));
  const __m128 pos = _mm_or_ps(_mm_or_ps(_mm_cmpgt_ps(u, zero), _mm_cmpgt_ps(v, zero)), _mm_cmpgt_ps(w, zero));
  const __m128 det = _mm_add_ps(_mm_add_ps(u, v), w);
  const __m128 az = _mm_mul_ps(SZ, _mm_set1_ps(tri.a[2]));
  const __m128 bz = _mm_mul_ps(SZ, _mm_set1_ps(tri.b[2]));
  const __m128 cz = _mm_mul_ps(SZ, _mm_set1_ps(tri.c[2]));
  const __m128 tt =
      _mm_div_ps(_mm_add_ps(_mm_add_ps(_mm_mul_ps(u, az), _mm_mul_ps(v, bz)), _mm_mul_ps(w, cz)), det);
  // det != 0 is true for NaN, as watertight_hit's det == 0 is false for it.
  const __m128 in_range = _mm_and_ps(_mm_cmpge_ps(tt, _mm_set1_ps(tmin)), _mm_cmple_ps(tt, TMAX));
  const __m128 hit = _mm_andnot_ps(_mm_and_ps(neg, pos), _mm_and_ps(_mm_cmpneq_ps(det, zero), in_range));
  Hits4 h;
  h.hit = _mm_movemask_ps(_mm_and_ps(sure, hit)) & live;
  h.unsure = ~_mm_movemask_ps(sure) & live;
  _mm_store_ps(h.t, tt);
  return h;
}

}  // namespace perclod::detail
