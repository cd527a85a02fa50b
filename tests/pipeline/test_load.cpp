// Loader: every triangle arrives with the right component; bad files give their documented errors.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <sstream>
#include <filesystem>

#include "perclod/export.h"
#include "perclod/load.h"
#include "test_util.h"

using namespace perclod;

namespace {

// Two groups. "panel": a quad (2 triangles), a duplicate triangle and a
// zero-area (collinear) triangle. "fin": three triangles on edge 2-3, which
// with the panel's triangles on that edge makes it non-manifold.
const char* kMessyObj = R"(# messy but legal
v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
v 2 0 0
v 0.5 0.5 1
v 0.5 0.5 -1
v 1.5 0.5 0.5
g panel
f 1 2 3 4
f 1 2 3
f 1 2 5
g fin
f 2 3 6
f 2 3 7
f 2 3 8
g panel
f 4 3 1
)";


}  // namespace

TEST(Load, MessyObjKeepsEveryTriangleWithItsGroup) {
  test::TempDir dir("load");
  auto path = dir.file("messy.obj", kMessyObj);
  LoadReport rep;
  Scene s = load_scene(path, {}, &rep);
  ASSERT_EQ(s.triangle_count(), 8u);  // quad -> 2, + dup + degenerate + 3 fins + 1
  EXPECT_EQ(rep.polygons, 7u);
  EXPECT_EQ(rep.polygons_triangulated, 1u);
  EXPECT_EQ(rep.degenerate_triangles, 1u);  // 1 2 5 is collinear
  ASSERT_EQ(s.component_count(), 2u);
  EXPECT_EQ(s.component_names[0], "panel");
  EXPECT_EQ(s.component_names[1], "fin");
  std::vector<uint32_t> expected = {0, 0, 0, 0, 1, 1, 1, 0};  // a repeated group name is the same group
  EXPECT_EQ(s.component, expected);
  SceneInfo info = analyse_scene(s);
  EXPECT_GE(info.non_manifold_edges, 1u);  // edge 2-3 has at least four faces
  EXPECT_EQ(info.degenerate_triangles, 1u);
}

TEST(Load, ConcavePolygonIsTriangulatedWithoutChangingItsArea) {
  // An L-shaped hexagon (area 3): a fan from vertex 1 would cover area outside it.
  test::TempDir dir("concave");
  auto path = dir.file("l.obj", "v 0 0 0\nv 2 0 0\nv 2 1 0\nv 1 1 0\nv 1 2 0\nv 0 2 0\nf 3 4 5 6 1 2\n");
  Scene s = load_scene(path);
  ASSERT_EQ(s.triangle_count(), 4u);
  double area = 0;
  for (size_t t = 0; t < 4; ++t) {
    const float* a = &s.positions[3 * s.indices[3 * t]];
    const float* b = &s.positions[3 * s.indices[3 * t + 1]];
    const float* c = &s.positions[3 * s.indices[3 * t + 2]];
    double cz = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
    EXPECT_GT(cz, 0) << "triangle " << t << " flipped or degenerate";
    area += 0.5 * cz;
  }
  EXPECT_NEAR(area, 3.0, 1e-6);
}

TEST(Load, FileWithoutGroupsGetsConnectedPartsAsComponents) {
  test::TempDir dir("parts");
  // Two separate triangles and a quad made of two triangles sharing an edge
  // (vertices repeated by position, not by index: welding must join them).
  auto path = dir.file("parts.obj",
                       "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 5 0 0\nv 6 0 0\nv 5 1 0\n"
                       "v 10 0 0\nv 11 0 0\nv 11 1 0\nv 10 0 0\nv 11 1 0\nv 10 1 0\n"
                       "f 1 2 3\nf 4 5 6\nf 7 8 9\nf 10 11 12\n");
  LoadReport rep;
  Scene s = load_scene(path, {}, &rep);
  EXPECT_TRUE(rep.components_from_connectivity);
  ASSERT_EQ(s.component_count(), 3u);
  EXPECT_EQ(s.component[2], s.component[3]);
  EXPECT_NE(s.component[0], s.component[1]);
  EXPECT_NE(s.component[1], s.component[2]);
}

TEST(Load, LargeOffsetIsRemovedInDoubleAndRestoredOnExport) {
  test::TempDir dir("offset");
  auto path = dir.file("utm.obj",
                       "v 678000.125 5403500.5 400\nv 678010.125 5403500.5 400\nv 678010.125 5403500.5 410\n"
                       "v 678000.001 5403500.001 400.001\nf 1 2 3\nf 1 2 4\n");
  Scene s = load_scene(path);
  EXPECT_NEAR(s.offset[0], 678005.063, 1e-3);
  EXPECT_NEAR(s.offset[1], 5403500.2505, 1e-4);
  // The millimetre detail survives recentring (float near 678000 would keep only 1/16 m).
  EXPECT_NEAR(double(s.positions[9]) + s.offset[0], 678000.001, 1e-5);
  EXPECT_NEAR(double(s.positions[10]) + s.offset[1], 5403500.001, 1e-5);
  auto out = dir / "back.obj";
  export_scene(s, out);
  Scene t = load_scene(out);
  ASSERT_EQ(t.triangle_count(), 2u);
  for (size_t v = 0; v < s.vertex_count(); ++v)
    for (int a = 0; a < 3; ++a)
      EXPECT_NEAR(double(t.positions[3 * v + a]) + t.offset[a], double(s.positions[3 * v + a]) + s.offset[a], 1e-5);
}

// OBJ carries the GLB's normals: a `vn` per normal group (a box: one per
// corner of each face, 24, each along an axis) and "v//vn" corners, and loads
// back with its triangles and components.
TEST(Export, ObjHasNormalsSplitAtCreases) {
  test::TempDir dir("export-vn");
  Scene box = test::box();
  export_scene(box, dir / "box.obj");
  std::ifstream in(dir / "box.obj");
  std::vector<std::array<double, 3>> normals;
  size_t faces = 0;
  for (std::string line; std::getline(in, line);) {
    std::istringstream ls(line);
    std::string tag;
    ls >> tag;
    if (tag == "vn") {
      std::array<double, 3> n;
      ls >> n[0] >> n[1] >> n[2];
      normals.push_back(n);
    } else if (tag == "f") {
      ++faces;
      for (std::string c; ls >> c;) EXPECT_NE(c.find("//"), std::string::npos) << line;
    }
  }
  EXPECT_EQ(faces, 12u);
  ASSERT_EQ(normals.size(), 24u);
  for (const auto& n : normals) {
    EXPECT_NEAR(std::abs(n[0]) + std::abs(n[1]) + std::abs(n[2]), 1, 1e-6);  // a unit axis
    EXPECT_NEAR(std::max({std::abs(n[0]), std::abs(n[1]), std::abs(n[2])}), 1, 1e-6);
  }
  EXPECT_EQ(load_scene(dir / "box.obj").triangle_count(), 12u);
}

// A scene without component or material arrays (Scene's contract: one
// component, the default material) exports to OBJ and GLB and loads back; a
// scene that breaks the contract is refused naming the output file, which is
// not written.
TEST(Export, SceneWithoutIdArraysExportsAndBrokenSceneIsRefused) {
  test::TempDir dir("export-ids");
  Scene s;
  s.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0};
  s.indices = {0, 1, 2, 1, 3, 2};
  for (const char* name : {"bare.obj", "bare.glb"}) {
    export_scene(s, dir / name);
    Scene t = load_scene(dir / name);
    EXPECT_EQ(t.triangle_count(), 2u) << name;
  }
  s.component = {0, 7};
  s.component_names = {"a"};
  try {
    export_scene(s, dir / "broken.obj");
    ADD_FAILURE() << "a component id without a name was exported";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("broken.obj"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("component 7"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(std::filesystem::exists(dir / "broken.obj"));
}

TEST(Load, UnitScaleAppliesToCoordinates) {
  test::TempDir dir("scale");
  auto path = dir.file("mm.obj", "v 0 0 0\nv 1000 0 0\nv 0 2000 0\nf 1 2 3\n");
  Scene s = load_scene(path, LoadOptions{0.001});
  Bounds b = scene_bounds(s);
  EXPECT_NEAR(b.hi[0] - b.lo[0], 1.0, 1e-6);
  EXPECT_NEAR(b.hi[1] - b.lo[1], 2.0, 1e-6);
}

// LoadOptions::centre: recentred on the point given (after the scale), so a
// second file shares the first's frame; the source coordinates stay
// position + offset.
TEST(Load, RecentresOnTheCentreGiven) {
  test::TempDir dir("centre");
  auto path = dir.file("far.obj", "v 678000 5403500 0\nv 678010 5403500 0\nv 678000 5403520 0\nf 1 2 3\n");
  const Scene own = load_scene(path);
  EXPECT_EQ(own.offset, (std::array<double, 3>{678005, 5403510, 0}));
  LoadOptions o;
  o.centre = std::array<double, 3>{678000, 5403500, -5};
  const Scene s = load_scene(path, o);
  EXPECT_EQ(s.offset, *o.centre);
  EXPECT_EQ(std::vector<float>(s.positions.begin(), s.positions.begin() + 3), (std::vector<float>{0, 0, 5}));
  EXPECT_EQ(s.positions[3], 10.0f);
  EXPECT_EQ(s.positions[7], 20.0f);
}

struct BadFile {
  const char* name;
  const char* text;  // nullptr: the file does not exist
  const char* expected;
};

class LoadErrors : public ::testing::TestWithParam<BadFile> {};

TEST_P(LoadErrors, NameTheFileAndTheProblem) {
  test::TempDir dir("bad");
  const BadFile& b = GetParam();
  std::string path = b.text ? dir.file(b.name, b.text) : dir / b.name;
  std::string msg = test::load_error(path);
  ASSERT_FALSE(msg.empty()) << "no error for " << b.name;
  EXPECT_NE(msg.find(b.name), std::string::npos) << msg;
  EXPECT_NE(msg.find(b.expected), std::string::npos) << msg;
}

INSTANTIATE_TEST_SUITE_P(
    Obj, LoadErrors,
    ::testing::Values(BadFile{"missing.obj", nullptr, "no such file"},
                      BadFile{"empty.obj", "", "no triangles"},
                      BadFile{"only_vertices.obj", "v 0 0 0\nv 1 0 0\n", "no triangles"},
                      BadFile{"nan.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n", ":2: vertex coordinate"},
                      BadFile{"inf.obj", "v 0 0 0\nv 1 0 0\nv 0 inf 0\nf 1 2 3\n", "NaN/inf"},
                      BadFile{"range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n", ":4: face index 4 out of range"},
                      BadFile{"zero.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", "not a vertex index"},
                      BadFile{"line.obj", "v 0 0 0\nv 1 0 0\nf 1 2\n", "a face needs 3"},
                      BadFile{"text.obj", "v 0 zero 0\n", "is not a number"},
                      BadFile{"garbage.ply", "this is not a ply file\n", "PLY file without an 'end_header' line"}),
    [](const auto& info) {
      std::string n = info.param.name;
      return n.substr(0, n.find('.')) + "_" + n.substr(n.find('.') + 1);
    });

TEST(Load, AssimpFormatsArriveWithComponents) {
  // An ASCII STL and a PLY of the same two triangles.
  test::TempDir dir("assimp");
  auto stl = dir.file("two.stl",
                      "solid two\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\n"
                      "facet normal 0 0 1\nouter loop\nvertex 1 0 0\nvertex 1 1 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid two\n");
  Scene s = load_scene(stl);
  EXPECT_EQ(s.triangle_count(), 2u);
  auto ply = dir.file("quad.ply",
                      "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
                      "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n");
  LoadReport rep;
  Scene q = load_scene(ply, {}, &rep);
  EXPECT_EQ(q.triangle_count(), 2u);
  EXPECT_EQ(q.component_count(), 1u);
}

TEST(Load, RealBuildingLoadsWithItsGroups) {
  Scene s = load_scene(PERCLOD_SOURCE_DIR "/data/ingolstadt/bldg_4018215.obj");
  EXPECT_EQ(s.triangle_count(), 12456u);
  EXPECT_EQ(s.component_count(), 50u);  // 51 g lines, one name used twice (the same group)
  // Its coordinates are already offset-free: the recentring offset is the box centre.
  Bounds b = scene_bounds(s);
  for (int a = 0; a < 3; ++a) EXPECT_NEAR(b.lo[a] + b.hi[a], 0.0f, 1e-3f);
}
