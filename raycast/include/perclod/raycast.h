// perclod/raycast.h - pixels back to triangles, per-triangle counts, labels.
//
// One ray per pixel centre (x + 0.5, y + 0.5) from the camera's eye along
// camera.ray_direction(), accepted for t in [znear, zfar] (t = eye depth).
// A Tracer writes, per pixel (row 0 at the top), the index + 1 of the triangle
// the ray hits first, 0 for a miss: the same encoding as the renderer's ID
// buffer, so both can be compared pixel by pixel.
//
// Tie rule, shared by every exact tracer: among the hits whose t lies within
// t_min * (1 + kTieEpsilon), kTieEpsilon = 1e-6, of the nearest one, the
// lowest triangle index wins. No
// back-face culling. Threads come from oneTBB (the caller may limit them with
// tbb::global_control).
//
// Two tracers:
//  * OctreeTracer - the paper's structure: an octree over component bounding
//    boxes (components are not split), and inside each component a small BVH
//    over its triangles; watertight ray/triangle test (Woop, Benthin, Wald).
//    Traversal is by 32x32 pixel tiles (see octree.cpp for the structure).
//  * EmbreeTracer - Embree 3 with RTC_SCENE_FLAG_ROBUST (watertight), as the
//    reference (Verify: rtcIntersect1 plus a second, restricted query that
//    applies the tie rule) or as a fast production tracer (Fast:
//    rtcIntersect16 packets of 4x4 pixels; exact ties resolved arbitrarily).
//
// Typical use for one view (the `perclod label` glue):
//   OctreeTracer tracer(scene);                       // once per scene
//   std::vector<uint32_t> ids = tracer.trace(camera); // per view, W*H
//   TriangleCounts counts = count_triangles(ids.data(), mask.data(), ids.size(),
//                                           scene.triangle_count());
//   std::vector<Label> view_labels = label_triangles(counts, ratio);
//   ... over the views: combine_views({view_labels...}), then
//   marking_colors(labels) -> RenderOptions' per-triangle colours.
//   Cross-checks: compare_traced(scene, camera, ids, embree_ids) and
//   compare_with_id_buffer(scene, camera, ids, render.ids).
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "perclod/camera.h"
#include "perclod/scene.h"

namespace perclod {

// Relative t window of the tie rule. The one tolerance of the rule: the
// octree, the brute-force oracle and Embree's verify mode all close the
// window with the same function (src/tie_window.h).
constexpr double kTieEpsilon = 1e-6;

// Default relative tolerance with which compare_traced() and
// compare_with_id_buffer() explain a mismatch as a tie. Deliberately ten
// times kTieEpsilon rather than equal to it: the comparison re-tests both
// triangles in double, while each tracer ranked float t values that differ
// from the double ones by its own rounding, so a tie within kTieEpsilon in
// float can lie further apart in double. Ten tie windows absorb that and are
// still far below the depth step between two distinct surfaces.
constexpr double kAgreementTieTolerance = 1e-5;

class Tracer {
 public:
  virtual ~Tracer() = default;
  // Fills tri_plus_one[W*H] (row 0 top; index + 1, 0 = miss) and, when t is
  // not null, t[W*H] (ray parameter = eye depth of the hit, 0 for a miss).
  // Throws std::invalid_argument for a camera with a non-positive size or
  // clip range that is not 0 <= znear < zfar.
  virtual void trace(const Camera& camera, uint32_t* tri_plus_one, float* t = nullptr) const = 0;
  // Several samples per pixel: out[k] (W*H each) receives what trace() gives
  // for the camera shifted by offsets[k] (added to Camera::shift_x,
  // shift_y; see sample_offsets). This default traces the shifted cameras
  // one after another; the octree walks its structure once for all of them.
  virtual void trace_samples(const Camera& camera, const std::vector<std::array<double, 2>>& offsets,
                             uint32_t* const* out) const;
  // Bytes held by the acceleration structure (and its copy of the geometry);
  // for Embree, what its device memory monitor reports.
  virtual size_t memory_bytes() const = 0;
  // Wall-clock seconds the constructor spent building the structure.
  virtual double build_seconds() const = 0;
  virtual const char* name() const = 0;

  // Convenience: returns a W*H buffer.
  std::vector<uint32_t> trace(const Camera& camera) const;
};

struct OctreeOptions {
  int max_depth = 9;                  // octree levels below the root
  int max_components_per_leaf = 40;   // a node holding more is split (until max_depth)
  int max_triangles_per_bvh_leaf = 16; // inside a component's BVH (measured best 16-64)
};

class OctreeTracer final : public Tracer {
 public:
  // Copies what it needs from the scene (the scene may go away afterwards).
  // Throws std::invalid_argument on an index out of range, a non-finite
  // position, a component/indices size mismatch or bad options.
  explicit OctreeTracer(const Scene& scene, const OctreeOptions& options = {});
  ~OctreeTracer() override;
  void trace(const Camera& camera, uint32_t* tri_plus_one, float* t = nullptr) const override;
  // One walk per tile for every kMaxSamples samples (16 samples: two
  // walks): the same buffers as tracing each shifted camera, bit for bit,
  // for the cost of one traversal and one projection of each triangle
  // reached per walk.
  static constexpr int kMaxSamples = 8;
  void trace_samples(const Camera& camera, const std::vector<std::array<double, 2>>& offsets,
                     uint32_t* const* out) const override;
  using Tracer::trace;
  size_t memory_bytes() const override;
  double build_seconds() const override;
  const char* name() const override { return "octree"; }

  struct Stats {
    size_t octree_nodes = 0, octree_leaves = 0, leaf_references = 0;
    int depth_reached = 0;
    size_t components = 0, bvh_nodes = 0;
  };
  Stats stats() const;

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

// The oracle: every ray against every triangle with the same float rays,
// the same watertight test and the same tie rule as OctreeTracer, so the
// octree must reproduce it bit for bit. O(pixels x triangles): tests only.
class BruteForceTracer final : public Tracer {
 public:
  explicit BruteForceTracer(const Scene& scene);
  void trace(const Camera& camera, uint32_t* tri_plus_one, float* t = nullptr) const override;
  using Tracer::trace;
  size_t memory_bytes() const override { return tris_.size() * sizeof(float); }
  double build_seconds() const override { return 0.0; }
  const char* name() const override { return "brute-force"; }

 private:
  std::vector<float> tris_;  // 9 floats per triangle
};

enum class EmbreeMode {
  Fast,    // rtcIntersect16, 4x4 pixel packets; no tie resolution
  Single,  // rtcIntersect1 per ray; no tie resolution (benchmark peer)
  Verify,  // rtcIntersect16 (4x4 packets), then per hit a single-ray query over [t(1-kTieEpsilon), t(1+kTieEpsilon)] keeping the lowest index
};

class EmbreeTracer final : public Tracer {
 public:
  // Throws std::invalid_argument like OctreeTracer, std::runtime_error when
  // Embree fails.
  EmbreeTracer(const Scene& scene, EmbreeMode mode = EmbreeMode::Verify);
  ~EmbreeTracer() override;
  void trace(const Camera& camera, uint32_t* tri_plus_one, float* t = nullptr) const override;
  using Tracer::trace;
  size_t memory_bytes() const override;
  double build_seconds() const override;
  const char* name() const override;
  EmbreeMode mode() const;

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

// ---- cross-checks ----------------------------------------------------------

// Comparison of two per-pixel triangle buffers (index + 1, 0 = miss).
struct Agreement {
  uint64_t pixels = 0;              // W * H
  uint64_t covered = 0;             // pixels where at least one buffer has a triangle
  uint64_t identical = 0;           // covered pixels where both agree
  uint64_t ties = 0;                // mismatches explained by the tie tolerance (double re-test)
  uint64_t edge_grazes = 0;         // mismatches where the nearer triangle is met within float
                                    // rounding of its boundary (silhouettes, shared edges)
  uint64_t real_disagreements = 0;  // all other mismatches
  double identical_rate() const { return covered ? double(identical) / double(covered) : 1.0; }
};

// Octree (a) against Embree (b), same camera. Every mismatch is re-tested in
// double precision along the pixel's ray: both triangles intersected in
// double (a miss counts as t = infinity). When both hit and their t agree
// within `tie_tolerance` (relative), the pixel is a tie; when the nearer of
// the two is hit only with its edges widened by float rounding (see
// intersect_pixel_double), an edge graze; otherwise a real disagreement.
Agreement compare_traced(const Scene& scene, const Camera& camera, const uint32_t* a,
                         const uint32_t* b, double tie_tolerance = kAgreementTieTolerance);

// Rays (a) against the renderer's ID buffer (b, same encoding). Mismatches
// are classified the same way; a rasteriser's edge rounding shows up as real
// disagreements near edges, so use identical_rate() against the target.
Agreement compare_with_id_buffer(const Scene& scene, const Camera& camera, const uint32_t* rays,
                                 const uint32_t* id_buffer, double tie_tolerance = kAgreementTieTolerance);

// Double-precision intersection of the ray through pixel centre (x+0.5, y+0.5)
// with one triangle (no culling), t in [znear, zfar]. Returns Miss, Inside
// (inside in double by more than the rounding of a float test: about 1e-6 of
// the vertices' distance from the eye) or Edge (within that rounding of the
// triangle's boundary, inside or out: a float tracer may decide either way).
// t is the eye depth.
enum class DoubleHit { Miss, Inside, Edge };
DoubleHit intersect_pixel_double(const Scene& scene, const Camera& camera, int x, int y,
                                 uint32_t triangle, double& t);

// ---- samples and frusta ----------------------------------------------------

// Sub-pixel sample positions for `n` samples per pixel, as offsets from the
// pixel centre (Camera::shift_x, shift_y): n = 1 the centre; 2 the diagonal
// (-1/4, -1/4), (1/4, 1/4); 4 the rotated grid (+-1/8, +-3/8 rotated);
// 8 the 8-rooks pattern of D3D's standard multisample positions; 9 and 16
// the ordered 3 x 3 and 4 x 4 grids (grid_offsets). Patterns 2-8 have one
// sample in each row and column of an n x n sub-grid and the grids one in
// each cell of theirs, so thin horizontal and vertical parts are sampled
// evenly. Throws for other n.
std::vector<std::array<double, 2>> sample_offsets(int n);

// The s x s ordered grid of sub-pixel offsets, ((a + 0.5) / s - 0.5, (b +
// 0.5) / s - 0.5), sample k = b s + a: the pixel centres of a render at s
// times the resolution (perclod/camera.h, refined). Throws unless 1 <= s <= 4.
std::vector<std::array<double, 2>> grid_offsets(int s);

// s when sample_offsets(n) is the s x s ordered grid (n = 9: 3, n = 16: 4),
// else 0.
int sample_grid(int n);

// Marks (sets to 1) the triangles that may lie inside `camera`'s frustum
// (between znear and zfar and within the image's four edge planes): a
// triangle is outside only when all three corners are outside one plane, so
// a few triangles just outside a corner of the frustum are marked too.
// `inside` must hold scene.triangle_count() entries.
void mark_in_frustum(const Scene& scene, const Camera& camera, std::vector<uint8_t>& inside);

// ---- counts and labels -----------------------------------------------------

struct TriangleCounts {
  std::vector<uint32_t> traced;         // per triangle: samples (pixels at 1 sample per pixel) whose ray hit it
  std::vector<uint32_t> imperceptible;  // of those, samples whose pixel is flagged imperceptible
};

// Counts from a per-pixel triangle buffer (index + 1) and a mask (1 byte per
// pixel, nonzero = imperceptible; may be null = nothing imperceptible).
// Throws std::invalid_argument when a pixel names a triangle >= triangle_count.
TriangleCounts count_triangles(const uint32_t* tri_plus_one, const uint8_t* imperceptible_mask,
                               size_t pixel_count, size_t triangle_count);
// Adds the counts of one more sample buffer (same encoding, same mask) to `c`.
void add_counts(TriangleCounts& c, const uint32_t* tri_plus_one, const uint8_t* imperceptible_mask,
                size_t pixel_count);

// traced == 0 -> Undisplayable; imperceptible / traced >= ratio -> Imperceptible;
// else Perceptible. Throws std::invalid_argument for mismatched vector sizes
// or a ratio outside [0, 1] (or NaN).
std::vector<Label> label_triangles(const TriangleCounts& counts, double ratio = 0.5);

// The combination rule, one view at a time: Perceptible in any view wins;
// Undisplayable only when undisplayable in every view; else Imperceptible.
// Start from Undisplayable (no view yet) and fold each view's label in.
inline Label combine_labels(Label so_far, Label view) {
  if (so_far == Label::Perceptible || view == Label::Perceptible) return Label::Perceptible;
  if (so_far == Label::Imperceptible || view == Label::Imperceptible) return Label::Imperceptible;
  return Label::Undisplayable;
}

// combine_labels over whole views. Throws on an empty list or views of
// different sizes.
std::vector<Label> combine_views(const std::vector<std::vector<Label>>& views);

struct LabelCounts {
  size_t perceptible = 0, imperceptible = 0, undisplayable = 0;
};
LabelCounts count_labels(const std::vector<Label>& labels);

// Marking colour of a label (the paper's figure 7): perceptible green,
// imperceptible red, undisplayable blue.
std::array<float, 3> marking_color(Label label);
// 3 floats per triangle, for RenderOptions' per-triangle colours.
std::vector<float> marking_colors(const std::vector<Label>& labels);

}  // namespace perclod
