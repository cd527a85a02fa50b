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

// Hit with t in [tmin, tmax] (inclusive): returns true and sets t.
inline bool watertight_hit(const ShearedRay& r, const float A[3], const float B[3],
                           const float C[3], float tmin, float tmax, float& t) {
  const float ax = A[r.kx] - r.sx * A[r.kz], ay = A[r.ky] - r.sy * A[r.kz];
  const float bx = B[r.kx] - r.sx * B[r.kz], by = B[r.ky] - r.sy * B[r.kz];
  const float cx = C[r.kx] - r.sx * C[r.kz], cy = C[r.ky] - r.sy * C[r.kz];
  float u = cx * by - cy * bx;
  float v = ax * cy - ay * cx;
  float w = bx * ay - by * ax;
  if (u == 0.0f || v == 0.0f || w == 0.0f) {  // edge case: re-evaluate in double
    u = float(double(cx) * double(by) - double(cy) * double(bx));
    v = float(double(ax) * double(cy) - double(ay) * double(cx));
    w = float(double(bx) * double(ay) - double(by) * double(ax));
  }
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
