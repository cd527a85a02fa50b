// The collapse simplifier: Garland-Heckbert quadrics and half-edge collapses
// (v0 removed, v1 kept where it is) on OpenMesh's half-edge structure, with a
// loop of our own rather than OpenMesh's Decimater (bench_simplify measures
// both). Why our own loop: the priority breaks ties between equal (zero)
// costs by edge length and refuses fans above a valence cap, which is what
// turns the Decimater's minute on a flat wall into milliseconds; and the
// label constraints are plain vertex flags checked once per candidate.
//
// Constraints (Paper, Bounded): a vertex of a perceptible triangle is never
// v0, so it neither moves nor disappears and every perceptible triangle keeps
// its vertices, connectivity and orientation; any collapse taken therefore
// only removes imperceptible or undisplayable triangles.
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numeric>
#include <queue>

#include "quadric.h"
#include "simplify_internal.h"

namespace perclod::detail {

namespace {

struct Traits : OpenMesh::DefaultTraits {
  VertexAttributes(OpenMesh::Attributes::Status);
  EdgeAttributes(OpenMesh::Attributes::Status);
  FaceAttributes(OpenMesh::Attributes::Status);
  HalfedgeAttributes(OpenMesh::Attributes::Status | OpenMesh::Attributes::PrevHalfedge);
};
using Mesh = OpenMesh::TriMesh_ArrayKernelT<Traits>;
using VH = OpenMesh::VertexHandle;
using FH = OpenMesh::FaceHandle;
using HH = OpenMesh::HalfedgeHandle;
using Vec = OpenMesh::Vec3d;

Vec to_d(const Mesh::Point& p) { return Vec(p[0], p[1], p[2]); }

// 4 sqrt(3) area / sum of squared edge lengths: 1 equilateral, 0 degenerate.
double quality(const Vec& a, const Vec& b, const Vec& c) {
  double l = (b - a).sqrnorm() + (c - b).sqrnorm() + (a - c).sqrnorm();
  if (l <= 0) return 0;
  return 2.0 * std::sqrt(3.0) * ((b - a) % (c - a)).norm() / l;
}

// The working mesh and everything we keep per element (vectors indexed by
// handle index; OpenMesh keeps handles stable until garbage collection, which
// we never run).
struct Model {
  Mesh mesh;
  std::vector<uint32_t> face_source;   // input triangle per face
  std::vector<uint32_t> vert_welded;   // welded vertex per mesh vertex
  std::vector<uint8_t> locked;         // vertex may not be v0
  std::vector<uint8_t> feature_edge;   // constraint line: never collapsed
  std::vector<Quadric> qa;             // area-weighted: the priority
  std::vector<Quadric> qd;             // unit-weight: the distance bound
  std::vector<uint32_t> merged_into;   // v0 -> v1 of its collapse
  size_t faces_alive = 0;
};

bool is_perceptible(const Work& w, uint32_t src) {
  return (*w.labels)[src] == Label::Perceptible;
}

// ---- building the mesh --------------------------------------------------

VH add_vertex(Model& m, const Work& w, uint32_t welded) {
  const float* p = &w.weld.positions[3 * size_t(welded)];
  VH v = m.mesh.add_vertex(Mesh::Point(p[0], p[1], p[2]));
  m.vert_welded.push_back(welded);
  return v;
}

// OpenMesh prints a line per refused face; we count them instead.
struct QuietOpenMesh {
  QuietOpenMesh() : was(omerr().is_enabled()) { omerr().disable(); }
  ~QuietOpenMesh() {
    if (was) omerr().enable();
  }
  bool was;
};

void build_mesh(Model& m, const Work& w, SimplifyStats& stats) {
  const Scene& s = *w.scene;
  QuietOpenMesh quiet;
  std::vector<int> vh_of(w.weld.positions.size() / 3, -1);
  m.mesh.reserve(w.faces.size(), 3 * w.faces.size() / 2, w.faces.size());
  m.vert_welded.reserve(w.faces.size());
  for (uint32_t src : w.faces) {
    uint32_t c[3];
    for (int k = 0; k < 3; ++k) c[k] = w.weld.remap[s.indices[3 * size_t(src) + k]];
    FH f;
    bool degenerate = c[0] == c[1] || c[1] == c[2] || c[0] == c[2];
    if (!degenerate) {
      VH v[3];
      for (int k = 0; k < 3; ++k) {
        if (vh_of[c[k]] < 0) vh_of[c[k]] = add_vertex(m, w, c[k]).idx();
        v[k] = VH(vh_of[c[k]]);
      }
      f = m.mesh.add_face(v[0], v[1], v[2]);
    }
    if (!f.is_valid()) {
      // Non-manifold edge or vertex (or repeated corners): the face gets its
      // own vertices, disconnected from its neighbours, and stays.
      (degenerate ? stats.degenerate_faces : stats.nonmanifold_faces_duplicated)++;
      VH v[3];
      for (int k = 0; k < 3; ++k) v[k] = add_vertex(m, w, c[k]);
      f = m.mesh.add_face(v[0], v[1], v[2]);
    }
    if (size_t(f.idx()) != m.face_source.size())
      throw std::logic_error("simplify: OpenMesh face numbering out of step");
    m.face_source.push_back(src);
  }
  m.faces_alive = m.face_source.size();
  m.merged_into.resize(m.mesh.n_vertices());
  std::iota(m.merged_into.begin(), m.merged_into.end(), 0u);
}

// ---- quadrics and constraints -------------------------------------------

// Plane through p containing edge direction e and perpendicular to the face
// normal n: keeps borders and creases from sliding.
void add_edge_plane(Model& m, VH a, VH b, const Vec& n, double weight) {
  Vec pa = to_d(m.mesh.point(a)), pb = to_d(m.mesh.point(b));
  Vec e = pb - pa;
  Vec q = e % n;
  double len = q.norm();
  if (len <= 0) return;
  q /= len;
  double d = -(q | pa);
  for (VH v : {a, b}) {
    m.qa[v.idx()].add_plane(q[0], q[1], q[2], d, weight * e.sqrnorm());
    m.qd[v.idx()].add_plane(q[0], q[1], q[2], d, 1.0);
  }
}

void init_quadrics(Model& m, const SimplifyOptions& opt) {
  Mesh& mesh = m.mesh;
  m.qa.assign(mesh.n_vertices(), Quadric{});
  m.qd.assign(mesh.n_vertices(), Quadric{});
  std::vector<Vec> normal(mesh.n_faces(), Vec(0, 0, 0));
  for (FH f : mesh.faces()) {
    HH h = mesh.halfedge_handle(f);
    VH v[3] = {mesh.from_vertex_handle(h), mesh.to_vertex_handle(h),
               mesh.to_vertex_handle(mesh.next_halfedge_handle(h))};
    Vec p0 = to_d(mesh.point(v[0])), p1 = to_d(mesh.point(v[1])), p2 = to_d(mesh.point(v[2]));
    Vec n = (p1 - p0) % (p2 - p0);
    double len = n.norm();
    if (len <= 0) continue;  // degenerate: no plane
    n /= len;
    normal[f.idx()] = n;
    double d = -(n | p0);
    for (VH x : v) {
      m.qa[x.idx()].add_plane(n[0], n[1], n[2], d, 0.5 * len);
      m.qd[x.idx()].add_plane(n[0], n[1], n[2], d, 1.0);
    }
  }
  const double cos_feature = std::cos(opt.feature_angle_deg * M_PI / 180.0);
  m.feature_edge.assign(mesh.n_edges(), 0);
  for (auto e : mesh.edges()) {
    HH h0 = mesh.halfedge_handle(e, 0), h1 = mesh.halfedge_handle(e, 1);
    VH a = mesh.from_vertex_handle(h0), b = mesh.to_vertex_handle(h0);
    FH f0 = mesh.face_handle(h0), f1 = mesh.face_handle(h1);
    if (!f0.is_valid() || !f1.is_valid()) {
      FH f = f0.is_valid() ? f0 : f1;
      add_edge_plane(m, a, b, normal[f.idx()], opt.boundary_weight);
      continue;
    }
    const Vec &n0 = normal[f0.idx()], &n1 = normal[f1.idx()];
    if (n0.sqrnorm() == 0 || n1.sqrnorm() == 0) continue;
    if ((n0 | n1) < cos_feature) {
      add_edge_plane(m, a, b, n0, opt.boundary_weight);
      add_edge_plane(m, a, b, n1, opt.boundary_weight);
      if (opt.constraint_lines) {
        m.feature_edge[e.idx()] = 1;
        m.locked[a.idx()] = m.locked[b.idx()] = 1;
      }
    }
  }
}

void lock_perceptible(Model& m, const Work& w) {
  for (FH f : m.mesh.faces())
    if (is_perceptible(w, m.face_source[f.idx()]))
      for (VH v : m.mesh.fv_range(f)) m.locked[v.idx()] = 1;
}

// ---- candidates ------------------------------------------------------------

struct Candidate {
  HH h;
  double cost = 0;
  double error = 0;  // distance bound: sqrt of the unit-weight quadric at v1
};

struct Limits {
  double cos_normal;
  double min_quality;
  int max_valence;
  double tolerance;  // < 0: none
  double tie;        // edge-length tie-break factor
};

// Would moving v0 onto p1 turn a surviving face too far or make a sliver?
bool geometry_ok(const Mesh& mesh, VH v0, VH v1, const Vec& p1, const Limits& lim) {
  for (HH h : mesh.voh_range(v0)) {
    FH f = mesh.face_handle(h);
    if (!f.is_valid()) continue;
    VH a = mesh.to_vertex_handle(h);
    VH b = mesh.to_vertex_handle(mesh.next_halfedge_handle(h));
    if (a == v1 || b == v1) continue;  // removed by the collapse
    Vec p0 = to_d(mesh.point(v0)), pa = to_d(mesh.point(a)), pb = to_d(mesh.point(b));
    Vec n_old = (pa - p0) % (pb - p0);
    Vec n_new = (pa - p1) % (pb - p1);
    double lo = n_old.norm(), ln = n_new.norm();
    if (lo > 0) {
      if (ln <= 0 || (n_old | n_new) < lim.cos_normal * lo * ln) return false;
    }
    double q_new = quality(p1, pa, pb);
    if (q_new < lim.min_quality && q_new < quality(p0, pa, pb)) return false;
  }
  return true;
}

// Topological legality of collapsing h (v0 -> v1), OpenMesh's rules without
// its per-call overhead: the one-rings of v0 and v1 share exactly the
// vertices opposite the edge (link condition); an edge joining two boundary
// vertices must be a boundary edge; a face whose two other edges are both
// on the boundary (an ear) is not collapsed away; the two faces of the edge
// must not share their third vertex. `ring1` holds v1's neighbours.
bool link_ok(const Mesh& mesh, HH h, const std::vector<VH>& ring1) {
  HH o = mesh.opposite_halfedge_handle(h);
  VH v0 = mesh.from_vertex_handle(h);
  VH vl, vr;
  if (mesh.face_handle(h).is_valid()) {
    HH h1 = mesh.next_halfedge_handle(h), h2 = mesh.next_halfedge_handle(h1);
    vl = mesh.to_vertex_handle(h1);
    if (mesh.is_boundary(mesh.opposite_halfedge_handle(h1)) &&
        mesh.is_boundary(mesh.opposite_halfedge_handle(h2)))
      return false;
  }
  if (mesh.face_handle(o).is_valid()) {
    HH o1 = mesh.next_halfedge_handle(o), o2 = mesh.next_halfedge_handle(o1);
    vr = mesh.to_vertex_handle(o1);
    if (mesh.is_boundary(mesh.opposite_halfedge_handle(o1)) &&
        mesh.is_boundary(mesh.opposite_halfedge_handle(o2)))
      return false;
  }
  if (vl.is_valid() && vl == vr) return false;
  VH v1 = mesh.to_vertex_handle(h);
  if (mesh.is_boundary(v0) && mesh.is_boundary(v1) && !mesh.is_boundary(h) && !mesh.is_boundary(o))
    return false;
  for (VH n : mesh.vv_range(v0)) {
    if (n == v1 || n == vl || n == vr) continue;
    if (std::find(ring1.begin(), ring1.end(), n) != ring1.end()) return false;
  }
  return true;
}

// The cheapest legal collapse of v0: costs of all outgoing half-edges first,
// then the (dearer) legality checks in order of cost until one passes.
bool best_candidate(const Model& m, VH v0, const Limits& lim, std::vector<VH>& ring1,
                    std::vector<Candidate>& options, Candidate& best) {
  const Mesh& mesh = m.mesh;
  const Vec p0 = to_d(mesh.point(v0));
  const Quadric& qa0 = m.qa[v0.idx()];
  options.clear();
  int val0 = 0;
  for (HH h : mesh.voh_range(v0)) {
    ++val0;
    VH v1 = mesh.to_vertex_handle(h);
    if (m.feature_edge[mesh.edge_handle(h).idx()]) continue;
    const Vec p1 = to_d(mesh.point(v1));
    double l2 = (p1 - p0).sqrnorm();
    double cost = (qa0 + m.qa[v1.idx()]).eval(p1[0], p1[1], p1[2]) + lim.tie * l2 * l2;
    double err = 0;
    if (lim.tolerance >= 0) {
      err = std::sqrt((m.qd[v0.idx()] + m.qd[v1.idx()]).eval(p1[0], p1[1], p1[2]));
      if (err > lim.tolerance) continue;
    }
    options.push_back({h, cost, err});
  }
  std::sort(options.begin(), options.end(),
            [](const Candidate& a, const Candidate& b) { return a.cost < b.cost; });
  for (const Candidate& c : options) {
    VH v1 = mesh.to_vertex_handle(c.h);
    ring1.clear();
    for (VH n : mesh.vv_range(v1)) ring1.push_back(n);
    if (val0 + int(ring1.size()) - 4 > lim.max_valence) continue;
    if (!link_ok(mesh, c.h, ring1)) continue;
    if (!geometry_ok(mesh, v0, v1, to_d(mesh.point(v1)), lim)) continue;
    best = c;
    if (lim.tolerance < 0)
      best.error = std::sqrt((m.qd[v0.idx()] + m.qd[v1.idx()]).eval(mesh.point(v1)[0], mesh.point(v1)[1], mesh.point(v1)[2]));
    return true;
  }
  return false;
}

// ---- the collapse loop ------------------------------------------------------

struct Entry {
  double cost;
  uint32_t vertex;
  uint32_t stamp;
  bool operator<(const Entry& o) const { return cost > o.cost; }  // min-heap
};

class Collapser {
 public:
  Collapser(Model& m, const Limits& lim, size_t target) : m_(m), lim_(lim), target_(target) {
    cand_.resize(m.mesh.n_vertices());
    stamp_.assign(m.mesh.n_vertices(), 0);
  }

  void run(SimplifyStats& stats) {
    for (VH v : m_.mesh.vertices()) update(v);
    while (!heap_.empty() && m_.faces_alive > target_) {
      Entry e = heap_.top();
      heap_.pop();
      VH v0(int(e.vertex));
      if (e.stamp != stamp_[e.vertex] || m_.mesh.status(v0).deleted()) continue;
      Candidate c = cand_[e.vertex];
      ring_.clear();
      for (VH n : m_.mesh.vv_range(m_.mesh.to_vertex_handle(c.h))) ring_.push_back(n);
      if (m_.mesh.status(c.h).deleted() || !link_ok(m_.mesh, c.h, ring_)) {
        update(v0);  // the neighbourhood changed under it: look again
        continue;
      }
      collapse(c, stats);
    }
  }

 private:
  void update(VH v) {
    uint32_t i = uint32_t(v.idx());
    ++stamp_[i];
    if (m_.locked[i] || m_.mesh.status(v).deleted()) return;
    Candidate c;
    if (!best_candidate(m_, v, lim_, ring_, options_, c)) return;
    cand_[i] = c;
    heap_.push({c.cost, i, stamp_[i]});
  }

  void collapse(const Candidate& c, SimplifyStats& stats) {
    Mesh& mesh = m_.mesh;
    VH v0 = mesh.from_vertex_handle(c.h), v1 = mesh.to_vertex_handle(c.h);
    size_t removed = mesh.face_handle(c.h).is_valid() + mesh.face_handle(mesh.opposite_halfedge_handle(c.h)).is_valid();
    mesh.collapse(c.h);
    m_.faces_alive -= removed;
    m_.qa[v1.idx()] += m_.qa[v0.idx()];
    m_.qd[v1.idx()] += m_.qd[v0.idx()];
    m_.merged_into[v0.idx()] = uint32_t(v1.idx());
    stats.collapses++;
    stats.max_error = std::max(stats.max_error, c.error);
    update(v1);
    for (VH n : mesh.vv_range(v1)) update(n);
  }

  Model& m_;
  Limits lim_;
  size_t target_;
  std::vector<Candidate> cand_;
  std::vector<uint32_t> stamp_;
  std::vector<VH> ring_;  // scratch: one-ring of a v1
  std::vector<Candidate> options_;  // scratch: collapses of one v0
  std::priority_queue<Entry> heap_;
};

// ---- leftover pieces ----------------------------------------------------------

uint32_t find(std::vector<uint32_t>& parent, uint32_t x) {
  while (parent[x] != x) x = parent[x] = parent[parent[x]];
  return x;
}

// Deletes connected pieces (faces sharing a vertex) that have no perceptible
// face: all of them in Paper mode; in Bounded mode those whose faces are all
// undisplayable or whose bounding-box diagonal is within the tolerance.
void remove_pieces(Model& m, const Work& w, SimplifyMode mode, double tolerance,
                   SimplifyStats& stats) {
  Mesh& mesh = m.mesh;
  std::vector<uint32_t> parent(mesh.n_vertices());
  std::iota(parent.begin(), parent.end(), 0u);
  for (FH f : mesh.faces()) {
    auto it = mesh.cfv_iter(f);
    uint32_t a = find(parent, uint32_t(it->idx()));
    for (++it; it.is_valid(); ++it) {
      uint32_t b = find(parent, uint32_t(it->idx()));
      if (a != b) parent[b] = a;
    }
  }
  struct Piece {
    bool perceptible = false, all_undisplayable = true;
    float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  };
  std::vector<Piece> piece(mesh.n_vertices());
  for (FH f : mesh.faces()) {
    uint32_t src = m.face_source[f.idx()];
    VH v0 = *mesh.cfv_iter(f);
    Piece& p = piece[find(parent, uint32_t(v0.idx()))];
    Label l = (*w.labels)[src];
    p.perceptible |= l == Label::Perceptible;
    p.all_undisplayable &= l == Label::Undisplayable;
    for (VH v : mesh.fv_range(f))
      for (int a = 0; a < 3; ++a) {
        p.lo[a] = std::min(p.lo[a], mesh.point(v)[a]);
        p.hi[a] = std::max(p.hi[a], mesh.point(v)[a]);
      }
  }
  std::vector<uint8_t> drop(mesh.n_vertices(), 0);
  for (size_t i = 0; i < piece.size(); ++i) {
    const Piece& p = piece[i];
    if (p.perceptible || p.lo[0] > p.hi[0]) continue;
    double dx = p.hi[0] - p.lo[0], dy = p.hi[1] - p.lo[1], dz = p.hi[2] - p.lo[2];
    double diag = std::sqrt(dx * dx + dy * dy + dz * dz);
    bool remove = mode == SimplifyMode::Paper || p.all_undisplayable || diag <= tolerance;
    if (remove) {
      drop[i] = 1;
      stats.pieces_removed++;
    }
  }
  std::vector<FH> doomed;
  for (FH f : mesh.faces())
    if (drop[find(parent, uint32_t(mesh.cfv_iter(f)->idx()))]) doomed.push_back(f);
  for (FH f : doomed) mesh.delete_face(f, true);
  m.faces_alive -= doomed.size();
  stats.pieces_triangles_removed += doomed.size();
}

// ---- output -----------------------------------------------------------------

void write_result(Model& m, const Work& w, bool keep_perceptible_exact, SimplifyStats& stats,
                  Result& out) {
  Mesh& mesh = m.mesh;
  const Scene& s = *w.scene;
  std::vector<uint32_t> out_index(mesh.n_vertices(), UINT32_MAX);
  auto emit_vertex = [&](VH v) {
    uint32_t& o = out_index[v.idx()];
    if (o == UINT32_MAX) {
      o = uint32_t(out.positions.size() / 3);
      const auto& p = mesh.point(v);
      out.positions.insert(out.positions.end(), {p[0], p[1], p[2]});
    }
    return o;
  };
  for (FH f : mesh.faces()) {
    uint32_t src = m.face_source[f.idx()];
    VH fv[3];
    int k = 0;
    for (VH v : mesh.fv_range(f)) fv[k++] = v;
    if (keep_perceptible_exact && is_perceptible(w, src)) {
      // Untouched: emit the input corners in input order with their input
      // positions (welding may have replaced a position by a neighbour's).
      for (int c = 0; c < 3; ++c) {
        uint32_t iv = s.indices[3 * size_t(src) + c];
        const float* p = &s.positions[3 * size_t(iv)];
        VH match;
        for (VH v : fv)
          if (m.vert_welded[v.idx()] == w.weld.remap[iv]) match = v;
        const auto& mp = match.is_valid() ? mesh.point(match) : Mesh::Point(0, 0, 0);
        if (match.is_valid() && std::memcmp(mp.data(), p, 3 * sizeof(float)) == 0) {
          out.indices.push_back(emit_vertex(match));
        } else {
          out.indices.push_back(uint32_t(out.positions.size() / 3));
          out.positions.insert(out.positions.end(), p, p + 3);
        }
      }
    } else {
      for (VH v : fv) out.indices.push_back(emit_vertex(v));
    }
    out.source.push_back(src);
  }
  stats.vertices_after = out.positions.size() / 3;
}

// Belblidia's measures: each mesh vertex against the vertex it collapsed into
// (transitively); vertices of removed pieces are not counted.
void displacement_stats(Model& m, const Work& w, SimplifyStats& stats) {
  Mesh& mesh = m.mesh;
  std::vector<uint8_t> alive(mesh.n_vertices(), 0);
  for (FH f : mesh.faces())
    for (VH v : mesh.fv_range(f)) alive[v.idx()] = 1;
  double sum = 0, mx = 0;
  size_t n = 0;
  for (size_t i = 0; i < m.merged_into.size(); ++i) {
    uint32_t r = uint32_t(i);
    while (m.merged_into[r] != r) r = m.merged_into[r];
    if (!alive[r]) continue;
    double d = (mesh.point(VH(int(i))) - mesh.point(VH(int(r)))).norm();
    sum += d;
    mx = std::max(mx, d);
    ++n;
  }
  double diag = w.diagonal > 0 ? w.diagonal : 1.0;
  stats.max_displacement_rel = mx / diag;
  stats.mean_displacement_rel = n ? sum / n / diag : 0.0;
}

}  // namespace

void collapse_simplify(const Work& w, const SimplifyOptions& opt, SimplifyStats& stats,
                       Result& out) {
  const bool labelled = opt.mode != SimplifyMode::Qem;
  Model m;
  build_mesh(m, w, stats);
  stats.vertices_before = m.mesh.n_vertices();
  m.locked.assign(m.mesh.n_vertices(), 0);
  init_quadrics(m, opt);
  if (labelled) lock_perceptible(m, w);

  double tolerance = -1;
  if (opt.mode == SimplifyMode::Bounded) tolerance = stats.tolerance = opt.k * opt.pixel_footprint;
  // Pieces that will be removed anyway need no collapses (pieces only split).
  if (labelled) remove_pieces(m, w, opt.mode, tolerance, stats);

  Limits lim;
  lim.cos_normal = std::cos(opt.max_normal_change_deg * M_PI / 180.0);
  lim.min_quality = opt.min_triangle_quality;
  lim.max_valence = opt.max_valence;
  lim.tolerance = tolerance;
  lim.tie = 1e-8;
  size_t target = opt.mode == SimplifyMode::Qem ? opt.target_triangles : 0;
  Collapser(m, lim, target).run(stats);

  if (labelled) remove_pieces(m, w, opt.mode, tolerance, stats);
  displacement_stats(m, w, stats);
  write_result(m, w, labelled, stats, out);
}

}  // namespace perclod::detail
