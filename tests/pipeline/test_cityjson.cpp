// CityJSON input: the converted demo building matches its OBJ, one component
// per CityObject grouped by building, transform in double, the LOD option,
// surfaces with holes, and malformed files rejected naming the file.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <iomanip>
#include <map>
#include <sstream>
#include <string>

#include "perclod/load.h"
#include "perclod/label.h"
#include "test_util.h"

using namespace perclod;

namespace {

const std::string kFixture = std::string(PERCLOD_SOURCE_DIR) + "/tests/pipeline/fixtures/bldg_4018215.city.json";
const std::string kSourceObj = std::string(PERCLOD_SOURCE_DIR) + "/data/ingolstadt/bldg_4018215.obj";

// A CityJSON document around CityObjects and vertices (JSON text).
std::string city(const std::string& objects, const std::string& vertices, const std::string& extra = "") {
  return R"({"type": "CityJSON", "version": "2.0", )" + extra + R"("CityObjects": {)" + objects +
         R"(}, "vertices": [)" + vertices + "]}";
}

double triangle_area(const Scene& s, size_t t) {
  const float* a = &s.positions[3 * size_t(s.indices[3 * t])];
  const float* b = &s.positions[3 * size_t(s.indices[3 * t + 1])];
  const float* c = &s.positions[3 * size_t(s.indices[3 * t + 2])];
  double u[3], v[3];
  for (int k = 0; k < 3; ++k) u[k] = double(b[k]) - a[k], v[k] = double(c[k]) - a[k];
  const double x = u[1] * v[2] - u[2] * v[1], y = u[2] * v[0] - u[0] * v[2], z = u[0] * v[1] - u[1] * v[0];
  return 0.5 * std::sqrt(x * x + y * y + z * z);
}

double total_area(const Scene& s) {
  double a = 0;
  for (size_t t = 0; t < s.triangle_count(); ++t) a += triangle_area(s, t);
  return a;
}

std::string last_part(const std::string& name) { return name.substr(name.rfind('/') + 1); }

std::map<std::string, size_t> triangles_per_component(const Scene& s) {
  std::map<std::string, size_t> n;
  for (size_t t = 0; t < s.triangle_count(); ++t) ++n[last_part(s.component_names[s.component_of(t)])];
  return n;
}

// "[v0,v1,...]". (Built with +=: GCC 12 reports a false -Wrestrict for
// "[" + std::to_string(...) chains once inlined into a unity batch.)
template <class T>
std::string json_list(std::initializer_list<T> values) {
  std::string s = "[";
  for (const T& v : values) {
    if (s.size() > 1) s += ',';
    s += std::to_string(v);
  }
  return s + "]";
}

// Square rings: four vertex indices, counter-clockwise seen from +z.
std::string quad(int a) { return json_list({a, a + 1, a + 2, a + 3}); }
std::string quad_reversed(int a) { return json_list({a + 3, a + 2, a + 1, a}); }
std::string rect_xy(double x0, double y0, double x1, double y1, double z = 0) {
  auto p = [&](double x, double y) { return json_list({x, y, z}); };
  return p(x0, y0) + "," + p(x1, y0) + "," + p(x1, y1) + "," + p(x0, y1);
}

// A unit cube's 8 vertices from `base` (Solid shell of 6 outward quads).
std::string cube_shell(int b) {
  auto f = [&](int i, int j, int k, int l) {
    return "[[" + std::to_string(b + i) + "," + std::to_string(b + j) + "," + std::to_string(b + k) + "," +
           std::to_string(b + l) + "]]";
  };
  return "[" + f(0, 3, 2, 1) + "," + f(4, 5, 6, 7) + "," + f(0, 1, 5, 4) + "," + f(1, 2, 6, 5) + "," +
         f(2, 3, 7, 6) + "," + f(3, 0, 4, 7) + "]";
}
std::string cube_vertices(double x, double y, double z) {
  std::string v;
  for (int k = 0; k < 8; ++k) {
    const double px = x + ((k == 1 || k == 2 || k == 5 || k == 6) ? 1 : 0);
    const double py = y + ((k == 2 || k == 3 || k == 6 || k == 7) ? 1 : 0);
    const double pz = z + (k >= 4 ? 1 : 0);
    std::ostringstream p;
    p << (k ? "," : "") << "[" << px << "," << py << "," << pz << "]";
    v += p.str();
  }
  return v;
}

}  // namespace

TEST(CityJson, FixtureMatchesTheObjItWasConvertedFrom) {
  LoadReport rep, obj_rep;
  const Scene s = load_scene(kFixture, {}, &rep);
  const Scene obj = load_scene(kSourceObj, {}, &obj_rep);
  ASSERT_EQ(obj.triangle_count(), 12456u);
  EXPECT_EQ(s.triangle_count(), obj.triangle_count());
  EXPECT_EQ(rep.polygons, 12456u);  // one triangle per surface (the default LOD is the highest: 3)
  EXPECT_EQ(rep.polygons_fanned, 0u);
  EXPECT_EQ(rep.polygons_skipped, 0u);
  EXPECT_EQ(rep.cityjson_objects_without_lod, 0u);
  EXPECT_FALSE(rep.components_from_connectivity);

  // One component per CityObject, each with its OBJ group's triangles.
  EXPECT_EQ(s.component_count(), 50u);
  EXPECT_EQ(s.component_count(), obj.component_count());
  EXPECT_EQ(triangles_per_component(s), triangles_per_component(obj));
  for (const auto& name : s.component_names) {
    EXPECT_EQ(name.substr(0, 8), "4018215/") << name;
    EXPECT_EQ(std::count(name.begin(), name.end(), '/'), 1) << name;
  }
  EXPECT_NE(std::find(s.component_names.begin(), s.component_names.end(), "4018215/4018215"), s.component_names.end());
  const Buildings b = find_buildings(s);
  ASSERT_EQ(b.names.size(), 1u);
  EXPECT_EQ(b.names[0], "4018215");

  // The file is in real UTM coordinates: its centre is the OBJ's plus the OBJ's
  // offset, to well under a millimetre (float would lose ~0.5 m at 5.4e6).
  const double origin[3] = {678000, 5403500, 400};
  for (int a = 0; a < 3; ++a) EXPECT_NEAR(s.offset[a], obj.offset[a] + origin[a], 1e-3) << "axis " << a;
  EXPECT_GT(s.offset[1], 5403500.0);
  const SceneInfo si = analyse_scene(s), oi = analyse_scene(obj);
  for (int a = 0; a < 3; ++a) {
    EXPECT_NEAR(si.bounds.lo[a], oi.bounds.lo[a], 1e-4);
    EXPECT_NEAR(si.bounds.hi[a], oi.bounds.hi[a], 1e-4);
  }
  EXPECT_NEAR(total_area(s), total_area(obj), 1e-6 * total_area(obj));
  // Windows and doors carry semantic types; the lod 3 building surfaces have none.
  bool window = false;
  for (const auto& m : s.materials) window |= m.name == "Window" && m.has_color;
  EXPECT_TRUE(window);
}

TEST(CityJson, LodOptionPicksTheLevelAndCountsObjectsWithoutIt) {
  LoadOptions opt;
  opt.cityjson_lod = "2";
  LoadReport rep;
  const Scene lod2 = load_scene(kFixture, opt, &rep);
  // Only the Building has the (made-up) lod 2 box: a Solid of 6 quads.
  EXPECT_EQ(lod2.triangle_count(), 12u);
  EXPECT_EQ(rep.polygons, 6u);
  EXPECT_EQ(rep.cityjson_objects_without_lod, 49u);
  ASSERT_EQ(lod2.component_count(), 1u);
  EXPECT_EQ(lod2.component_names[0], "4018215");  // no child has lod 2 geometry
  std::map<std::string, size_t> per_material;
  for (size_t t = 0; t < lod2.triangle_count(); ++t) ++per_material[lod2.material_of(t)->name];
  EXPECT_EQ(per_material["RoofSurface"], 2u);
  EXPECT_EQ(per_material["GroundSurface"], 2u);
  EXPECT_EQ(per_material["WallSurface"], 8u);
  for (const auto& m : lod2.materials) {
    if (m.name == "RoofSurface") {
      EXPECT_GT(m.color[0], m.color[2]);  // red-ish
    }
  }

  opt.cityjson_lod = "3.0";  // compared as a number
  const Scene lod3 = load_scene(kFixture, opt, &rep);
  EXPECT_EQ(lod3.triangle_count(), 12456u);
  EXPECT_EQ(rep.cityjson_objects_without_lod, 0u);

  opt.cityjson_lod = "1";
  const std::string none = test::load_error(kFixture, opt);
  EXPECT_NE(none.find(kFixture), std::string::npos) << none;
  EXPECT_NE(none.find("LOD 1"), std::string::npos) << none;
  EXPECT_NE(none.find("50"), std::string::npos) << none;
  opt.cityjson_lod = "two";
  EXPECT_NE(test::load_error(kFixture, opt).find("not a number"), std::string::npos);
}

TEST(CityJson, SurfacesWithHolesTriangulateToTheirArea) {
  test::TempDir dir("cityjson-holes");
  // 0-3: a 10x10 floor; 4-7: a 2x2 hole (clockwise, as CityJSON wants);
  // 8-11: a 1x3 hole given counter-clockwise (turned by the loader);
  // 12-15: a 4x3 wall in the x-z plane; 16-19: its 1x1 window hole.
  const std::string vertices = rect_xy(0, 0, 10, 10) + "," + rect_xy(2, 2, 4, 4) + "," + rect_xy(6, 1, 7, 4) +
                               ",[0,20,0],[4,20,0],[4,20,3],[0,20,3],[1,20,1],[2,20,1],[2,20,2],[1,20,2]";
  const std::string objects = R"("floor": {"type": "Building", "geometry": [{"type": "MultiSurface", "lod": "2",
      "boundaries": [[)" + quad(0) + "," + quad_reversed(4) + "," + quad(8) + R"(], [[12,13,14,15],[19,18,17,16]]]}]})";
  LoadReport rep;
  const Scene s = load_scene(dir.file("holes.city.json", city(objects, vertices)), {}, &rep);
  EXPECT_EQ(rep.polygons, 2u);
  EXPECT_EQ(rep.polygons_with_holes, 2u);
  EXPECT_EQ(rep.polygons_holes_failed, 0u);
  EXPECT_EQ(rep.polygons_fanned, 0u);
  EXPECT_NEAR(total_area(s), (100 - 4 - 3) + (12 - 1), 1e-4);
  // A ring with h corners and k holes of m corners: h + sum(m) + 2k - 2 triangles.
  EXPECT_EQ(s.triangle_count(), (4 + 8 + 4 - 2) + (4 + 4 + 2 - 2));

  // A concave (L-shaped) outer ring with a hole in each arm, and a grid of 25
  // holes in one square: bridges cross earlier bridges' rings.
  std::string v2 = "[0,0,0],[6,0,0],[6,2,0],[2,2,0],[2,6,0],[0,6,0]," + rect_xy(0.5, 3, 1.5, 5) + "," +
                   rect_xy(3, 0.5, 5, 1.5) + "," + rect_xy(0, 0, 10, 10, 5);
  std::string grid = "[" + quad(14);
  for (int i = 0; i < 25; ++i) {
    const double x = 1 + 1.7 * (i % 5), y = 1 + 1.7 * (i / 5) + 0.1 * (i % 3);  // uneven rows
    v2 += ",";
    v2 += rect_xy(x, y, x + 0.5, y + 0.5, 5);
    grid += ",";
    grid += quad_reversed(18 + 4 * i);
  }
  grid += "]";
  const std::string o2 = R"("L": {"type": "Building", "geometry": [{"type": "MultiSurface", "lod": "2",
      "boundaries": [[[0,1,2,3,4,5],)" + quad_reversed(6) + "," + quad_reversed(10) + "], " + grid + "]}]}";
  const Scene s2 = load_scene(dir.file("many.city.json", city(o2, v2)), {}, &rep);
  EXPECT_EQ(rep.polygons_with_holes, 2u);
  EXPECT_EQ(rep.polygons_holes_failed, 0u);
  EXPECT_EQ(rep.polygons_fanned, 0u);
  EXPECT_NEAR(total_area(s2), (20 - 2 - 2) + (100 - 25 * 0.25), 1e-4);

  // A hole outside its outer ring cannot be cut: counted, never silent.
  const std::string v3 = rect_xy(0, 0, 1, 1) + "," + rect_xy(5, 5, 6, 6);
  const std::string o3 = R"("x": {"type": "Building", "geometry": [{"type": "MultiSurface", "lod": 1,
      "boundaries": [[)" + quad(0) + "," + quad_reversed(4) + "]]}]}";
  load_scene(dir.file("outside.city.json", city(o3, v3)), {}, &rep);
  EXPECT_EQ(rep.polygons_with_holes, 1u);
  EXPECT_EQ(rep.polygons_holes_failed, 1u);
}

TEST(CityJson, ComponentsFollowParentsAndGeometryTypesAreRead) {
  test::TempDir dir("cityjson-tree");
  // Vertices: cubes at 0, 8, 16, 24, 32 (8 each); a template triangle anchor at 40.
  const std::string vertices = cube_vertices(0, 0, 0) + "," + cube_vertices(2, 0, 0) + "," + cube_vertices(4, 0, 0) +
                               "," + cube_vertices(6, 0, 0) + "," + cube_vertices(8, 0, 0) + ",[20,0,0]";
  const std::string objects = R"(
    "B1": {"type": "Building", "children": ["P1", "P2"]},
    "P1": {"type": "BuildingPart", "parents": ["B1"], "children": ["I1"],
           "geometry": [{"type": "Solid", "lod": "2", "boundaries": [)" + cube_shell(0) + R"(]}]},
    "P2": {"type": "BuildingPart", "parents": ["B1"],
           "geometry": [{"type": "MultiSolid", "lod": "2", "boundaries": [[)" + cube_shell(8) + "],[" + cube_shell(16) +
                            R"(]]}]},
    "I1": {"type": "BuildingInstallation", "parents": ["P1"],
           "geometry": [{"type": "CompositeSurface", "lod": "2", "boundaries": [[[24,27,26,25]]]}]},
    "B2": {"type": "Building", "children": ["W"],
           "geometry": [{"type": "MultiSurface", "lod": "2.2", "boundaries": [[[32,35,34,33]],[[36,37,38,39]]],
                         "semantics": {"surfaces": [{"type": "GroundSurface"}, {"type": "RoofSurface"}],
                                       "values": [0, 1]},
                         "material": {"look": {"values": [null, 0]}}},
                        {"type": "MultiLineString", "lod": "2.2", "boundaries": [[32, 33]]}]},
    "W": {"type": "BuildingInstallation", "parents": ["B2"],
          "geometry": [{"type": "CompositeSolid", "lod": "1", "boundaries": [[)" + cube_shell(0) + R"(]]}]},
    "Tree/1": {"type": "SolitaryVegetationObject",
               "geometry": [{"type": "GeometryInstance", "template": 0, "boundaries": [40],
                             "transformationMatrix": [2,0,0,0, 0,2,0,0, 0,0,2,0, 0,0,0,1]}]})";
  const std::string extra = R"("appearance": {"materials": [{"name": "blue", "diffuseColor": [0, 0, 1]}]},
    "geometry-templates": {"templates": [{"type": "MultiSurface", "lod": "2", "boundaries": [[[0, 1, 2]]]}],
                           "vertices-templates": [[0,0,0],[1,0,0],[0,1,0]]},)";
  LoadReport rep;
  const Scene s = load_scene(dir.file("tree.city.json", city(objects, vertices, extra)), {}, &rep);
  std::map<std::string, size_t> tris;
  for (size_t t = 0; t < s.triangle_count(); ++t) ++tris[s.component_names[s.component_of(t)]];
  const std::map<std::string, size_t> expected = {{"B1/P1", 12},   {"B1/P2", 24}, {"B1/P1/I1", 2},
                                                  {"B2/B2", 4},    {"B2/W", 12},  {"Tree|1", 1}};
  EXPECT_EQ(tris, expected);
  EXPECT_EQ(rep.cityjson_geometries_unsupported, 1u);  // the MultiLineString
  const Buildings b = find_buildings(s);
  EXPECT_EQ(b.names, (std::vector<std::string>{"B1", "B2", "Tree|1"}));

  // The roof has the appearance material (blue), the ground its semantic colour.
  for (size_t t = 0; t < s.triangle_count(); ++t) {
    if (s.component_names[s.component_of(t)] != "B2/B2") continue;
    const Material* m = s.material_of(t);
    ASSERT_NE(m, nullptr);
    const float z = s.positions[3 * size_t(s.indices[3 * t]) + 2] + float(s.offset[2]);
    if (z > 0.5f) {
      EXPECT_EQ(m->name, "blue");
      EXPECT_EQ(m->color, (std::array<float, 3>{0, 0, 1}));
    } else {
      EXPECT_EQ(m->name, "GroundSurface");
    }
  }
  // The template triangle, scaled by 2 and placed at its anchor (20, 0, 0).
  for (size_t t = 0; t < s.triangle_count(); ++t) {
    if (s.component_names[s.component_of(t)] != "Tree|1") continue;
    EXPECT_NEAR(triangle_area(s, t), 2.0, 1e-6);
    double maxx = -1e9;
    for (int k = 0; k < 3; ++k) maxx = std::max(maxx, s.positions[3 * size_t(s.indices[3 * t + k])] + s.offset[0]);
    EXPECT_NEAR(maxx, 22.0, 1e-6);
  }

  // lod 1: only W has it; everything else with geometry is counted.
  LoadOptions opt;
  opt.cityjson_lod = "1";
  const Scene s1 = load_scene(dir.file("tree.city.json", city(objects, vertices, extra)), opt, &rep);
  EXPECT_EQ(s1.triangle_count(), 12u);
  EXPECT_EQ(rep.cityjson_objects_without_lod, 5u);  // P1, P2, I1, B2, Tree/1
}

TEST(CityJson, TransformIsAppliedInDoublePrecision) {
  test::TempDir dir("cityjson-transform");
  const std::string objects = R"("a": {"type": "Building", "geometry": [{"type": "MultiSurface", "lod": "2",
      "boundaries": [[[0,1,2]]]}]})";
  const std::string extra = R"("transform": {"scale": [0.001, 0.001, 0.01], "translate": [678000.5, 5403500.25, 400]},)";
  const Scene s =
      load_scene(dir.file("t.json", city(objects, "[1,2,3],[1001,2,3],[1,4002,303]", extra)), {}, nullptr);
  EXPECT_NEAR(s.offset[0], 678000.5 + 0.001 * 501, 1e-7);
  EXPECT_NEAR(s.offset[1], 5403500.25 + 0.001 * 2002, 1e-7);
  EXPECT_NEAR(s.offset[2], 400 + 0.01 * 153, 1e-7);
  EXPECT_NEAR(triangle_area(s, 0), 0.5 * 1.0 * std::hypot(4.0, 3.0), 1e-5);

  // No extension: the content decides.
  const Scene bare = load_scene(dir.file("noext", city(objects, "[0,0,0],[1,0,0],[0,1,0]")));
  EXPECT_EQ(bare.triangle_count(), 1u);
}

TEST(CityJson, MalformedFilesThrowLoadErrorNamingTheFile) {
  test::TempDir dir("cityjson-bad");
  const std::string tri = R"("obj-7": {"type": "Building", "geometry": [{"type": "MultiSurface", "lod": "2",
      "boundaries": [[[0,1,2]]]}]})";
  const std::string ok_vertices = "[0,0,0],[1,0,0],[0,1,0]";
  struct Case {
    std::string name, text, expect;
  };
  const std::vector<Case> cases = {
      {"truncated.city.json", city(tri, ok_vertices).substr(0, 60), "malformed JSON"},
      {"geojson.json", R"({"type": "FeatureCollection", "features": []})", "not a CityJSON file"},
      {"array.json", "[1, 2, 3]", "not a CityJSON file"},
      {"novertices.city.json", R"({"type": "CityJSON", "version": "1.1", "CityObjects": {}})", "no \"vertices\""},
      {"range.city.json", city(tri, "[0,0,0],[1,0,0]"), "obj-7"},
      {"negative.city.json", city(R"("n": {"type": "Building", "geometry": [{"type": "MultiSurface", "lod": "2",
          "boundaries": [[[0,1,-1]]]}]})", ok_vertices), "out of range"},
      {"nanstring.city.json", city(tri, R"([0,0,0],[1,0,0],[0,"NaN",0])"), "vertex 2 coordinate 1"},
      {"null.city.json", city(tri, "[0,0,0],[1,0,0],[0,null,0]"), "not a number"},
      {"huge.city.json", city(tri, "[0,0,0],[1,0,0],[0,1e999,0]"), ""},
      {"short.city.json", city(tri, "[0,0,0],[1,0],[0,1,0]"), "not 3 numbers"},
      {"nolod.city.json", city(R"("q": {"type": "Building", "geometry": [{"type": "MultiSurface",
          "boundaries": [[[0,1,2]]]}]})", ok_vertices), "\"lod\""},
      {"ring.city.json", city(R"("r": {"type": "Building", "geometry": [{"type": "MultiSurface", "lod": "2",
          "boundaries": [[[0,1,"x"]]]}]})", ok_vertices), "not a vertex index"},
      {"parent.city.json", city(R"("c": {"type": "BuildingPart", "parents": ["ghost"], "geometry": [
          {"type": "MultiSurface", "lod": "2", "boundaries": [[[0,1,2]]]}]})", ok_vertices), "ghost"},
      {"cycle.city.json", city(R"("c1": {"type": "BuildingPart", "parents": ["c2"], "geometry": [
          {"type": "MultiSurface", "lod": "2", "boundaries": [[[0,1,2]]]}]},
          "c2": {"type": "BuildingPart", "parents": ["c1"]})", ok_vertices), "cycle"},
      {"transform.city.json", city(tri, ok_vertices, R"("transform": {"scale": [1, 1]},)"), "transform"},
      {"typeint.city.json", R"({"type": 5, "CityObjects": {}, "vertices": []})", "not a CityJSON file"},
      {"empty.city.json", city("", ""), "no triangles"},
  };
  for (const auto& c : cases) {
    const std::string path = dir.file(c.name, c.text);
    const std::string msg = test::load_error(path);
    EXPECT_NE(msg, "(no LoadError)") << c.name;
    EXPECT_NE(msg.find(path), std::string::npos) << c.name << ": " << msg;
    EXPECT_NE(msg.find(c.expect), std::string::npos) << c.name << ": " << msg;
  }
  // The out-of-range message names the index and the vertex count.
  const std::string msg = test::load_error(dir / "range.city.json");
  EXPECT_NE(msg.find("index 2 out of range (2 vertices)"), std::string::npos) << msg;
}

TEST(CityJson, RandomPolygonsWithHolesKeepTheirArea) {
  // Star-shaped outer rings (concave, 5-40 corners) with up to 12 holes of
  // 3-8 corners in separate cells (some sharing x or y with one another), in
  // random planes: every surface's triangles must cover outer minus holes.
  test::TempDir dir("cityjson-random-holes");
  uint64_t state = 12345;
  auto rnd = [&] {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return double(state >> 11) / double(1ULL << 53);
  };
  const double kPi = 3.14159265358979323846;
  for (int round = 0; round < 40; ++round) {
    std::ostringstream verts, bounds;
    int nv = 0;
    double expected = 0;
    // A random orthonormal frame (u, v) to place the plane in 3D, far from the origin.
    double u[3] = {rnd() - 0.5, rnd() - 0.5, rnd() - 0.5}, w[3] = {rnd() - 0.5, rnd() - 0.5, rnd() - 0.5};
    const double un = std::sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
    for (double& c : u) c /= un;
    const double d = w[0] * u[0] + w[1] * u[1] + w[2] * u[2];
    for (int k = 0; k < 3; ++k) w[k] -= d * u[k];
    const double wn = std::sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
    for (double& c : w) c /= wn;
    auto add = [&](double x, double y) {
      verts << (nv ? "," : "") << std::setprecision(17) << "[" << 1000 + x * u[0] + y * w[0] << ","
            << 2000 + x * u[1] + y * w[1] << "," << 30 + x * u[2] + y * w[2] << "]";
      return nv++;
    };
    auto ring_area = [](const std::vector<std::pair<double, double>>& r) {
      double a = 0;
      for (size_t i = 0; i < r.size(); ++i) {
        const auto& p = r[i];
        const auto& q = r[(i + 1) % r.size()];
        a += p.first * q.second - q.first * p.second;
      }
      return 0.5 * a;
    };
    const int corners = 5 + int(rnd() * 36);
    std::vector<std::pair<double, double>> outer;
    for (int i = 0; i < corners; ++i) {
      const double t = 2 * kPi * i / corners, r = 6 + 4 * rnd();
      outer.push_back({r * std::cos(t), r * std::sin(t)});
    }
    expected += ring_area(outer);
    bounds << "[[";
    for (size_t i = 0; i < outer.size(); ++i) bounds << (i ? "," : "") << add(outer[i].first, outer[i].second);
    bounds << "]";
    // Holes in cells of a 4x4 grid over [-4, 4]^2 (inside every outer ring).
    std::vector<int> cells(16);
    for (int i = 0; i < 16; ++i) cells[size_t(i)] = i;
    const int holes = int(rnd() * 13);
    for (int h = 0; h < holes; ++h) {
      const size_t pick = size_t(h) + size_t(rnd() * double(16 - h));
      std::swap(cells[size_t(h)], cells[pick]);
      const double cx = -3 + 2 * (cells[size_t(h)] % 4), cy = -3 + 2 * (cells[size_t(h)] / 4);
      const int m = 3 + int(rnd() * 6);
      std::vector<std::pair<double, double>> hole;
      const bool square = rnd() < 0.3;  // axis-aligned: corners share x and y with other holes
      for (int i = 0; i < m && !square; ++i) {
        const double t = 2 * kPi * i / m, r = 0.3 + 0.6 * rnd();
        hole.push_back({cx + r * std::cos(t), cy + r * std::sin(t)});
      }
      if (square) hole = {{cx - 0.5, cy - 0.5}, {cx + 0.5, cy - 0.5}, {cx + 0.5, cy + 0.5}, {cx - 0.5, cy + 0.5}};
      if (rnd() < 0.5) std::reverse(hole.begin(), hole.end());  // either orientation is accepted
      expected -= std::fabs(ring_area(hole));
      bounds << ",[";
      for (size_t i = 0; i < hole.size(); ++i) bounds << (i ? "," : "") << add(hole[i].first, hole[i].second);
      bounds << "]";
    }
    bounds << "]";
    const std::string objects = R"("s": {"type": "Building", "geometry": [{"type": "MultiSurface", "lod": "2",
        "boundaries": [)" + bounds.str() + "]}]}";
    LoadReport rep;
    const Scene s = load_scene(dir.file("r.city.json", city(objects, verts.str())), {}, &rep);
    EXPECT_EQ(rep.polygons_holes_failed, 0u) << "round " << round;
    EXPECT_EQ(rep.polygons_fanned, 0u) << "round " << round;
    EXPECT_NEAR(total_area(s), expected, 1e-4 * expected) << "round " << round << ", " << holes << " holes";
    EXPECT_EQ(s.triangle_count(), size_t(nv + 2 * holes - 2)) << "round " << round;
  }
}
