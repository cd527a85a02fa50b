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
// Bounds (Bounded, Fidelity): each vertex carries a tolerance in scene units
// (Bounded: one for all; Fidelity: the tightest of its faces' labels, and of
// every vertex merged into it); a collapse whose error bound exceeds the
// tolerance of either end is refused.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>
#include <new>
#include <numeric>
#include <string>
#include <unordered_map>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "collapse_rules.h"
#include "free_collapse.h"
#include "mesh_edits.h"
#include "quadric.h"
#include "simplify_internal.h"

namespace perclod::detail {

namespace {

Vec to_d(const Mesh::Point& p) { return Vec(p[0], p[1], p[2]); }

// The working mesh and everything we keep per element (vectors indexed by
// handle index; OpenMesh keeps handles stable until garbage collection, which
// we never run).
struct Model {
  Mesh mesh;
  std::vector<uint32_t> face_source;   // input triangle per face
  std::vector<uint8_t> flipped;        // face added with the input winding reversed
  std::vector<uint32_t> vert_welded;   // welded vertex per mesh vertex
  std::vector<uint8_t> locked;         // vertex may not be v0
  std::vector<uint8_t> feature_edge;   // constraint line: never collapsed
  // Per vertex, side by side (a candidate reads both of both ends): the
  // area-weighted quadric (the priority), then with a distance bound
  // (Bounded, Fidelity) the unit-weight one.
  std::vector<Quadric> quadrics;
  size_t quadric_stride = 1;  // 2 with the unit-weight quadrics
  Quadric& qa(VH v) { return quadrics[quadric_stride * size_t(v.idx())]; }
  const Quadric& qa(VH v) const { return quadrics[quadric_stride * size_t(v.idx())]; }
  Quadric& qd(VH v) { return quadrics[quadric_stride * size_t(v.idx()) + 1]; }
  const Quadric& qd(VH v) const { return quadrics[quadric_stride * size_t(v.idx()) + 1]; }
  bool has_qd() const { return quadric_stride == 2; }
  std::vector<double> tol;             // per vertex: largest error allowed (empty: no bound)
  std::vector<double> area_budget;     // Fidelity, per vertex: surface area its collapses may change
  std::vector<double> area_used;       // Fidelity, per vertex: area changed by collapses merged into it
  std::vector<uint32_t> merged_into;   // v0 -> v1 of its collapse
  size_t faces_alive = 0;
};

bool is_perceptible(const Work& w, uint32_t src) {
  return (*w.labels)[src] == Label::Perceptible;
}

// ---- building the mesh --------------------------------------------------

VH add_vertex(Model& m, MeshBuilder& make, const Work& w, uint32_t welded) {
  const float* p = &w.weld.positions[3 * size_t(welded)];
  VH v = make.new_vertex(Mesh::Point(p[0], p[1], p[2]));
  m.vert_welded.push_back(welded);
  return v;
}

// vh_of: the mesh vertex of each welded vertex, -1 until made; one table for
// every chunk (chunks hold whole pieces, so no welded vertex is in two), which
// spares each chunk clearing a table of every welded vertex.
void build_mesh(Model& m, const Work& w, const std::vector<uint32_t>& faces, std::vector<int>& vh_of,
                SimplifyStats& stats) {
  m.mesh.reserve(faces.size(), 3 * faces.size() / 2, faces.size());
  MeshBuilder make(m.mesh);
  m.vert_welded.reserve(faces.size());
  m.face_source.reserve(faces.size());
  m.flipped.reserve(faces.size());
  auto record = [&](FH f, uint32_t src, uint8_t flipped) {
    if (size_t(f.idx()) != m.face_source.size())
      throw std::logic_error("simplify: OpenMesh face numbering out of step");
    m.face_source.push_back(src);
    m.flipped.push_back(flipped);
  };
  // Shared vertices first. A face add_triangle refuses (non-manifold edge or
  // vertex) may fit once its neighbours are in: those are retried after the
  // first pass, and only faces refused again get their own vertices.
  std::vector<uint32_t> refused;
  // A face whose edge is already used in the same direction (its neighbour
  // is wound the other way, common in CityGML-derived models) is tried again
  // reversed: the mesh then holds one consistently oriented surface, and the
  // output restores the input winding (Model::flipped).
  auto try_shared = [&](uint32_t src) {
    const uint32_t* c = &w.weld.corner[3 * size_t(src)];
    VH v[3];
    for (int k = 0; k < 3; ++k) {
      if (vh_of[c[k]] < 0) vh_of[c[k]] = add_vertex(m, make, w, c[k]).idx();
      v[k] = VH(vh_of[c[k]]);
    }
    for (int flip = 0; flip < 2; ++flip) {
      const VH t[3] = {v[0], flip ? v[2] : v[1], flip ? v[1] : v[2]};
      FH f = add_triangle(m.mesh, t, make);
      if (!f.is_valid()) continue;
      record(f, src, uint8_t(flip));
      return true;
    }
    return false;
  };
  auto add_alone = [&](uint32_t src) {  // disconnected from its neighbours, but kept
    const uint32_t* c = &w.weld.corner[3 * size_t(src)];
    VH v[3];
    for (int k = 0; k < 3; ++k) v[k] = add_vertex(m, make, w, c[k]);
    record(add_triangle(m.mesh, v, make), src, 0);
  };
  for (uint32_t src : faces) {
    const uint32_t* c = &w.weld.corner[3 * size_t(src)];
    if (c[0] == c[1] || c[1] == c[2] || c[0] == c[2]) {
      stats.degenerate_faces++;
      add_alone(src);
    } else if (!try_shared(src)) {
      refused.push_back(src);
    }
  }
  for (uint32_t src : refused)
    if (!try_shared(src)) {
      stats.nonmanifold_faces_duplicated++;
      add_alone(src);
    }
  make.finish();
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
    m.qa(v).add_plane(q[0], q[1], q[2], d, weight * e.sqrnorm());
    if (m.has_qd()) m.qd(v).add_plane(q[0], q[1], q[2], d, 1.0);
  }
}

// with_distance: also the unit-weight quadrics behind Bounded's error bound
// (memory is time here: they are only built when a tolerance needs them).
// `joined_edges` (may be null): per edge, whether it joins two or more faces
// of the welded triangle list although the mesh has it on its boundary (a
// face OpenMesh could not join got its own vertices); such an edge gets no
// boundary plane.
void init_quadrics(Model& m, const SimplifyOptions& opt, bool with_distance,
                   const std::vector<uint8_t>* joined_edges = nullptr) {
  Mesh& mesh = m.mesh;
  m.quadric_stride = with_distance ? 2 : 1;
  m.quadrics.assign(m.quadric_stride * mesh.n_vertices(), Quadric{});
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
      m.qa(x).add_plane(n[0], n[1], n[2], d, 0.5 * len);
      if (with_distance) m.qd(x).add_plane(n[0], n[1], n[2], d, 1.0);
    }
  }
  const double cos_feature = std::cos(opt.feature_angle_deg * kPi / 180.0);
  m.feature_edge.assign(mesh.n_edges(), 0);
  for (auto e : mesh.edges()) {
    HH h0 = mesh.halfedge_handle(e, 0), h1 = mesh.halfedge_handle(e, 1);
    VH a = mesh.from_vertex_handle(h0), b = mesh.to_vertex_handle(h0);
    FH f0 = mesh.face_handle(h0), f1 = mesh.face_handle(h1);
    if (!f0.is_valid() || !f1.is_valid()) {
      if (joined_edges && (*joined_edges)[e.idx()]) continue;
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

// free_topology: the mesh's boundary edges that the welded triangle list
// has two or more faces on (joined_edges of init_quadrics), and in `copy`
// every vertex whose welded vertex the mesh holds more than once: those the
// half-edge loop must not move away from their twins before the
// triangle-list pass joins them again.
std::vector<uint8_t> find_joined_edges_and_copies(const Model& m, std::vector<uint8_t>& copy) {
  const Mesh& mesh = m.mesh;
  auto key = [](uint32_t a, uint32_t b) { return a < b ? uint64_t(a) << 32 | b : uint64_t(b) << 32 | a; };
  std::unordered_map<uint64_t, uint32_t> faces_on;
  std::unordered_map<uint32_t, uint32_t> copies;
  for (FH f : mesh.faces()) {
    uint32_t w[3];
    int k = 0;
    for (VH v : mesh.fv_range(f)) w[k++] = m.vert_welded[v.idx()];
    for (k = 0; k < 3; ++k) faces_on[key(w[k], w[(k + 1) % 3])]++;
  }
  for (VH v : mesh.vertices()) copies[m.vert_welded[v.idx()]]++;
  copy.assign(mesh.n_vertices(), 0);
  for (VH v : mesh.vertices()) copy[v.idx()] = copies[m.vert_welded[v.idx()]] > 1;
  std::vector<uint8_t> joined(mesh.n_edges(), 0);
  for (auto e : mesh.edges()) {
    if (!mesh.is_boundary(e)) continue;
    const HH h = mesh.halfedge_handle(e, 0);
    const uint32_t a = m.vert_welded[mesh.from_vertex_handle(h).idx()], b = m.vert_welded[mesh.to_vertex_handle(h).idx()];
    joined[e.idx()] = faces_on[key(a, b)] > 1;
  }
  return joined;
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
  double error2 = 0;       // square of the distance bound: both ends' unit-weight quadrics at v1
  double area_change = 0;  // surface area the collapse adds (or removes, < 0)
};

// Would moving v0 onto p1 turn a surviving face too far or make a sliver?
// `area_change` (may be null) receives the change in surface area of v0's
// faces: 0 where a flat region is re-tessellated, minus the area of a thin
// part that collapses away.
bool geometry_ok(const Mesh& mesh, VH v0, VH v1, const Vec& p1, const Limits& lim, double* area_change = nullptr) {
  double twice_change = 0;
  for (HH h : mesh.voh_range(v0)) {
    FH f = mesh.face_handle(h);
    if (!f.is_valid()) continue;
    VH a = mesh.to_vertex_handle(h);
    VH b = mesh.to_vertex_handle(mesh.next_halfedge_handle(h));
    if (!face_follows(to_d(mesh.point(v0)), p1, to_d(mesh.point(a)), to_d(mesh.point(b)), a == v1 || b == v1, lim,
                      twice_change))
      return false;
  }
  if (area_change) *area_change = 0.5 * twice_change;
  return true;
}

// within_area_budget for v0 and v1 (Fidelity; no budgets, no rule).
bool area_ok(const Model& m, VH v0, VH v1, double area_change) {
  if (m.area_budget.empty()) return true;
  return within_area_budget(m.area_used[v0.idx()], m.area_used[v1.idx()], area_change, m.area_budget[v0.idx()],
                            m.area_budget[v1.idx()]);
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

// The candidates h (v0 -> v1) and its opposite (v1 -> v0), as side 0 and 1:
// each side's cost, and its error when there is a tolerance; live[s] is false
// when that side may never collapse (its v0 locked, a constraint line, error
// above the tolerance). Both sides sum the same two quadrics and differ only
// in the end they are evaluated at (addition commutes, so each side's figures
// are what evaluating it alone would give).
void evaluate_edge(const Model& m, HH h, const Limits& lim, Candidate c[2], bool live[2]) {
  const Mesh& mesh = m.mesh;
  const VH v[2] = {mesh.from_vertex_handle(h), mesh.to_vertex_handle(h)};
  const bool free_edge = !m.feature_edge[mesh.edge_handle(h).idx()];
  live[0] = free_edge && !m.locked[v[0].idx()];
  live[1] = free_edge && !m.locked[v[1].idx()];
  c[0] = Candidate{h};
  c[1] = Candidate{mesh.opposite_halfedge_handle(h)};
  if (!live[0] && !live[1]) return;
  const Mesh::Point &p0 = mesh.point(v[0]), &p1 = mesh.point(v[1]);
  // Lane s: side s, which moves v[s] onto v[1 - s], so evaluated there.
  const Double2 x = {p1[0], p0[0]}, y = {p1[1], p0[1]}, z = {p1[2], p0[2]};
  if (!m.tol.empty()) {  // the bound first: a refusal needs no cost
    const Double2 e2 = (m.qd(v[0]) + m.qd(v[1])).eval2(x, y, z);
    const double t = std::min(m.tol[v[0].idx()], m.tol[v[1].idx()]);
    for (int s = 0; s < 2; ++s)
      if (live[s]) {
        c[s].error2 = e2[s];
        live[s] = root_within(c[s].error2, t);
      }
    if (!live[0] && !live[1]) return;
  }
  const Double2 e = (m.qa(v[0]) + m.qa(v[1])).eval2(x, y, z);
  const double l2 = (to_d(p1) - to_d(p0)).sqrnorm();
  for (int s = 0; s < 2; ++s)
    if (live[s]) c[s].cost = e[s] + lim.tie * l2 * l2;
}

// Side 0 of evaluate_edge: h alone.
bool evaluate(const Model& m, HH h, const Limits& lim, Candidate& c) {
  Candidate both[2];
  bool live[2];
  evaluate_edge(m, h, lim, both, live);
  c = both[0];
  return live[0];
}

// Everything that depends on the neighbourhood: fan size, link condition,
// flips, slivers and the area rule. Checked when a collapse comes off the
// queue; returns the first rule that refuses it (Legal when none does).
// `area_change` is set when the geometry is checked.
enum class Legality { Legal, Valence, Topology, Shape };
Legality legality(const Model& m, HH h, const Limits& lim, std::vector<VH>& ring1, double& area_change) {
  const Mesh& mesh = m.mesh;
  VH v0 = mesh.from_vertex_handle(h), v1 = mesh.to_vertex_handle(h);
  ring1.clear();
  for (VH n : mesh.vv_range(v1)) ring1.push_back(n);
  if (valence_of(mesh, v0) + int(ring1.size()) - 4 > lim.max_valence) return Legality::Valence;
  if (!link_ok(mesh, h, ring1)) return Legality::Topology;
  if (!geometry_ok(mesh, v0, v1, to_d(mesh.point(v1)), lim, &area_change) || !area_ok(m, v0, v1, area_change))
    return Legality::Shape;
  return Legality::Legal;
}

// Why nothing more collapses, in words (qem's stop_reason).
std::string describe_refusals(const SimplifyStats::Refused& r) {
  std::string why = "every remaining collapse is refused: " + std::to_string(r.topology) +
                    " half-edges by topology (link condition, boundary ears), " + std::to_string(r.shape) +
                    " by the normal-change, sliver or area limits, " + std::to_string(r.valence) +
                    " by the valence cap, " + std::to_string(r.bound_or_locked) +
                    " are locked or over the error bound";
  if (r.legal) why += ", " + std::to_string(r.legal) + " became legal only at the end";
  return why;
}

// ---- the collapse loop ------------------------------------------------------

// Edges that cannot become candidates are skipped (Collapser::dead_).
// tests/simplify/test_dead_edges.cpp builds this file a second time with
// PERCLOD_EVALUATE_EVERY_EDGE and checks that the skip changes no LOD.
#ifdef PERCLOD_EVALUATE_EVERY_EDGE
constexpr bool kSkipDeadEdges = false;
#else
constexpr bool kSkipDeadEdges = true;
#endif

// The one order of collapse candidates: half-edge a (cost ca) before b
// (cost cb). The heap and the Collapser's per-vertex choice both use it.
bool cheaper_candidate(double ca, uint32_t a, double cb, uint32_t b) {
  return ca < cb || (ca == cb && a < b);
}

// A 4-ary min-heap of vertices, each keyed by the cheapest collapse that
// removes it: (cost, half-edge) of its best outgoing candidate, indexed so a
// key can change in place. Equal costs (flat walls collapse at cost 0 plus
// an edge-length tie-break that regular grids repeat) are ordered by
// half-edge index, so the heap's top is the cheapest half-edge of the whole
// mesh by a strict order that depends on the mesh alone and not on the
// heap's history: a chunk of pieces simplified on its own then makes
// exactly the collapses it makes as part of the whole mesh. One entry per
// vertex rather than per half-edge (about six leave each vertex): a smaller
// heap, and a collapse re-keys v1 and its neighbours instead of taking out
// and putting back every half-edge around v0 and v1.
class VertexHeap {
 public:
  explicit VertexHeap(size_t n)
      : pos_(n, -1), store_(new (std::align_val_t(kLine)) Node[n + kPad]), heap_(store_.get() + kPad) {}
  bool empty() const { return size_ == 0; }
  // Every vertex with a candidate (best[v]: its cheapest half-edge, or
  // UINT32_MAX for none; cost: per half-edge), then one O(n) heapify.
  void build(const std::vector<uint32_t>& best, const std::vector<double>& cost) {
    for (uint32_t v = 0; v < uint32_t(best.size()); ++v)
      if (best[v] != UINT32_MAX) {
        pos_[v] = int(size_);
        heap_[size_++] = {cost[best[v]], best[v], v};
      }
    const size_t n = size_;
    for (size_t i = n > 1 ? (n - 2) / kArity + 1 : 0; i-- > 0;) down(i);  // every node with a child
  }
  uint32_t top() const { return heap_[0].h; }  // the cheapest half-edge
  // v's key's half-edge, or -1 when v is not in the heap.
  int64_t best_of(uint32_t v) const { return pos_[v] < 0 ? -1 : int64_t(heap_[size_t(pos_[v])].h); }
  void set(uint32_t v, double cost, uint32_t h) {
    const Node n{cost, h, v};
    if (pos_[v] < 0) {
      pos_[v] = int(size_);
      heap_[size_++] = n;
      up(size_t(pos_[v]));
    } else {
      size_t i = size_t(pos_[v]);
      const Node old = heap_[i];
      heap_[i] = n;
      if (before(n, old)) up(i); else down(i);
    }
  }
  void remove(uint32_t v) {
    if (pos_[v] < 0) return;
    size_t i = size_t(pos_[v]);
    pos_[v] = -1;
    Node last = heap_[--size_];
    if (i == size_) return;
    heap_[i] = last;
    pos_[last.v] = int(i);
    up(i);
    down(size_t(pos_[last.v]));
  }

 private:
  // Four children per node: half the levels of a binary heap, and the four
  // children of a node are one 64-byte cache line: node i's are 4i+1..4i+4,
  // so with the root kPad nodes into a line-aligned block they start on a
  // line.
  static constexpr size_t kArity = 4;
  struct Node {
    double cost;
    uint32_t h;  // the vertex's cheapest outgoing half-edge
    uint32_t v;
  };
  static constexpr size_t kLine = 64;
  static constexpr size_t kPad = kLine / sizeof(Node) - 1;
  static_assert(kArity * sizeof(Node) == kLine);
  static bool before(const Node& a, const Node& b) { return cheaper_candidate(a.cost, a.h, b.cost, b.h); }
  void place(size_t i, const Node& n) {
    heap_[i] = n;
    pos_[n.v] = int(i);
  }
  void up(size_t i) {
    Node n = heap_[i];
    while (i > 0) {
      size_t p = (i - 1) / kArity;
      if (!before(n, heap_[p])) break;
      place(i, heap_[p]);
      i = p;
    }
    place(i, n);
  }
  void down(size_t i) {
    Node n = heap_[i];
    const size_t size = size_;
    for (;;) {
      const size_t first = kArity * i + 1;
      if (first >= size) break;
      size_t c = first;
      const size_t last = std::min(first + kArity, size);
      for (size_t k = first + 1; k < last; ++k)
        if (before(heap_[k], heap_[c])) c = k;
      if (!before(heap_[c], n)) break;
      place(i, heap_[c]);
      i = c;
    }
    place(i, n);
  }
  struct FreeAligned {
    void operator()(Node* p) const { ::operator delete[](p, std::align_val_t(kLine)); }
  };
  std::vector<int> pos_;
  std::unique_ptr<Node[], FreeAligned> store_;  // room for every vertex, never reallocated
  Node* heap_;                                  // the root: store_ + kPad
  size_t size_ = 0;
};

// The candidates are every half-edge that may collapse (both directions of
// an edge), each with its cost; the queue holds each vertex's cheapest. A
// collapse into v1 changes the costs of v1's edges only, so only those are
// evaluated again, and v1 and its neighbours re-keyed; legality is checked
// when a half-edge reaches the top. One refused there stops being a
// candidate and is tried again in the next pass if the mesh around it has
// changed since, until a pass collapses nothing.
class Collapser {
 public:
  Collapser(Model& m, const Limits& lim, size_t target)
      : m_(m),
        lim_(lim),
        target_(target),
        heap_(m.mesh.n_vertices()),
        cost_(m.mesh.n_halfedges(), 0.0),
        live_(m.mesh.n_halfedges(), 0),
        dead_(m.mesh.n_edges(), 0) {}

  void run(SimplifyStats& stats, bool explain, int max_passes = 8) {
    const Mesh& mesh = m_.mesh;
    changed_.assign(mesh.n_vertices(), 0);
    for (auto e : mesh.edges()) offer_edge(mesh.halfedge_handle(e, 0));
    // Each vertex's cheapest candidate, in one pass over the half-edges.
    std::vector<uint32_t> best(mesh.n_vertices(), UINT32_MAX);
    for (uint32_t i = 0; i < uint32_t(mesh.n_halfedges()); ++i) {
      if (!live_[i]) continue;
      uint32_t& b = best[size_t(mesh.from_vertex_handle(HH(int(i))).idx())];
      if (b == UINT32_MAX || cheaper(i, b)) b = i;
    }
    heap_.build(best, cost_);
    int pass = 0;
    for (; pass < max_passes && m_.faces_alive > target_; ++pass) {
      if (pass > 0) requeue_refused();
      if (drain(stats) == 0) break;
    }
    const bool missed = target_ > 0 && m_.faces_alive > target_;
    if (explain || missed) {
      count_refusals(stats.refused);
      stats.refused_counted = true;
    }
    if (missed) {
      stats.target_reached = false;
      stats.stop_reason = pass == max_passes ? "the pass limit (" + std::to_string(max_passes) + ") was reached; "
                                             : std::string();
      stats.stop_reason += describe_refusals(stats.refused);
    }
  }

 private:
  // Every half-edge left, by the first rule that refuses it.
  void count_refusals(SimplifyStats::Refused& r) {
    const Mesh& mesh = m_.mesh;
    for (auto e : mesh.edges()) {
      if (mesh.status(e).deleted()) continue;
      for (int side = 0; side < 2; ++side) {
        HH h = mesh.halfedge_handle(e, side);
        Candidate c;
        if (!evaluate(m_, h, lim_, c)) {
          ++r.bound_or_locked;
          continue;
        }
        switch (legality(m_, h, lim_, ring_, c.area_change)) {
          case Legality::Valence: ++r.valence; break;
          case Legality::Topology: ++r.topology; break;
          case Legality::Shape: ++r.shape; break;
          case Legality::Legal: ++r.legal; break;
        }
      }
    }
  }

  // h becomes a candidate at its current cost, or stops being one.
  void offer(HH h) {
    Candidate c;
    const size_t i = size_t(h.idx());
    live_[i] = evaluate(m_, h, lim_, c);
    cost_[i] = c.cost;
  }
  // offer() of both half-edges of h's edge, from one evaluate_edge, unless
  // the edge is dead (see dead_).
  void offer_edge(HH h) {
    uint8_t& dead = dead_[size_t(m_.mesh.edge_handle(h).idx())];
    if (kSkipDeadEdges && dead) return;  // both half-edges stay non-candidates
    Candidate c[2];
    bool live[2];
    evaluate_edge(m_, h, lim_, c, live);
    dead = !live[0] && !live[1];
    for (int s = 0; s < 2; ++s) {
      const size_t i = size_t(c[s].h.idx());
      live_[i] = live[s];
      cost_[i] = c[s].cost;
    }
  }
  // cheaper_candidate of half-edges a and b at their current costs.
  bool cheaper(uint32_t a, uint32_t b) const { return cheaper_candidate(cost_[a], a, cost_[b], b); }
  // v's cheapest candidate; UINT32_MAX when it has none.
  uint32_t cheapest(VH v) const {
    uint32_t best = UINT32_MAX;
    for (HH h : m_.mesh.voh_range(v)) {
      const uint32_t i = uint32_t(h.idx());
      if (live_[i] && (best == UINT32_MAX || cheaper(i, best))) best = i;
    }
    return best;
  }
  void rekey(VH v) {
    const uint32_t b = cheapest(v);
    if (b != UINT32_MAX)
      heap_.set(uint32_t(v.idx()), cost_[b], b);
    else
      heap_.remove(uint32_t(v.idx()));
  }
  // The same when only `changed`, one of v's half-edges, has changed (its
  // cost, or whether it is a candidate) or v's key may name a deleted one:
  // v's other costs are as they were, so the whole fan is read again only
  // when the key's half-edge itself changed.
  void rekey(VH v, HH changed) {
    const uint32_t c = uint32_t(changed.idx());
    const int64_t key = heap_.best_of(uint32_t(v.idx()));
    if (key == int64_t(c) || (key >= 0 && !live_[size_t(key)])) return rekey(v);
    if (!live_[c]) return;
    if (key < 0 || cheaper(c, uint32_t(key))) heap_.set(uint32_t(v.idx()), cost_[c], c);
  }

  // A refused half-edge comes back only if the one-ring of one of its ends
  // changed after the refusal (legality depends on nothing else).
  void requeue_refused() {
    std::vector<Refusal> retry;
    retry.swap(refused_);
    const Mesh& mesh = m_.mesh;
    for (const Refusal& r : retry) {
      HH h{int(r.halfedge)};
      if (mesh.status(mesh.edge_handle(h)).deleted()) continue;
      if (changed_[mesh.from_vertex_handle(h).idx()] <= r.when &&
          changed_[mesh.to_vertex_handle(h).idx()] <= r.when) {
        refused_.push_back(r);  // still refused, nothing to retry yet
        continue;
      }
      offer(h);
      rekey(mesh.from_vertex_handle(h), h);
    }
  }

  // Candidate::error2 of h, as evaluate_edge computes it (0 with no bound).
  double error2_of(HH h) const {
    if (m_.tol.empty()) return 0;
    const Mesh& mesh = m_.mesh;
    const VH v0 = mesh.from_vertex_handle(h), v1 = mesh.to_vertex_handle(h);
    const Mesh::Point& p = mesh.point(v1);
    return (m_.qd(v0) + m_.qd(v1)).eval(p[0], p[1], p[2]);
  }

  size_t drain(SimplifyStats& stats) {
    size_t done = 0;
    while (!heap_.empty() && m_.faces_alive > target_) {
      HH h(int(heap_.top()));
      live_[size_t(h.idx())] = 0;  // no longer a candidate: collapsed or refused
      // The top is a candidate at its current cost: whatever changes a
      // cost (a collapse into an end: its quadrics and bound) offers the
      // end's edges again. So only legality is left to check.
      Candidate c{h};
      if (legality(m_, h, lim_, ring_, c.area_change) != Legality::Legal) {
        refused_.push_back({uint32_t(h.idx()), clock_});
        rekey(m_.mesh.from_vertex_handle(h));
        continue;
      }
      c.error2 = error2_of(h);
      collapse(c, stats);
      ++done;
    }
    return done;
  }

  void collapse(const Candidate& c, SimplifyStats& stats) {
    Mesh& mesh = m_.mesh;
    VH v0 = mesh.from_vertex_handle(c.h), v1 = mesh.to_vertex_handle(c.h);
    // The half-edges the collapse may delete: v0's (both directions) and
    // the far edges of the faces of c.h. Those deleted stop being
    // candidates; the others end up around v1 and are evaluated below.
    touched_.clear();
    for (HH h : mesh.voh_range(v0)) {
      touched_.insert(touched_.end(), {h, mesh.opposite_halfedge_handle(h)});
      dead_[size_t(mesh.edge_handle(h).idx())] = 0;  // it may join v1: one end moves
    }
    for (HH h : {c.h, mesh.opposite_halfedge_handle(c.h)})
      if (mesh.face_handle(h).is_valid()) {
        HH n = mesh.next_halfedge_handle(h);
        touched_.insert(touched_.end(), {n, mesh.opposite_halfedge_handle(n)});
      }
    size_t removed = mesh.face_handle(c.h).is_valid() + mesh.face_handle(mesh.opposite_halfedge_handle(c.h)).is_valid();
    collapse_halfedge(mesh, c.h);
    for (HH h : touched_)
      if (mesh.status(mesh.edge_handle(h)).deleted()) live_[size_t(h.idx())] = 0;
    heap_.remove(uint32_t(v0.idx()));
    m_.faces_alive -= removed;
    m_.qa(v1) += m_.qa(v0);
    if (m_.has_qd()) m_.qd(v1) += m_.qd(v0);
    if (!m_.tol.empty()) m_.tol[v1.idx()] = std::min(m_.tol[v1.idx()], m_.tol[v0.idx()]);
    if (!m_.area_budget.empty()) {
      m_.area_used[v1.idx()] += m_.area_used[v0.idx()] + std::fabs(c.area_change);
      m_.area_budget[v1.idx()] = std::min(m_.area_budget[v1.idx()], m_.area_budget[v0.idx()]);
    }
    m_.merged_into[v0.idx()] = uint32_t(v1.idx());
    stats.collapses++;
    stats.max_error = std::max(stats.max_error, std::sqrt(c.error2));
    ++clock_;
    changed_[v1.idx()] = clock_;
    for (HH h : mesh.voh_range(v1)) {
      const VH n = mesh.to_vertex_handle(h);
      const HH back = mesh.opposite_halfedge_handle(h);
      changed_[n.idx()] = clock_;
      offer_edge(h);
      rekey(n, back);  // n's only half-edge whose cost changed
    }
    rekey(v1);
  }

  Model& m_;
  Limits lim_;
  size_t target_;
  VertexHeap heap_;
  std::vector<double> cost_;      // per half-edge: its cost when it is a candidate
  std::vector<uint8_t> live_;     // per half-edge: a candidate (may collapse, not refused)
  // Per edge: evaluate_edge found neither half-edge a candidate, and none
  // will be while both ends stay where they are: a locked end stays locked,
  // a constraint line stays one, and an error over the bound stays over it
  // (a collapse into either end adds a quadric, which never lowers the
  // error at the same point, and keeps the smaller bound; in exact
  // arithmetic, so rounding could only matter within an ulp of the bound).
  // Such an edge is not evaluated again until one of its ends is a
  // collapse's v0. (On the 1M facade at 56 m three in four re-evaluations
  // after a collapse found neither half-edge a candidate.)
  std::vector<uint8_t> dead_;
  std::vector<VH> ring_;          // scratch: one-ring of a v1
  std::vector<HH> touched_;       // scratch: half-edges a collapse may delete
  struct Refusal {
    uint32_t halfedge;
    uint64_t when;  // clock_ at the refusal
  };
  std::vector<Refusal> refused_;
  uint64_t clock_ = 0;             // collapses so far
  std::vector<uint64_t> changed_;  // per vertex: clock_ when its one-ring last changed
};

// ---- leftover pieces ----------------------------------------------------------

// A connected piece (faces sharing a vertex) as the removal rule sees it.
struct Piece {
  bool perceptible = false, all_undisplayable = true, used = false;
  float scale = INFINITY;  // the least bound_scale of its faces
  Bounds box = Bounds::empty();

  void add(Label l, const float* p, float face_scale) {
    used = true;
    perceptible |= l == Label::Perceptible;
    all_undisplayable &= l == Label::Undisplayable;
    scale = std::min(scale, face_scale);
    box.grow(p);
  }
  // No perceptible face, and: Paper mode, or all undisplayable, or (Bounded,
  // Fidelity) a bounding-box diagonal within the tolerance (times its scale).
  bool removable(SimplifyMode mode, double tolerance) const {
    if (!used || perceptible) return false;
    if (mode == SimplifyMode::Paper || all_undisplayable) return true;
    double dx = box.hi[0] - box.lo[0], dy = box.hi[1] - box.lo[1], dz = box.hi[2] - box.lo[2];
    return std::sqrt(dx * dx + dy * dy + dz * dz) <= tolerance * double(scale);
  }
};
float scale_of(const SimplifyOptions& opt, uint32_t triangle) {
  return opt.mode != SimplifyMode::Fidelity || opt.bound_scale.empty() ? 1.f : opt.bound_scale[triangle];
}

// The connected piece (faces sharing a welded vertex) of each of `faces`,
// named by a welded vertex of it: piece[i] is faces[i]'s.
std::vector<uint32_t> pieces_of(const Work& w, const std::vector<uint32_t>& faces) {
  DisjointSets sets(w.weld.positions.size() / 3);
  auto corner = [&](uint32_t t, int k) { return w.weld.corner[3 * size_t(t) + k]; };
  for (uint32_t t : faces)
    for (int k = 1; k < 3; ++k) sets.unite(corner(t, 0), corner(t, k));
  std::vector<uint32_t> piece(faces.size());
  for (size_t i = 0; i < faces.size(); ++i) piece[i] = sets.find(corner(faces[i], 0));
  return piece;
}

// Before the mesh is built: drops the faces of removable pieces of the welded
// triangle list (and their entries of `piece`, pieces_of's), so no time goes
// into building and collapsing them.
void drop_pieces_early(const Work& w, std::vector<uint32_t>& faces, std::vector<uint32_t>& piece,
                       const SimplifyOptions& opt, double tolerance, SimplifyStats& stats) {
  const SimplifyMode mode = opt.mode;
  // A Piece per piece, not per welded vertex: far fewer, and less memory
  // for a fresh process to touch.
  std::vector<uint32_t> dense(w.weld.positions.size() / 3, UINT32_MAX);
  std::vector<Piece> pieces;
  for (size_t i = 0; i < faces.size(); ++i) {
    uint32_t& d = dense[piece[i]];
    if (d == UINT32_MAX) {
      d = uint32_t(pieces.size());
      pieces.emplace_back();
    }
    for (int k = 0; k < 3; ++k)
      pieces[d].add((*w.labels)[faces[i]], &w.weld.positions[3 * size_t(w.weld.corner[3 * size_t(faces[i]) + k])],
                    scale_of(opt, faces[i]));
  }
  std::vector<uint8_t> drop(pieces.size(), 0);
  for (size_t d = 0; d < pieces.size(); ++d)
    if (pieces[d].removable(mode, tolerance)) {
      drop[d] = 1;
      stats.pieces_removed++;
    }
  size_t kept = 0;
  for (size_t i = 0; i < faces.size(); ++i)
    if (!drop[dense[piece[i]]]) faces[kept] = faces[i], piece[kept] = piece[i], ++kept;
  stats.pieces_triangles_removed += faces.size() - kept;
  faces.resize(kept);
  piece.resize(kept);
}

// After collapsing: deletes the removable pieces of the mesh (collapses can
// split a piece; non-manifold faces are pieces of their own here).
void remove_pieces(Model& m, const Work& w, const SimplifyOptions& opt, double tolerance, SimplifyStats& stats) {
  const SimplifyMode mode = opt.mode;
  Mesh& mesh = m.mesh;
  DisjointSets sets(mesh.n_vertices());
  for (FH f : mesh.faces()) {
    auto it = mesh.cfv_iter(f);
    const uint32_t first = uint32_t(it->idx());
    for (++it; it.is_valid(); ++it) sets.unite(first, uint32_t(it->idx()));
  }
  std::vector<Piece> piece(mesh.n_vertices());
  for (FH f : mesh.faces()) {
    const uint32_t src = m.face_source[f.idx()];
    Piece& p = piece[sets.find(uint32_t(mesh.cfv_iter(f)->idx()))];
    for (VH v : mesh.fv_range(f)) p.add((*w.labels)[src], mesh.point(v).data(), scale_of(opt, src));
  }
  std::vector<uint8_t> drop(mesh.n_vertices(), 0);
  for (size_t i = 0; i < piece.size(); ++i)
    if (piece[i].removable(mode, tolerance)) {
      drop[i] = 1;
      stats.pieces_removed++;
    }
  std::vector<FH> doomed;
  for (FH f : mesh.faces())
    if (drop[sets.find(uint32_t(mesh.cfv_iter(f)->idx()))]) doomed.push_back(f);
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
          if (m.vert_welded[v.idx()] == w.weld.corner[3 * size_t(src) + c]) match = v;
        const auto& mp = match.is_valid() ? mesh.point(match) : Mesh::Point(0, 0, 0);
        if (match.is_valid() && std::memcmp(mp.data(), p, 3 * sizeof(float)) == 0) {
          out.indices.push_back(emit_vertex(match));
        } else {
          out.indices.push_back(uint32_t(out.positions.size() / 3));
          out.positions.insert(out.positions.end(), p, p + 3);
        }
      }
    } else {
      if (m.flipped[f.idx()]) std::swap(fv[1], fv[2]);  // the input winding
      for (VH v : fv) out.indices.push_back(emit_vertex(v));
    }
    out.source.push_back(src);
  }
  stats.vertices_after = out.positions.size() / 3;
}

// ---- past the half-edge topology (free_topology) ----------------------------

// The model's faces as a plain triangle list in the input winding, on the
// same vertex numbers. Copies of one welded vertex (the vertices OpenMesh
// gave a face it could not join) become one again: the first copy a face
// with three distinct welded corners uses takes the others' quadrics,
// bounds and area, and they merge into it at its (equal) position. A face
// whose welded corners repeat keeps its own vertices.
FreeMesh to_free_mesh(const Model& m) {
  const Mesh& mesh = m.mesh;
  FreeMesh f;
  const size_t nv = mesh.n_vertices();
  f.points.resize(3 * nv);
  for (size_t v = 0; v < nv; ++v) {
    const auto& p = mesh.point(VH(int(v)));
    std::copy(p.data(), p.data() + 3, &f.points[3 * v]);
  }
  f.qa.resize(nv);
  if (m.has_qd()) f.qd.resize(nv);
  for (size_t v = 0; v < nv; ++v) {
    f.qa[v] = m.qa(VH(int(v)));
    if (m.has_qd()) f.qd[v] = m.qd(VH(int(v)));
  }
  f.tol = m.tol;
  f.area_budget = m.area_budget;
  f.area_used = m.area_used;
  f.locked = m.locked;
  f.merged_into = m.merged_into;
  std::unordered_map<uint32_t, uint32_t> first_of;  // welded vertex -> its first copy in use
  std::vector<uint8_t> merged(nv, 0);
  for (FH fh : mesh.faces()) {
    VH fv[3];
    int k = 0;
    for (VH v : mesh.fv_range(fh)) fv[k++] = v;
    if (m.flipped[fh.idx()]) std::swap(fv[1], fv[2]);
    uint32_t c[3];
    for (int i = 0; i < 3; ++i) c[i] = uint32_t(fv[i].idx());
    const uint32_t w[3] = {m.vert_welded[c[0]], m.vert_welded[c[1]], m.vert_welded[c[2]]};
    if (w[0] != w[1] && w[1] != w[2] && w[0] != w[2])
      for (int i = 0; i < 3; ++i) {
        const uint32_t first = first_of.emplace(w[i], c[i]).first->second;
        if (first == c[i]) continue;
        if (!merged[c[i]]) {  // c[i]'s figures go to the first copy once
          merged[c[i]] = 1;
          f.qa[first] += f.qa[c[i]];
          if (!f.qd.empty()) f.qd[first] += f.qd[c[i]];
          if (!f.tol.empty()) f.tol[first] = std::min(f.tol[first], f.tol[c[i]]);
          if (!f.area_budget.empty()) {
            f.area_used[first] += f.area_used[c[i]];
            f.area_budget[first] = std::min(f.area_budget[first], f.area_budget[c[i]]);
          }
          f.locked[first] |= f.locked[c[i]];
          f.merged_into[c[i]] = first;
        }
        c[i] = first;
      }
    f.tri.insert(f.tri.end(), c, c + 3);
    f.source.push_back(m.face_source[fh.idx()]);
  }
  f.alive.assign(f.source.size(), 1);
  f.faces_alive = f.source.size();
  return f;
}

// remove_pieces on the triangle list.
void remove_free_pieces(FreeMesh& f, const Work& w, const SimplifyOptions& opt, double tolerance,
                        SimplifyStats& stats) {
  const size_t nv = f.points.size() / 3;
  DisjointSets sets(nv);
  for (size_t t = 0; t < f.alive.size(); ++t)
    if (f.alive[t])
      for (int k = 1; k < 3; ++k) sets.unite(f.tri[3 * t], f.tri[3 * t + k]);
  std::vector<Piece> piece(nv);
  for (size_t t = 0; t < f.alive.size(); ++t) {
    if (!f.alive[t]) continue;
    Piece& p = piece[sets.find(f.tri[3 * t])];
    for (int k = 0; k < 3; ++k)
      p.add((*w.labels)[f.source[t]], &f.points[3 * size_t(f.tri[3 * t + k])], scale_of(opt, f.source[t]));
  }
  std::vector<uint8_t> drop(nv, 0);
  for (size_t i = 0; i < nv; ++i)
    if (piece[i].removable(opt.mode, tolerance)) {
      drop[i] = 1;
      stats.pieces_removed++;
    }
  for (size_t t = 0; t < f.alive.size(); ++t)
    if (f.alive[t] && drop[sets.find(f.tri[3 * t])]) {
      f.alive[t] = 0;
      --f.faces_alive;
      stats.pieces_triangles_removed++;
    }
}

void write_free_result(const FreeMesh& f, SimplifyStats& stats, Result& out) {
  std::vector<uint32_t> out_index(f.points.size() / 3, UINT32_MAX);
  for (size_t t = 0; t < f.alive.size(); ++t) {
    if (!f.alive[t]) continue;
    for (int k = 0; k < 3; ++k) {
      const uint32_t v = f.tri[3 * t + k];
      uint32_t& o = out_index[v];
      if (o == UINT32_MAX) {
        o = uint32_t(out.positions.size() / 3);
        out.positions.insert(out.positions.end(), &f.points[3 * size_t(v)], &f.points[3 * size_t(v)] + 3);
      }
      out.indices.push_back(o);
    }
    out.source.push_back(f.source[t]);
  }
  stats.vertices_after = out.positions.size() / 3;
}

// Belblidia's measures: each mesh vertex against the vertex it collapsed into
// (transitively); vertices of removed pieces are not counted. Sums, so that
// chunks add up.
struct Displacement {
  double sum = 0, max = 0;
  size_t count = 0;
  void add(const Displacement& o) {
    sum += o.sum;
    max = std::max(max, o.max);
    count += o.count;
  }
};

// `alive`: per vertex, whether a face left uses it; `point(v)`: its position.
template <class PointOf>
Displacement displacement(const std::vector<uint32_t>& merged_into, const std::vector<uint8_t>& alive,
                          PointOf point) {
  Displacement d;
  for (size_t i = 0; i < merged_into.size(); ++i) {
    uint32_t r = uint32_t(i);
    while (merged_into[r] != r) r = merged_into[r];
    if (!alive[r]) continue;
    double dist = (point(uint32_t(i)) - point(r)).norm();
    d.sum += dist;
    d.max = std::max(d.max, dist);
    ++d.count;
  }
  return d;
}

Displacement displacement(const Model& m) {
  const Mesh& mesh = m.mesh;
  std::vector<uint8_t> alive(mesh.n_vertices(), 0);
  for (FH f : mesh.faces())
    for (VH v : mesh.fv_range(f)) alive[v.idx()] = 1;
  return displacement(m.merged_into, alive, [&](uint32_t v) { return to_d(mesh.point(VH(int(v)))); });
}

Displacement displacement(const FreeMesh& f) {
  std::vector<uint8_t> alive(f.points.size() / 3, 0);
  for (size_t t = 0; t < f.alive.size(); ++t)
    if (f.alive[t])
      for (int k = 0; k < 3; ++k) alive[f.tri[3 * t + k]] = 1;
  return displacement(f.merged_into, alive, [&](uint32_t v) {
    const float* p = &f.points[3 * size_t(v)];
    return Vec(p[0], p[1], p[2]);
  });
}

}  // namespace

// Per-vertex tolerances: Bounded one for all, Fidelity the tightest bound
// of each vertex's faces (labels -> pixels -> scene units).
void init_tolerances(Model& m, const Work& w, const SimplifyOptions& opt) {
  if (opt.mode == SimplifyMode::Bounded) {
    m.tol.assign(m.mesh.n_vertices(), opt.k * opt.pixel_footprint);
    return;
  }
  const double bound_px[3] = {opt.bound_perceptible_px, opt.bound_imperceptible_px, opt.bound_undisplayable_px};
  // The area budget grows with the square of the label's distance bound
  // (from 1 px up; the default half-pixel bounds keep bound_area_px2): a
  // vertex that may move the surface e px may sweep about e^2 px^2 of it.
  // A fixed budget refused what looser bounds allow, whatever the bound.
  const double px2 = opt.pixel_footprint * opt.pixel_footprint;
  auto area_for = [&](double bound_px) {
    const double s = std::max(1.0, bound_px);
    return opt.bound_area_px2 * s * s * px2;
  };
  m.tol.assign(m.mesh.n_vertices(), INFINITY);
  m.area_budget.assign(m.mesh.n_vertices(), INFINITY);
  m.area_used.assign(m.mesh.n_vertices(), 0.0);
  for (FH f : m.mesh.faces()) {
    const uint32_t src = m.face_source[f.idx()];
    const size_t l = size_t((*w.labels)[src]);
    // bound_scale scales the perceptible and imperceptible bounds.
    const double px = l == size_t(Label::Undisplayable) ? bound_px[l] : bound_px[l] * double(scale_of(opt, src));
    const double tol = px * opt.pixel_footprint, area = l == size_t(Label::Undisplayable) ? INFINITY : area_for(px);
    for (VH v : m.mesh.fv_range(f)) {
      m.tol[v.idx()] = std::min(m.tol[v.idx()], tol);
      m.area_budget[v.idx()] = std::min(m.area_budget[v.idx()], area);
    }
  }
}

namespace {

// Splits `faces` into chunks of whole connected pieces (piece: pieces_of's):
// each piece goes to the chunk that is open when its first face comes, and a
// chunk closes once it holds chunk_faces faces or more. Faces keep their
// input order within a chunk. No collapse, piece removal or face refused by
// OpenMesh reaches outside its piece, so each chunk can be simplified on its
// own.
std::vector<std::vector<uint32_t>> split_into_chunks(const Work& w, const std::vector<uint32_t>& faces,
                                                     const std::vector<uint32_t>& piece, size_t chunk_faces) {
  if (chunk_faces == 0 || faces.size() <= chunk_faces) return {faces};
  std::vector<uint32_t> piece_faces(w.weld.positions.size() / 3, 0);
  for (uint32_t root : piece) piece_faces[root]++;
  std::vector<uint32_t> chunk_of(piece_faces.size(), UINT32_MAX);
  std::vector<std::vector<uint32_t>> chunks(1);
  size_t filled = 0;
  for (size_t i = 0; i < faces.size(); ++i) {
    const uint32_t root = piece[i];
    if (chunk_of[root] == UINT32_MAX) {
      if (filled >= chunk_faces) {
        chunks.emplace_back();
        filled = 0;
      }
      chunk_of[root] = uint32_t(chunks.size() - 1);
      filled += piece_faces[root];
    }
    chunks[chunk_of[root]].push_back(faces[i]);
  }
  return chunks;
}

struct Chunk {
  std::vector<uint32_t> faces;
  Result result;
  SimplifyStats stats;  // this chunk's counts
  Displacement moved;
};

// Everything after welding, for one chunk of pieces (or the whole mesh).
void simplify_chunk(const Work& w, const SimplifyOptions& opt, double tolerance, std::vector<int>& vh_of, Chunk& c) {
  const bool labelled = simplify_mode_uses_labels(opt.mode);
  const bool bounded = opt.mode == SimplifyMode::Bounded || opt.mode == SimplifyMode::Fidelity;
  const bool keep_perceptible = simplify_mode_keeps_perceptible(opt.mode);
  SimplifyStats& stats = c.stats;
  Model m;
  build_mesh(m, w, c.faces, vh_of, stats);
  std::vector<uint32_t>().swap(c.faces);
  stats.vertices_before = m.mesh.n_vertices();
  m.locked.assign(m.mesh.n_vertices(), 0);
  const bool free_topology = opt.mode == SimplifyMode::Fidelity && opt.free_topology;
  std::vector<uint8_t> joined_edges, copy;
  if (free_topology && stats.nonmanifold_faces_duplicated + stats.degenerate_faces > 0)
    joined_edges = find_joined_edges_and_copies(m, copy);
  init_quadrics(m, opt, bounded, joined_edges.empty() ? nullptr : &joined_edges);
  if (bounded) init_tolerances(m, w, opt);
  if (keep_perceptible) lock_perceptible(m, w);
  std::vector<uint8_t> rule_locks;  // the rules' own locks, while the copies are locked too
  if (!copy.empty()) {
    rule_locks = m.locked;
    for (size_t v = 0; v < copy.size(); ++v) m.locked[v] |= copy[v];
  }
  // Faces OpenMesh refused, and degenerate ones, were added as pieces of
  // their own: drop those that are removable too. Otherwise the mesh's pieces
  // are the welded ones drop_pieces_early already judged.
  if (labelled && stats.nonmanifold_faces_duplicated + stats.degenerate_faces > 0)
    remove_pieces(m, w, opt, tolerance, stats);
  Limits lim;
  lim.cos_normal = std::cos(opt.max_normal_change_deg * kPi / 180.0);
  lim.min_quality = opt.min_triangle_quality;
  lim.max_valence = opt.max_valence;
  lim.tie = 1e-8;
  size_t target = opt.mode == SimplifyMode::Qem ? opt.target_triangles : 0;
  Collapser(m, lim, target).run(stats, opt.explain_stop);

  if (labelled) remove_pieces(m, w, opt, tolerance, stats);
  if (free_topology) {
    if (!copy.empty()) m.locked = std::move(rule_locks);  // the copies are joined now
    FreeMesh f = to_free_mesh(m);
    m = Model{};
    if (opt.explain_stop) stats.refused = SimplifyStats::Refused{};  // what stops the last pass
    stats.free_collapses = free_collapse(f, lim, stats.max_error, opt.explain_stop ? &stats.refused : nullptr);
    stats.collapses += stats.free_collapses;
    remove_free_pieces(f, w, opt, tolerance, stats);
    c.moved = displacement(f);
    write_free_result(f, stats, c.result);
    return;
  }
  c.moved = displacement(m);
  write_result(m, w, keep_perceptible, stats, c.result);
}

// Appends a chunk's triangles (vertex indices shifted past those already
// there) and adds up its counts.
void merge_chunk(Chunk& c, SimplifyStats& stats, Result& out) {
  const uint32_t base = uint32_t(out.positions.size() / 3);
  out.positions.insert(out.positions.end(), c.result.positions.begin(), c.result.positions.end());
  for (uint32_t i : c.result.indices) out.indices.push_back(base + i);
  out.source.insert(out.source.end(), c.result.source.begin(), c.result.source.end());
  c.result = Result{};
  const SimplifyStats& s = c.stats;
  stats.vertices_before += s.vertices_before;
  stats.vertices_after += s.vertices_after;
  stats.pieces_removed += s.pieces_removed;
  stats.pieces_triangles_removed += s.pieces_triangles_removed;
  stats.nonmanifold_faces_duplicated += s.nonmanifold_faces_duplicated;
  stats.degenerate_faces += s.degenerate_faces;
  stats.collapses += s.collapses;
  stats.free_collapses += s.free_collapses;
  stats.max_error = std::max(stats.max_error, s.max_error);
  if (s.refused_counted) {
    stats.refused_counted = true;
    stats.refused.bound_or_locked += s.refused.bound_or_locked;
    stats.refused.valence += s.refused.valence;
    stats.refused.topology += s.refused.topology;
    stats.refused.shape += s.refused.shape;
    stats.refused.legal += s.refused.legal;
  }
  if (!s.target_reached) {
    stats.target_reached = false;
    stats.stop_reason = s.stop_reason;
  }
}

}  // namespace

void collapse_simplify(const Work& w, const SimplifyOptions& opt, SimplifyStats& stats,
                       Result& out) {
  const bool labelled = simplify_mode_uses_labels(opt.mode);  // collapse modes: paper, bounded, fidelity, qem
  double tolerance = -1;  // pieces without a perceptible face within this are removed
  if (opt.mode == SimplifyMode::Bounded) tolerance = stats.tolerance = opt.k * opt.pixel_footprint;
  if (opt.mode == SimplifyMode::Fidelity) {
    tolerance = stats.tolerance = opt.bound_imperceptible_px * opt.pixel_footprint;
    stats.tolerance_perceptible = opt.bound_perceptible_px * opt.pixel_footprint;
  }
  std::vector<uint32_t> faces = w.faces;
  // Qem's target counts the whole mesh: one chunk, and no piece is dropped.
  const size_t chunk_faces = opt.mode == SimplifyMode::Qem ? 0 : opt.chunk_faces;
  std::vector<uint32_t> piece;
  if (labelled || chunk_faces > 0) piece = pieces_of(w, faces);
  // Pieces that will be removed anyway are neither built nor collapsed.
  if (labelled) drop_pieces_early(w, faces, piece, opt, tolerance, stats);
  std::vector<std::vector<uint32_t>> parts = split_into_chunks(w, faces, piece, chunk_faces);
  std::vector<uint32_t>().swap(faces);
  std::vector<uint32_t>().swap(piece);
  stats.chunks = parts.size();
  std::vector<Chunk> chunks(parts.size());
  for (size_t i = 0; i < parts.size(); ++i) chunks[i].faces = std::move(parts[i]);
  std::vector<int> vh_of(w.weld.positions.size() / 3, -1);  // build_mesh's, shared by the chunks
  tbb::parallel_for(tbb::blocked_range<size_t>(0, chunks.size(), 1), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) simplify_chunk(w, opt, tolerance, vh_of, chunks[i]);
  });
  Displacement moved;
  for (Chunk& c : chunks) {
    merge_chunk(c, stats, out);
    moved.add(c.moved);
  }
  const double diag = w.diagonal > 0 ? w.diagonal : 1.0;
  stats.max_displacement_rel = moved.max / diag;
  stats.mean_displacement_rel = moved.count ? moved.sum / moved.count / diag : 0.0;
}

}  // namespace perclod::detail
