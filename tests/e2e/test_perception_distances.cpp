// Perception on real renders: a generated facade seen from five increasing
// distances. The farther the view, the more of the building's detail falls
// beyond what the eye resolves, so the imperceptible fraction (among the
// building's pixels; background from the triangle-ID buffer) grows.
#include <gtest/gtest.h>

#include <vector>

#include "perclod/config.h"
#include "perclod/facade.h"
#include "perclod/perception.h"
#include "perclod/render.h"
#include "perclod/views.h"

namespace {

TEST(PerceptionDistances, ImperceptibleFractionGrowsWithDistance) {
  perclod::FacadeParams p;  // 4 floors x 6 bays, frames, columns, balusters
  perclod::Scene scene = perclod::generate_facade(p);
  perclod::Bounds bounds = perclod::scene_bounds(scene);
  perclod::DisplayProfile display = perclod::default_display_profile();
  perclod::PerceptionSettings settings = perclod::perception_settings_for(display);

  perclod::Renderer renderer;
  renderer.set_scene(scene);
  double previous = -1.0;
  for (double d : {10.0, 25.0, 56.0, 132.0, 300.0}) {
    perclod::Camera cam = perclod::facade_camera(bounds, perclod::UpAxis::Z, "-y", d, display);
    perclod::RenderOutput out = renderer.render(cam);
    std::vector<uint8_t> background(out.ids.size());
    for (size_t i = 0; i < out.ids.size(); ++i) background[i] = out.ids[i] == 0;
    perclod::PerceptionResult r =
        perclod::perceive(out.rgb.data(), out.width, out.height, settings, background.data());
    ASSERT_GT(r.counted_pixels, 100) << "the facade must be on screen at " << d << " m";
    EXPECT_GT(r.imperceptible_fraction, previous) << "at " << d << " m";
    std::printf("  %6.0f m: %lld building pixels, %.1f%% imperceptible\n", d, r.counted_pixels,
                100.0 * r.imperceptible_fraction);
    previous = r.imperceptible_fraction;
  }
}

}  // namespace
