// The simplifier's half-edge mesh (OpenMesh's array kernel with status flags
// and stored prev links) and the edits the collapse simplifier makes to it.
//
// Debian builds libOpenMeshCore with its assertions on, so each handle that
// its add_face, collapse, find_halfedge and valence touch is range-checked by
// an out-of-line call: a third of simplify()'s time on one thread. These make
// the same edits through the kernel's inline accessors and circulators, with
// the same outcome (which faces are refused, handle numbering, every vertex's
// and face's first half-edge), so the output is the same bytes.
#pragma once

#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>

#include <utility>

namespace perclod::detail {

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

// The half-edge from a to b, or an invalid handle.
inline HH halfedge_between(const Mesh& mesh, VH a, VH b) {
  for (HH h : mesh.voh_range(a))
    if (mesh.to_vertex_handle(h) == b) return h;
  return HH();
}

inline int valence_of(const Mesh& mesh, VH v) {
  int n = 0;
  for (HH h : mesh.voh_range(v)) (void)h, ++n;
  return n;
}

// A vertex on the boundary starts its fan at its (first) outgoing boundary
// half-edge, as OpenMesh's circulators and boundary tests expect. So
// mesh.is_boundary(v) reads one half-edge; callers that know v was not on
// the boundary before an edit that cannot open it skip this walk round the
// fan, which would find nothing (a few percent of simplify()'s one-thread
// time on the million-triangle facade).
inline void start_at_boundary(Mesh& mesh, VH v) {
  for (HH h : mesh.voh_range(v))
    if (mesh.is_boundary(h)) {
      mesh.set_halfedge_handle(v, h);
      return;
    }
}

// New elements for a mesh built in bulk: the element arrays and their
// properties grow kBatch elements at a time, and finish() trims them to the
// elements made. The handles, links and (zero) flags are those OpenMesh's
// add_vertex, new_edge and new_face make, which resize every property by one
// element each time: nearly two fifths of the instructions of building the
// meshes (callgrind, the 1M facade at 427 m: 1.28 G with them, 0.79 G
// without).
class MeshBuilder {
 public:
  explicit MeshBuilder(Mesh& mesh) : mesh_(mesh), v_(mesh.n_vertices()), e_(mesh.n_edges()), f_(mesh.n_faces()) {}
  VH new_vertex(const Mesh::Point& p) {
    if (v_ == mesh_.n_vertices()) mesh_.resize(v_ + kBatch, mesh_.n_edges(), mesh_.n_faces());
    const VH v(int(v_++));
    mesh_.set_point(v, p);
    return v;
  }
  HH new_edge(VH from, VH to) {
    if (e_ == mesh_.n_edges()) mesh_.resize(mesh_.n_vertices(), e_ + kBatch, mesh_.n_faces());
    const OpenMesh::EdgeHandle e(int(e_++));
    const HH h = mesh_.halfedge_handle(e, 0);
    mesh_.set_vertex_handle(h, to);
    mesh_.set_vertex_handle(mesh_.opposite_halfedge_handle(h), from);
    return h;
  }
  FH new_face() {
    if (f_ == mesh_.n_faces()) mesh_.resize(mesh_.n_vertices(), mesh_.n_edges(), f_ + kBatch);
    return FH(int(f_++));
  }
  // The mesh holds the elements made, no more (their properties too).
  void finish() { mesh_.resize(v_, e_, f_); }

 private:
  static constexpr size_t kBatch = 4096;
  Mesh& mesh_;
  size_t v_, e_, f_;  // elements made
};

// Adds triangle v[0] v[1] v[2] as OpenMesh's add_face does, or returns an
// invalid handle, changing nothing, where it would refuse: a corner with no
// free gap in its fan, a side already bounded on this side, or two old sides
// whose fans cannot be relinked to meet. New edges and the face come from
// `make`, the builder of `mesh`.
inline FH add_triangle(Mesh& mesh, const VH v[3], MeshBuilder& make) {
  HH side[3];  // v[i] -> v[i+1]
  bool fresh[3];
  for (int i = 0; i < 3; ++i) {
    if (!mesh.is_boundary(v[i])) return FH();
    side[i] = halfedge_between(mesh, v[i], v[(i + 1) % 3]);
    fresh[i] = !side[i].is_valid();
    if (!fresh[i] && !mesh.is_boundary(side[i])) return FH();
  }
  // The next-links to set, collected first so a refusal changes nothing and
  // every read below sees the mesh as it was.
  std::pair<HH, HH> link[18];
  int links = 0;
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3;
    if (fresh[i] || fresh[j]) continue;
    const HH in = side[i], out = side[j];  // meet at v[j]
    if (mesh.next_halfedge_handle(in) == out) continue;
    // The fan part between `in` and `out` moves to another gap of v[j].
    HH gap = mesh.opposite_halfedge_handle(out);
    do gap = mesh.opposite_halfedge_handle(mesh.next_halfedge_handle(gap));
    while (!mesh.is_boundary(gap));
    if (gap == in) return FH();
    link[links++] = {gap, mesh.next_halfedge_handle(in)};
    link[links++] = {mesh.prev_halfedge_handle(out), mesh.next_halfedge_handle(gap)};
    link[links++] = {in, out};
  }
  for (int i = 0; i < 3; ++i)
    if (fresh[i]) side[i] = make.new_edge(v[i], v[(i + 1) % 3]);
  const FH f = make.new_face();
  mesh.set_halfedge_handle(f, side[2]);
  bool restart[3] = {false, false, false};  // start v[j]'s fan at a boundary half-edge again
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3;
    const VH corner = v[j];
    const HH in = side[i], out = side[j];
    if (fresh[i] || fresh[j]) {
      const HH outer_in = mesh.opposite_halfedge_handle(out), outer_out = mesh.opposite_halfedge_handle(in);
      if (!fresh[j]) {  // only `in` is new
        link[links++] = {mesh.prev_halfedge_handle(out), outer_out};
        mesh.set_halfedge_handle(corner, outer_out);
      } else if (!fresh[i]) {  // only `out` is new
        const HH after = mesh.next_halfedge_handle(in);
        link[links++] = {outer_in, after};
        mesh.set_halfedge_handle(corner, after);
      } else if (!mesh.halfedge_handle(corner).is_valid()) {  // both new, a vertex on its own
        mesh.set_halfedge_handle(corner, outer_out);
        link[links++] = {outer_in, outer_out};
      } else {  // both new, into the gap the corner's fan starts at
        const HH gap_out = mesh.halfedge_handle(corner);
        link[links++] = {mesh.prev_halfedge_handle(gap_out), outer_out};
        link[links++] = {outer_in, gap_out};
      }
      link[links++] = {in, out};
    } else {
      restart[j] = mesh.halfedge_handle(corner) == out;
    }
    mesh.set_face_handle(in, f);
  }
  for (int k = 0; k < links; ++k) mesh.set_next_halfedge_handle(link[k].first, link[k].second);
  for (int i = 0; i < 3; ++i)
    if (restart[i]) start_at_boundary(mesh, v[i]);
  return f;
}

// Removes the two-edge loop that starts at `h` (left where a collapsed face
// was): h's edge goes, the next half-edge takes the face on h's far side.
inline void remove_loop(Mesh& mesh, HH h) {
  const HH next = mesh.next_halfedge_handle(h);
  const HH far = mesh.opposite_halfedge_handle(h);
  const VH a = mesh.to_vertex_handle(h), b = mesh.to_vertex_handle(next);
  const FH gone = mesh.face_handle(h), kept = mesh.face_handle(far);
  // Removing the loop opens no boundary: where `far` is a boundary
  // half-edge (so `next` becomes one) it already left a and entered b.
  const bool a_open = mesh.is_boundary(a), b_open = mesh.is_boundary(b);
  mesh.set_next_halfedge_handle(next, mesh.next_halfedge_handle(far));
  mesh.set_next_halfedge_handle(mesh.prev_halfedge_handle(far), next);
  mesh.set_face_handle(next, kept);
  mesh.set_halfedge_handle(a, next);
  if (a_open) start_at_boundary(mesh, a);
  mesh.set_halfedge_handle(b, mesh.opposite_halfedge_handle(next));
  if (b_open) start_at_boundary(mesh, b);
  if (kept.is_valid() && mesh.halfedge_handle(kept) == far) mesh.set_halfedge_handle(kept, next);
  if (gone.is_valid()) {
    mesh.set_halfedge_handle(gone, HH());
    mesh.status(gone).set_deleted(true);
  }
  mesh.status(mesh.edge_handle(h)).set_deleted(true);
  mesh.status(h).set_deleted(true);
  mesh.status(far).set_deleted(true);
}

// Collapses h: its from-vertex v0 goes, everything of v0 now ends at its
// to-vertex v1, and the faces of h's edge (now two-edge loops) go too.
inline void collapse_halfedge(Mesh& mesh, HH h) {
  const HH o = mesh.opposite_halfedge_handle(h);
  const HH h_next = mesh.next_halfedge_handle(h), h_prev = mesh.prev_halfedge_handle(h);
  const HH o_next = mesh.next_halfedge_handle(o), o_prev = mesh.prev_halfedge_handle(o);
  const FH fh = mesh.face_handle(h), fo = mesh.face_handle(o);
  const VH v1 = mesh.to_vertex_handle(h), v0 = mesh.to_vertex_handle(o);
  const bool open = mesh.is_boundary(v0) || mesh.is_boundary(v1);  // v1 is on the boundary after
  for (auto it = mesh.vih_iter(v0); it.is_valid(); ++it) mesh.set_vertex_handle(*it, v1);
  mesh.set_next_halfedge_handle(h_prev, h_next);
  mesh.set_next_halfedge_handle(o_prev, o_next);
  if (fh.is_valid()) mesh.set_halfedge_handle(fh, h_next);
  if (fo.is_valid()) mesh.set_halfedge_handle(fo, o_next);
  if (mesh.halfedge_handle(v1) == o) mesh.set_halfedge_handle(v1, h_next);
  if (open) start_at_boundary(mesh, v1);
  mesh.set_isolated(v0);
  mesh.status(mesh.edge_handle(h)).set_deleted(true);
  mesh.status(v0).set_deleted(true);
  mesh.status(h).set_deleted(true);
  mesh.status(o).set_deleted(true);
  if (mesh.next_halfedge_handle(mesh.next_halfedge_handle(h_next)) == h_next)
    remove_loop(mesh, mesh.next_halfedge_handle(h_next));
  if (mesh.next_halfedge_handle(mesh.next_halfedge_handle(o_next)) == o_next) remove_loop(mesh, o_next);
}

}  // namespace perclod::detail
