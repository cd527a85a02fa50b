// octree.cpp - the component octree and its tile traversal.
//
// Structure (three flat arrays and a triangle array, all indices uint32):
//
//   OctNode[]   the octree of the paper. The root is the scene's bounding box;
//               a node holding more than `max_components_per_leaf` component
//               boxes splits at its centre into 8 children (stored
//               consecutively; child bit 0 = upper x half, bit 1 = y, bit 2 =
//               z) until `max_depth`. Components are NOT split: a component
//               whose box overlaps several leaves is referenced by each of
//               them (closed-interval overlap). A split that leaves every child
//               with as many components as the parent is not made.
//   leaf_refs[] component ids referenced by the leaves, leaf by leaf.
//   Component[] per component: its bounding box and the root of its BVH.
//   BvhNode[]   one small binary BVH per component over its own triangles
//               (object-median split on the longest centroid axis, leaves of
//               at most `max_triangles_per_bvh_leaf` triangles), so a
//               100k-triangle wall is a log-depth tree, not a linear list.
//   PackedTri[] the triangles, reordered component by component and leaf by
//               leaf: 9 floats of vertex positions and the original index.
//
// Traversal: all primary rays of a camera share one origin, the eye. The
// image is cut into 32x32-pixel tiles; each tile walks the structure once for
// its 1024 rays (a tile is the "packet"; tiles are spread over oneTBB threads),
// or for its 1024 rays per sample when several sub-pixel samples are traced
// together (trace_samples: a box or triangle is kept when it may hold any
// sample point, a triangle is projected once, each sample keeps its own ray,
// window and tie state, so each sample's hits are those of its own trace):
//   * a box in front of the eye is projected to the image by interval
//     arithmetic and skipped unless its rectangle (plus a float-rounding
//     margin, see float_bounds.h) contains one of the tile's pixel centres, so geometry that falls
//     between the rays is dropped as a packet tracer's per-ray box tests would
//     drop it; a box reaching the eye plane is tested against the tile's
//     frustum (four planes through the eye and the tile's outer pixel edges);
//     a box is also skipped when its nearest eye depth exceeds the farthest t
//     any pixel of the tile still accepts;
//   * octree children are visited front to back: a ray from the eye crosses
//     each splitting plane at most once, away from the eye's side, so ordering
//     children by the number of axes on which they lie across the centre from
//     the eye (0, then 1, 2, 3) is a valid front-to-back order for every ray
//     of the tile at once (this replaces Revelles' per-ray parametric order,
//     and stays exact for an eye on a splitting plane or rays parallel to one);
//   * a component is tested once per tile (a per-thread stamp array), against
//     all the tile's rays, whichever leaf reaches it first; a leaf's visible
//     components and a BVH node's visible children are taken nearest box first;
//   * a triangle is projected to the image (in double); its edge functions
//     give, row by row, the span of pixel centres it can cover (widened by the
//     rounding margin), and only those centres whose current t window reaches
//     the triangle's nearest depth get the exact watertight test. A triangle
//     touching the eye plane is tested against the whole tile.
//   * in a tile whose rays all share one axis permutation (nearly every tile)
//     the exact test runs on four consecutive samples of a row at once
//     (watertight_hit4, SSE, the same float operations as the scalar test);
//     a footprint at most 8 pixels wide skips the row spans: testing its rows
//     whole costs less than computing them. A tile's rays are likewise set
//     up four at a time (shear_rays4). On the 1M facade view of
//     bench_raycast these made the octree 1.27x faster (68.5 -> 54 ms on one
//     thread; BENCHMARKS.md#one-view-in-detail).
// The result is the same, bit for bit, as testing every ray against every
// triangle (BruteForceTracer; the tests check it): the culling is
// conservative and the exact test is the same function.
// Tie rule: each pixel keeps the nearest t and accepts hits up to
// tie_window_end(t) = t * (1 + kTieEpsilon) (tie_window.h). Besides the
// nearest hit it remembers up to kTieKeep other hits (t and index) inside that
// window; when a nearer hit narrows the window, the remembered hits that fall
// outside it are forgotten. Every hit inside the final window was accepted when
// it was found (windows only shrink) and is still remembered, so the lowest
// index among the nearest and the remembered hits is exactly "lowest index
// among hits within t_min (1 + kTieEpsilon)". A pixel whose window holds more
// than kTieKeep + 1 hits (stacked coplanar copies) is flagged instead, and
// after the tile is done its tile is walked again with the windows fixed,
// keeping the lowest index among all hits in them. (Shared edges through pixel
// centres make two-hit ties common: on the 1M facade 46% of the tiles had one,
// and before the remembered hits each of those tiles was walked twice.)
#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <numeric>
#include <stdexcept>

#include "float_bounds.h"
#include "geometry_checks.h"
#include "perclod/raycast.h"
#include "pixel_rays.h"
#include "tie_window.h"
#include "watertight.h"

namespace perclod {

using detail::ShearedRay;

namespace {

struct Box {
  float lo[3], hi[3];
};

Box empty_box() {
  Box b;
  for (int k = 0; k < 3; ++k) {
    b.lo[k] = std::numeric_limits<float>::infinity();
    b.hi[k] = -std::numeric_limits<float>::infinity();
  }
  return b;
}

void grow(Box& b, const Box& o) {
  for (int k = 0; k < 3; ++k) {
    b.lo[k] = std::min(b.lo[k], o.lo[k]);
    b.hi[k] = std::max(b.hi[k], o.hi[k]);
  }
}

bool overlaps(const Box& a, const Box& b) {
  for (int k = 0; k < 3; ++k)
    if (a.hi[k] < b.lo[k] || b.hi[k] < a.lo[k]) return false;
  return true;
}

struct PackedTri {
  float v[9];
  uint32_t index;  // triangle index in the Scene
};

struct BvhNode {
  Box box;
  uint32_t first;  // leaf: first PackedTri; inner: left child (right = first + 1)
  uint32_t info;   // bits 0-1: split axis; bits 2..: triangle count (0 = inner)
  uint32_t count() const { return info >> 2; }
  int axis() const { return int(info & 3u); }
};

struct ComponentNode {
  Box box;
  uint32_t bvh_root;
  uint32_t triangles;
};

constexpr uint32_t kLeafBit = 0x80000000u;
struct OctNode {
  Box box;
  uint32_t first;  // inner: first of 8 children; leaf: first leaf_ref
  uint32_t info;   // leaf: kLeafBit | reference count; inner: 0
  bool leaf() const { return (info & kLeafBit) != 0; }
  uint32_t count() const { return info & ~kLeafBit; }
};

constexpr int kTile = 32;
constexpr int kTilePixels = kTile * kTile;
constexpr int kMaxSamples = OctreeTracer::kMaxSamples;  // sample_offsets' largest pattern
constexpr int kTieKeep = 3;     // hits remembered besides the nearest, per sample
// The deepest octree OctreeOptions::max_depth may ask for, and so a walk's
// stack: 7 siblings waiting at each of its levels, and the 8 children of
// the deepest.
constexpr int kMaxOctreeDepth = 20;
constexpr int kOctreeStack = 7 * kMaxOctreeDepth + 8;
constexpr uint8_t kTieOverflow = 255;  // Tile::tie: more than kTieKeep, walk again

// Per sample s and pixel p of the tile, entry q = s * kTilePixels + p.
// The rays are stored by component (the shear constants of ShearedRay, and
// its axis permutation packed in one byte) so that four consecutive entries
// load as SSE lanes; the arrays the four-lane test reads have three floats of
// padding after the last entry.
constexpr int kEntries = kMaxSamples * kTilePixels;
struct Tile {
  int x0, y0, w, h;
  float ray_sx[kEntries + 3], ray_sy[kEntries + 3], ray_sz[kEntries + 3];
  uint8_t ray_axes[kEntries];  // kx | ky << 2 | kz << 4
  bool one_axes;               // every entry has the same permutation (axes below)
  uint8_t kx, ky, kz;
  float sx_max, sy_max;        // largest |sx|, |sy| of the tile's rays
  float best[kMaxSamples * kTilePixels];    // nearest t so far
  float bound[kEntries + 3];   // largest t still accepted
  uint32_t hit[kMaxSamples * kTilePixels];  // triangle index + 1, 0 = none
  uint8_t tie[kMaxSamples * kTilePixels];  // remembered hits (0..kTieKeep) or kTieOverflow
  float tie_t[kMaxSamples * kTilePixels][kTieKeep];
  uint32_t tie_id[kMaxSamples * kTilePixels][kTieKeep];
  int unhit;  // samples without a hit yet (normal pass)
  double plane[4][3];  // inward normals of the frustum planes through the eye
  double centre_dir[3];
  double tmax;  // widen_far(max over pixels of bound)
  bool collect;
};

}  // namespace

struct OctreeTracer::Impl {
  OctreeOptions options;
  std::vector<PackedTri> tris;
  std::vector<BvhNode> bvh;
  std::vector<ComponentNode> components;
  std::vector<OctNode> octree;
  std::vector<uint32_t> leaf_refs;
  int depth_reached = 0;
  double build_seconds = 0;

  struct Scratch {
    std::vector<uint32_t> stamp;
    uint32_t clock = 0;
    std::shared_ptr<Tile> tile;  // a tile's rays and hits for every sample (too big for a worker's stack)
  };
  mutable tbb::enumerable_thread_specific<Scratch> scratch;

  void build(const Scene& scene);
  void build_bvhs(const Scene& scene);
  void build_octree(const Box& root);
  // out[s] (and tout[s] when tout is not null) for the camera shifted by
  // offsets[s]; one walk through the structure per tile serves every sample.
  void trace(const Camera& camera, const std::array<double, 2>* offsets, int samples, uint32_t* const* out,
             float* const* tout) const;
};

// ---------------------------------------------------------------- building

namespace {

Box triangle_box(const float* p, const uint32_t* idx) {
  Box b = empty_box();
  for (int c = 0; c < 3; ++c)
    for (int k = 0; k < 3; ++k) {
      float v = p[3 * size_t(idx[c]) + k];
      b.lo[k] = std::min(b.lo[k], v);
      b.hi[k] = std::max(b.hi[k], v);
    }
  return b;
}

// Builds the BVH of one component over ids[begin, end) into `nodes`
// (node 0 = root, indices local); reorders ids leaf by leaf.
struct BvhBuilder {
  const std::vector<Box>& tri_box;
  const std::vector<std::array<float, 3>>& centroid;
  int leaf_size;
  std::vector<BvhNode> nodes;

  void build(uint32_t* ids, uint32_t begin, uint32_t end) {
    nodes.push_back({});
    split(ids, 0, begin, end, 0);
  }

  void split(uint32_t* ids, uint32_t node, uint32_t begin, uint32_t end, int depth) {
    Box b = empty_box(), cb = empty_box();
    for (uint32_t i = begin; i < end; ++i) {
      grow(b, tri_box[ids[i]]);
      const auto& c = centroid[ids[i]];
      for (int k = 0; k < 3; ++k) {
        cb.lo[k] = std::min(cb.lo[k], c[k]);
        cb.hi[k] = std::max(cb.hi[k], c[k]);
      }
    }
    nodes[node].box = b;
    const uint32_t n = end - begin;
    if (n <= uint32_t(leaf_size) || depth >= 60) {
      nodes[node].first = begin;
      nodes[node].info = n << 2;
      return;
    }
    int axis = 0;
    for (int k = 1; k < 3; ++k)
      if (cb.hi[k] - cb.lo[k] > cb.hi[axis] - cb.lo[axis]) axis = k;
    const uint32_t mid = begin + n / 2;
    std::nth_element(ids + begin, ids + mid, ids + end, [&](uint32_t a, uint32_t c) {
      return centroid[a][axis] < centroid[c][axis];
    });
    const uint32_t left = uint32_t(nodes.size());
    nodes.push_back({});
    nodes.push_back({});
    nodes[node].first = left;
    nodes[node].info = uint32_t(axis);
    split(ids, left, begin, mid, depth + 1);
    split(ids, left + 1, mid, end, depth + 1);
  }
};

}  // namespace

void OctreeTracer::Impl::build_bvhs(const Scene& scene) {
  const size_t nt = scene.triangle_count();
  const uint32_t nc = detail::component_slots(scene);
  auto comp_of = [&](size_t t) { return scene.component_of(t); };

  // Triangles grouped by component (counting sort, stable).
  std::vector<uint32_t> start(size_t(nc) + 1, 0);
  for (size_t t = 0; t < nt; ++t) ++start[comp_of(t) + 1];
  std::partial_sum(start.begin(), start.end(), start.begin());
  std::vector<uint32_t> ids(nt);
  {
    std::vector<uint32_t> fill(start.begin(), start.end() - 1);
    for (size_t t = 0; t < nt; ++t) ids[fill[comp_of(t)]++] = uint32_t(t);
  }

  std::vector<Box> tri_box(nt);
  std::vector<std::array<float, 3>> centroid(nt);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, nt, 4096), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t t = r.begin(); t < r.end(); ++t) {
      tri_box[t] = triangle_box(scene.positions.data(), &scene.indices[3 * t]);
      for (int k = 0; k < 3; ++k) centroid[t][k] = 0.5f * (tri_box[t].lo[k] + tri_box[t].hi[k]);
    }
  });

  // One BVH per component, in parallel; then concatenated.
  std::vector<std::vector<BvhNode>> local(nc);
  tbb::parallel_for(tbb::blocked_range<uint32_t>(0, nc, 1), [&](const tbb::blocked_range<uint32_t>& r) {
    for (uint32_t c = r.begin(); c < r.end(); ++c) {
      if (start[c] == start[c + 1]) continue;
      BvhBuilder b{tri_box, centroid, options.max_triangles_per_bvh_leaf, {}};
      b.build(ids.data(), start[c], start[c + 1]);
      local[c] = std::move(b.nodes);
    }
  });

  components.assign(nc, ComponentNode{empty_box(), 0, 0});
  std::vector<uint32_t> base(size_t(nc) + 1, 0);
  for (uint32_t c = 0; c < nc; ++c) base[c + 1] = base[c] + uint32_t(local[c].size());
  bvh.resize(base[nc]);
  tbb::parallel_for(tbb::blocked_range<uint32_t>(0, nc, 16), [&](const tbb::blocked_range<uint32_t>& r) {
    for (uint32_t c = r.begin(); c < r.end(); ++c) {
      for (size_t i = 0; i < local[c].size(); ++i) {
        BvhNode n = local[c][i];
        if (n.count() == 0) n.first += base[c];  // inner: child index becomes global
        bvh[base[c] + i] = n;
      }
      if (!local[c].empty()) components[c] = {local[c][0].box, base[c], start[c + 1] - start[c]};
      std::vector<BvhNode>().swap(local[c]);
    }
  });

  tris.resize(nt);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, nt, 4096), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i < r.end(); ++i) {
      const uint32_t t = ids[i];
      PackedTri& p = tris[i];
      for (int c = 0; c < 3; ++c)
        for (int k = 0; k < 3; ++k) p.v[3 * c + k] = scene.positions[3 * size_t(scene.indices[3 * size_t(t) + c]) + k];
      p.index = t;
    }
  });
}

void OctreeTracer::Impl::build_octree(const Box& root) {
  struct Pending {
    uint32_t node;
    int depth;
    std::vector<uint32_t> comps;
  };
  octree.clear();
  leaf_refs.clear();
  std::vector<Pending> work;
  std::vector<uint32_t> all;
  for (uint32_t c = 0; c < components.size(); ++c)
    if (components[c].triangles) all.push_back(c);
  octree.push_back({root, 0, 0});
  work.push_back({0, 0, std::move(all)});
  while (!work.empty()) {
    Pending p = std::move(work.back());
    work.pop_back();
    depth_reached = std::max(depth_reached, p.depth);
    const Box box = octree[p.node].box;
    bool split = int(p.comps.size()) > options.max_components_per_leaf && p.depth < options.max_depth;
    std::array<std::vector<uint32_t>, 8> kids;
    std::array<Box, 8> kid_box;
    if (split) {
      size_t largest = 0;
      for (int c = 0; c < 8; ++c) {
        Box& kb = kid_box[c];
        for (int k = 0; k < 3; ++k) {
          const float mid = 0.5f * (box.lo[k] + box.hi[k]);
          const bool upper = (c >> k) & 1;
          kb.lo[k] = upper ? mid : box.lo[k];
          kb.hi[k] = upper ? box.hi[k] : mid;
        }
        for (uint32_t id : p.comps)
          if (overlaps(components[id].box, kb)) kids[c].push_back(id);
        largest = std::max(largest, kids[c].size());
      }
      split = largest < p.comps.size();  // a split that helps no child is not made
    }
    if (!split) {
      octree[p.node].first = uint32_t(leaf_refs.size());
      octree[p.node].info = kLeafBit | uint32_t(p.comps.size());
      leaf_refs.insert(leaf_refs.end(), p.comps.begin(), p.comps.end());
      continue;
    }
    const uint32_t first = uint32_t(octree.size());
    octree[p.node].first = first;
    octree[p.node].info = 0;
    for (int c = 0; c < 8; ++c) octree.push_back({kid_box[c], 0, 0});
    for (int c = 0; c < 8; ++c) work.push_back({first + c, p.depth + 1, std::move(kids[c])});
  }
}

void OctreeTracer::Impl::build(const Scene& scene) {
  const auto t0 = std::chrono::steady_clock::now();
  build_bvhs(scene);
  Box root = empty_box();
  for (const auto& c : components)
    if (c.triangles) grow(root, c.box);
  if (components.empty() || tris.empty()) root = Box{{0, 0, 0}, {0, 0, 0}};
  build_octree(root);
  build_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// ---------------------------------------------------------------- tracing

namespace {

using Scratch = OctreeTracer::Impl::Scratch;

// What a tile needs to know about the camera. Image points are in the
// camera's own pixel coordinates; sample s of pixel (x, y) sits at
// (x + 0.5 + ox[s], y + 0.5 + oy[s]) there, and its ray is dirs[s]'s.
struct Frame {
  const Camera* cam;
  int samples;
  const detail::PixelDirections* dirs[kMaxSamples];
  double ox[kMaxSamples], oy[kMaxSamples];
  double ox_min, ox_max, oy_min, oy_max;
  double eye[3], fwd[3], right[3], up[3];
  float eyef[3];
  float znear, zfar;
  bool pos_fwd[3], pos_right[3], pos_up[3];  // coefficient >= 0
  double fmax;  // max(fx, fy)
  double fx, fy, cx, cy;  // image point = (cx + fx * x/z, cy - fy * y/z) in camera axes
};

Frame make_frame(const Camera& cam, const std::array<double, 2>* offsets,
                 const std::vector<std::unique_ptr<detail::PixelDirections>>& dirs) {
  Frame f;
  f.cam = &cam;
  f.samples = int(dirs.size());
  f.ox_min = f.oy_min = INFINITY;
  f.ox_max = f.oy_max = -INFINITY;
  for (int s = 0; s < f.samples; ++s) {
    f.dirs[s] = dirs[size_t(s)].get();
    f.ox[s] = offsets[s][0];
    f.oy[s] = offsets[s][1];
    f.ox_min = std::min(f.ox_min, f.ox[s]), f.ox_max = std::max(f.ox_max, f.ox[s]);
    f.oy_min = std::min(f.oy_min, f.oy[s]), f.oy_max = std::max(f.oy_max, f.oy[s]);
  }
  for (int k = 0; k < 3; ++k) {
    f.fwd[k] = cam.forward[k];
    f.right[k] = cam.right[k];
    f.up[k] = cam.up[k];
  }
  detail::eye_float(cam, f.eyef);
  // Rays start at the float eye: every conservative test measures from it.
  for (int k = 0; k < 3; ++k) f.eye[k] = double(f.eyef[k]);
  f.znear = float(cam.znear);
  f.zfar = float(cam.zfar);
  const double th = cam.tan_half_y();
  f.fx = 0.5 * cam.width / (th * cam.aspect());
  f.fy = 0.5 * cam.height / th;
  f.cx = 0.5 * cam.width - cam.shift_x;  // pixel coordinates of the shifted camera
  f.cy = 0.5 * cam.height - cam.shift_y;
  f.fmax = std::max(f.fx, f.fy);
  for (int k = 0; k < 3; ++k) {
    f.pos_fwd[k] = f.fwd[k] >= 0;
    f.pos_right[k] = f.right[k] >= 0;
    f.pos_up[k] = f.up[k] >= 0;
  }
  return f;
}


void update_tile_tmax(const Frame& f, Tile& tile) {
  if (!tile.collect && tile.unhit > 0) return;  // some sample still accepts up to zfar
  float m = 0.0f;
  const int n = tile.w * tile.h;
  for (int s = 0; s < f.samples; ++s)
    for (int i = s * kTilePixels; i < s * kTilePixels + n; ++i)
      if (!tile.collect || tile.tie[i] == kTieOverflow) m = std::max(m, tile.bound[i]);
  tile.tmax = detail::widen_far(double(m));
}

void setup_tile(const Frame& f, Tile& tile, int x0, int y0) {
  const Camera& cam = *f.cam;
  tile.x0 = x0;
  tile.y0 = y0;
  tile.w = std::min(kTile, cam.width - x0);
  tile.h = std::min(kTile, cam.height - y0);
  tile.collect = false;
  tile.unhit = f.samples * tile.w * tile.h;
  // The rays, four at a time, with the first ray's axis permutation as the
  // guess for all of them; a group where shear_ray picks another permutation
  // for some ray is set up ray by ray.
  float first[3];
  f.dirs[0]->direction(x0, y0, first);
  const ShearedRay r0 = detail::shear_ray(first);
  const uint8_t axes = uint8_t(r0.kx | r0.ky << 2 | r0.kz << 4);
  tile.kx = r0.kx;
  tile.ky = r0.ky;
  tile.kz = r0.kz;
  tile.one_axes = true;
  float sx_max = 0.0f, sy_max = 0.0f;
  alignas(16) float d[3][kTile + 3] = {};  // a row's directions, by component
  for (int s = 0; s < f.samples; ++s)
    for (int j = 0; j < tile.h; ++j) {
      f.dirs[s]->row(x0, tile.w, y0 + j, d[0], d[1], d[2]);
      const int row = s * kTilePixels + j * tile.w;
      for (int i = 0; i < tile.w; i += 4) {
        const int q = row + i, lanes = std::min(4, tile.w - i), all = (1 << lanes) - 1;
        // Writes four entries from q: those past the row are the next row's
        // (written after) or padding.
        const int same = all & detail::shear_rays4(d[0] + i, d[1] + i, d[2] + i, r0.kx, r0.ky, r0.kz,
                                                   tile.ray_sx + q, tile.ray_sy + q, tile.ray_sz + q);
        for (int l = 0; l < lanes; ++l) {
          if (!(same >> l & 1)) {
            const float dl[3] = {d[0][i + l], d[1][i + l], d[2][i + l]};
            const ShearedRay r = detail::shear_ray(dl);
            tile.ray_sx[q + l] = r.sx;
            tile.ray_sy[q + l] = r.sy;
            tile.ray_sz[q + l] = r.sz;
            tile.ray_axes[q + l] = uint8_t(r.kx | r.ky << 2 | r.kz << 4);
            tile.one_axes &= tile.ray_axes[q + l] == axes;
          } else {
            tile.ray_axes[q + l] = axes;
          }
          sx_max = std::max(sx_max, std::fabs(tile.ray_sx[q + l]));
          sy_max = std::max(sy_max, std::fabs(tile.ray_sy[q + l]));
        }
      }
      std::fill_n(tile.best + row, tile.w, f.zfar);
      std::fill_n(tile.bound + row, tile.w, f.zfar);
      std::fill_n(tile.hit + row, tile.w, 0u);
      std::fill_n(tile.tie + row, tile.w, uint8_t(0));
    }
  tile.sx_max = sx_max;
  tile.sy_max = sy_max;
  // Frustum through the tile's outer pixel edges.
  const Eigen::Vector3d c = cam.ray_direction(x0 + 0.5 * tile.w, y0 + 0.5 * tile.h);
  const Eigen::Vector3d corner[4] = {
      cam.ray_direction(x0, y0), cam.ray_direction(x0 + tile.w, y0),
      cam.ray_direction(x0 + tile.w, y0 + tile.h), cam.ray_direction(x0, y0 + tile.h)};
  for (int k = 0; k < 4; ++k) {
    Eigen::Vector3d n = corner[k].cross(corner[(k + 1) % 4]);
    if (n.dot(c) < 0) n = -n;
    for (int a = 0; a < 3; ++a) tile.plane[k][a] = n[a];
  }
  for (int a = 0; a < 3; ++a) tile.centre_dir[a] = c[a];
  tile.tmax = detail::widen_far(double(f.zfar));
}

// floor(v) clamped to [lo, hi] (and ceil), without libm calls or branches
// (these run several times per triangle and tile, on data-dependent values):
// the clamp, which sends NaN to lo, keeps the int conversion in range, and
// the truncation toward zero is corrected by one comparison.
inline int floor_within(double v, int lo, int hi) {
  double c = v > lo ? v : double(lo);
  c = c < hi ? c : double(hi);
  const int i = int(c);
  return i - int(double(i) > c);
}
inline int ceil_within(double v, int lo, int hi) {
  double c = v > lo ? v : double(lo);
  c = c < hi ? c : double(hi);
  const int i = int(c);
  return i + int(double(i) < c);
}

struct PixelRect {
  int xa, xb, ya, yb;  // inclusive pixel range inside the tile
};

// Conservative: false only when no ray of the tile can hit inside the box
// within its current t range. A box in front of the eye is projected by
// interval arithmetic (x = N / D with N and D ranging over the box), and
// survives only if its projected rectangle (plus pixel_margin()) contains a
// sample point of the tile (rect: the pixels whose sample points it may
// contain, for any sample): sub-pixel geometry that falls between the rays
// is dropped here, as a packet tracer's per-ray box tests would. A box
// reaching the eye plane gets the four frustum planes instead. Sets near (a
// lower bound on any float hit t inside the box) and rect (the tile's pixels
// it can cover).
bool box_visible(const Frame& f, const Tile& tile, const Box& b, double& near, PixelRect& rect) {
  double lo[3], hi[3], mag = 0;
  for (int k = 0; k < 3; ++k) {
    lo[k] = double(b.lo[k]) - f.eye[k];
    hi[k] = double(b.hi[k]) - f.eye[k];
    mag = std::max(mag, std::max(-lo[k], hi[k]));  // >= max |coordinate| (lo <= hi)
  }
  // Extremes of a linear function over the box: the corner picked by the
  // signs of its coefficients (precomputed per frame in Frame::pos_*).
  double dmin = 0, dmax = 0, nxmin = 0, nxmax = 0, nymin = 0, nymax = 0;
  for (int k = 0; k < 3; ++k) dmin += f.fwd[k] * (f.pos_fwd[k] ? lo[k] : hi[k]);
  near = dmin - detail::hit_depth_slack(mag);  // below any t the float test can return inside the box
  if (near > tile.tmax) return false;  // occluded for every pixel of the tile
  for (int k = 0; k < 3; ++k) {
    dmax += f.fwd[k] * (f.pos_fwd[k] ? hi[k] : lo[k]);
    nxmin += f.right[k] * (f.pos_right[k] ? lo[k] : hi[k]);
    nxmax += f.right[k] * (f.pos_right[k] ? hi[k] : lo[k]);
    nymin += f.up[k] * (f.pos_up[k] ? lo[k] : hi[k]);
    nymax += f.up[k] * (f.pos_up[k] ? hi[k] : lo[k]);
  }
  if (detail::before_near_plane(dmax, double(f.znear))) return false;
  if (detail::projectable(dmin, mag)) {
    const double i0 = 1.0 / dmin, i1 = 1.0 / dmax;
    const double xlo = nxmin * (nxmin >= 0 ? i1 : i0), xhi = nxmax * (nxmax >= 0 ? i0 : i1);
    const double ylo = nymin * (nymin >= 0 ? i1 : i0), yhi = nymax * (nymax >= 0 ? i0 : i1);
    const double margin = detail::pixel_margin(mag, i0, f.fmax);
    const double pxlo = f.cx + f.fx * xlo, pxhi = f.cx + f.fx * xhi;
    const double pylo = f.cy - f.fy * yhi, pyhi = f.cy - f.fy * ylo;
    const int xa = ceil_within(pxlo - margin - 0.5 - f.ox_max, tile.x0, tile.x0 + tile.w);
    const int xb = floor_within(pxhi + margin - 0.5 - f.ox_min, tile.x0 - 1, tile.x0 + tile.w - 1);
    if (xa > xb) return false;
    const int ya = ceil_within(pylo - margin - 0.5 - f.oy_max, tile.y0, tile.y0 + tile.h);
    const int yb = floor_within(pyhi + margin - 0.5 - f.oy_min, tile.y0 - 1, tile.y0 + tile.h - 1);
    if (ya > yb) return false;
    rect = {xa, xb, ya, yb};
    return true;
  }
  for (int p = 0; p < 4; ++p) {
    const double* n = tile.plane[p];
    double s = 0;
    for (int k = 0; k < 3; ++k) s += n[k] * (n[k] >= 0 ? hi[k] : lo[k]);
    if (s < 0) return false;
  }
  rect = {tile.x0, tile.x0 + tile.w - 1, tile.y0, tile.y0 + tile.h - 1};
  return true;
}


// ---- the exact test and the tie rule

// Remembers a hit inside entry p's window besides its nearest one (or flags
// the entry for a second walk when kTieKeep are remembered already).
inline void remember_tie(Tile& tile, int p, float t, uint32_t id) {
  uint8_t& n = tile.tie[p];
  if (n == kTieOverflow) return;
  if (n == kTieKeep) {
    n = kTieOverflow;
    return;
  }
  tile.tie_t[p][n] = t;
  tile.tie_id[p][n] = id;
  ++n;
}

inline ShearedRay ray_at(const Tile& tile, int q) {
  const uint8_t a = tile.ray_axes[q];
  return {uint8_t(a & 3u), uint8_t((a >> 2) & 3u), uint8_t(a >> 4), tile.ray_sx[q], tile.ray_sy[q], tile.ray_sz[q]};
}

// The tie-rule bookkeeping of a hit at t of entry p, found in the normal
// pass. Returns true when the sample's nearest hit changed.
inline bool accept_hit(const Frame& f, Tile& tile, int p, uint32_t id, float t) {
  const float end = detail::tie_window_end(t, f.zfar);
  if (tile.hit[p] == 0) {
    --tile.unhit;
  } else if (t >= tile.best[p]) {  // inside the window of the nearest
    remember_tie(tile, p, t, id);
    return false;
  } else if (tile.tie[p] != kTieOverflow) {  // a nearer hit: forget what leaves the window
    uint8_t kept = 0;
    for (uint8_t k = 0; k < tile.tie[p]; ++k)
      if (tile.tie_t[p][k] <= end) {
        tile.tie_t[p][kept] = tile.tie_t[p][k];
        tile.tie_id[p][kept] = tile.tie_id[p][k];
        ++kept;
      }
    tile.tie[p] = kept;
    if (tile.best[p] <= end) remember_tie(tile, p, tile.best[p], tile.hit[p]);  // the old nearest stays in
  }
  tile.best[p] = t;
  tile.hit[p] = id;
  tile.bound[p] = end;
  return true;
}

// The exact test of one sample's ray (entry p of the tile) and the tie-rule
// bookkeeping. Returns true when the sample's nearest hit changed.
inline bool test_pixel(const Frame& f, Tile& tile, int p, uint32_t id, const float A[3], const float B[3],
                       const float C[3]) {
  float t;
  if (tile.collect) {
    if (tile.tie[p] == kTieOverflow && id < tile.hit[p] &&
        detail::watertight_hit(ray_at(tile, p), A, B, C, f.znear, tile.bound[p], t))
      tile.hit[p] = id;
    return false;
  }
  if (!detail::watertight_hit(ray_at(tile, p), A, B, C, f.znear, tile.bound[p], t)) return false;
  return accept_hit(f, tile, p, id, t);
}

// The triangle's vertices relative to the float eye, as the exact test takes them.
inline void relative_vertices(const Frame& f, const PackedTri& tri, float A[3], float B[3], float C[3]) {
  for (int k = 0; k < 3; ++k) {
    A[k] = tri.v[k] - f.eyef[k];
    B[k] = tri.v[3 + k] - f.eyef[k];
    C[k] = tri.v[6 + k] - f.eyef[k];
  }
}

// A triangle against a single pixel (its leaf box can hold sample points of
// one pixel of the tile only): no projection needed, the exact test decides
// for each sample.
inline bool test_triangle_at(const Frame& f, Tile& tile, const PackedTri& tri, int x, int y) {
  float A[3], B[3], C[3];
  relative_vertices(f, tri, A, B, C);
  const int p = (y - tile.y0) * tile.w + (x - tile.x0);
  bool changed = false;
  for (int s = 0; s < f.samples; ++s) changed |= test_pixel(f, tile, s * kTilePixels + p, tri.index + 1, A, B, C);
  return changed;
}

// ---- a triangle's pixels

// The pixels of a tile a triangle can cover: a rectangle and, when the
// triangle projects to more than a sliver, its three edge functions in
// pixels (interior >= 0, widened by the pixel margin).
struct TriangleFootprint {
  int xa, xb, ya, yb;  // inclusive pixel range inside the tile
  bool edges;
  double ea[3], eb[3], ec[3];  // edge i at image point (X, Y): ea X + eb Y + ec
  double inv_ea[3];            // 1 / ea, 0 where ea == 0
};

// The edge functions of the projected triangle P (pixels). The margin is
// scaled by |ex| + |ey|, which is at least the edge length, so the filter
// stays conservative. Leaves fp.edges false for a sliver.
inline void set_edge_functions(const double P[3][2], double margin, TriangleFootprint& fp) {
  const double area2 = (P[1][0] - P[0][0]) * (P[2][1] - P[0][1]) - (P[1][1] - P[0][1]) * (P[2][0] - P[0][0]);
  double l1max = 0;
  for (int i = 0; i < 3; ++i) {
    const int j = i == 2 ? 0 : i + 1;
    l1max = std::max(l1max, std::fabs(P[j][0] - P[i][0]) + std::fabs(P[j][1] - P[i][1]));
  }
  fp.edges = std::fabs(area2) > detail::kSliverAreaRel * l1max * l1max;
  if (!fp.edges) return;
  const double sgn = area2 > 0 ? 1.0 : -1.0;
  for (int i = 0; i < 3; ++i) {
    const int j = i == 2 ? 0 : i + 1;
    const double ex = P[j][0] - P[i][0], ey = P[j][1] - P[i][1];
    fp.ea[i] = -sgn * ey;
    fp.eb[i] = sgn * ex;
    fp.ec[i] = -(fp.ea[i] * P[i][0] + fp.eb[i] * P[i][1]) + margin * (std::fabs(ex) + std::fabs(ey));
  }
  for (int i = 0; i < 3; ++i) fp.inv_ea[i] = fp.ea[i] != 0 ? 1.0 / fp.ea[i] : 0.0;
}

// Restricts fp to the projection of a triangle wholly in front of the eye:
// V are its vertices relative to the eye, z their depths, mag their largest
// |coordinate|. Returns false when no pixel centre of the tile is left.
inline bool project_triangle(const Frame& f, const Tile& tile, const float* const V[3], const double z[3],
                             double mag, TriangleFootprint& fp) {
  double pxmin = INFINITY, pxmax = -INFINITY, pymin = INFINITY, pymax = -INFINITY;
  double P[3][2], izmax = 0;  // izmax = 1 / zmin
  for (int c = 0; c < 3; ++c) {
    const double rx = f.right[0] * V[c][0] + f.right[1] * V[c][1] + f.right[2] * V[c][2];
    const double ry = f.up[0] * V[c][0] + f.up[1] * V[c][1] + f.up[2] * V[c][2];
    const double iz = 1.0 / z[c];
    izmax = std::max(izmax, iz);
    const double px = f.cx + f.fx * rx * iz, py = f.cy - f.fy * ry * iz;
    P[c][0] = px;
    P[c][1] = py;
    pxmin = std::min(pxmin, px);
    pxmax = std::max(pxmax, px);
    pymin = std::min(pymin, py);
    pymax = std::max(pymax, py);
  }
  const double margin = detail::pixel_margin(mag, izmax, f.fmax);
  fp.xa = std::max(fp.xa, ceil_within(pxmin - margin - 0.5 - f.ox_max, tile.x0, tile.x0 + tile.w));
  fp.xb = std::min(fp.xb, floor_within(pxmax + margin - 0.5 - f.ox_min, tile.x0 - 1, tile.x0 + tile.w));
  fp.ya = std::max(fp.ya, ceil_within(pymin - margin - 0.5 - f.oy_max, tile.y0, tile.y0 + tile.h));
  fp.yb = std::min(fp.yb, floor_within(pymax + margin - 0.5 - f.oy_min, tile.y0 - 1, tile.y0 + tile.h));
  if (fp.xa > fp.xb || fp.ya > fp.yb) return false;
  if (fp.xa < fp.xb || fp.ya < fp.yb) set_edge_functions(P, margin, fp);  // more than one pixel
  return true;
}

// Scanline span: on row y the edge functions bound the sample points (offset
// ox, oy from the pixel centres) to [xl, xr] (each edge with ea != 0 gives
// one side; ea == 0 accepts or rejects the whole row). Narrows [x_from,
// x_to]; returns false for an empty row.
inline bool row_span(const TriangleFootprint& fp, const Tile& tile, int y, double ox, double oy, int& x_from,
                     int& x_to) {
  const double Y = y + 0.5 + oy;
  double xl = -INFINITY, xr = INFINITY;
  bool empty = false;
  for (int i = 0; i < 3; ++i) {
    const double r = fp.eb[i] * Y + fp.ec[i];  // edge value at X = 0
    if (fp.ea[i] > 0) xl = std::max(xl, -r * fp.inv_ea[i]);
    else if (fp.ea[i] < 0) xr = std::min(xr, -r * fp.inv_ea[i]);
    else empty |= r < 0;
  }
  if (empty) return false;
  // X = x + 0.5 + ox in [xl, xr], widened by the rounding of xl and xr.
  const double hair = detail::span_hair(xl, xr);
  x_from = std::max(x_from, ceil_within(xl - hair - 0.5 - ox, tile.x0, tile.x0 + tile.w));
  x_to = std::min(x_to, floor_within(xr + hair - 0.5 - ox, tile.x0 - 1, tile.x0 + tile.w));
  return true;
}

// Entries row + x_from .. row + x_to (one row of one sample) against the
// triangle, four at a time (watertight_hit4); lanes whose window ends before
// zlow are skipped, unsure lanes go to the scalar test. Returns true if any
// sample's nearest hit changed.
inline bool test_row4(const Frame& f, Tile& tile, const detail::PermutedTriangle& pt, int row, int x_from,
                      int x_to, float zlow, uint32_t id, const float A[3], const float B[3], const float C[3]) {
  bool changed = false;
  const __m128 zlow4 = _mm_set1_ps(zlow);
  for (int x = x_from; x <= x_to; x += 4) {
    const int q = row + x;
    // Lanes whose window reaches the triangle's nearest depth (usually none behind a hit).
    const int live = ((1 << std::min(4, x_to - x + 1)) - 1) &
                     _mm_movemask_ps(_mm_cmpge_ps(_mm_loadu_ps(tile.bound + q), zlow4));
    if (live == 0) continue;
    const detail::Hits4 h =
        detail::watertight_hit4(pt, tile.ray_sx + q, tile.ray_sy + q, tile.ray_sz + q, f.znear, tile.bound + q, live);
    for (int m = h.hit; m != 0; m &= m - 1) {
      const int l = __builtin_ctz(unsigned(m));
      changed |= accept_hit(f, tile, q + l, id, h.t[l]);
    }
    for (int m = h.unsure; m != 0; m &= m - 1)
      changed |= test_pixel(f, tile, q + __builtin_ctz(unsigned(m)), id, A, B, C);
  }
  return changed;
}

// The exact per-sample work for one triangle: only the sample points of its
// footprint whose t window reaches its nearest depth get the exact test. A
// triangle touching the eye plane is tested against the whole tile. Returns
// true if any sample's nearest hit changed. The projection and edge
// functions are computed once for every sample.
bool test_triangle(const Frame& f, Tile& tile, const PackedTri& tri) {
  float A[3], B[3], C[3];
  relative_vertices(f, tri, A, B, C);
  const float* V[3] = {A, B, C};
  double z[3], mag = 0;
  for (int c = 0; c < 3; ++c) {
    z[c] = f.fwd[0] * V[c][0] + f.fwd[1] * V[c][1] + f.fwd[2] * V[c][2];
    for (int k = 0; k < 3; ++k) mag = std::max(mag, double(std::fabs(V[c][k])));
  }
  const double zmin = std::min({z[0], z[1], z[2]}), zmax = std::max({z[0], z[1], z[2]});
  const double zlow = zmin - detail::hit_depth_slack(mag);  // below any t the float test can return
  if (zlow > tile.tmax) return false;
  if (detail::before_near_plane(zmax, double(f.znear))) return false;

  TriangleFootprint fp{};
  fp.xa = tile.x0;
  fp.xb = tile.x0 + tile.w - 1;
  fp.ya = tile.y0;
  fp.yb = tile.y0 + tile.h - 1;
  fp.edges = false;
  if (detail::projectable(zmin, mag) && !project_triangle(f, tile, V, z, mag, fp)) return false;

  bool changed = false;
  const uint32_t id = tri.index + 1;
  const float zlow_f = detail::float_at_or_below(zlow);
  // In a tile whose rays share one axis permutation, four samples of a row
  // at a time; a narrow footprint's rows are tested whole, as four lanes cost
  // less than their span.
  const bool four = tile.one_axes && !tile.collect;
  detail::PermutedTriangle pt;
  if (four) pt = detail::permute_triangle(A, B, C, tile.kx, tile.ky, tile.kz, tile.sx_max, tile.sy_max);
  const bool spans = fp.edges && (!four || fp.xb - fp.xa >= 8);
  for (int s = 0; s < f.samples; ++s)
    for (int y = fp.ya; y <= fp.yb; ++y) {
      int x_from = fp.xa, x_to = fp.xb;
      if (spans && !row_span(fp, tile, y, f.ox[s], f.oy[s], x_from, x_to)) continue;
      const int row = s * kTilePixels + (y - tile.y0) * tile.w - tile.x0;  // entry of pixel x: row + x
      if (four) {
        changed |= test_row4(f, tile, pt, row, x_from, x_to, zlow_f, id, A, B, C);
        continue;
      }
      for (int x = x_from; x <= x_to; ++x) {
        const int q = row + x;
        if (zlow_f > tile.bound[q]) continue;  // all of the triangle lies beyond this sample's window
        changed |= test_pixel(f, tile, q, id, A, B, C);
      }
    }
  return changed;
}

// ---- the walk through the structure

using Structure = OctreeTracer::Impl;

// The triangles of one BVH leaf; a leaf whose box covers a single pixel
// centre of the tile skips the projection.
inline bool test_bvh_leaf(const Structure& s, const Frame& f, Tile& tile, const BvhNode& leaf,
                          const PixelRect& rect) {
  bool changed = false;
  if (rect.xa == rect.xb && rect.ya == rect.yb) {
    for (uint32_t i = 0; i < leaf.count(); ++i)
      changed |= test_triangle_at(f, tile, s.tris[leaf.first + i], rect.xa, rect.ya);
  } else {
    for (uint32_t i = 0; i < leaf.count(); ++i) changed |= test_triangle(f, tile, s.tris[leaf.first + i]);
  }
  return changed;
}

// One component's BVH, children nearest box first. Its root box is visible,
// with nearest depth root_near and pixel rectangle root_rect.
void walk_component(const Structure& s, const Frame& f, Tile& tile, uint32_t c, double root_near,
                    const PixelRect& root_rect) {
  struct Entry {
    double near;
    uint32_t node;
    PixelRect rect;
  };
  Entry stack[128];
  int top = 0;
  stack[top++] = {root_near, s.components[c].bvh_root, root_rect};
  while (top > 0) {
    const Entry e = stack[--top];
    if (e.near > tile.tmax) continue;
    const BvhNode& b = s.bvh[e.node];
    if (b.count() != 0) {
      if (test_bvh_leaf(s, f, tile, b, e.rect)) update_tile_tmax(f, tile);
      continue;
    }
    double n0, n1;
    PixelRect r0, r1;
    const bool v0 = box_visible(f, tile, s.bvh[b.first].box, n0, r0);
    const bool v1 = box_visible(f, tile, s.bvh[b.first + 1].box, n1, r1);
    if (v0 && v1) {
      const bool left_near = n0 <= n1;
      stack[top++] = left_near ? Entry{n1, b.first + 1, r1} : Entry{n0, b.first, r0};
      stack[top++] = left_near ? Entry{n0, b.first, r0} : Entry{n1, b.first + 1, r1};
    } else if (v0) {
      stack[top++] = {n0, b.first, r0};
    } else if (v1) {
      stack[top++] = {n1, b.first + 1, r1};
    }
  }
}

// An octree leaf: its components not yet tested in this pass (each is tested
// once per tile, whichever leaf reaches it first) and visible, nearest box
// first.
void walk_leaf(const Structure& s, const Frame& f, Tile& tile, Scratch& scratch, const OctNode& node) {
  struct Pick {
    double near;
    uint32_t c;
    PixelRect rect;
  };
  Pick picks[256];
  uint32_t np = 0;
  double near;
  PixelRect rect;
  for (uint32_t r = 0; r < node.count(); ++r) {
    const uint32_t c = s.leaf_refs[node.first + r];
    if (scratch.stamp[c] == scratch.clock) continue;
    scratch.stamp[c] = scratch.clock;
    if (!box_visible(f, tile, s.components[c].box, near, rect)) continue;
    if (np == 256) {  // a huge leaf (max_components_per_leaf > 256): no sorting
      walk_component(s, f, tile, c, near, rect);
      continue;
    }
    uint32_t k = np++;
    while (k > 0 && picks[k - 1].near > near) {
      picks[k] = picks[k - 1];
      --k;
    }
    picks[k] = {near, c, rect};
  }
  for (uint32_t k = 0; k < np; ++k)
    if (picks[k].near <= tile.tmax) walk_component(s, f, tile, picks[k].c, picks[k].near, picks[k].rect);
}

// Front-to-back child order for an eye in octant 0 of a node (see the top of
// the file); for another octant, xor the child index with the eye's side.
constexpr int kChildOrder[8] = {0, 1, 2, 4, 3, 5, 6, 7};

// One pass of a tile through the whole structure: octree nodes front to back.
void walk_tile(const Structure& s, const Frame& f, Tile& tile, Scratch& scratch) {
  if (++scratch.clock == 0) {  // wrapped: restart the stamps
    std::fill(scratch.stamp.begin(), scratch.stamp.end(), 0u);
    scratch.clock = 1;
  }
  update_tile_tmax(f, tile);
  double near;
  PixelRect rect;
  uint32_t stack[kOctreeStack];
  int top = 0;
  if (!s.octree.empty() && !s.tris.empty()) stack[top++] = 0;
  while (top > 0) {
    const OctNode& node = s.octree[stack[--top]];
    if (!box_visible(f, tile, node.box, near, rect)) continue;
    if (node.leaf()) {
      walk_leaf(s, f, tile, scratch, node);
      continue;
    }
    int side = 0;
    for (int k = 0; k < 3; ++k)
      if (f.eye[k] > 0.5 * (double(node.box.lo[k]) + double(node.box.hi[k]))) side |= 1 << k;
    for (int j = 7; j >= 0; --j) stack[top++] = node.first + uint32_t(kChildOrder[j] ^ side);
  }
}

// A tile from start to finish: the nearest hits, each with the lowest index
// among its remembered ties; then, only if some sample's window held more hits
// than it remembers, a pass over the fixed windows that keeps the lowest
// index; then the tile's samples are written out.
void trace_tile(const Structure& s, const Frame& f, Tile& tile, Scratch& scratch, uint32_t* const* out,
                float* const* tout) {
  walk_tile(s, f, tile, scratch);
  bool overflow = false;
  const int n = tile.w * tile.h;
  for (int k = 0; k < f.samples; ++k)
    for (int p = k * kTilePixels; p < k * kTilePixels + n; ++p) {
      const uint8_t ties = tile.tie[p];
      if (ties == kTieOverflow) {
        overflow = true;
      } else {
        for (uint8_t j = 0; j < ties; ++j) tile.hit[p] = std::min(tile.hit[p], tile.tie_id[p][j]);
      }
    }
  if (overflow) {
    tile.collect = true;
    walk_tile(s, f, tile, scratch);
  }
  const int width = f.cam->width;
  for (int k = 0; k < f.samples; ++k)
    for (int j = 0; j < tile.h; ++j)
      for (int i = 0; i < tile.w; ++i) {
        const int q = k * kTilePixels + j * tile.w + i;
        const size_t o = size_t(tile.y0 + j) * size_t(width) + size_t(tile.x0 + i);
        out[k][o] = tile.hit[q];
        if (tout) tout[k][o] = tile.hit[q] ? tile.best[q] : 0.0f;
      }
}

}  // namespace

void OctreeTracer::Impl::trace(const Camera& cam, const std::array<double, 2>* offsets, int samples,
                               uint32_t* const* out, float* const* tout) const {
  std::vector<Camera> shifted(size_t(samples), cam);
  std::vector<std::unique_ptr<detail::PixelDirections>> dirs;
  for (int k = 0; k < samples; ++k) {
    shifted[size_t(k)].shift_x += offsets[k][0];
    shifted[size_t(k)].shift_y += offsets[k][1];
    dirs.push_back(std::make_unique<detail::PixelDirections>(shifted[size_t(k)]));
  }
  const Frame f = make_frame(cam, offsets, dirs);
  const int tiles_x = (cam.width + kTile - 1) / kTile, tiles_y = (cam.height + kTile - 1) / kTile;
  const uint32_t nc = uint32_t(components.size());
  tbb::parallel_for(tbb::blocked_range<int>(0, tiles_x * tiles_y, 2), [&](const tbb::blocked_range<int>& r) {
    detail::DenormalsOff ftz;
    Scratch& s = scratch.local();
    if (s.stamp.size() != nc) {
      s.stamp.assign(nc, 0u);
      s.clock = 0;
    }
    if (!s.tile) s.tile = std::make_shared<Tile>();
    Tile& tile = *s.tile;
    for (int ti = r.begin(); ti < r.end(); ++ti) {
      setup_tile(f, tile, (ti % tiles_x) * kTile, (ti / tiles_x) * kTile);
      trace_tile(*this, f, tile, s, out, tout);
    }
  });
}

// ---------------------------------------------------------------- public


OctreeTracer::OctreeTracer(const Scene& scene, const OctreeOptions& options)
    : impl_(std::make_unique<Impl>()) {
  if (options.max_depth < 0 || options.max_depth > kMaxOctreeDepth)
    throw std::invalid_argument("octree: max_depth " + std::to_string(options.max_depth) +
                                " must lie in [0, " + std::to_string(kMaxOctreeDepth) + "]");
  if (options.max_components_per_leaf < 1)
    throw std::invalid_argument("octree: max_components_per_leaf must be at least 1");
  if (options.max_triangles_per_bvh_leaf < 1 || options.max_triangles_per_bvh_leaf > (1 << 20))
    throw std::invalid_argument("octree: max_triangles_per_bvh_leaf must lie in [1, 2^20]");
  validate(scene);
  if (scene.triangle_count() >= size_t(std::numeric_limits<uint32_t>::max()) / 2)
    throw std::invalid_argument("octree: too many triangles for 32-bit indices");
  impl_->options = options;
  impl_->build(scene);
}

OctreeTracer::~OctreeTracer() = default;

void OctreeTracer::trace(const Camera& camera, uint32_t* tri_plus_one, float* t) const {
  detail::check_camera(camera);
  if (!tri_plus_one) throw std::invalid_argument("octree trace: output buffer is null");
  const std::array<double, 2> centre = {0.0, 0.0};
  impl_->trace(camera, &centre, 1, &tri_plus_one, t ? &t : nullptr);
}

void OctreeTracer::trace_samples(const Camera& camera, const std::vector<std::array<double, 2>>& offsets,
                                 uint32_t* const* out) const {
  detail::check_camera(camera);
  if (offsets.empty()) throw std::invalid_argument("octree trace: no sample offsets");
  for (size_t k = 0; k < offsets.size(); ++k)
    if (!out[k]) throw std::invalid_argument("octree trace: output buffer is null");
  for (size_t k0 = 0; k0 < offsets.size(); k0 += kMaxSamples)  // a walk holds at most kMaxSamples
    impl_->trace(camera, offsets.data() + k0, int(std::min(offsets.size() - k0, size_t(kMaxSamples))), out + k0,
                 nullptr);
}

size_t OctreeTracer::memory_bytes() const {
  return impl_->tris.size() * sizeof(PackedTri) + impl_->bvh.size() * sizeof(BvhNode) +
         impl_->components.size() * sizeof(ComponentNode) + impl_->octree.size() * sizeof(OctNode) +
         impl_->leaf_refs.size() * sizeof(uint32_t);
}

double OctreeTracer::build_seconds() const { return impl_->build_seconds; }

OctreeTracer::Stats OctreeTracer::stats() const {
  Stats s;
  s.octree_nodes = impl_->octree.size();
  for (const auto& n : impl_->octree) s.octree_leaves += n.leaf() ? 1 : 0;
  s.leaf_references = impl_->leaf_refs.size();
  s.depth_reached = impl_->depth_reached;
  s.components = impl_->components.size();
  s.bvh_nodes = impl_->bvh.size();
  return s;
}

void Tracer::trace_samples(const Camera& camera, const std::vector<std::array<double, 2>>& offsets,
                           uint32_t* const* out) const {
  for (size_t k = 0; k < offsets.size(); ++k) {
    Camera c = camera;
    c.shift_x += offsets[k][0];
    c.shift_y += offsets[k][1];
    trace(c, out[k]);
  }
}

std::vector<uint32_t> Tracer::trace(const Camera& camera) const {
  detail::check_camera(camera);
  std::vector<uint32_t> out(size_t(camera.width) * size_t(camera.height));
  trace(camera, out.data(), nullptr);
  return out;
}

}  // namespace perclod
