// Sampled Hausdorff distance between two scenes, for the benchmarks (header
// only). Points are every vertex plus `samples` points spread over the
// surface by area (fixed seed); each point's distance to the other surface is
// an exact closest-point query (Embree's rtcPointQuery over the other
// scene's triangles). The result is a lower bound of the true Hausdorff
// distance that tightens with `samples`.
#pragma once

#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>
#include <vector>

#include "perclod/scene.h"

namespace perclod::bench {

namespace hausdorff_detail {

struct V3 {
  double x, y, z;
};
inline V3 operator-(V3 a, V3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline V3 operator+(V3 a, V3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline V3 operator*(double s, V3 a) { return {s * a.x, s * a.y, s * a.z}; }
inline double dot(V3 a, V3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline V3 cross(V3 a, V3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }

inline V3 corner(const Scene& s, size_t t, int k) {
  const float* p = &s.positions[3 * size_t(s.indices[3 * t + k])];
  return {p[0], p[1], p[2]};
}

// Squared distance from p to triangle abc: the closest point lies in the
// face, on an edge or at a corner; try the face's plane first, then each
// edge segment (the corners are the segments' ends).
inline double dist2_point_triangle(V3 p, V3 a, V3 b, V3 c) {
  const V3 ab = b - a, ac = c - a, n = cross(ab, ac);
  const double nn = dot(n, n);
  if (nn > 0) {
    const V3 ap = p - a;
    // Barycentric coordinates of p's projection onto the plane.
    const double v = dot(cross(ap, ac), n) / nn, w = dot(cross(ab, ap), n) / nn;
    if (v >= 0 && w >= 0 && v + w <= 1) {
      const double h = dot(ap, n);
      return h * h / nn;
    }
  }
  auto seg = [&](V3 s0, V3 s1) {
    const V3 d = s1 - s0;
    const double dd = dot(d, d);
    const double t = dd > 0 ? std::clamp(dot(p - s0, d) / dd, 0.0, 1.0) : 0.0;
    const V3 q = s0 + t * d - p;
    return dot(q, q);
  };
  return std::min({seg(a, b), seg(b, c), seg(c, a)});
}

struct Query {
  const Scene* scene;
  V3 p;
  double best2;
};

inline bool closest(RTCPointQueryFunctionArguments* args) {
  auto* q = static_cast<Query*>(args->userPtr);
  const size_t t = args->primID;
  const double d2 = dist2_point_triangle(q->p, corner(*q->scene, t, 0), corner(*q->scene, t, 1),
                                         corner(*q->scene, t, 2));
  if (d2 < q->best2) {
    q->best2 = d2;
    args->query->radius = float(std::sqrt(d2));
    return true;
  }
  return false;
}

// Points on `s`: its vertices (those some triangle uses) and `samples` more
// by area.
inline std::vector<V3> surface_points(const Scene& s, size_t samples) {
  std::vector<V3> pts;
  std::vector<char> used(s.positions.size() / 3, 0);
  for (uint32_t i : s.indices) used[i] = 1;
  for (size_t v = 0; v < used.size(); ++v)
    if (used[v]) pts.push_back({s.positions[3 * v], s.positions[3 * v + 1], s.positions[3 * v + 2]});
  const size_t nt = s.triangle_count();
  std::vector<double> cdf(nt);
  double total = 0;
  for (size_t t = 0; t < nt; ++t) {
    const V3 n = cross(corner(s, t, 1) - corner(s, t, 0), corner(s, t, 2) - corner(s, t, 0));
    total += 0.5 * std::sqrt(dot(n, n));
    cdf[t] = total;
  }
  if (total <= 0) return pts;
  std::mt19937_64 rng(12345);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (size_t i = 0; i < samples; ++i) {
    const size_t t = size_t(std::lower_bound(cdf.begin(), cdf.end(), u(rng) * total) - cdf.begin());
    double r1 = u(rng), r2 = u(rng);
    if (r1 + r2 > 1) r1 = 1 - r1, r2 = 1 - r2;
    const V3 a = corner(s, std::min(t, nt - 1), 0), b = corner(s, std::min(t, nt - 1), 1),
             c = corner(s, std::min(t, nt - 1), 2);
    pts.push_back(a + r1 * (b - a) + r2 * (c - a));
  }
  return pts;
}

// `s`'s triangles as an Embree scene for closest-point queries.
inline RTCScene point_query_scene(RTCDevice device, const Scene& s) {
  RTCScene scene = rtcNewScene(device);
  RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
  float* vb = static_cast<float*>(
      rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), s.positions.size() / 3));
  std::copy(s.positions.begin(), s.positions.end(), vb);
  unsigned* ib = static_cast<unsigned*>(
      rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), s.triangle_count()));
  std::copy(s.indices.begin(), s.indices.end(), ib);
  rtcCommitGeometry(g);
  rtcAttachGeometry(scene, g);
  rtcReleaseGeometry(g);
  rtcCommitScene(scene);
  return scene;
}

// The largest distance from `points` to the surface of `to` (its query scene
// `scene`), each distance capped at `radius`.
inline double one_sided(const std::vector<V3>& points, RTCScene scene, const Scene& to, double radius) {
  if (to.triangle_count() == 0) return radius;
  double worst = 0;
  for (const V3& p : points) {
    RTCPointQuery pq;
    pq.x = float(p.x), pq.y = float(p.y), pq.z = float(p.z), pq.time = 0, pq.radius = float(radius);
    RTCPointQueryContext ctx;
    rtcInitPointQueryContext(&ctx);
    Query q{&to, p, radius * radius};
    rtcPointQuery(scene, &pq, &ctx, closest, &q);
    worst = std::max(worst, std::sqrt(q.best2));
  }
  return worst;
}

}  // namespace hausdorff_detail

// Sampled Hausdorff distances from one reference scene (an original) to the
// scenes it is compared with: the reference's query scene and surface points
// are built once, not once per comparison.
class HausdorffReference {
 public:
  explicit HausdorffReference(const Scene& a, size_t samples = 20000)
      : a_(a), samples_(samples), diag_(scene_bounds(a).diagonal()) {
    device_ = rtcNewDevice(nullptr);
    if (!device_) throw std::runtime_error("hausdorff: cannot create an Embree device");
    if (diag_ > 0) {
      scene_a_ = hausdorff_detail::point_query_scene(device_, a);
      points_a_ = hausdorff_detail::surface_points(a, samples);
    }
  }
  ~HausdorffReference() {
    if (scene_a_) rtcReleaseScene(scene_a_);
    rtcReleaseDevice(device_);
  }
  HausdorffReference(const HausdorffReference&) = delete;
  HausdorffReference& operator=(const HausdorffReference&) = delete;

  // Symmetric sampled Hausdorff distance between the reference and `b`,
  // divided by the diagonal of the reference's bounding box (an empty `b`
  // scores the whole diagonal, 1).
  double relative(const Scene& b) const {
    if (!(diag_ > 0)) return 0.0;
    if (b.triangle_count() == 0) return 1.0;
    RTCScene scene_b = hausdorff_detail::point_query_scene(device_, b);
    const double h = std::max(hausdorff_detail::one_sided(points_a_, scene_b, b, diag_),
                              hausdorff_detail::one_sided(hausdorff_detail::surface_points(b, samples_), scene_a_, a_,
                                                          diag_));
    rtcReleaseScene(scene_b);
    return std::min(1.0, h / diag_);
  }

 private:
  const Scene& a_;
  size_t samples_;
  double diag_;
  RTCDevice device_ = nullptr;
  RTCScene scene_a_ = nullptr;
  std::vector<hausdorff_detail::V3> points_a_;
};

}  // namespace perclod::bench
