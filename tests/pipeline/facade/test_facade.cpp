// The parametric facade: counts follow the parameters, the mesh is well
// formed, and each switch builds the fixture it promises. What
// `perclod generate facade` writes is checked in e2e/test_cli_facade.cpp.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include "facade_fixtures.h"
#include "perclod/facade.h"

namespace perclod {
namespace {

using test::facade_fixtures::all_on;
using test::facade_fixtures::corner;
using test::facade_fixtures::Vec;
using test::facade_fixtures::vertex;

Vec sub(Vec a, Vec b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
Vec cross(Vec a, Vec b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double dot(Vec a, Vec b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
double norm(Vec a) { return std::sqrt(dot(a, a)); }
Vec normal(const Scene& s, size_t tri) {
  Vec a = corner(s, tri, 0);
  return cross(sub(corner(s, tri, 1), a), sub(corner(s, tri, 2), a));
}

bool contains(const std::string& name, const std::string& part) {
  return name.find(part) != std::string::npos;
}
bool ends_with(const std::string& name, const std::string& part) {
  return name.size() >= part.size() && name.compare(name.size() - part.size(), part.size(), part) == 0;
}

size_t components_ending(const Scene& s, const std::string& part) {
  return size_t(std::count_if(s.component_names.begin(), s.component_names.end(),
                              [&](const std::string& n) { return ends_with(n, part); }));
}

struct Box3 {
  Vec lo{1e30, 1e30, 1e30}, hi{-1e30, -1e30, -1e30};
  void add(Vec p) {
    for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], p[a]), hi[a] = std::max(hi[a], p[a]);
  }
};

// Bounding box of the triangles whose component name passes `pick`.
template <class Pick>
Box3 box_of(const Scene& s, Pick pick) {
  Box3 b;
  for (size_t t = 0; t < s.triangle_count(); ++t)
    if (pick(s.component_names[s.component[t]]))
      for (int k = 0; k < 3; ++k) b.add(corner(s, t, k));
  return b;
}

TEST(Facade, GeneratedCountEqualsPredictionOverASweep) {
  int checked = 0;
  for (int sides : {1, 4})
    for (int floors : {1, 3})
      for (int bays : {1, 2, 5})
        for (int seg : {3, 12})
          for (int detail : {0, 3})
            for (int variant = 0; variant < 3; ++variant) {
              FacadeParams p = all_on(floors, bays, sides);
              p.column_segments = seg;
              p.ornament_detail = detail;
              p.mullions_per_window = variant;
              p.transoms_per_window = 2 - variant;
              p.balusters_per_bay = 1 + 4 * variant;
              p.baluster_segments = 3 + variant;
              if (variant == 1) p.frames = p.hidden_interior = p.cornices = false;
              if (variant == 2) p.sills = p.columns = p.coplanar_panels = false;
              Scene s = generate_facade(p);
              ASSERT_EQ(s.triangle_count(), facade_triangle_count(p))
                  << "sides " << sides << " floors " << floors << " bays " << bays << " seg "
                  << seg << " detail " << detail << " variant " << variant;
              ++checked;
            }
  EXPECT_EQ(checked, 144);
}

// The triangles each switch adds, worked out by hand from the part list:
// a box is 12 triangles, a quad 2, a turned part with R rings and S segments
// 2S(R-1) + 2S.
TEST(Facade, EachSwitchChangesTheCountByItsParts) {
  const FacadeParams base = all_on(3, 4, 4);  // 4 sides x 3 floors x 4 bays = 48 cells
  const size_t cells = 48, bays = 16, columns = 4 * 3 * 3;
  const size_t S = 12, B = 8, n = 6, m = 1, tr = 1;
  const size_t column = 12 + (2 * S * 1 + 2 * S) + (2 * S * 2 + 2 * S) + 12;  // shaft 2 rings, capital 3
  const size_t baluster = 2 * B * 5 + 2 * B;                                   // 6 rings
  struct Case {
    const char* name;
    bool FacadeParams::*flag;
    size_t expected;
  };
  const Case cases[] = {
      {"frames", &FacadeParams::frames, cells * 4 * 12},
      {"mullions", &FacadeParams::mullions, cells * (m + tr * (m + 1)) * 12},
      {"sills", &FacadeParams::sills, cells * 12},
      {"cornices", &FacadeParams::cornices, cells * 2 * 12},
      {"columns", &FacadeParams::columns, columns * column},
      {"balusters", &FacadeParams::balusters, bays * (2 * 12 + n * baluster)},
      {"hidden_interior", &FacadeParams::hidden_interior, 3 * 4 * 12},
      {"coplanar_panels", &FacadeParams::coplanar_panels, cells * 2 * 2},
      {"subpixel_ornaments", &FacadeParams::subpixel_ornaments, cells * 6 * 12},
  };
  const size_t on = generate_facade(base).triangle_count();
  for (const Case& c : cases) {
    FacadeParams off = base;
    off.*c.flag = false;
    size_t predicted = facade_triangle_count(off), generated = generate_facade(off).triangle_count();
    EXPECT_EQ(generated, predicted) << c.name;
    EXPECT_EQ(on - generated, c.expected) << c.name;
  }
}

TEST(Facade, DoublingBaysDoublesTheWindowParts) {
  Scene a = generate_facade(all_on(3, 4)), b = generate_facade(all_on(3, 8));
  for (const char* part : {"_frame", "_glass", "_sill", "_cornice", "_mullion0", "_transom0",
                           "_wall_left", "_ornaments", "_plaque_a"}) {
    EXPECT_EQ(components_ending(a, part), 12u) << part;
    EXPECT_EQ(components_ending(b, part), 24u) << part;
  }
  // Columns stand between bays: 3 floors x (bays - 1).
  EXPECT_EQ(components_ending(a, "_column"), 9u);
  EXPECT_EQ(components_ending(b, "_column"), 21u);
  double ratio = double(b.triangle_count()) / double(a.triangle_count());
  EXPECT_GT(ratio, 1.8);
  EXPECT_LT(ratio, 2.1);
  // More tessellation and detail grow the turned parts only.
  FacadeParams fine = all_on(3, 4);
  fine.column_segments = 48;
  EXPECT_GT(facade_triangle_count(fine), facade_triangle_count(all_on(3, 4)));
  fine.ornament_detail = 10;
  EXPECT_GT(facade_triangle_count(fine), 2 * facade_triangle_count(all_on(3, 4)));
}

void expect_well_formed(const Scene& s) {
  ASSERT_EQ(s.indices.size(), 3 * s.triangle_count());
  ASSERT_EQ(s.component.size(), s.triangle_count());
  ASSERT_EQ(s.material.size(), s.triangle_count());
  ASSERT_EQ(s.positions.size() % 3, 0u);
  for (float v : s.positions) ASSERT_TRUE(std::isfinite(v));
  for (uint32_t i : s.indices) ASSERT_LT(i, s.vertex_count());
  std::vector<size_t> per_component(s.component_count(), 0);
  for (size_t t = 0; t < s.triangle_count(); ++t) {
    ASSERT_LT(s.component[t], s.component_count());
    ASSERT_LT(s.material[t], s.materials.size());
    ++per_component[s.component[t]];
    double area = 0.5 * norm(normal(s, t));
    ASSERT_GT(area, 1e-7) << "triangle " << t << " of " << s.component_names[s.component[t]];
  }
  for (size_t c = 0; c < s.component_count(); ++c)
    EXPECT_GT(per_component[c], 0u) << s.component_names[c];
  std::vector<std::string> names = s.component_names;
  std::sort(names.begin(), names.end());
  EXPECT_EQ(std::adjacent_find(names.begin(), names.end()), names.end()) << "duplicate name";
  for (const Material& m : s.materials) EXPECT_TRUE(m.has_color) << m.name;
}

TEST(Facade, SceneIsWellFormed) {
  for (int sides : {1, 4}) {
    FacadeParams p = all_on(2, 3, sides);
    p.column_segments = 5;
    p.ornament_detail = 2;
    expect_well_formed(generate_facade(p));
  }
  FacadeParams bare;
  bare.floors = 1;
  bare.bays = 1;
  bare.frames = bare.mullions = bare.sills = bare.cornices = bare.columns = bare.balusters = false;
  expect_well_formed(generate_facade(bare));
}

TEST(Facade, ComponentsDoNotShareVertices) {
  Scene s = generate_facade(all_on(2, 3, 4));
  std::vector<int64_t> owner(s.vertex_count(), -1);
  for (size_t t = 0; t < s.triangle_count(); ++t)
    for (int k = 0; k < 3; ++k) {
      int64_t& o = owner[s.indices[3 * t + k]];
      if (o < 0) o = s.component[t];
      ASSERT_EQ(o, int64_t(s.component[t])) << "vertex shared across components";
    }
}

// Every solid part is closed with consistent orientation (each directed edge
// appears once, its reverse once) and encloses positive volume, so the
// triangles are counter-clockwise seen from outside.
TEST(Facade, SolidsAreClosedAndFaceOutwards) {
  FacadeParams p = all_on(2, 3, 4);
  p.column_segments = 7;
  Scene s = generate_facade(p);
  std::vector<std::map<std::pair<uint32_t, uint32_t>, int>> edges(s.component_count());
  std::vector<double> volume(s.component_count(), 0.0);
  for (size_t t = 0; t < s.triangle_count(); ++t) {
    uint32_t c = s.component[t];
    for (int k = 0; k < 3; ++k) edges[c][{s.indices[3 * t + k], s.indices[3 * t + (k + 1) % 3]}]++;
    volume[c] += dot(corner(s, t, 0), cross(corner(s, t, 1), corner(s, t, 2))) / 6.0;
  }
  size_t solids = 0;
  for (size_t c = 0; c < s.component_count(); ++c) {
    const std::string& name = s.component_names[c];
    if (contains(name, "glass") || contains(name, "plaque")) continue;  // single quads
    ++solids;
    for (const auto& [e, n] : edges[c]) {
      ASSERT_EQ(n, 1) << name << ": directed edge used twice";
      ASSERT_EQ(edges[c].count({e.second, e.first}), 1u) << name << ": open edge";
    }
    EXPECT_GT(volume[c], 0.0) << name;
  }
  EXPECT_GT(solids, 100u);
}

TEST(Facade, MainFacadeFacesMinusYAndOffsetRestoresTheWallPlane) {
  Scene s = generate_facade(all_on(2, 3));
  Bounds b = scene_bounds(s);
  for (int a = 0; a < 3; ++a) EXPECT_NEAR(b.center()[a], 0.0f, 1e-4f) << "axis " << a;
  size_t glass = 0;
  for (size_t t = 0; t < s.triangle_count(); ++t) {
    if (!ends_with(s.component_names[s.component[t]], "_glass")) continue;
    Vec n = normal(s, t);
    EXPECT_LT(n[1] / norm(n), -0.999);
    ++glass;
  }
  EXPECT_EQ(glass, 2u * 6);
  // Source coordinates: the main wall's outer face is the plane y = 0, the
  // building stands on z = 0 from x = 0.
  Box3 wall = box_of(s, [](const std::string& n) { return contains(n, "_wall_"); });
  EXPECT_NEAR(wall.lo[1] + s.offset[1], 0.0, 1e-5);
  EXPECT_NEAR(wall.lo[2] + s.offset[2], 0.0, 1e-5);
  EXPECT_NEAR(wall.lo[0] + s.offset[0], 0.0, 1e-5);
  EXPECT_NEAR(wall.hi[2] - wall.lo[2], 2 * 3.5, 1e-5);
}

TEST(Facade, GenerationIsDeterministic) {
  FacadeParams p = all_on(2, 2, 4);
  Scene a = generate_facade(p), b = generate_facade(p);
  EXPECT_EQ(a.positions, b.positions);
  EXPECT_EQ(a.indices, b.indices);
  EXPECT_EQ(a.component, b.component);
  EXPECT_EQ(a.component_names, b.component_names);
  EXPECT_EQ(a.offset, b.offset);
}

TEST(Facade, FourSidesAreOneWallTurnedFourTimes) {
  Scene s = generate_facade(all_on(2, 3, 4));
  Bounds b = scene_bounds(s);
  EXPECT_NEAR(b.hi[0] - b.lo[0], b.hi[1] - b.lo[1], 1e-4);
  for (const char* side : {"side0_", "side1_", "side2_", "side3_"})
    EXPECT_EQ(size_t(std::count_if(s.component_names.begin(), s.component_names.end(),
                                   [&](const std::string& n) { return n.rfind(side, 0) == 0; })),
              (s.component_count() - 2 - 2 * 3) / 4)  // minus roof, foundation, interior
        << side;
  // Pinwheel corners: no two wall panels of different sides overlap.
  std::vector<std::pair<char, Box3>> panels;
  for (size_t c = 0; c < s.component_count(); ++c)
    if (contains(s.component_names[c], "_wall_"))
      panels.push_back({s.component_names[c][4], box_of(s, [&](const std::string& n) {
                          return n == s.component_names[c];
                        })});
  ASSERT_EQ(panels.size(), 4u * 2 * 3 * 4);
  for (size_t i = 0; i < panels.size(); ++i)
    for (size_t j = i + 1; j < panels.size(); ++j) {
      if (panels[i].first == panels[j].first) continue;
      const Box3 &p = panels[i].second, &q = panels[j].second;
      bool overlap = true;
      for (int a = 0; a < 3; ++a)
        overlap = overlap && std::min(p.hi[a], q.hi[a]) - std::max(p.lo[a], q.lo[a]) > 1e-4;
      EXPECT_FALSE(overlap) << "panels " << i << " and " << j;
    }
}

TEST(Facade, HiddenInteriorLiesStrictlyInsideTheWalls) {
  for (int sides : {1, 4}) {
    Scene s = generate_facade(all_on(3, 4, sides));
    auto is_wall = [](const std::string& n) { return contains(n, "wall_"); };
    auto is_interior = [](const std::string& n) { return n.rfind("interior_", 0) == 0; };
    Box3 walls = box_of(s, is_wall), inside = box_of(s, is_interior);
    EXPECT_EQ(components_ending(s, "_slab"), 3u);
    EXPECT_EQ(components_ending(s, "_partition1"), 3u);
    for (int a = 0; a < 2; ++a) {  // clear of the 0.3 m walls' inner faces
      EXPECT_GT(inside.lo[a], walls.lo[a] + 0.3) << "sides " << sides << " axis " << a;
      EXPECT_LT(inside.hi[a], walls.hi[a] - 0.3) << "sides " << sides << " axis " << a;
    }
    EXPECT_GT(inside.lo[2], walls.lo[2]);
    EXPECT_LT(inside.hi[2], walls.hi[2]);
  }
}

TEST(Facade, CoplanarPanelsAreCoplanarAndOverlap) {
  Scene s = generate_facade(all_on(1, 1));
  Box3 a = box_of(s, [](const std::string& n) { return ends_with(n, "_plaque_a"); });
  Box3 b = box_of(s, [](const std::string& n) { return ends_with(n, "_plaque_b"); });
  Box3 wall = box_of(s, [](const std::string& n) { return ends_with(n, "_wall_above"); });
  // Both lie exactly in the wall's outer face plane (same float y)...
  EXPECT_EQ(a.lo[1], a.hi[1]);
  EXPECT_EQ(b.lo[1], b.hi[1]);
  EXPECT_EQ(a.lo[1], b.lo[1]);
  EXPECT_EQ(a.lo[1], wall.lo[1]);
  // ...facing outwards, and overlap each other and the wall panel in x and z.
  for (size_t t = 0; t < s.triangle_count(); ++t)
    if (contains(s.component_names[s.component[t]], "plaque")) {
      EXPECT_LT(normal(s, t)[1], 0.0);
    }
  for (int axis : {0, 2}) {
    EXPECT_GT(std::min(a.hi[axis], b.hi[axis]) - std::max(a.lo[axis], b.lo[axis]), 0.05);
    EXPECT_GE(a.lo[axis], wall.lo[axis]);
    EXPECT_LE(b.hi[axis], wall.hi[axis]);
  }
}

TEST(Facade, SubpixelOrnamentsAreTinyAndStandOnTheWall) {
  Scene s = generate_facade(all_on(1, 2));
  EXPECT_EQ(components_ending(s, "_ornaments"), 2u);
  // Each stud is a closed box: 12 consecutive triangles of its component.
  std::vector<size_t> tris;
  for (size_t t = 0; t < s.triangle_count(); ++t)
    if (ends_with(s.component_names[s.component[t]], "_ornaments")) tris.push_back(t);
  ASSERT_EQ(tris.size() % 12, 0u);
  size_t studs = 0;
  for (size_t i = 0; i < tris.size(); i += 12) {
    Box3 stud;
    for (size_t j = i; j < i + 12; ++j)
      for (int k = 0; k < 3; ++k) stud.add(corner(s, tris[j], k));
    for (int a = 0; a < 3; ++a) EXPECT_LE(stud.hi[a] - stud.lo[a], 0.0151);
    ++studs;
  }
  EXPECT_EQ(studs, 12u);
  Box3 wall = box_of(s, [](const std::string& n) { return ends_with(n, "_wall_above"); });
  Box3 all = box_of(s, [](const std::string& n) { return ends_with(n, "_ornaments"); });
  EXPECT_NEAR(all.hi[1], wall.lo[1], 1e-5);  // backs touch the wall face
}

TEST(Facade, ParamsForTargetsHitTheBudget) {
  for (size_t target : {1000u, 100000u}) {
    FacadeParams p = facade_params_for_triangles(target);
    double n = double(generate_facade(p).triangle_count());
    EXPECT_NEAR(n / double(target), 1.0, 0.1) << target;
  }
  for (size_t target : {1000000u, 2000000u, 5000000u}) {
    double n = double(facade_triangle_count(facade_params_for_triangles(target)));
    EXPECT_NEAR(n / double(target), 1.0, 0.1) << target;
  }
  EXPECT_THROW(facade_params_for_triangles(10), std::invalid_argument);
}

TEST(Facade, BadParametersNameTheField) {
  auto message = [](FacadeParams p) {
    try {
      facade_triangle_count(p);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  FacadeParams p;
  p.floors = 0;
  EXPECT_TRUE(contains(message(p), "floors")) << message(p);
  p = {};
  p.sides = 2;
  EXPECT_TRUE(contains(message(p), "sides")) << message(p);
  p = {};
  p.column_segments = 2;
  EXPECT_TRUE(contains(message(p), "column_segments")) << message(p);
  p = {};
  p.bay_width = 0.5;
  EXPECT_TRUE(contains(message(p), "bay_width")) << message(p);
  p = {};
  p.floor_height = NAN;
  EXPECT_TRUE(contains(message(p), "floor_height")) << message(p);
  p = {};
  p.mullions_per_window = 40;
  EXPECT_TRUE(contains(message(p), "mullions_per_window")) << message(p);
  p = {};
  p.floors = p.bays = 100000;
  EXPECT_TRUE(contains(message(p), "1e9 triangles")) << message(p);
  p = {};
  p.depth = -1;
  EXPECT_THROW(generate_facade(p), std::invalid_argument);
}

}  // namespace
}  // namespace perclod
