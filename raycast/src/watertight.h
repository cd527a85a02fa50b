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

}  // namespace perclod::detail
