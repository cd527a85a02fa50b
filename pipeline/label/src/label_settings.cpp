// The label settings' names and choices: tracer, per-building labelling,
// samples per pixel (and auto's choice per view), how views combine, and the
// buildings of a scene.
#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "perclod/label.h"

namespace perclod {
using namespace detail;

TracerKind parse_tracer(const std::string& s) {
  if (s == "octree") return TracerKind::Octree;
  if (s == "embree") return TracerKind::Embree;
  throw std::invalid_argument("tracer must be 'octree' or 'embree', not '" + s + "'");
}

std::unique_ptr<Tracer> make_tracer(const Scene& scene, TracerKind kind) {
  if (kind == TracerKind::Octree) return std::make_unique<OctreeTracer>(scene);
  return std::make_unique<EmbreeTracer>(scene, EmbreeMode::Fast);
}

PerBuilding parse_per_building(const std::string& s) {
  if (s == "false" || s == "off") return PerBuilding::Off;
  if (s == "true" || s == "on") return PerBuilding::On;
  if (s == "auto") return PerBuilding::Auto;
  throw std::invalid_argument("per_building must be true, false or auto, not '" + s + "'");
}

int parse_samples(const std::string& s) {
  if (s == "auto") return kAutoSamples;
  try {
    size_t used = 0;
    const int n = std::stoi(s, &used);
    if (used == s.size()) {
      sample_offsets(n);  // the patterns there are: throws for any other count
      return n;
    }
  } catch (const std::exception&) {
  }
  throw std::invalid_argument("samples must be auto, 1, 2, 4, 8, 9 or 16, not '" + s + "'");
}

int effective_samples(const LabelJob& job) {
  if (job.samples == kAutoSamples && (job.mask_per_sample || job.keep_unsampled_surface)) return 4;
  return job.samples;
}

std::string samples_name(int samples) { return samples == kAutoSamples ? "auto" : std::to_string(samples); }

nlohmann::json samples_json(int samples) {
  return samples == kAutoSamples ? nlohmann::json("auto") : nlohmann::json(samples);
}

ViewSampling choose_sampling(size_t window_pixels, size_t frame_pixels, size_t triangles) {
  if (16 * triangles > frame_pixels) return {4, false};
  if (16 * window_pixels <= frame_pixels) return {16, true};
  if (4 * window_pixels <= 2 * frame_pixels) return {4, true};
  return {4, false};
}

CombineViews parse_combine_views(const std::string& s) {
  if (s == "any") return CombineViews::AnyView;
  if (s == "pooled") return CombineViews::Pooled;
  throw std::invalid_argument("combine_views must be any or pooled, not '" + s + "'");
}

Buildings find_buildings(const Scene& scene) {
  Buildings b;
  const size_t nc = std::max<size_t>(scene.component_count(), 1);
  b.of_component.resize(nc);
  std::map<std::string, uint32_t> index;
  for (size_t c = 0; c < nc; ++c) {
    std::string name = c < scene.component_names.size() ? scene.component_names[c] : std::string();
    size_t slash = name.find('/');
    std::string key = slash == std::string::npos ? name + "\n" + std::to_string(c) : name.substr(0, slash);
    auto [it, added] = index.emplace(key, uint32_t(b.names.size()));
    if (added) b.names.push_back(slash == std::string::npos ? name : key);
    if (added && slash != std::string::npos) ++b.named;
    b.of_component[c] = it->second;
  }
  return b;
}

Framing framing_of(const LabelJob& job) { return {job.up, job.display, job.distance}; }

PerceptionSettings perception_for(const LabelJob& job) {
  PerceptionSettings ps = job.perception;
  ps.ppd = job.display.pixels_per_degree();
  return ps;
}

Camera perception_window(const Camera& cam, const Bounds& box, const PerceptionSettings& ps) {
  const int levels = ps.levels > 0 ? ps.levels : default_levels(0.5 * ps.ppd, ps.k);
  const int align = 1 << std::min(levels, 10), margin = 12 * align;
  double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
  for (int c = 0; c < 8; ++c) {
    const Eigen::Vector3d p(c & 1 ? box.hi[0] : box.lo[0], c & 2 ? box.hi[1] : box.lo[1], c & 4 ? box.hi[2] : box.lo[2]);
    double px = 0, py = 0, depth = 0;
    if (!cam.project(p, px, py, depth)) return cam;  // a corner behind the eye: the whole frame
    lo[0] = std::min(lo[0], px), hi[0] = std::max(hi[0], px);
    lo[1] = std::min(lo[1], py), hi[1] = std::max(hi[1], py);
  }
  const int size[2] = {cam.width, cam.height};
  int a[2], b[2];
  for (int k = 0; k < 2; ++k) {
    a[k] = int(std::clamp(std::floor((lo[k] - margin) / align) * align, 0.0, double(size[k])));
    b[k] = int(std::clamp(std::ceil(hi[k] + margin), 0.0, double(size[k])));
  }
  if (b[0] <= a[0] || b[1] <= a[1]) return cam;
  return cropped(cam, a[0], a[1], b[0] - a[0], b[1] - a[1]);
}

}  // namespace perclod
