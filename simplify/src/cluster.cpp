// Rossignac-Borrel vertex clustering (Rossignac & Borrel 1993), with Belblidia's option of
// keeping each component's bounding box (Belblidia, Perrin, Paul 1995).
//
//   1. Grading: weight of a vertex = (longest incident edge) / (largest angle
//      between two incident edges, radians): vertices likely on a silhouette
//      and vertices bounding big faces weigh more.
//   2. Clustering: a uniform grid of cell size k * p(d) from the bounding-box
//      corner; with preserve_bbox each component is clustered on its own.
//   3. Representative per cell: the weighted centre of mass, or the heaviest
//      vertex. With preserve_bbox, a representative whose cell holds a vertex
//      on its component's box face is snapped onto that face.
//   4. Elimination: triangles whose corners fall in one or two cells become
//      points or edges; duplicate triangles are dropped; dangling edges (not
//      bounding a kept triangle) and isolated points (bounding nothing kept)
//      are counted - a Scene holds triangles only.
#include <algorithm>
#include <array>
#include <cmath>
#include <unordered_map>
#include <unordered_set>

#include "simplify_internal.h"

namespace perclod::detail {

namespace {

struct CellKey {
  int64_t group, x, y, z;
  bool operator==(const CellKey& o) const {
    return group == o.group && x == o.x && y == o.y && z == o.z;
  }
};
struct CellHash {
  size_t operator()(const CellKey& k) const {
    uint64_t h = uint64_t(k.group) * 0x9E3779B97F4A7C15ull;
    h ^= uint64_t(k.x) * 0xC2B2AE3D27D4EB4Full + (h << 6) + (h >> 2);
    h ^= uint64_t(k.y) * 0x165667B19E3779F9ull + (h << 6) + (h >> 2);
    h ^= uint64_t(k.z) * 0x27D4EB2F165667C5ull + (h << 6) + (h >> 2);
    return size_t(h);
  }
};

struct Vec3 {
  double x, y, z;
};
Vec3 sub(Vec3 a, Vec3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
double dot(Vec3 a, Vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
double norm(Vec3 a) { return std::sqrt(dot(a, a)); }

// A vertex as clustering sees it: a welded vertex within one group (the
// component with preserve_bbox, else 0).
struct Instances {
  std::vector<uint32_t> welded;       // per instance
  std::vector<uint32_t> group;        // per instance
  std::vector<uint32_t> corner;       // per corner of the faces in play: instance
};

Instances make_instances(const Work& w, bool per_component) {
  const Scene& s = *w.scene;
  Instances in;
  std::unordered_map<uint64_t, uint32_t> id;
  in.corner.reserve(3 * w.faces.size());
  for (uint32_t t : w.faces) {
    uint32_t g = per_component ? s.component_of(t) : 0;
    for (int k = 0; k < 3; ++k) {
      uint32_t wv = w.weld.corner[3 * size_t(t) + k];
      auto [it, fresh] = id.try_emplace((uint64_t(g) << 32) | wv, uint32_t(in.welded.size()));
      if (fresh) {
        in.welded.push_back(wv);
        in.group.push_back(g);
      }
      in.corner.push_back(it->second);
    }
  }
  return in;
}

Vec3 position(const Work& w, uint32_t welded) {
  const float* p = &w.weld.positions[3 * size_t(welded)];
  return {p[0], p[1], p[2]};
}

// Rossignac-Borrel grading over the welded vertices (edges of every face).
std::vector<double> grade(const Work& w, const Instances& in) {
  const size_t nv = in.welded.size();
  std::vector<uint32_t> start(nv + 1, 0);
  for (uint32_t c : in.corner) start[c + 1] += 2;
  for (size_t i = 0; i < nv; ++i) start[i + 1] += start[i];
  std::vector<uint32_t> fill(start.begin(), start.end() - 1), nbr(start[nv]);
  for (size_t f = 0; f < in.corner.size() / 3; ++f)
    for (int k = 0; k < 3; ++k) {
      uint32_t a = in.corner[3 * f + k];
      nbr[fill[a]++] = in.corner[3 * f + (k + 1) % 3];
      nbr[fill[a]++] = in.corner[3 * f + (k + 2) % 3];
    }
  std::vector<double> weight(nv, 0.0);
  constexpr uint32_t kMaxPairs = 48;  // huge fans: the first edges suffice
  std::vector<Vec3> dir;
  for (size_t v = 0; v < nv; ++v) {
    Vec3 p = position(w, in.welded[v]);
    dir.clear();
    double longest = 0;
    for (uint32_t i = start[v]; i < start[v + 1]; ++i) {
      Vec3 d = sub(position(w, in.welded[nbr[i]]), p);
      double l = norm(d);
      if (l <= 0) continue;
      longest = std::max(longest, l);
      if (dir.size() < kMaxPairs) dir.push_back({d.x / l, d.y / l, d.z / l});
    }
    double max_angle = 0;
    for (size_t i = 0; i < dir.size(); ++i)
      for (size_t j = i + 1; j < dir.size(); ++j)
        max_angle = std::max(max_angle, std::acos(std::clamp(dot(dir[i], dir[j]), -1.0, 1.0)));
    weight[v] = max_angle > 0 ? longest / max_angle : longest;
  }
  return weight;
}

struct Cells {
  std::vector<uint32_t> of_instance;  // cell per instance
  std::vector<Vec3> rep;              // representative per cell
};

Cells cluster(const Work& w, const Instances& in, const std::vector<double>& weight,
              double cell, const SimplifyOptions& opt) {
  const Bounds b = scene_bounds(*w.scene);
  Cells c;
  std::unordered_map<CellKey, uint32_t, CellHash> id;
  c.of_instance.resize(in.welded.size());
  std::vector<double> wsum;
  std::vector<Vec3> acc;
  std::vector<uint32_t> heaviest;
  std::vector<uint32_t> count;
  for (size_t i = 0; i < in.welded.size(); ++i) {
    Vec3 p = position(w, in.welded[i]);
    CellKey k{in.group[i], int64_t(std::floor((p.x - b.lo[0]) / cell)),
              int64_t(std::floor((p.y - b.lo[1]) / cell)), int64_t(std::floor((p.z - b.lo[2]) / cell))};
    auto [it, fresh] = id.try_emplace(k, uint32_t(wsum.size()));
    if (fresh) {
      wsum.push_back(0);
      acc.push_back({0, 0, 0});
      heaviest.push_back(uint32_t(i));
      count.push_back(0);
    }
    uint32_t ci = it->second;
    c.of_instance[i] = ci;
    double wt = weight[i];
    wsum[ci] += wt;
    acc[ci] = {acc[ci].x + wt * p.x, acc[ci].y + wt * p.y, acc[ci].z + wt * p.z};
    count[ci]++;
    if (wt > weight[heaviest[ci]]) heaviest[ci] = uint32_t(i);
  }
  c.rep.resize(wsum.size());
  for (size_t ci = 0; ci < wsum.size(); ++ci) {
    if (opt.cluster_center_of_mass && wsum[ci] > 0)
      c.rep[ci] = {acc[ci].x / wsum[ci], acc[ci].y / wsum[ci], acc[ci].z / wsum[ci]};
    else
      c.rep[ci] = position(w, in.welded[heaviest[ci]]);
  }
  if (opt.cluster_center_of_mass) {  // all-zero weights: plain centroid
    std::vector<Vec3> mean(wsum.size(), {0, 0, 0});
    for (size_t i = 0; i < in.welded.size(); ++i) {
      uint32_t ci = c.of_instance[i];
      if (wsum[ci] > 0) continue;
      Vec3 p = position(w, in.welded[i]);
      mean[ci] = {mean[ci].x + p.x / count[ci], mean[ci].y + p.y / count[ci], mean[ci].z + p.z / count[ci]};
    }
    for (size_t ci = 0; ci < wsum.size(); ++ci)
      if (!(wsum[ci] > 0)) c.rep[ci] = mean[ci];
  }
  return c;
}

// Belblidia: a cell holding a vertex on its group's box face puts its
// representative on that face (if it touches both opposite faces, the nearer).
void snap_to_boxes(const Work& w, const Instances& in, Cells& c) {
  size_t ng = 0;
  for (uint32_t g : in.group) ng = std::max<size_t>(ng, g + 1);
  std::vector<std::array<double, 6>> box(ng, {INFINITY, INFINITY, INFINITY, -INFINITY, -INFINITY, -INFINITY});
  for (size_t i = 0; i < in.welded.size(); ++i) {
    Vec3 p = position(w, in.welded[i]);
    auto& bx = box[in.group[i]];
    double v[3] = {p.x, p.y, p.z};
    for (int a = 0; a < 3; ++a) {
      bx[a] = std::min(bx[a], v[a]);
      bx[3 + a] = std::max(bx[3 + a], v[a]);
    }
  }
  // touch[cell][axis]: bit 1 = on the low face, bit 2 = on the high face
  std::vector<std::array<uint8_t, 3>> touch(c.rep.size(), {0, 0, 0});
  std::vector<uint32_t> group_of(c.rep.size(), 0);
  for (size_t i = 0; i < in.welded.size(); ++i) {
    Vec3 p = position(w, in.welded[i]);
    const auto& bx = box[in.group[i]];
    double v[3] = {p.x, p.y, p.z};
    uint32_t ci = c.of_instance[i];
    group_of[ci] = in.group[i];
    for (int a = 0; a < 3; ++a) {
      if (v[a] == bx[a]) touch[ci][a] |= 1;
      if (v[a] == bx[3 + a]) touch[ci][a] |= 2;
    }
  }
  for (size_t ci = 0; ci < c.rep.size(); ++ci) {
    const auto& bx = box[group_of[ci]];
    double* r[3] = {&c.rep[ci].x, &c.rep[ci].y, &c.rep[ci].z};
    for (int a = 0; a < 3; ++a) {
      uint8_t t = touch[ci][a];
      if (t == 1) *r[a] = bx[a];
      if (t == 2) *r[a] = bx[3 + a];
      if (t == 3) *r[a] = (*r[a] - bx[a] <= bx[3 + a] - *r[a]) ? bx[a] : bx[3 + a];
    }
  }
}

uint64_t edge_key(uint32_t a, uint32_t b) {
  if (a > b) std::swap(a, b);
  return (uint64_t(a) << 32) | b;
}

}  // namespace

void cluster_simplify(const Work& w, const SimplifyOptions& opt, SimplifyStats& stats, Result& out) {
  const double cell = opt.k * opt.pixel_footprint;
  stats.tolerance = cell;
  Instances in = make_instances(w, opt.preserve_bbox);
  stats.vertices_before = in.welded.size();
  std::vector<double> weight = grade(w, in);
  Cells c = cluster(w, in, weight, cell, opt);
  if (opt.preserve_bbox) snap_to_boxes(w, in, c);

  // Elimination: triangles, then edges and points that bound nothing kept.
  struct TriKey {
    uint32_t a, b, c;
    bool operator==(const TriKey& o) const { return a == o.a && b == o.b && c == o.c; }
  };
  struct TriHash {
    size_t operator()(const TriKey& k) const {
      return size_t(k.a) * 0x9E3779B97F4A7C15ull ^ size_t(k.b) * 0xC2B2AE3D27D4EB4Full ^ size_t(k.c);
    }
  };
  std::unordered_set<TriKey, TriHash> tris;
  std::unordered_set<uint64_t> tri_edges, edges;
  std::unordered_set<uint32_t> touched, points;
  std::vector<uint32_t> out_of_cell(c.rep.size(), UINT32_MAX);
  for (size_t f = 0; f < w.faces.size(); ++f) {
    uint32_t k[3];
    for (int j = 0; j < 3; ++j) k[j] = c.of_instance[in.corner[3 * f + j]];
    if (k[0] != k[1] && k[1] != k[2] && k[0] != k[2]) {
      uint32_t s[3] = {k[0], k[1], k[2]};
      std::sort(s, s + 3);
      if (!tris.insert({s[0], s[1], s[2]}).second) continue;  // duplicate
      for (int j = 0; j < 3; ++j) {
        tri_edges.insert(edge_key(k[j], k[(j + 1) % 3]));
        touched.insert(k[j]);
        uint32_t& o = out_of_cell[k[j]];
        if (o == UINT32_MAX) {
          o = uint32_t(out.positions.size() / 3);
          out.positions.insert(out.positions.end(),
                               {float(c.rep[k[j]].x), float(c.rep[k[j]].y), float(c.rep[k[j]].z)});
        }
        out.indices.push_back(o);
      }
      out.source.push_back(w.faces[f]);
    } else if (k[0] != k[1] || k[1] != k[2]) {
      uint32_t a = k[0], b = k[0] != k[1] ? k[1] : k[2];
      edges.insert(edge_key(a, b));
    } else {
      points.insert(k[0]);
    }
  }
  for (uint64_t e : edges) {
    if (tri_edges.count(e)) continue;
    stats.cluster_dangling_edges++;
    touched.insert(uint32_t(e >> 32));
    touched.insert(uint32_t(e & 0xffffffffu));
  }
  for (uint32_t p : points) stats.cluster_isolated_points += !touched.count(p);
  stats.vertices_after = out.positions.size() / 3;

  // Belblidia's measures: every vertex against its cell's representative.
  double sum = 0, mx = 0;
  for (size_t i = 0; i < in.welded.size(); ++i) {
    Vec3 d = sub(position(w, in.welded[i]), c.rep[c.of_instance[i]]);
    double l = norm(d);
    sum += l;
    mx = std::max(mx, l);
  }
  double diag = w.diagonal > 0 ? w.diagonal : 1.0;
  stats.max_displacement_rel = mx / diag;
  stats.mean_displacement_rel = in.welded.empty() ? 0 : sum / in.welded.size() / diag;
}

}  // namespace perclod::detail
