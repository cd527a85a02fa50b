// tie_window.h - the t window of the tie rule, one definition for every
// exact tracer (private).
//
// The rule (perclod/raycast.h): among the hits whose t lies within
// t_min * (1 + kTieEpsilon) of the nearest, the lowest triangle index wins.
// The window's far end is computed in double and rounded to float once, and
// clamped to zfar, so the octree, the brute-force oracle and Embree's verify
// mode close it at the same float for the same t.
#pragma once

#include <algorithm>

#include "perclod/raycast.h"

namespace perclod::detail {

// Largest t still inside the window opened by the nearest hit t.
inline float tie_window_end(float t, float zfar) { return std::min(zfar, float(double(t) * (1.0 + kTieEpsilon))); }

// Where Embree's second (tie) query starts. Its first query already returned
// the nearest hit t, so the rule itself needs no lower end (the octree and the
// oracle have none); the query starts kTieEpsilon below t anyway, as a guard,
// so that the nearest hit itself is inside the query's [tnear, tfar]. The
// same constant on purpose: the window is symmetric, not a second tolerance.
inline float tie_window_start(float t, float znear) {
  return std::max(znear, float(double(t) * (1.0 - kTieEpsilon)));
}

}  // namespace perclod::detail
