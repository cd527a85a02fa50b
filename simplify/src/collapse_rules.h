// The shape and area rules of a collapse v0 -> v1 (v1 stays where it is),
// whatever holds the mesh: the half-edge loop (collapse.cpp) and the
// triangle-list pass past its topology (free_collapse.cpp) check every face
// of v0 and the area budgets with these, so both passes refuse alike.
#pragma once

#include <algorithm>
#include <cmath>

#include <OpenMesh/Core/Geometry/VectorT.hh>

namespace perclod::detail {

using Vec = OpenMesh::Vec3d;

struct Limits {
  double cos_normal;  // a surviving face may turn at most this far (cosine)
  double min_quality; // and not become a sliver (unless it was one)
  int max_valence;    // the half-edge loop's fan cap
  double tie;         // edge-length tie-break factor
};

// 4 sqrt(3) area / sum of squared edge lengths: 1 equilateral, 0 degenerate.
inline double quality(const Vec& a, const Vec& b, const Vec& c) {
  double l = (b - a).sqrnorm() + (c - b).sqrnorm() + (a - c).sqrnorm();
  if (l <= 0) return 0;
  return 2.0 * std::sqrt(3.0) * ((b - a) % (c - a)).norm() / l;
}

// Face (v0, a, b) of v0 as v0 moves from p0 onto p1 (`removed`: the face
// holds v1 and goes). Adds the change of twice its area to `twice_change`;
// false when a surviving face would turn too far or become a sliver.
inline bool face_follows(const Vec& p0, const Vec& p1, const Vec& pa, const Vec& pb, bool removed, const Limits& lim,
                         double& twice_change) {
  Vec n_old = (pa - p0) % (pb - p0);
  if (removed) {
    twice_change -= n_old.norm();
    return true;
  }
  Vec n_new = (pa - p1) % (pb - p1);
  double lo = n_old.norm(), ln = n_new.norm();
  twice_change += ln - lo;
  if (lo > 0) {
    if (ln <= 0 || (n_old | n_new) < lim.cos_normal * lo * ln) return false;
  }
  double q_new = quality(p1, pa, pb);
  return !(q_new < lim.min_quality && q_new < quality(p0, pa, pb));
}

// Fidelity's area rule: the area changed by this collapse, added to what
// both ends already changed (`used0`, `used1`), must stay within both ends'
// budgets. A distance bound alone lets a long part thinner than the bound (a
// mullion, a column seen edge-on) collapse to nothing, one sub-pixel move at
// a time.
inline bool within_area_budget(double used0, double used1, double area_change, double budget0, double budget1) {
  return used0 + used1 + std::fabs(area_change) <= std::min(budget0, budget1);
}

}  // namespace perclod::detail
