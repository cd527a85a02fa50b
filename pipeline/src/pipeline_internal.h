// Small helpers shared by the pipeline's orchestration files (private).
#pragma once

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "packing.h"
#include "worker.h"
#include "perclod/pipeline.h"

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace perclod::detail {

using Clock = std::chrono::steady_clock;
inline double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// The job's perception settings at its display's pixel density.
inline PerceptionSettings perception_for(const LabelJob& job) {
  PerceptionSettings ps = job.perception;
  ps.ppd = job.display.pixels_per_degree();
  return ps;
}

// 1 where the render drew no triangle (from its ID buffer).
inline void background_of(const RenderOutput& img, std::vector<uint8_t>& background) {
  background.resize(img.ids.size());
  for (size_t i = 0; i < img.ids.size(); ++i) background[i] = img.ids[i] == 0;
}

// A ViewRecord of the original from one view's render (rgb, 3 bytes a
// pixel, and its background mask): the rectangle it draws, widened by
// kRecordMargin and clipped to the image.
inline ViewRecord view_record(const std::string& name, const Camera& camera, const std::vector<uint8_t>& rgb,
                              const std::vector<uint8_t>& background, const std::string& set) {
  ViewRecord r;
  r.view = name;
  r.camera = camera;
  r.set = set;
  const int W = camera.width, H = camera.height;
  int x0 = W, y0 = H, x1 = -1, y1 = -1;
  size_t undrawn = background.size();  // some undrawn pixel, for the background's colour
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const size_t i = size_t(y) * size_t(W) + size_t(x);
      if (background[i]) {
        undrawn = i;
        continue;
      }
      x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = y;
    }
  if (undrawn < background.size()) std::copy_n(&rgb[3 * undrawn], 3, r.background_rgb);
  if (x1 < 0) return r;  // nothing drawn: nothing kept
  r.x0 = std::max(0, x0 - kRecordMargin), r.y0 = std::max(0, y0 - kRecordMargin);
  r.w = std::min(W - 1, x1 + kRecordMargin) - r.x0 + 1, r.h = std::min(H - 1, y1 + kRecordMargin) - r.y0 + 1;
  const size_t n = size_t(r.w) * size_t(r.h);
  thread_local std::vector<uint8_t> kept;  // the rectangle's colours, packed below
  kept.resize(3 * n);
  r.background.resize(n);
  for (int y = 0; y < r.h; ++y) {
    const size_t row = size_t(y + r.y0) * size_t(W) + size_t(r.x0), k = size_t(y) * size_t(r.w);
    std::copy_n(&rgb[3 * row], 3 * size_t(r.w), &kept[3 * k]);
    for (int x = 0; x < r.w; ++x) r.background[k + size_t(x)] = background[row + size_t(x)] != 0;
  }
  r.packed_rgb = pack_bytes(kept.data(), kept.size());
  return r;
}

// Frames each of `views` at every distance (frame_view) on job's display and
// up axis, so a view that cannot be framed (too many tiles) fails before any
// rendering starts.
inline void check_framing(const Scene& scene, const LabelJob& job, const std::vector<std::string>& views,
                          const std::vector<double>& distances) {
  const Bounds b = scene_bounds(scene);
  for (double d : distances)
    for (const auto& v : views) frame_view(b, job.up, v, d, job.display);
}

// Hands memory freed between a job's stages (ID buffers, the simplifier's
// mesh) back to the system, so the next stage's peak is not stacked on
// free chunks the heap kept (glibc; a no-op elsewhere).
inline void release_free_memory() {
#if defined(__GLIBC__)
  malloc_trim(0);
#endif
}

// "octree built in 120 ms, 4096 KiB": the progress line after a tracer build.
std::string tracer_summary(const Tracer& tracer);

}  // namespace perclod::detail
