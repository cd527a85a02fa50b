// The label settings' names and choices: tracer, per-building labelling,
// samples per pixel (and auto's choice per view), how views combine, and the
// buildings of a scene.
#include <algorithm>
#include <cmath>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <thread>

#include <sched.h>

#include "perclod/label.h"
#include "view_pass.h"

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

ViewSampling choose_sampling(size_t window_pixels, size_t frame_pixels, size_t triangles, size_t box_pixels) {
  if (16 * triangles > frame_pixels) return {4, false};
  if (box_pixels >= kSparseViewPixels * triangles) return {1, false};
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

namespace {

// How far `members`' boxes reach along `axis`, together.
float extent_along(const std::vector<Bounds>& boxes, const std::vector<uint32_t>& members, int axis) {
  float lo = INFINITY, hi = -INFINITY;
  for (uint32_t b : members) lo = std::min(lo, boxes[b].lo[axis]), hi = std::max(hi, boxes[b].hi[axis]);
  return hi - lo;
}

void split_group(const std::vector<Bounds>& boxes, const int across[2], double span, std::vector<uint32_t> members,
                 std::vector<std::vector<uint32_t>>& groups) {
  const float ex[2] = {extent_along(boxes, members, across[0]), extent_along(boxes, members, across[1])};
  if (members.size() == 1 || std::max(ex[0], ex[1]) <= span) {
    groups.push_back(std::move(members));
    return;
  }
  const int axis = across[ex[1] > ex[0] ? 1 : 0];
  auto centre = [&](uint32_t b) { return boxes[b].lo[axis] + boxes[b].hi[axis]; };
  // Ties broken by index, so the split does not depend on the sort.
  std::sort(members.begin(), members.end(),
            [&](uint32_t a, uint32_t b) { return centre(a) < centre(b) || (centre(a) == centre(b) && a < b); });
  // Split where the longer part is shortest along the axis: at the middle of
  // an even row, at the gap between two clusters; ties nearest the middle.
  const size_t n = members.size();
  std::vector<float> left_lo(n), right_hi(n);  // of members [0, k] and [k, n)
  float lo = INFINITY, hi = -INFINITY;
  for (size_t k = 0; k < n; ++k) left_lo[k] = lo = std::min(lo, boxes[members[k]].lo[axis]);
  for (size_t k = n; k-- > 0;) right_hi[k] = hi = std::max(hi, boxes[members[k]].hi[axis]);
  std::vector<float> left_hi(n), right_lo(n);
  hi = -INFINITY, lo = INFINITY;
  for (size_t k = 0; k < n; ++k) left_hi[k] = hi = std::max(hi, boxes[members[k]].hi[axis]);
  for (size_t k = n; k-- > 0;) right_lo[k] = lo = std::min(lo, boxes[members[k]].lo[axis]);
  size_t best = n / 2;
  double best_len = INFINITY;
  for (size_t k = 1; k < n; ++k) {  // [0, k) and [k, n)
    const double len = std::max(left_hi[k - 1] - left_lo[k - 1], right_hi[k] - right_lo[k]);
    const auto off_middle = [&](size_t i) { return std::abs(2 * double(i) - double(n)); };
    if (len < best_len || (len == best_len && off_middle(k) < off_middle(best))) best_len = len, best = k;
  }
  split_group(boxes, across, span, {members.begin(), members.begin() + best}, groups);
  split_group(boxes, across, span, {members.begin() + best, members.end()}, groups);
}

}  // namespace

std::vector<std::vector<uint32_t>> group_boxes(const std::vector<Bounds>& boxes, UpAxis up, double span) {
  std::vector<uint32_t> all;
  for (uint32_t b = 0; b < boxes.size(); ++b)
    if (!boxes[b].is_empty()) all.push_back(b);
  std::vector<std::vector<uint32_t>> groups;
  if (!(span > 0)) {  // each alone, even boxes without extent across
    for (uint32_t b : all) groups.push_back({b});
    return groups;
  }
  const int across[2] = {0, up == UpAxis::Z ? 1 : 2};
  split_group(boxes, across, span, std::move(all), groups);
  for (auto& g : groups) std::sort(g.begin(), g.end());
  std::sort(groups.begin(), groups.end(), [](const auto& a, const auto& b) { return a.front() < b.front(); });
  return groups;
}

size_t building_lanes(const LabelJob& job) {
  if (job.building_threads > 0) return size_t(job.building_threads);
  cpu_set_t cpus;  // the CPUs this process may run on (a Slurm task's, a taskset's)
  if (sched_getaffinity(0, sizeof cpus, &cpus) == 0 && CPU_COUNT(&cpus) > 0) return size_t(CPU_COUNT(&cpus));
  return std::max<size_t>(1, std::thread::hardware_concurrency());
}

Framing framing_of(const LabelJob& job) { return {job.up, job.display, job.distance}; }

PerceptionSettings perception_for(const LabelJob& job) {
  PerceptionSettings ps = job.perception;
  ps.ppd = job.display.pixels_per_degree();
  return ps;
}

using detail::PixelRect;

namespace {
// perception_window's part of the frame; none when a box corner is behind
// the eye (or the box is outside the frame). The margin is 12 x 2^L pixels,
// more than the reach R of the L-level DWT, its CSF filters and its
// inverse. Around a box that holds everything drawn (`alone`) half of it
// does: the frame is background beyond the box, and the whole-sample
// symmetric extension at a window's edge reflects pixels from within the
// margin, so a pixel of the box reads background up to twice the margin
// out, as in the whole frame.
std::optional<PixelRect> window_part(const Camera& cam, const Bounds& box, const PerceptionSettings& ps, bool alone) {
  const int levels = ps.levels > 0 ? ps.levels : default_levels(0.5 * ps.ppd, ps.k);
  const int align = 1 << std::min(levels, 10), margin = (alone ? 6 : 12) * align;
  double lo[2], hi[2];
  if (!detail::projected_extent(cam, box, false, lo, hi)) return std::nullopt;
  const int size[2] = {cam.width, cam.height};
  int a[2], b[2];
  for (int k = 0; k < 2; ++k) {
    a[k] = int(std::clamp(std::floor((lo[k] - margin) / align) * align, 0.0, double(size[k])));
    b[k] = int(std::clamp(std::ceil(hi[k] + margin), 0.0, double(size[k])));
  }
  if (b[0] <= a[0] || b[1] <= a[1]) return std::nullopt;
  return PixelRect{a[0], a[1], b[0] - a[0], b[1] - a[1]};
}
}  // namespace

PixelRect detail::window_rect(const Camera& cam, const Bounds& box, const PerceptionSettings& ps, bool alone) {
  return window_part(cam, box, ps, alone).value_or(PixelRect{0, 0, cam.width, cam.height});
}

Camera perception_window(const Camera& cam, const Bounds& box, const PerceptionSettings& ps, bool alone) {
  const std::optional<PixelRect> r = window_part(cam, box, ps, alone);
  return r ? cropped(cam, r->x, r->y, r->w, r->h) : cam;
}

}  // namespace perclod
