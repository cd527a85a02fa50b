// Octree against Embree (verify mode) on the generated facade and on a real
// model: identical on >= 99.99% of covered pixels, no real disagreement.
// The real model comes through the pipeline's loader; the check against the
// renderer's ID buffer is the pipeline's end-to-end test.
#include "perclod/facade.h"
#include "perclod/load.h"
#include "raycast_fixtures.h"

namespace perclod::test {
namespace {

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
  const Scene s = load_scene(std::string(PERCLOD_SHARED_DATA) + "/ingolstadt/bldg_4018215.obj");
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
