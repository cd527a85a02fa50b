// Octree against Embree (verify mode) on the generated facade and on a real
// model: identical on >= 99.99% of covered pixels, no real disagreement.
// The real model is read by a minimal OBJ reader below (v and f lines, g/o
// groups as components) because raycast_tests do not link the pipeline's
// loader; the loader-based check against the renderer's ID buffer is the
// pipeline's end-to-end test.
#include <fstream>
#include <sstream>

#include "perclod/facade.h"
#include "raycast_fixtures.h"

namespace perclod::test {
namespace {

// Reads v/f/g/o of an OBJ: polygons fan-triangulated, positions recentred on
// the bounding-box centre (in double, like the loader). Throws on a bad face.
Scene read_obj_minimal(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot open " + path);
  std::vector<double> pos;
  Scene s;
  uint32_t comp = 0;
  bool group_used = false;
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream ls(line);
    std::string tag;
    ls >> tag;
    if (tag == "v") {
      double x, y, z;
      ls >> x >> y >> z;
      pos.insert(pos.end(), {x, y, z});
    } else if (tag == "g" || tag == "o") {
      if (group_used) ++comp;
      group_used = false;
    } else if (tag == "f") {
      std::vector<uint32_t> f;
      std::string tok;
      while (ls >> tok) {
        long i = std::stol(tok.substr(0, tok.find('/')));
        if (i < 0) i += long(pos.size() / 3) + 1;
        if (i < 1 || size_t(i) > pos.size() / 3) throw std::runtime_error("bad face index in " + path);
        f.push_back(uint32_t(i - 1));
      }
      for (size_t k = 2; k < f.size(); ++k) add_triangle(s, f[0], f[k - 1], f[k], comp);
      group_used = true;
    }
  }
  double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  for (size_t i = 0; i < pos.size(); ++i) {
    lo[i % 3] = std::min(lo[i % 3], pos[i]);
    hi[i % 3] = std::max(hi[i % 3], pos[i]);
  }
  for (int k = 0; k < 3; ++k) s.offset[k] = 0.5 * (lo[k] + hi[k]);
  for (size_t i = 0; i < pos.size(); ++i) s.positions.push_back(float(pos[i] - s.offset[i % 3]));
  return s;
}

// Z-up facade view: eye `distance` in front of the bounding box's -y face.
Camera facade_view(const Scene& s, double distance, double sideways, int w, int h) {
  const Bounds b = scene_bounds(s);
  const auto c = b.center();
  const double diag = b.diagonal();
  const V3 eye(c[0] + sideways, b.lo[1] - distance, c[2]);
  return look_at(eye, V3(c[0], c[1], c[2]), V3(0, 0, 1), 0.585, w, h, 0.05, distance + 2 * diag);
}

void expect_agreement(const Scene& s, const Camera& cam, const OctreeTracer& oct, const EmbreeTracer& emb) {
  const auto a = oct.trace(cam);
  const auto e = emb.trace(cam);
  const Agreement g = compare_traced(s, cam, a.data(), e.data());
  EXPECT_GT(g.covered, g.pixels / 50);
  EXPECT_EQ(g.real_disagreements, 0u);
  EXPECT_GE(g.identical_rate(), 0.9999) << "identical " << g.identical << " of " << g.covered << ", ties "
                                        << g.ties << ", edge grazes " << g.edge_grazes;
  ::testing::Test::RecordProperty("identical_rate", std::to_string(g.identical_rate()));
}

TEST(RaycastAgreement, GeneratedFacadeOctreeVsEmbree) {
  FacadeParams p;
  p.floors = 3;
  p.bays = 5;
  p.hidden_interior = true;
  p.coplanar_panels = true;
  p.subpixel_ornaments = true;
  const Scene s = generate_facade(p);
  ASSERT_GT(s.triangle_count(), 5000u);
  const OctreeTracer oct(s);
  const EmbreeTracer emb(s, EmbreeMode::Verify);
  expect_agreement(s, facade_view(s, 12.0, 0.0, 320, 240), oct, emb);
  expect_agreement(s, facade_view(s, 30.0, 9.0, 320, 240), oct, emb);
  expect_agreement(s, facade_view(s, 120.0, -20.0, 256, 192), oct, emb);

  // Hidden interior parts are never traced from outside.
  std::vector<uint8_t> interior(s.triangle_count(), 0);
  for (size_t t = 0; t < s.triangle_count(); ++t)
    interior[t] = s.component_names[s.component[t]].rfind("interior", 0) == 0;
  const auto ids = oct.trace(facade_view(s, 12.0, 0.0, 320, 240));
  const TriangleCounts counts = count_triangles(ids.data(), nullptr, ids.size(), s.triangle_count());
  size_t interior_traced = 0, interior_total = 0;
  for (size_t t = 0; t < s.triangle_count(); ++t)
    if (interior[t]) {
      ++interior_total;
      interior_traced += counts.traced[t];
    }
  EXPECT_GT(interior_total, 0u);
  EXPECT_EQ(interior_traced, 0u);
}

TEST(RaycastAgreement, RealBuildingOctreeVsEmbree) {
  const Scene s = read_obj_minimal(std::string(PERCLOD_SHARED_DATA) + "/ingolstadt/bldg_4018215.obj");
  ASSERT_EQ(s.triangle_count(), 12456u);
  const OctreeTracer oct(s);
  const EmbreeTracer emb(s, EmbreeMode::Verify);
  expect_agreement(s, facade_view(s, 20.0, 0.0, 320, 256), oct, emb);
  expect_agreement(s, facade_view(s, 56.0, 15.0, 320, 256), oct, emb);
  // From above and behind, looking down at the roof.
  const Bounds b = scene_bounds(s);
  const auto c = b.center();
  const Camera top = look_at(V3(c[0] + 10, b.hi[1] + 25, b.hi[2] + 30), V3(c[0], c[1], c[2]), V3(0, 0, 1), 0.7,
                             320, 256, 0.1, 500);
  expect_agreement(s, top, oct, emb);
}

}  // namespace
}  // namespace perclod::test
