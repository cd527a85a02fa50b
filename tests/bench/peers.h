// The strongest peer the benchmarks hold perclod against: a visibility cull
// (what a user of a visibility-aware simplifier does before simplifying),
// and the lower envelope that turns a sweep of LODs into "the fewest
// triangles that reach a given fidelity". Header only, for bench_fidelity.
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "perclod/camera.h"
#include "perclod/render.h"
#include "perclod/scene.h"
#include "perclod/views.h"

namespace perclod::bench {

// A dense hemisphere around the model: rings of 16 views at 0, 15, 30 and
// 45 degrees up, 12 at 60, 4 at 75, and the view from above (81 views).
// Each ring is turned by half a step against the one below, so no two
// views share an azimuth and none is a labelling or held-out view.
inline std::vector<std::string> hemisphere_views() {
  std::vector<std::string> v;
  const int counts[6] = {16, 16, 16, 16, 12, 4};
  for (int r = 0; r < 6; ++r) {
    const double step = 360.0 / counts[r];
    for (int i = 0; i < counts[r]; ++i) {
      std::ostringstream ss;
      ss << "az" << (i + 0.5 * (r % 2) + 0.25) * step << "el" << 15 * r;
      v.push_back(ss.str());
    }
  }
  v.push_back("top");
  return v;
}

// The triangles of `scene` that some view of hemisphere_views() shows at
// `distance` on `display`, each view (or tile of a view) rendered at
// `supersample` times its resolution per axis: a triangle is kept when it
// owns at least one of those pixels. `seen` (may be null) receives the count.
inline Scene visibility_culled(Renderer& renderer, const Scene& scene, UpAxis up, const DisplayProfile& display,
                               double distance, int supersample = 2, size_t* seen = nullptr) {
  const Bounds box = scene_bounds(scene);
  std::vector<uint8_t> shown(scene.triangle_count(), 0);
  renderer.set_scene(scene);
  for (const std::string& view : hemisphere_views())
    for (const ViewTile& tile : frame_view(box, up, view, distance, display)) {
      const RenderOutput r = renderer.render(refined(tile.camera, supersample));
      for (uint32_t id : r.ids)
        if (id) shown[id - 1] = 1;
    }
  Scene out = scene;
  out.indices.clear();
  out.component.clear();
  out.material.clear();
  size_t n = 0;
  for (size_t t = 0; t < scene.triangle_count(); ++t) {
    if (!shown[t]) continue;
    ++n;
    for (int k = 0; k < 3; ++k) out.indices.push_back(scene.indices[3 * t + k]);
    if (!scene.component.empty()) out.component.push_back(scene.component[t]);
    if (!scene.material.empty()) out.material.push_back(scene.material[t]);
  }
  if (seen) *seen = n;
  return out;
}

// One LOD of a sweep: its triangle count and a fidelity figure.
using SweepPoint = std::pair<size_t, double>;

// The fewest triangles at which the sweep's lower envelope reaches `goal`:
// for a figure where higher is better (SSIM) the envelope is the best figure
// at or below each count; where lower is better (the visible ratio), the
// same with the order reversed. Linear between points; `full` (the input's
// count, taken as exact) when no point reaches the goal.
inline double fewest_reaching(std::vector<SweepPoint> sweep, double goal, bool higher_is_better, size_t full) {
  const double sign = higher_is_better ? 1.0 : -1.0;
  sweep.push_back({full, higher_is_better ? 1.0 : 0.0});
  std::sort(sweep.begin(), sweep.end());
  for (size_t i = 1; i < sweep.size(); ++i)
    if (sign * sweep[i].second < sign * sweep[i - 1].second) sweep[i].second = sweep[i - 1].second;
  for (size_t k = 0; k < sweep.size(); ++k) {
    if (sign * sweep[k].second < sign * goal) continue;
    if (k == 0) return double(sweep[0].first);
    const SweepPoint &a = sweep[k - 1], &b = sweep[k];
    const double t = b.second != a.second ? (goal - a.second) / (b.second - a.second) : 1.0;
    return double(a.first) + std::clamp(t, 0.0, 1.0) * double(b.first - a.first);
  }
  return double(full);
}

}  // namespace perclod::bench
