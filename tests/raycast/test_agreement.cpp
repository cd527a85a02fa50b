// Octree against Embree (verify mode) on the generated facade: identical on
// >= 99.99% of covered pixels, no real disagreement. The same check on a real
// building (it needs the pipeline's loader) is e2e/test_raycast_building.cpp.
#include "perclod/facade.h"
#include "raycast_fixtures.h"

namespace perclod::test {
namespace {

// A facade with the hard cases: coplanar panels (ties), sub-pixel studs and
// a hidden interior.
Scene hard_facade(int floors, int bays) {
  FacadeParams p;
  p.floors = floors;
  p.bays = bays;
  p.hidden_interior = true;
  p.coplanar_panels = true;
  p.subpixel_ornaments = true;
  return generate_facade(p);
}

TEST(RaycastAgreement, GeneratedFacadeOctreeVsEmbree) {
  const Scene s = hard_facade(3, 5);
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

// trace_samples walks the octree once for every sample of a tile: its
// buffers must be those of one trace per shifted camera, bit for bit (the
// same rays and exact test; only the culling is shared), and the brute-force
// oracle's. The facade has coplanar panels (ties), sub-pixel studs and a
// hidden interior; the views are near, oblique and far, and one camera is
// itself shifted (the offsets add to its shift). 16 samples (the 4 x 4
// grid) take two walks of eight.
TEST(RaycastAgreement, SamplesInOneWalkEqualOneTracePerSample) {
  const Scene s = hard_facade(2, 3);
  const OctreeTracer oct(s);
  const BruteForceTracer brute(s);
  Camera shifted = facade_view(s, 40.0, 3.0, 160, 120);
  shifted.shift_x = 0.1;
  shifted.shift_y = -0.2;
  const Camera views[] = {facade_view(s, 8.0, 0.0, 160, 120), facade_view(s, 25.0, 12.0, 200, 150),
                          facade_view(s, 150.0, -30.0, 96, 64), shifted};
  size_t compared = 0;
  for (const Camera& cam : views)
    for (int n : {1, 2, 4, 8, 16}) {
      // The oracle (Tracer's default: one trace per shifted camera) for the
      // default pattern on the near and the shifted view; it is slow.
      const bool oracle = n == 4 && (&cam == &views[0] || &cam == &views[3]);
      const auto offsets = sample_offsets(n);
      const auto walked = trace_samples(oct, cam, offsets, 7u);
      const auto each = oracle ? trace_samples(brute, cam, offsets) : std::vector<std::vector<uint32_t>>{};
      for (size_t k = 0; k < offsets.size(); ++k) {
        Camera c = cam;
        c.shift_x += offsets[k][0];
        c.shift_y += offsets[k][1];
        EXPECT_EQ(walked[k], oct.trace(c)) << n << " samples, sample " << k;
        if (oracle) {
          EXPECT_EQ(walked[k], each[k]) << "sample " << k << " against brute force";
        }
        compared += count_nonzero(walked[k]);
      }
    }
  EXPECT_GT(compared, 100000u);
  EXPECT_THROW(oct.trace_samples(views[0], {}, nullptr), std::invalid_argument);
}

}  // namespace
}  // namespace perclod::test
