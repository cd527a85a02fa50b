// Octree against Embree (verify mode) on the generated facade: identical on
// >= 99.99% of covered pixels, no real disagreement. The same check on a real
// building (it needs the pipeline's loader) is e2e/test_raycast_building.cpp.
#include "perclod/facade.h"
#include "raycast_fixtures.h"

namespace perclod::test {
namespace {

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

}  // namespace
}  // namespace perclod::test
