// A Garland-Heckbert quadric: the sum of squared distances to a set of planes,
// stored as the 10 distinct entries of the symmetric 4x4 matrix.
#pragma once

#include <cmath>

namespace perclod::detail {

// Two doubles, or two 64-bit masks, in one SSE2 register (GCC and Clang
// vector extensions).
typedef double Double2 __attribute__((vector_size(16)));
typedef long long Mask2 __attribute__((vector_size(16)));

struct Quadric {
  double a2 = 0, ab = 0, ac = 0, ad = 0, b2 = 0, bc = 0, bd = 0, c2 = 0, cd = 0, d2 = 0;

  // Adds w * (n.p + d)^2 for a unit normal n = (a, b, c).
  void add_plane(double a, double b, double c, double d, double w) {
    a2 += w * a * a; ab += w * a * b; ac += w * a * c; ad += w * a * d;
    b2 += w * b * b; bc += w * b * c; bd += w * b * d;
    c2 += w * c * c; cd += w * c * d; d2 += w * d * d;
  }
  Quadric& operator+=(const Quadric& q) {
    a2 += q.a2; ab += q.ab; ac += q.ac; ad += q.ad; b2 += q.b2;
    bc += q.bc; bd += q.bd; c2 += q.c2; cd += q.cd; d2 += q.d2;
    return *this;
  }
  // The error at two points at once, lane s at (x[s], y[s], z[s]); clamped
  // at 0 against rounding. A candidate edge needs it at both ends, and the
  // two lanes share one SSE2 register: each lane does the same operations
  // in the same order as one scalar evaluation, so its bits are eval's.
  Double2 eval2(Double2 x, Double2 y, Double2 z) const {
    const Double2 e = a2 * x * x + 2 * ab * x * y + 2 * ac * x * z + 2 * ad * x +
                      b2 * y * y + 2 * bc * y * z + 2 * bd * y +
                      c2 * z * z + 2 * cd * z + d2;
    const Double2 zero = {0, 0};
    return Double2(Mask2(e) & Mask2(e > zero));  // e where e > 0 (not NaN), else +0
  }
  // The error at point (x, y, z): one lane of eval2.
  double eval(double x, double y, double z) const { return eval2(Double2{x, x}, Double2{y, y}, Double2{z, z})[0]; }
};

inline Quadric operator+(Quadric a, const Quadric& b) { return a += b; }

// sqrt(e2) <= t for e2 >= 0, taking the root only where the squares are too
// close to tell: t * t is within an ulp of t^2, so a margin of 1e-9 either
// side decides exactly as the root would (e2 below it has a root below t;
// above it, a root more than half an ulp above t). Outside the range where
// t * t is a normal number, and inside the margin, the root is taken.
inline bool root_within(double e2, double t) {
  const double t2 = t * t;
  if (t2 > 1e-300 && t2 < 1e300) {
    if (e2 <= t2 * (1 - 1e-9)) return true;
    if (e2 >= t2 * (1 + 1e-9)) return false;
  }
  return std::sqrt(e2) <= t;
}

}  // namespace perclod::detail
