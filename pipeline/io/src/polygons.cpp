// Polygons into triangles: ear clipping in the plane of the polygon's Newell
// normal (near-linear for large polygons), holes bridged into their outer
// ring, and a fan where clipping cannot finish (counted, never dropped).
#include "readers.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>

namespace perclod::detail {
namespace fs = std::filesystem;
namespace {

// Polygons with more corners than this are clipped by triangulate_large:
// ear clipping below restarts its scan after every ear and tests every
// corner, O(n^2) or worse (one 100k-corner polygon took 35 s).
constexpr size_t kLargePolygon = 1000;

// Ear clipping in near-linear time for large polygons: a linked ring that
// walks on after each ear (never rescanning from the start), and an ear test
// against the reflex corners only (a convex corner cannot lie inside an ear),
// found through a uniform grid. Same ear rule as triangulate(); gives up to a
// fan the same way when no ear is left, or when a work budget linear in the
// corner count is spent (hostile shapes: the rest is a fan, possibly overlapping).
template <class FX, class FY, class FC>
bool triangulate_large(const std::vector<uint32_t>& poly, const FX& X, const FY& Y, const FC& cross,
                       std::vector<uint32_t>& out) {
  const size_t n = poly.size();
  std::vector<uint32_t> prev(n), next(n);
  std::vector<char> alive(n, 1), reflex(n, 0);
  double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
  for (size_t i = 0; i < n; ++i) {
    prev[i] = uint32_t((i + n - 1) % n), next[i] = uint32_t((i + 1) % n);
    lo[0] = std::min(lo[0], X(poly[i])), hi[0] = std::max(hi[0], X(poly[i]));
    lo[1] = std::min(lo[1], Y(poly[i])), hi[1] = std::max(hi[1], Y(poly[i]));
  }
  auto corner_cross = [&](uint32_t i) { return cross(poly[prev[i]], poly[i], poly[next[i]]); };
  const int side = std::max(1, int(std::sqrt(double(n))));
  const double cw = std::max(hi[0] - lo[0], 1e-300) / side, ch = std::max(hi[1] - lo[1], 1e-300) / side;
  auto cell = [&](double v, double l, double c) { return std::clamp(int((v - l) / c), 0, side - 1); };
  std::vector<std::vector<uint32_t>> grid(size_t(side) * side);
  size_t reflex_left = 0;
  for (uint32_t i = 0; i < n; ++i)
    if (corner_cross(i) <= 0) {
      reflex[i] = 1, ++reflex_left;
      grid[size_t(cell(Y(poly[i]), lo[1], ch)) * side + cell(X(poly[i]), lo[0], cw)].push_back(i);
    }
  // Work budget (ear tests, grid cells and corners visited): shapes such as
  // spirals have only a few ears at a time and would still clip in O(n^2).
  // Once spent, the rest becomes a fan, as when no ear is left.
  long long budget = 200LL * (long long)n;
  auto is_ear = [&](uint32_t b) {
    const uint32_t ia = prev[b], ic = next[b];
    const uint32_t a = poly[ia], v = poly[b], c = poly[ic];
    --budget;
    if (cross(a, v, c) <= 0) return false;  // reflex or flat corner
    if (reflex_left == 0) return true;
    const int x0 = cell(std::min({X(a), X(v), X(c)}), lo[0], cw), x1 = cell(std::max({X(a), X(v), X(c)}), lo[0], cw);
    const int y0 = cell(std::min({Y(a), Y(v), Y(c)}), lo[1], ch), y1 = cell(std::max({Y(a), Y(v), Y(c)}), lo[1], ch);
    budget -= (long long)(y1 - y0 + 1) * (x1 - x0 + 1);
    if (budget < 0) return false;
    for (int gy = y0; gy <= y1; ++gy)
      for (int gx = x0; gx <= x1; ++gx)
        for (uint32_t j : grid[size_t(gy) * side + gx]) {
          --budget;
          if (!alive[j] || !reflex[j]) continue;
          const uint32_t q = poly[j];
          if (q == a || q == v || q == c) continue;
          if (cross(a, v, q) >= 0 && cross(v, c, q) >= 0 && cross(c, a, q) >= 0) return false;
        }
    return true;
  };
  size_t left = n;
  uint32_t cur = 0, stop = 0;
  bool first = true;
  while (left > 3 && budget > 0) {
    if (!first && cur == stop) break;  // a whole turn without an ear
    first = false;
    if (!is_ear(cur)) {
      cur = next[cur];
      continue;
    }
    const uint32_t a = prev[cur], c = next[cur];
    out.insert(out.end(), {poly[a], poly[cur], poly[c]});
    alive[cur] = 0;
    if (reflex[cur]) reflex[cur] = 0, --reflex_left;
    next[a] = c, prev[c] = a;
    --left;
    for (uint32_t k : {a, c})
      if (reflex[k] && corner_cross(k) > 0) reflex[k] = 0, --reflex_left;  // a reflex corner turned convex
    cur = next[c];  // walk on: strips, not a fan of ever longer triangles
    stop = cur, first = true;
  }
  // Whatever is left: a fan, as in triangulate().
  std::vector<uint32_t> ring;
  for (uint32_t i = cur, k = 0; k < left; ++k, i = next[i]) ring.push_back(poly[i]);
  for (size_t i = 1; i + 1 < ring.size(); ++i) out.insert(out.end(), {ring[0], ring[i], ring[i + 1]});
  return ring.size() > 3;
}

// Newell normal of a ring (indices into pos): its direction is the ring's
// facing (counter-clockwise seen from the tip), its length twice the area.
std::array<double, 3> newell(const std::vector<double>& pos, const std::vector<uint32_t>& ring) {
  auto P = [&](uint32_t i, int a) { return pos[3 * size_t(i) + a]; };
  std::array<double, 3> nrm{0, 0, 0};
  for (size_t i = 0, n = ring.size(); i < n; ++i) {
    uint32_t a = ring[i], b = ring[(i + 1) % n];
    nrm[0] += (P(a, 1) - P(b, 1)) * (P(a, 2) + P(b, 2));
    nrm[1] += (P(a, 2) - P(b, 2)) * (P(a, 0) + P(b, 0));
    nrm[2] += (P(a, 0) - P(b, 0)) * (P(a, 1) + P(b, 1));
  }
  return nrm;
}

// The 2D frame polygons are clipped in: the axis plane most perpendicular to
// a normal, mirrored (s) so a ring counter-clockwise about the normal stays
// counter-clockwise.
struct Plane2 {
  int ax = 0, ay = 1;
  double s = 1;
};
Plane2 plane_of(const std::array<double, 3>& nrm) {
  const double nx = nrm[0], ny = nrm[1], nz = nrm[2];
  Plane2 p;
  double sign = nz;
  if (std::fabs(nx) >= std::fabs(ny) && std::fabs(nx) >= std::fabs(nz)) p.ax = 1, p.ay = 2, sign = nx;
  else if (std::fabs(ny) >= std::fabs(nz)) p.ax = 2, p.ay = 0, sign = ny;
  p.s = sign >= 0 ? 1.0 : -1.0;
  return p;
}



// Joins `hole` into `ring` (both indices into pos, in the 2D frame X/Y where
// ring is counter-clockwise and hole clockwise) by a bridge edge, so the
// result is one ring ear clipping can take: ..., P, M, hole..., M, P, ...
// M is the hole's rightmost corner; P a ring corner M sees, found by casting
// a ray from M towards +x: the nearer end of the first edge it meets, unless
// a reflex corner inside the triangle (M, hit, that end) hides it, then the
// hiding corner closest in angle to the ray. Returns false when the ray meets
// no edge (a hole outside its outer ring): the hole is then left out.
template <class FX, class FY>
bool bridge_hole(std::vector<uint32_t>& ring, const std::vector<uint32_t>& hole, const FX& X, const FY& Y) {
  const size_t h = hole.size(), n = ring.size();
  size_t mi = 0;
  for (size_t i = 1; i < h; ++i)
    if (X(hole[i]) > X(hole[mi]) || (X(hole[i]) == X(hole[mi]) && Y(hole[i]) < Y(hole[mi]))) mi = i;
  const double mx = X(hole[mi]), my = Y(hole[mi]);
  double hit = INFINITY;
  size_t edge = SIZE_MAX;
  for (size_t k = 0; k < n; ++k) {
    const uint32_t a = ring[k], b = ring[(k + 1) % n];
    const double ay = Y(a), by = Y(b);
    if ((ay < my && by < my) || (ay > my && by > my)) continue;
    double x;
    if (ay == by) {  // along the ray: its nearer end ahead of M
      const double lo = std::min(X(a), X(b)), hi = std::max(X(a), X(b));
      x = lo >= mx ? lo : hi;
    } else {
      x = X(a) + (my - ay) * (X(b) - X(a)) / (by - ay);
    }
    if (x >= mx && x < hit) hit = x, edge = k;
  }
  if (edge == SIZE_MAX) return false;
  const size_t ka = edge, kb = (edge + 1) % n;
  size_t pk;
  if (X(ring[ka]) == hit && Y(ring[ka]) == my) pk = ka;
  else if (X(ring[kb]) == hit && Y(ring[kb]) == my) pk = kb;
  else pk = X(ring[ka]) > X(ring[kb]) ? ka : kb;
  auto cross2 = [](double ax, double ay, double bx, double by, double cx, double cy) {
    return (bx - ax) * (cy - ay) - (by - ay) * (cx - ax);
  };
  if (!(X(ring[pk]) == hit && Y(ring[pk]) == my)) {
    const double px = X(ring[pk]), py = Y(ring[pk]);
    double best_tan = INFINITY, best_d = INFINITY;
    size_t best = SIZE_MAX;
    for (size_t j = 0; j < n; ++j) {
      const uint32_t r = ring[j];
      if (r == ring[pk]) continue;
      const uint32_t a = ring[(j + n - 1) % n], c = ring[(j + 1) % n];
      if (cross2(X(a), Y(a), X(r), Y(r), X(c), Y(c)) > 0) continue;  // convex corners hide nothing
      const double rx = X(r), ry = Y(r);
      const double d1 = cross2(mx, my, hit, my, rx, ry), d2 = cross2(hit, my, px, py, rx, ry),
                   d3 = cross2(px, py, mx, my, rx, ry);
      const bool neg = d1 < 0 || d2 < 0 || d3 < 0, pos = d1 > 0 || d2 > 0 || d3 > 0;
      if (neg && pos) continue;  // outside the triangle
      const double t = rx > mx ? std::fabs(ry - my) / (rx - mx) : INFINITY;
      const double d = (rx - mx) * (rx - mx) + (ry - my) * (ry - my);
      if (best == SIZE_MAX || t < best_tan || (t == best_tan && d < best_d)) best = j, best_tan = t, best_d = d;
    }
    if (best != SIZE_MAX) pk = best;
  }
  // P may be in the ring more than once (an earlier bridge ends there): take
  // the occurrence whose inside wedge holds the direction to M.
  const uint32_t p = ring[pk];
  auto in_wedge = [&](size_t at) {  // M seen from P at ring[at] is inside the polygon's corner there
    const uint32_t pa = ring[(at + n - 1) % n], pc = ring[(at + 1) % n];
    const double ux = X(pc) - X(p), uy = Y(pc) - Y(p), vx = X(pa) - X(p), vy = Y(pa) - Y(p);
    const double dx = mx - X(p), dy = my - Y(p);
    const double ud = ux * dy - uy * dx, dv = dx * vy - dy * vx;
    return cross2(X(pa), Y(pa), X(p), Y(p), X(pc), Y(pc)) > 0 ? ud > 0 && dv > 0 : ud > 0 || dv > 0;
  };
  for (size_t k = 0; k < n; ++k) {
    if (ring[k] != p || k == pk) continue;
    if (!in_wedge(pk) && in_wedge(k)) {
      pk = k;
      break;
    }
  }
  std::vector<uint32_t> joined;
  joined.reserve(n + h + 2);
  joined.insert(joined.end(), ring.begin(), ring.begin() + long(pk) + 1);
  for (size_t t = 0; t <= h; ++t) joined.push_back(hole[(mi + t) % h]);
  joined.push_back(p);
  joined.insert(joined.end(), ring.begin() + long(pk) + 1, ring.end());
  ring.swap(joined);
  return true;
}

}  // namespace

bool triangulate(const std::vector<double>& pos, const std::vector<uint32_t>& poly,
                 std::vector<uint32_t>& out, const std::array<double, 3>* normal) {
  size_t n = poly.size();
  if (n == 3) {
    out.insert(out.end(), poly.begin(), poly.end());
    return false;
  }
  auto P = [&](uint32_t i, int a) { return pos[3 * size_t(i) + a]; };
  // Project onto the plane most perpendicular to the normal, keeping orientation.
  const Plane2 pl = plane_of(normal ? *normal : newell(pos, poly));
  const int ax = pl.ax, ay = pl.ay;
  const double s = pl.s;
  auto X = [&](uint32_t i) { return P(i, ax); };
  auto Y = [&](uint32_t i) { return P(i, ay) * s; };
  auto cross = [&](uint32_t a, uint32_t b, uint32_t c) {
    return (X(b) - X(a)) * (Y(c) - Y(a)) - (Y(b) - Y(a)) * (X(c) - X(a));
  };
  if (n > kLargePolygon) return triangulate_large(poly, X, Y, cross, out);
  std::vector<uint32_t> ring(poly);
  size_t guard = 0;
  while (ring.size() > 3 && guard < 4 * n * n) {
    bool clipped = false;
    size_t m = ring.size();
    for (size_t i = 0; i < m; ++i, ++guard) {
      uint32_t a = ring[(i + m - 1) % m], b = ring[i], c = ring[(i + 1) % m];
      if (cross(a, b, c) <= 0) continue;  // reflex or flat corner
      bool inside = false;
      for (size_t j = 0; j < m && !inside; ++j) {
        uint32_t q = ring[j];
        if (q == a || q == b || q == c) continue;
        inside = cross(a, b, q) >= 0 && cross(b, c, q) >= 0 && cross(c, a, q) >= 0;
      }
      if (inside) continue;
      out.insert(out.end(), {a, b, c});
      ring.erase(ring.begin() + long(i));
      clipped = true;
      break;
    }
    if (!clipped) break;
  }
  // Whatever is left (3 corners, or a polygon ear clipping could not handle): a fan.
  for (size_t i = 1; i + 1 < ring.size(); ++i) out.insert(out.end(), {ring[0], ring[i], ring[i + 1]});
  return ring.size() > 3;
}


void triangulate_with_holes(const std::vector<double>& pos, std::vector<std::vector<uint32_t>> rings,
                            std::vector<uint32_t>& out, LoadReport& rep) {
  const std::array<double, 3> nrm = newell(pos, rings[0]);
  const Plane2 pl = plane_of(nrm);
  auto X = [&](uint32_t i) { return pos[3 * size_t(i) + pl.ax]; };
  auto Y = [&](uint32_t i) { return pos[3 * size_t(i) + pl.ay] * pl.s; };
  // Twice the signed area, relative to the ring's first corner (UTM-sized
  // coordinates would otherwise cancel digits).
  auto area2 = [&](const std::vector<uint32_t>& r) {
    double a = 0;
    const double ox = X(r[0]), oy = Y(r[0]);
    for (size_t i = 0; i < r.size(); ++i) {
      const uint32_t p = r[i], q = r[(i + 1) % r.size()];
      a += (X(p) - ox) * (Y(q) - oy) - (Y(p) - oy) * (X(q) - ox);
    }
    return a;
  };
  const double outer = area2(rings[0]);
  double expected = outer;
  std::vector<std::pair<double, size_t>> order;  // holes by rightmost x, right first
  for (size_t k = 1; k < rings.size(); ++k) {
    double a = area2(rings[k]);
    if (a > 0) std::reverse(rings[k].begin(), rings[k].end()), a = -a;
    expected += a;
    double right = -INFINITY;
    for (uint32_t i : rings[k]) right = std::max(right, X(i));
    order.push_back({right, k});
  }
  std::sort(order.begin(), order.end(), [](auto& a, auto& b) { return a.first > b.first; });
  std::vector<uint32_t> ring = rings[0];
  bool bridged = outer > 0;  // a ring that does not face its own normal cannot hold holes
  for (auto& [right, k] : order) bridged &= bridge_hole(ring, rings[k], X, Y);
  const size_t before = out.size();
  rep.polygons_fanned += triangulate(pos, ring, out, &nrm);
  double got = 0;
  for (size_t t = before; t < out.size(); t += 3) got += std::fabs(area2({out[t], out[t + 1], out[t + 2]}));
  if (!bridged || !(std::fabs(got - expected) <= 1e-6 * std::fabs(outer))) ++rep.polygons_holes_failed;
}

}  // namespace perclod::detail
