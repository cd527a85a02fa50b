// Small helpers shared by the pipeline's orchestration files (private).
#pragma once

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "perclod/pipeline.h"

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

// A ViewRecord of the original from one view's perception result.
inline ViewRecord view_record(const std::string& name, const Camera& camera, const PerceptionResult& pr,
                              const std::vector<uint8_t>& background, const std::string& set) {
  ViewRecord r;
  r.view = name;
  r.camera = camera;
  r.simulated = pr.simulated;
  r.luminance.resize(pr.luminance.size());
  for (size_t i = 0; i < pr.luminance.size(); ++i)
    r.luminance[i] = uint8_t(std::lround(std::clamp(pr.luminance[i], 0.f, 255.f)));
  r.background = background;
  r.set = set;
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

// "octree built in 120 ms, 4096 KiB": the progress line after a tracer build.
std::string tracer_summary(const Tracer& tracer);

}  // namespace perclod::detail
