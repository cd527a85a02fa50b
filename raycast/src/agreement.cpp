// agreement.cpp - pixel-by-pixel comparison of triangle buffers, with every
// mismatch re-tested in double precision.
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "geometry_checks.h"
#include "perclod/raycast.h"

namespace perclod {

namespace {

// The double re-test widens a triangle's edges by the float test's sideways
// rounding, expressed in barycentric units: kGrazeLateralRel times the
// vertices' largest |coordinate| from the eye (reach), over the triangle's
// size. The float test's edge signs are exact for its float vertices
// (watertight.h); what moves them is the shear rounding, about 6 u = 3.4e-7
// of reach (float_bounds.h), so 1e-6 leaves 3x. Deliberately tighter than
// the octree's kHitDepthSlack (67 u): the culling slack must never drop a
// hit, while this one must not excuse a real disagreement as a graze.
constexpr double kGrazeLateralRel = 1e-6;
// A triangle tiny against its distance would get a huge barycentric
// widening; it is capped at 1% of the triangle, so a mismatch on it is not
// excused wholesale. kMinSize only keeps a zero-area triangle finite.
constexpr double kGrazeBarycentricCap = 1e-2;
constexpr double kMinSize = 1e-30;

}  // namespace

DoubleHit intersect_pixel_double(const Scene& scene, const Camera& cam, int x, int y, uint32_t tri,
                                 double& t) {
  if (size_t(tri) >= scene.triangle_count())
    throw std::invalid_argument("intersect_pixel_double: triangle " + std::to_string(tri) +
                                " out of range");
  const Eigen::Vector3d d = cam.ray_direction(x + 0.5, y + 0.5);
  Eigen::Vector3d v[3];
  for (int c = 0; c < 3; ++c) {
    const size_t i = scene.indices[3 * size_t(tri) + c];
    v[c] = Eigen::Vector3d(scene.positions[3 * i], scene.positions[3 * i + 1], scene.positions[3 * i + 2]);
  }
  // Moller-Trumbore in double, no culling. The edges are widened by the
  // rounding of a float test (kGrazeLateralRel of the vertex distance from
  // the eye, relative to the triangle's size): a pixel centre that float
  // tracers may put on either side of an edge counts as a hit, on the edge.
  const Eigen::Vector3d e1 = v[1] - v[0], e2 = v[2] - v[0];
  const Eigen::Vector3d p = d.cross(e2);
  const double det = e1.dot(p);
  if (det == 0.0) return DoubleHit::Miss;
  const Eigen::Vector3d s = cam.eye - v[0];
  const double size = std::sqrt(e1.cross(e2).norm());
  const double reach = std::max({(v[0] - cam.eye).cwiseAbs().maxCoeff(), (v[1] - cam.eye).cwiseAbs().maxCoeff(),
                                 (v[2] - cam.eye).cwiseAbs().maxCoeff()});
  const double slack = std::min(kGrazeBarycentricCap, kGrazeLateralRel * reach / std::max(size, kMinSize));
  const double u = s.dot(p) / det;
  if (u < -slack || u > 1.0 + slack) return DoubleHit::Miss;
  const Eigen::Vector3d q = s.cross(e1);
  const double w = d.dot(q) / det;
  if (w < -slack || u + w > 1.0 + slack) return DoubleHit::Miss;
  t = e2.dot(q) / det;
  if (!(t >= cam.znear && t <= cam.zfar)) return DoubleHit::Miss;
  // Inside only when no float rounding can put the ray outside: a pixel
  // centre within the slack of an edge, on either side, is an edge graze (a
  // float ray, its direction rounded, may cross a shared edge the double ray
  // does not).
  return (u >= slack && w >= slack && u + w <= 1.0 - slack) ? DoubleHit::Inside : DoubleHit::Edge;
}

namespace {

Agreement compare(const Scene& scene, const Camera& cam, const uint32_t* a, const uint32_t* b,
                  double tol) {
  detail::check_camera(cam);
  if (!a || !b) throw std::invalid_argument("compare: a triangle buffer is null");
  if (!(tol >= 0)) throw std::invalid_argument("compare: tie tolerance must be >= 0");
  const size_t nt = scene.triangle_count();
  Agreement g;
  g.pixels = uint64_t(cam.width) * uint64_t(cam.height);
  const double inf = std::numeric_limits<double>::infinity();
  for (int y = 0; y < cam.height; ++y)
    for (int x = 0; x < cam.width; ++x) {
      const size_t o = size_t(y) * size_t(cam.width) + size_t(x);
      const uint32_t ia = a[o], ib = b[o];
      if (ia > nt || ib > nt)
        throw std::invalid_argument("compare: pixel (" + std::to_string(x) + ", " + std::to_string(y) +
                                    ") names a triangle beyond the scene's " + std::to_string(nt));
      if (ia == 0 && ib == 0) continue;
      ++g.covered;
      if (ia == ib) {
        ++g.identical;
        continue;
      }
      double ta = inf, tb = inf;
      const DoubleHit ha = ia ? intersect_pixel_double(scene, cam, x, y, ia - 1, ta) : DoubleHit::Miss;
      const DoubleHit hb = ib ? intersect_pixel_double(scene, cam, x, y, ib - 1, tb) : DoubleHit::Miss;
      if (ha == DoubleHit::Miss) ta = inf;
      if (hb == DoubleHit::Miss) tb = inf;
      const DoubleHit nearer = ta <= tb ? ha : hb;
      if (ha != DoubleHit::Miss && hb != DoubleHit::Miss && std::fabs(ta - tb) <= tol * std::min(ta, tb))
        ++g.ties;
      else if (nearer == DoubleHit::Edge)
        ++g.edge_grazes;
      else
        ++g.real_disagreements;
    }
  return g;
}

}  // namespace

Agreement compare_traced(const Scene& scene, const Camera& camera, const uint32_t* a, const uint32_t* b,
                         double tie_tolerance) {
  return compare(scene, camera, a, b, tie_tolerance);
}

Agreement compare_with_id_buffer(const Scene& scene, const Camera& camera, const uint32_t* rays,
                                 const uint32_t* id_buffer, double tie_tolerance) {
  return compare(scene, camera, rays, id_buffer, tie_tolerance);
}

}  // namespace perclod
