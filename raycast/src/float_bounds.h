// float_bounds.h - float rounding bounds of the ray casting: pbrt's gamma(n)
// and the slacks that keep the octree's culling conservative, one name and
// one derivation each (private).
//
// The octree (octree.cpp) drops boxes, triangles and pixels before the exact
// float test (watertight.h) runs. A drop is only allowed where that test
// could not have accepted the ray, so each culling comparison is widened by a
// bound on the rounding of the quantities it compares. Those widenings live
// here.
//
// Rounding model, as in pbrt (Pharr, Jakob, Humphreys, "Physically Based
// Rendering", 3rd ed., sec. 3.9): a float operation returns the exact result
// times (1 + d), |d| <= u = 2^-24 (round to nearest), and n such factors in a
// row stay within 1 +- gamma(n), gamma(n) = n u / (1 - n u). For double,
// u = 2^-53. The budgets below are first order in u.
//
// The constants keep the values the tracer was validated with: its output
// equals the brute-force oracle's bit for bit on every test scene and real
// model. Each is checked by a static_assert against its derived bound, and
// the comment says how much headroom that leaves. Raising a constant only
// costs speed; lowering one towards its bound risks a wrong pixel wherever a
// budget's assumptions do not hold (see kHitDepthSlack).
//
// Notation: mag is the largest |coordinate| of the geometry (a triangle's
// vertices, a box's corners) relative to the float eye; fwd is the camera's
// forward axis and d a pixel's float ray direction, fwd . d = 1, so t is the
// eye depth and |d| <= sqrt(3) for fields of view up to 90 degrees.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

namespace perclod::detail {

// pbrt's gamma(n) for float and for double.
constexpr double float_gamma(int n) {
  constexpr double u = 0x1p-24;
  return n * u / (1 - n * u);
}
constexpr double double_gamma(int n) {
  constexpr double u = 0x1p-53;
  return n * u / (1 - n * u);
}

constexpr double kSqrt3 = 1.7320508075688772;

// ---- depth: where a float hit can lie ----------------------------------

// A float hit t of a triangle lies within kHitDepthSlack * mag of the eye
// depths of its vertices, [zmin, zmax] (for a box: of its corners).
// Budget for a well-shaped triangle no larger than mag:
//   * t is interpolated from the sheared vertex depths A[kz] / d[kz], each
//     with |.| <= sqrt(3) mag (d[kz] is d's largest component, so
//     |d[kz]| >= |d| / sqrt(3) >= 1 / sqrt(3)): gamma(2) for sz = 1 / d[kz]
//     and the product, gamma(6) for (u az + v bz + w cz) / (u + v + w);
//     together sqrt(3) gamma(8) mag, about 14 u mag;
//   * the interpolated point sits off the ray by the shear rounding
//     (2 sqrt(2) gamma(2) mag, about 6 u mag) and by the edge products'
//     rounding (about 7 gamma(2) times the triangle's size when the ray meets
//     it near a vertex, at most 14 u mag), and a sideways offset changes the
//     depth by at most its length;
//   * a box's corners are exact floats, but the vertices inside it reach the
//     test as fl(v - eye): sqrt(3) u mag more.
// About 35 u mag in all; kHitDepthSlack = 4e-6 is 67 u, twice that. For long
// slivers and for triangles much larger than their distance from the eye the
// barycentric rounding grows with the aspect ratio and no mag-relative bound
// holds; there the brute-force agreement tests, not this budget, carry the
// claim.
constexpr double kHitDepthSlack = 4e-6;
static_assert(kHitDepthSlack >=
              kSqrt3 * float_gamma(8) + 2 * 1.4142135623730951 * float_gamma(2) + 7 * float_gamma(2) +
                  kSqrt3 * float_gamma(1));
inline double hit_depth_slack(double mag) { return kHitDepthSlack * mag; }

// A box (or triangle) is projected to the image only when its nearest depth
// exceeds kProjectableDepthRel * mag; nearer ones are culled by the tile's
// frustum planes instead. This is a conditioning choice, not a rounding
// bound: it has to exceed kHitDepthSlack, so that every float hit inside the
// box is in front of the eye and the projection's 1 / depth is finite and
// positive, and at 25 times that the depth part of pixel_margin() stays
// below fmax / 25 pixels.
constexpr double kProjectableDepthRel = 1e-4;
static_assert(kProjectableDepthRel > kHitDepthSlack);
inline bool projectable(double nearest_depth, double mag) { return nearest_depth > kProjectableDepthRel * mag; }

// ---- projection to pixels -----------------------------------------------

// How far, in pixels, a pixel centre may lie outside the double projection
// of a triangle (or box) whose float test accepts that pixel's ray.
//   * The float test's edge signs are exact for its float sheared vertices
//     (watertight.h, kEdgeRecomputeRel), so what
//     moves the accepted region is the shear rounding, 2 sqrt(2) gamma(2) mag
//     sideways (see kHitDepthSlack). Seen from depth >= zmin that is a
//     direction error of that over zmin, and a direction error e shifts the
//     image point by at most |d| e fmax pixels (fmax = max(fx, fy)): with
//     |d| <= sqrt(3), about 10 u mag fmax / zmin pixels. The margin reuses
//     the depth slack, 67 u, which leaves 6x.
//   * kProjectionFloorPx covers what does not scale with mag / zmin: the
//     float rounding of the pixel's direction (one rounding per component,
//     at most |d|^2 u fmax <= 3 u fmax pixels, 1e-3 pixels up to fmax = 5600)
//     and the double rounding of the projection itself (about 1e-12 pixels
//     for images below 10^4 pixels).
constexpr double kProjectionFloorPx = 1e-3;
inline double pixel_margin(double mag, double inv_zmin, double fmax) {
  return kProjectionFloorPx + hit_depth_slack(mag) * inv_zmin * fmax;
}

// The projected triangle's edge functions are used as a per-row filter only
// when twice its projected area exceeds kSliverAreaRel times the square of
// its longest edge (L1 length). Correctness needs only the orientation sign,
// whose double rounding is below double_gamma(3) of that square; the value is
// a choice: thinner slivers are tested over their whole rectangle, which is
// always correct.
constexpr double kSliverAreaRel = 1e-6;
static_assert(kSliverAreaRel > 1e6 * double_gamma(3));

// The ends xl, xr of a row's span of pixel centres come from the edge
// functions in double: r = eb Y + ec, then -r / ea (four roundings,
// double_gamma(4) of the operands). The operands can exceed |xl| + |xr| when
// r cancels, so the span is widened by 1e-9 (about 2^-30) of |xl| + |xr| + 1
// pixels: room for 2 * 10^6 of cancellation, and at least 1e-9 pixels.
constexpr double kSpanHairRel = 1e-9;
static_assert(kSpanHairRel > 1e6 * double_gamma(4));
inline double span_hair(double xl, double xr) { return kSpanHairRel * (std::fabs(xl) + std::fabs(xr) + 1.0); }

// ---- the tile's t window and the near plane -------------------------------

// A tile stops visiting boxes whose nearest depth (already lowered by
// hit_depth_slack) is beyond the farthest t any of its pixels accepts, and
// boxes or triangles that lie wholly before the near plane. Comparing a float
// t in double is exact, so neither test needs more than the depth slack; both
// carry a fixed guard instead, independent of mag: kCullGuardRel = 1e-5 (ten
// tie windows, about 168 u) and kCullGuardAbs = 1e-7 (about one float ulp at
// t = 1; for a window or near plane close to t = 0, where a relative guard
// vanishes). kCullGuardRel has the value of perclod::kAgreementTieTolerance
// but is not a tie tolerance: it widens the tile's t window, which already
// contains every pixel's tie window, and changes no pixel's answer.
//   Note: the near-plane test uses only this guard, not the depth slack, so
// by the budget above it is conservative only where kHitDepthSlack * mag is
// below the guard. A triangle whose vertices all lie within
// kHitDepthSlack * mag in front of the near plane could in principle have a
// float hit at t >= znear that the octree drops; the brute-force tests include
// a near-plane scene and agree. Left as it is: changing it changes behaviour.
constexpr double kCullGuardRel = 1e-5;
constexpr double kCullGuardAbs = 1e-7;
inline double widen_far(double t) { return t * (1.0 + kCullGuardRel) + kCullGuardAbs; }
inline bool before_near_plane(double farthest_depth, double znear) {
  return farthest_depth < znear * (1.0 - kCullGuardRel) - kCullGuardAbs;
}

// The float one step above f (nextafter(f, +inf) for f not NaN, +inf
// staying +inf), without a libm call: these run per triangle and tile.
inline float float_step_up(float f) {
  uint32_t b;
  std::memcpy(&b, &f, sizeof b);
  if (b == 0x80000000u) b = 1u;           // -0: the smallest positive denormal
  else if (b == 0x7f800000u) return f;     // +inf
  else if ((b >> 31) == 0) ++b;            // positive: away from zero
  else --b;                                // negative: toward zero
  std::memcpy(&f, &b, sizeof b);
  return f;
}

// The largest float at or below v: a double depth bound compared with float
// t windows without rounding it upwards.
inline float float_at_or_below(double v) {
  const float f = float(v);
  return double(f) > v ? -float_step_up(-f) : f;
}

// The smallest float at or above v.
inline float float_at_or_above(double v) {
  const float f = float(v);
  return double(f) < v ? float_step_up(f) : f;
}

}  // namespace perclod::detail
