// The simplifier's own mesh edits (mesh_edits.h) against OpenMesh's
// add_face and collapse, which they replace: the same faces refused, the same
// handles, links and deleted flags, on grids added in shuffled order with
// some faces reversed (fans that must be relinked) and on random soups full
// of non-manifold edges and vertices.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <random>
#include <string>
#include <vector>

#include "mesh_edits.h"

namespace perclod::detail {
namespace {

using Tri = std::array<int, 3>;

// Every link and flag of the two meshes, element by element; the first
// difference found is reported.
::testing::AssertionResult same_connectivity(const Mesh& a, const Mesh& b) {
  auto differ = [](const std::string& what, int i) {
    return ::testing::AssertionFailure() << what << " " << i << " differs";
  };
  if (a.n_vertices() != b.n_vertices() || a.n_edges() != b.n_edges() || a.n_faces() != b.n_faces())
    return ::testing::AssertionFailure() << "element counts differ: " << a.n_vertices() << "/" << a.n_edges() << "/"
                                         << a.n_faces() << " against " << b.n_vertices() << "/" << b.n_edges() << "/"
                                         << b.n_faces();
  for (int i = 0; i < int(a.n_vertices()); ++i) {
    const VH v(i);
    if (a.halfedge_handle(v) != b.halfedge_handle(v)) return differ("vertex's first half-edge", i);
    if (a.status(v).deleted() != b.status(v).deleted()) return differ("vertex's deleted flag", i);
  }
  for (int i = 0; i < int(a.n_halfedges()); ++i) {
    const HH h(i);
    if (a.status(a.edge_handle(h)).deleted() != b.status(b.edge_handle(h)).deleted())
      return differ("edge's deleted flag of half-edge", i);
    if (a.status(h).deleted() != b.status(h).deleted()) return differ("half-edge's deleted flag", i);
    if (a.to_vertex_handle(h) != b.to_vertex_handle(h)) return differ("half-edge's vertex", i);
    if (a.face_handle(h) != b.face_handle(h)) return differ("half-edge's face", i);
    // The links of deleted half-edges are left as they were: not compared.
    if (a.status(a.edge_handle(h)).deleted()) continue;
    if (a.next_halfedge_handle(h) != b.next_halfedge_handle(h)) return differ("half-edge's next", i);
    if (a.prev_halfedge_handle(h) != b.prev_halfedge_handle(h)) return differ("half-edge's prev", i);
  }
  for (int i = 0; i < int(a.n_faces()); ++i) {
    const FH f(i);
    if (a.halfedge_handle(f) != b.halfedge_handle(f)) return differ("face's half-edge", i);
    if (a.status(f).deleted() != b.status(f).deleted()) return differ("face's deleted flag", i);
  }
  return ::testing::AssertionSuccess();
}

// Two meshes of n_vertices each, one built with OpenMesh's add_vertex and
// add_face, the other in bulk with a MeshBuilder and add_triangle, as the
// simplifier builds; every face must be taken or refused by both. finish()
// trims the bulk mesh and compares the two.
struct Twins {
  Mesh om, ours;
  MeshBuilder make{ours};
  size_t refused = 0;

  explicit Twins(int n_vertices) {
    for (int i = 0; i < n_vertices; ++i) {
      const Mesh::Point p(float(i), float(i * i % 7), 0.0f);
      om.add_vertex(p);
      make.new_vertex(p);
    }
  }
  void add(const Tri& t) {
    const VH v[3] = {VH(t[0]), VH(t[1]), VH(t[2])};
    const FH a = om.add_face(v[0], v[1], v[2]);
    const FH b = add_triangle(ours, v, make);
    ASSERT_EQ(a, b) << "face " << t[0] << " " << t[1] << " " << t[2];
    refused += !a.is_valid();
  }
  ::testing::AssertionResult finish() {
    make.finish();
    return same_connectivity(om, ours);
  }
};

// OpenMesh prints a line for each face it refuses; the soups refuse many.
struct Quiet {
  Quiet() { omerr().disable(); }
  ~Quiet() { omerr().enable(); }
};

// An n x n grid of quads split in two, in shuffled order, every
// `reverse_every`-th face (0: none) wound the other way.
std::vector<Tri> shuffled_grid(int n, int reverse_every, std::mt19937& rng) {
  std::vector<Tri> tris;
  auto id = [n](int x, int y) { return y * (n + 1) + x; };
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      tris.push_back({id(x, y), id(x + 1, y), id(x + 1, y + 1)});
      tris.push_back({id(x, y), id(x + 1, y + 1), id(x, y + 1)});
    }
  std::shuffle(tris.begin(), tris.end(), rng);
  if (reverse_every > 0)
    for (size_t i = 0; i < tris.size(); i += size_t(reverse_every)) std::swap(tris[i][1], tris[i][2]);
  return tris;
}

// Random triangles over few vertices: many edges and vertices end up
// shared by more faces than a manifold allows.
std::vector<Tri> soup(int n_vertices, int n_faces, std::mt19937& rng) {
  std::uniform_int_distribution<int> pick(0, n_vertices - 1);
  std::vector<Tri> tris;
  while (int(tris.size()) < n_faces) {
    Tri t{pick(rng), pick(rng), pick(rng)};
    if (t[0] != t[1] && t[1] != t[2] && t[0] != t[2]) tris.push_back(t);
  }
  return tris;
}

// Collapses up to `steps` random half-edges that OpenMesh calls legal, in
// both meshes, comparing them after each.
void collapse_both(Twins& t, int steps, std::mt19937& rng) {
  for (int s = 0; s < steps; ++s) {
    std::vector<HH> legal;
    for (int i = 0; i < int(t.om.n_halfedges()); ++i)
      if (t.om.is_collapse_ok(HH(i))) legal.push_back(HH(i));
    if (legal.empty()) return;
    const HH h = legal[std::uniform_int_distribution<size_t>(0, legal.size() - 1)(rng)];
    t.om.collapse(h);
    collapse_halfedge(t.ours, h);
    ASSERT_TRUE(same_connectivity(t.om, t.ours)) << "after collapse " << s << " (half-edge " << h.idx() << ")";
  }
}

TEST(MeshEdits, GridsInAnyOrderBuildAndCollapseAsOpenMeshDoes) {
  Quiet quiet;
  for (int seed = 1; seed <= 20; ++seed) {
    std::mt19937 rng(seed);
    const int n = 3 + seed % 5;
    Twins t((n + 1) * (n + 1));
    for (const Tri& tri : shuffled_grid(n, seed % 4 == 0 ? 0 : 3 + seed % 3, rng)) {
      t.add(tri);
      ASSERT_FALSE(::testing::Test::HasFatalFailure()) << "seed " << seed;
    }
    ASSERT_TRUE(t.finish()) << "seed " << seed;
    collapse_both(t, 2 * n * n, rng);
    ASSERT_FALSE(::testing::Test::HasFatalFailure()) << "seed " << seed;
  }
}

TEST(MeshEdits, NonManifoldSoupsRefuseAndCollapseAsOpenMeshDoes) {
  Quiet quiet;
  size_t refused = 0, taken = 0;
  for (int seed = 1; seed <= 40; ++seed) {
    std::mt19937 rng(1000 + seed);
    const int nv = 6 + seed % 10;
    Twins t(nv);
    for (const Tri& tri : soup(nv, 3 * nv, rng)) {
      t.add(tri);
      ASSERT_FALSE(::testing::Test::HasFatalFailure()) << "seed " << seed;
    }
    ASSERT_TRUE(t.finish()) << "seed " << seed;
    refused += t.refused;
    taken += t.om.n_faces();
    collapse_both(t, nv, rng);
    ASSERT_FALSE(::testing::Test::HasFatalFailure()) << "seed " << seed;
  }
  // The soups must exercise both outcomes, or the comparison says little.
  EXPECT_GT(refused, 100u);
  EXPECT_GT(taken, 100u);
}

// A grid big enough that the bulk mesh grows by several batches of
// vertices, edges and faces, and is trimmed after.
TEST(MeshEdits, BulkBuildsOverManyBatchesMatchOpenMesh) {
  Quiet quiet;
  std::mt19937 rng(7);
  const int n = 64;  // 4,225 vertices, up to 12,416 edges and 8,192 faces
  Twins t((n + 1) * (n + 1));
  for (const Tri& tri : shuffled_grid(n, 5, rng)) {
    t.add(tri);
    ASSERT_FALSE(::testing::Test::HasFatalFailure());
  }
  ASSERT_TRUE(t.finish());  // the same element counts too
  EXPECT_GT(t.ours.n_vertices(), 4096u);
  EXPECT_GT(t.ours.n_edges(), 2 * 4096u);
  EXPECT_GT(t.ours.n_faces(), 4096u);
  collapse_both(t, 50, rng);
}

TEST(MeshEdits, HalfedgeLookupAndValence) {
  Twins t(5);
  for (const Tri& tri : {Tri{0, 1, 2}, Tri{0, 2, 3}, Tri{0, 3, 4}}) t.add(tri);
  ASSERT_TRUE(t.finish());
  EXPECT_EQ(halfedge_between(t.ours, VH(0), VH(2)), t.om.find_halfedge(VH(0), VH(2)));
  EXPECT_EQ(t.ours.to_vertex_handle(halfedge_between(t.ours, VH(3), VH(4))), VH(4));
  EXPECT_FALSE(halfedge_between(t.ours, VH(1), VH(3)).is_valid());
  EXPECT_EQ(valence_of(t.ours, VH(0)), 4);
  EXPECT_EQ(valence_of(t.ours, VH(1)), 2);
}

}  // namespace
}  // namespace perclod::detail
