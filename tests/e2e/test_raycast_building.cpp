// Octree against Embree (verify mode) on the Ingolstadt building that ships
// in data/: identical on >= 99.99% of covered pixels, no real disagreement.
// The synthetic half of this check is raycast/test_agreement.cpp; this half
// needs the pipeline's loader, so it lives here.
#include <string>

#include "../raycast/raycast_fixtures.h"
#include "perclod/load.h"

namespace perclod::test {
namespace {

TEST(RaycastAgreement, RealBuildingOctreeVsEmbree) {
  const Scene s = load_scene(std::string(PERCLOD_SOURCE_DIR) + "/data/ingolstadt/bldg_4018215.obj");
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
