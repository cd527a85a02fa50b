// Labelling (the method's sections 2-4 for one distance): per view (framed,
// tiled when needed) render -> perceive -> trace each sample -> count; labels
// from the counts, combined over views; per-building views; the labels file
// and marking renders.
#include <cstdio>
#include <algorithm>
#include <cmath>
#include <functional>
#include <future>
#include <map>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "perclod/image_io.h"
#include "perclod/labels_io.h"
#include "perclod/label.h"
#include "perclod/packing.h"
#include "perclod/worker.h"

namespace perclod {
using namespace detail;
namespace {

nlohmann::json to_json(const LabelCounts& c) {
  return {{"perceptible", c.perceptible}, {"imperceptible", c.imperceptible}, {"undisplayable", c.undisplayable}};
}

nlohmann::json to_json(const Agreement& a) {
  return {{"covered", a.covered},
          {"identical", a.identical},
          {"ties", a.ties},
          {"edge_grazes", a.edge_grazes},
          {"real_disagreements", a.real_disagreements},
          {"identical_rate", a.identical_rate()}};
}

// Marking colours of `labels`: each labelling view and tile coloured from its
// own ID buffer (no second render), and with job.marking_near each view
// (untiled: the whole model, cut off where it overfills the frame) rendered
// from distance * closer_factor.
std::vector<std::string> write_marking_images(Renderer& renderer, const Scene& scene,
                                              const std::vector<Label>& labels, std::vector<IdBuffer>& id_buffers,
                                              const LabelJob& job) {
  std::vector<std::string> files;
  if (job.out.dir.empty() || !job.write_view_images) return files;
  RenderOptions opt;
  opt.triangle_colors = marking_colors(labels);
  opt.want_ids = false;
  std::vector<uint32_t> ids;
  for (IdBuffer& b : id_buffers) {
    b.ids_into(ids);
    files.push_back(job.out.view(b.view, job.distance, "_marking.png"));
    write_png_via(job.images, files.back(), b.camera.width, b.camera.height, 3,
                  shade_ids(scene, b.camera, ids, opt.triangle_colors, opt));
    b.packed_ids = {};
  }
  if (!job.marking_near) return files;
  const Bounds bounds = scene_bounds(scene);
  for (const auto& view : job.views) {
    const Camera closer = view_camera(bounds, job.up, view, job.distance * job.closer_factor, job.display);
    RenderOutput o = renderer.render(closer, opt);
    files.push_back(job.out.view(view, job.distance, "_marking_near.png"));
    write_png_via(job.images, files.back(), o.width, o.height, 3, std::move(o.rgb));
  }
  return files;
}

}  // namespace

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

namespace {

// Per-triangle state over the views of one distance: the labels combined so
// far (combine_labels) and whether any view's frustum held the triangle.
struct Accumulator {
  std::vector<Label> combined;
  std::vector<uint8_t> in_frustum;
  explicit Accumulator(size_t nt) : combined(nt, Label::Undisplayable), in_frustum(nt) {}
};

struct ViewOutcome {
  PerceptionResult perception;
  std::vector<uint8_t> background;
  RenderOutput image;
  std::vector<std::vector<uint32_t>> samples;  // the traced samples, kept for the slot's next view
  std::vector<uint8_t> packed_ids;             // image.ids packed, for a marking image
  // With an ordered grid of samples (sample_grid): the render at grid times
  // the resolution, and of its sample pictures 1.. what counting reads, the
  // ID buffer and the mask (image and perception above are sample 0's);
  // each picture is split and perceived in the scratch buffers.
  RenderOutput fine, scratch;
  PerceptionResult scratch_perception;
  std::vector<uint8_t> scratch_background;
  std::vector<std::vector<uint32_t>> more_ids;
  std::vector<std::vector<uint8_t>> more_masks;
  double t_render = 0, t_perceive = 0;
  nlohmann::json report;
};

// Labels views one after another with the two halves overlapped: while a
// worker thread traces and counts view k, the calling thread (which owns the
// OpenGL context) renders and perceives view k+1. One view is in flight at a
// time and the counts are added in view order, so the result is the one a
// sequential run gives, bit for bit. seen(k, outcome) runs on the calling
// thread once view k is rendered and perceived (its ID buffer still in use),
// counted(k, outcome) once it is also traced.
class ViewPipeline {
 public:
  using Step = std::function<void(size_t, ViewOutcome&)>;
  ViewPipeline(bool overlap, Step seen, Step counted) : seen_(std::move(seen)), counted_(std::move(counted)) {
    if (overlap) worker_.emplace();
  }
  template <class See, class Count>
  void add(See see, Count count) {
    ViewOutcome& o = slot_[next_ % 2];
    see(o);
    seen_(next_, o);
    drain();
    if (worker_) {
      pending_ = worker_->submit([count, &o] { count(o); });
    } else {
      count(o);
      counted_(next_, o);
    }
    ++next_;
  }
  void drain() {  // waits for the view in flight and hands it over
    if (!pending_.valid()) return;
    pending_.get();
    counted_(next_ - 1, slot_[(next_ - 1) % 2]);
  }

 private:
  Step seen_, counted_;
  ViewOutcome slot_[2];
  size_t next_ = 0;
  // After the slots: an exception ends the worker (finishing the count in
  // flight) before the slot it counts is freed.
  std::optional<Worker> worker_;
  std::future<void> pending_;
};

// The samples of a pixel sit off its centre (sample_offsets), where the
// rasteriser decides what it draws: a sliver can cover a centre and no
// sample. Such a triangle is drawn, so it is not undisplayable: it takes the
// decision of each pixel it was drawn on (imperceptible where the mask is set)
// with one sample's weight there. ids: the render's ID buffer (triangle + 1).
void add_drawn_but_missed(const uint32_t* ids, const uint8_t* mask, size_t pixels, const std::vector<uint32_t>* owner,
                          uint32_t building, TriangleCounts& counts) {
  // Which triangles (of this building) were drawn but missed, decided before
  // any is counted.
  std::vector<uint8_t> missed(counts.traced.size(), 0);
  for (size_t i = 0; i < pixels; ++i) {
    const uint32_t id = ids[i];
    if (id && counts.traced[id - 1] == 0 && (!owner || (*owner)[id - 1] == building)) missed[id - 1] = 1;
  }
  for (size_t i = 0; i < pixels; ++i) {
    if (!ids[i] || !missed[ids[i] - 1]) continue;
    counts.traced[ids[i] - 1] += 1;
    counts.imperceptible[ids[i] - 1] += mask[i] != 0;
  }
}

// A triangle that no sample and no pixel centre hit is not necessarily out
// of sight: on a finely tessellated surface (a turned column at 132 m) most
// triangles are a fraction of a pixel, and deleting them as undisplayable
// perforates what the eye sees. With job.keep_unsampled_surface such a
// triangle counts as drawn when
//  * it is smaller than a pixel (a larger one on the surface would hold a
//    sample);
//  * its centroid lies on the drawn surface: the depth drawn at the
//    centroid's pixel is within kSurfaceDepthPx pixel footprints of the
//    centroid's;
//  * the triangle drawn at that pixel's centre does not cover the centroid:
//    if it did, the two overlap there (a window polygon lying in its wall's
//    plane, a coplanar copy) and the unsampled one is the hidden one;
//  * the triangles found so for that pixel cover at least kOpenPixelArea of
//    it (deleting them would open that much of the pixel).
// Each takes its pixel's decision with one sample's weight, as
// add_drawn_but_missed does. Returns how many it counted. depth: the
// render's eye depth (0 = background); ids: its ID buffer (triangle + 1).
constexpr double kSurfaceDepthPx = 0.5;
constexpr double kOpenPixelArea = 0.5;

// With samples auto, LabelResult::totals count this many samples a pixel
// (each view's counts times kAutoCountUnit / its samples).
constexpr int kAutoCountUnit = 16;

// Whether labelling runs add_unsampled_surface (and so renders depth).
bool finds_unsampled_surface(const LabelJob& job) { return job.samples > 1 && job.keep_unsampled_surface; }

size_t add_unsampled_surface(const Scene& scene, const Camera& cam, const float* depth, const uint32_t* ids,
                             const uint8_t* mask, const std::vector<uint32_t>* owner, uint32_t building,
                             TriangleCounts& counts) {
  const size_t nt = scene.triangle_count();
  const float* P = scene.positions.data();
  // Triangle t's corners in image coordinates and eye depth; false when a
  // corner is behind the eye.
  auto project = [&](size_t t, double px[3], double py[3], double z[3]) {
    for (int k = 0; k < 3; ++k) {
      const float* v = P + 3 * size_t(scene.indices[3 * t + k]);
      if (!cam.project(Eigen::Vector3d(v[0], v[1], v[2]), px[k], py[k], z[k])) return false;
    }
    return true;
  };
  std::vector<std::pair<uint32_t, uint32_t>> found;  // triangle, pixel
  std::vector<float> open(size_t(cam.width) * cam.height, 0.f);  // their area per pixel, pixels^2
  for (size_t t = 0; t < nt; ++t) {
    if (counts.traced[t] || (owner && (*owner)[t] != building)) continue;
    double px[3], py[3], z[3];
    if (!project(t, px, py, z)) continue;
    const double area = 0.5 * std::fabs((px[1] - px[0]) * (py[2] - py[0]) - (px[2] - px[0]) * (py[1] - py[0]));
    if (!(area < 1.0)) continue;
    const double cx = (px[0] + px[1] + px[2]) / 3, cy = (py[0] + py[1] + py[2]) / 3;
    const double cz = (z[0] + z[1] + z[2]) / 3;
    if (!(cx >= 0 && cy >= 0 && cx < cam.width && cy < cam.height)) continue;
    const size_t i = size_t(cy) * cam.width + size_t(cx);
    if (depth[i] <= 0 || !ids[i] || std::fabs(double(depth[i]) - cz) > kSurfaceDepthPx * cam.pixel_footprint(cz))
      continue;
    double qx[3], qy[3], qz[3];
    if (project(ids[i] - 1, qx, qy, qz)) {  // does the drawn triangle cover the centroid?
      double e[3];
      for (int k = 0; k < 3; ++k) {
        const int l = (k + 1) % 3;
        e[k] = (qx[l] - qx[k]) * (cy - qy[k]) - (qy[l] - qy[k]) * (cx - qx[k]);
      }
      if ((e[0] >= 0 && e[1] >= 0 && e[2] >= 0) || (e[0] <= 0 && e[1] <= 0 && e[2] <= 0)) continue;
    }
    found.push_back({uint32_t(t), uint32_t(i)});
    open[i] += float(area);
  }
  size_t added = 0;
  for (auto [t, i] : found) {
    if (open[i] < kOpenPixelArea) continue;
    counts.traced[t] += 1;
    counts.imperceptible[t] += mask[i] != 0;
    ++added;
  }
  return added;
}

// The camera of the picture a view keeps (its image, record, ID buffer):
// `cam` itself, or with a grid of samples sample 0's picture of the refined
// render, `cam` shifted by grid_offsets(grid)[0].
Camera kept_picture_camera(Camera cam, int grid) {
  if (grid) {
    const auto o = grid_offsets(grid)[0];
    cam.shift_x += o[0], cam.shift_y += o[1];
  }
  return cam;
}

// Sample (a, b) of a render at `s` times the resolution: its pixel (x, y) is
// fine pixel (s x + a, s y + b).
void decimate(const RenderOutput& fine, int s, int a, int b, RenderOutput& out) {
  out.width = fine.width / s;
  out.height = fine.height / s;
  const size_t n = size_t(out.width) * out.height;
  out.rgb.resize(3 * n);
  out.ids.resize(fine.ids.empty() ? 0 : n);
  out.depth.resize(fine.depth.empty() ? 0 : n);
  for (int y = 0; y < out.height; ++y)
    for (int x = 0; x < out.width; ++x) {
      const size_t i = size_t(y) * out.width + x, f = size_t(s * y + b) * fine.width + size_t(s * x + a);
      for (int c = 0; c < 3; ++c) out.rgb[3 * i + c] = fine.rgb[3 * f + c];
      if (!out.ids.empty()) out.ids[i] = fine.ids[f];
      if (!out.depth.empty()) out.depth[i] = fine.depth[f];
    }
}

// The first half of labelling a view, on the thread that owns the OpenGL
// context: render and perceive one camera. grid >= 2: render it at grid
// times the resolution and perceive each of the grid x grid sample pictures.
void see_view(Renderer& renderer, const PerceptionSettings& ps, const Camera& cam, bool want_depth, ViewOutcome& out,
              int grid = 0) {
  auto t0 = Clock::now();
  RenderOptions ro;
  ro.want_depth = want_depth;  // add_unsampled_surface reads it
  if (grid >= 2) {
    renderer.render(refined(cam, grid), out.fine, ro);
    out.t_render = since(t0);
    t0 = Clock::now();
    const size_t n = size_t(grid) * grid;
    out.more_ids.resize(n - 1);
    out.more_masks.resize(n - 1);
    for (size_t k = 0; k < n; ++k) {  // sample 0 into out.image / out.perception, the others via the scratch
      RenderOutput& im = k ? out.scratch : out.image;
      PerceptionResult& pr = k ? out.scratch_perception : out.perception;
      std::vector<uint8_t>& bg = k ? out.scratch_background : out.background;
      decimate(out.fine, grid, int(k % grid), int(k / grid), im);
      background_of(im, bg);
      perceive_into(im.rgb.data(), im.width, im.height, ps, bg.data(), pr);
      if (k) {  // swapped, not copied: the scratch takes the old buffers back for the next picture
        out.more_ids[k - 1].swap(im.ids);
        out.more_masks[k - 1].swap(pr.mask);
      }
    }
    out.t_perceive = since(t0);  // splitting included
    return;
  }
  renderer.render(cam, out.image, ro);
  out.t_render = since(t0);
  background_of(out.image, out.background);
  t0 = Clock::now();
  perceive_into(out.image.rgb.data(), out.image.width, out.image.height, ps, out.background.data(), out.perception);
  out.t_perceive = since(t0);
}

// The second half, on any thread: trace the view seen by see_view at
// vs.samples samples per pixel (with vs.mask_per_sample, `cam` is one
// sample pass, traced at its pixel centres); adds its counts and labels for
// the triangles of `owner[t] == building` (all when `owner` is null).
void count_view(const Scene& scene, const Tracer& tracer, const EmbreeTracer* reference, const LabelJob& job,
                const ViewSampling& vs, const std::string& name, const Camera& cam,
                const std::vector<uint32_t>* owner, uint32_t building, LabelResult& res, Accumulator& acc,
                ViewOutcome& out) {
  const size_t nt = scene.triangle_count();
  const double t_render = out.t_render, t_perceive = out.t_perceive;
  auto t0 = Clock::now();

  const size_t pixels = size_t(out.image.width) * out.image.height;
  TriangleCounts counts;
  counts.traced.assign(nt, 0);
  counts.imperceptible.assign(nt, 0);
  t0 = Clock::now();
  // Every sample of the view in one call: the octree walks its structure
  // once for every eight of them. With a mask per sample this render is one sample
  // pass, its camera shifted by the pass's offset: one ray per pixel centre.
  const int grid = sample_grid(vs.samples);
  const int samples = grid ? grid * grid : vs.mask_per_sample ? 1 : vs.samples;
  std::vector<std::array<double, 2>> offsets =
      grid                 ? grid_offsets(grid)
      : vs.mask_per_sample ? std::vector<std::array<double, 2>>{{0.0, 0.0}}
                           : sample_offsets(vs.samples);
  // verify compares the octree with Embree and with the ID buffer at the
  // pixel centres: with several samples the centre rides along in the same
  // walk, as one more sample, when the walk has room for it.
  const bool centre_in_walk = !grid && reference && !owner && samples > 1 && samples < OctreeTracer::kMaxSamples;
  if (centre_in_walk) offsets.push_back({cam.shift_x, cam.shift_y});  // trace(cam), relative to `base`
  std::vector<std::vector<uint32_t>>& traced = out.samples;
  traced.resize(offsets.size());
  std::vector<uint32_t*> buffers;
  for (auto& t : traced) {
    t.resize(pixels);  // every pixel is written by the trace
    buffers.push_back(t.data());
  }
  // The offsets are from base's pixel centres: the view's camera unshifted,
  // or a mask-per-sample pass's own camera (shifted, one offset of zero).
  Camera base = cam;
  if (!vs.mask_per_sample && !grid) base.shift_x = base.shift_y = 0;
  tracer.trace_samples(base, offsets, buffers.data());
  auto mask_of = [&](size_t k) -> const uint8_t* {
    return grid && k ? out.more_masks[k - 1].data() : out.perception.mask.data();
  };
  for (size_t k = 0; k < size_t(samples); ++k) {
    std::vector<uint32_t>& rays = traced[k];
    if (owner)
      for (uint32_t& id : rays)
        if (id && (*owner)[id - 1] != building) id = 0;
    add_counts(counts, rays.data(), mask_of(k), pixels);
  }
  const std::vector<uint32_t>& rays = traced[0];
  if (grid) {
    for (size_t k = 0; k < size_t(samples); ++k)
      add_drawn_but_missed(k ? out.more_ids[k - 1].data() : out.image.ids.data(), mask_of(k), pixels, owner, building,
                           counts);
  } else if (samples > 1) {
    add_drawn_but_missed(out.image.ids.data(), out.perception.mask.data(), pixels, owner, building, counts);
  }
  size_t unsampled_surface = 0;
  if (finds_unsampled_surface(job))
    unsampled_surface = add_unsampled_surface(scene, cam, out.image.depth.data(), out.image.ids.data(),
                                              out.perception.mask.data(), owner, building, counts);
  const double t_trace = since(t0);

  const std::vector<Label> labels = label_triangles(counts, job.ratio);
  // The frustum marks a building's view may set are its own triangles'.
  std::vector<uint8_t> seen;
  if (owner) {
    seen.assign(nt, 0);
    mark_in_frustum(scene, cam, seen);
  } else {
    mark_in_frustum(scene, cam, acc.in_frustum);
  }
  // With samples auto the views' sample counts differ (4 or 16 a pixel):
  // the totals count sixteenths of a pixel, so every view weighs by area.
  const uint32_t weight = job.samples == kAutoSamples ? uint32_t(kAutoCountUnit / vs.samples) : 1;
  for (size_t t = 0; t < nt; ++t) {
    if (owner && (*owner)[t] != building) continue;
    res.totals.traced[t] += weight * counts.traced[t];
    res.totals.imperceptible[t] += weight * counts.imperceptible[t];
    acc.combined[t] = combine_labels(acc.combined[t], labels[t]);
    if (owner) acc.in_frustum[t] |= seen[t];
  }
  out.report = {{"view", name},
                {"rendered_pixels", grid ? pixels * size_t(samples) : pixels},
                {"covered_pixels", out.perception.counted_pixels},
                {"imperceptible_fraction", out.perception.imperceptible_fraction},
                {"levels", out.perception.levels},
                {"labels", to_json(count_labels(labels))},
                {"unsampled_surface", unsampled_surface},
                {"seconds", {{"render", t_render}, {"perceive", t_perceive}, {"trace", t_trace}}}};
  if (!owner) {
    // Rays against the renderer's ID buffer and, with verify, octree against
    // Embree: both at the pixel centres, where the rasteriser samples. With
    // one sample per pixel that is the trace above; otherwise verify traces
    // the centres once more, and without verify the comparison is left out.
    std::vector<uint32_t> traced_centre;
    const uint32_t* centre = nullptr;
    const Camera drawn = kept_picture_camera(cam, grid);  // the camera of out.image
    if (samples == 1 || grid) {
      centre = rays.data();  // the one sample is the centre (of this pass's camera; with grid, sample 0's image)
    } else if (centre_in_walk) {
      centre = traced.back().data();
    } else if (reference) {
      traced_centre.resize(pixels);
      tracer.trace(cam, traced_centre.data());
      centre = traced_centre.data();
    }
    if (centre)
      out.report["rays_vs_id_buffer"] = to_json(compare_with_id_buffer(scene, drawn, centre, out.image.ids.data()));
    if (reference) {
      std::vector<uint32_t> ref(pixels);
      t0 = Clock::now();
      reference->trace(drawn, ref.data());
      out.report["seconds"]["trace_embree_verify"] = since(t0);
      out.report["octree_vs_embree"] = to_json(compare_traced(scene, drawn, centre, ref.data()));
    }
  }
}

// One render of a view to label: pass `pass` of the view's `passes`
// (its first stands for the view in the records, images and report).
struct ViewPass {
  size_t tile = 0;  // index into the job's tiles (or a building's)
  size_t pass = 0, passes = 1;
  Camera camera;     // what see_view renders (a grid's: before refining)
  ViewSampling sampling;
  int grid() const { return sample_grid(sampling.samples); }
};

// How a view of camera `cam` is sampled: the job's samples, or with
// kAutoSamples the choice for its window on the model (`window`,
// perception_window).
ViewSampling sampling_of(const LabelJob& job, const Camera& cam, const Camera& window, size_t triangles) {
  if (job.samples != kAutoSamples) return {job.samples, job.mask_per_sample};
  return choose_sampling(size_t(window.width) * window.height, size_t(cam.width) * cam.height, triangles);
}

// The renders of one view of camera `cam`, whose window on the model is
// `window`: one that every sample reads (the whole frame; a grid's is the
// window at grid times the resolution), or with a mask per sample one
// render of the window per sample offset, its camera shifted by it.
// Appended to `out`.
void add_view_passes(size_t tile, const Camera& cam, const Camera& window, const ViewSampling& vs,
                     std::vector<ViewPass>& out) {
  const int grid = sample_grid(vs.samples);
  if (grid || !vs.mask_per_sample || vs.samples == 1) {
    out.push_back({tile, 0, 1, grid ? window : cam, vs});
    return;
  }
  const auto offsets = sample_offsets(vs.samples);
  for (size_t p = 0; p < offsets.size(); ++p) {
    Camera c = window;
    c.shift_x += offsets[p][0];
    c.shift_y += offsets[p][1];
    out.push_back({tile, p, offsets.size(), c, vs});
  }
}

std::string sampling_name(const ViewSampling& vs) {
  if (sample_grid(vs.samples)) return std::to_string(vs.samples) + " (grid)";
  return std::to_string(vs.samples) + (vs.mask_per_sample && vs.samples > 1 ? " (mask per sample)" : "");
}

// Adds a later pass's timings to the report of the view's first pass.
void add_pass_report(nlohmann::json& first, const nlohmann::json& pass, size_t passes) {
  for (const auto& [k, v] : pass["seconds"].items()) first["seconds"][k] = first["seconds"][k].get<double>() + v.get<double>();
  first["rendered_pixels"] = first["rendered_pixels"].get<size_t>() + pass["rendered_pixels"].get<size_t>();
  first["passes"] = passes;
}

std::string progress_line(const std::string& name, double d, const nlohmann::json& report) {
  std::ostringstream ss;
  ss.precision(3);
  const auto& s = report["seconds"];
  ss << "  " << name << " at " << d << " m: " << report["covered_pixels"].get<size_t>() << " px, "
     << 100 * report["imperceptible_fraction"].get<double>() << "% imperceptible";
  if (report.contains("passes")) ss << " in the first of " << report["passes"].get<size_t>() << " passes; all passes:";
  else ss << ";";
  ss << " render " << 1e3 * s["render"].get<double>()
     << " ms, perceive " << 1e3 * s["perceive"].get<double>() << " ms, trace " << 1e3 * s["trace"].get<double>()
     << " ms";
  if (report.contains("sampling")) ss << " (samples " << report["sampling"].get<std::string>() << ")";  // auto's choice
  return ss.str();
}

}  // namespace

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

LabelResult label_scene(Renderer& renderer, const Scene& scene, const Tracer& tracer, const LabelJob& asked,
                        const Progress& progress, const EmbreeTracer* verify_tracer) {
  LabelJob job = asked;
  job.samples = effective_samples(asked);
  if (job.views.empty()) throw std::invalid_argument("no views to label from");
  const bool automatic = job.samples == kAutoSamples;
  if (!automatic) sample_offsets(job.samples);  // checks the count
  const int grid = sample_grid(job.samples);  // 0 unless an ordered grid of samples
  // (auto with keep_unsampled_surface is 4 samples by now: effective_samples.)
  if ((job.mask_per_sample || grid) && job.keep_unsampled_surface && job.samples > 1)
    throw std::invalid_argument(
        "keep_unsampled_surface cannot be combined with mask_per_sample or a grid of samples (9, 16): the "
        "unsampled-surface rule needs every sample of a pixel in one picture");
  const size_t nt = scene.triangle_count();
  Bounds bounds = scene_bounds(scene);
  const PerceptionSettings ps = perception_for(job);
  const bool depth = finds_unsampled_surface(job);  // the renders' depth, for add_unsampled_surface
  std::unique_ptr<EmbreeTracer> own;  // built here unless the caller keeps one for the job
  if (job.verify && !verify_tracer) own = std::make_unique<EmbreeTracer>(scene, EmbreeMode::Verify);
  const EmbreeTracer* reference = job.verify ? (verify_tracer ? verify_tracer : own.get()) : nullptr;
  const bool write_files = !job.out.dir.empty();
  if (write_files) ensure_directory(job.out.dir);
  renderer.set_scene(scene);

  LabelResult res;
  res.totals.traced.assign(nt, 0);
  res.totals.imperceptible.assign(nt, 0);
  res.report = {{"distance", job.distance},
                {"tracer", tracer.name()},
                {"samples_per_pixel", samples_json(job.samples)},
                {"combine_views", job.combine == CombineViews::Pooled ? "pooled" : "any"},
                {"keep_unsampled_surface", depth},
                {"views", nlohmann::json::array()}};
  if (job.mask_per_sample || grid) res.report["mask_per_sample"] = true;
  if (grid) res.report["sample_grid"] = grid;
  Accumulator acc(nt);
  std::vector<ViewTile> tiles;
  for (const auto& view : job.views)
    for (ViewTile& tile : frame_view(bounds, job.up, view, job.distance, job.display)) tiles.push_back(std::move(tile));
  // Pipeline item k renders passes[k]; a view's first pass stands for it in
  // the records, images and report.
  std::vector<ViewPass> passes;
  std::map<std::string, size_t> chosen;  // with samples auto: views per setting
  for (size_t i = 0; i < tiles.size(); ++i) {
    const Camera window = perception_window(tiles[i].camera, bounds, ps);
    const ViewSampling vs = sampling_of(job, tiles[i].camera, window, nt);
    if (automatic) ++chosen[sampling_name(vs)];
    add_view_passes(i, tiles[i].camera, window, vs, passes);
  }
  if (automatic) res.report["sampling_chosen"] = chosen;
  {
    ViewPipeline pipeline(
        job.overlap,
        [&](size_t k, ViewOutcome& o) {  // rendered and perceived: record it, queue its images
          const ViewPass& vp = passes[k];
          if (vp.pass) return;
          const ViewTile& tile = tiles[vp.tile];
          res.views.push_back(
              view_record(tile.name, kept_picture_camera(vp.camera, vp.grid()), o.image.rgb, o.background, "labelling"));
          if (!write_files) return;
          auto file = [&](const char* suffix) { return job.out.view(tile.name, job.distance, suffix); };
          const int w = o.image.width, h = o.image.height;
          if (job.write_view_images) write_png_via(job.images, file(".png"), w, h, 3, std::move(o.image.rgb));
          if (job.write_perception_images) {
            write_png_via(job.images, file("_simulated.png"), w, h, 1, simulated_view(o.perception));
            write_png_via(job.images, file("_difference.png"), w, h, 1, difference_view(o.perception));
            write_png_via(job.images, file("_mask.png"), w, h, 1, mask_view(o.perception));
          }
        },
        [&](size_t k, ViewOutcome& o) {  // traced and counted
          const ViewPass& vp = passes[k];
          const ViewTile& tile = tiles[vp.tile];
          if (vp.pass == 0) {
            if (write_files && job.write_view_images)
              res.id_buffers.push_back(
                  IdBuffer{tile.name, kept_picture_camera(vp.camera, vp.grid()), std::move(o.packed_ids)});
            res.report["views"].push_back(o.report);
            if (automatic) res.report["views"].back()["sampling"] = sampling_name(vp.sampling);
          } else {
            add_pass_report(res.report["views"].back(), o.report, vp.passes);
          }
          if (progress && vp.pass + 1 == vp.passes)
            progress(progress_line(tile.name, job.distance, res.report["views"].back()));
        });
    for (const ViewPass& vp : passes)
      pipeline.add([&](ViewOutcome& o) { see_view(renderer, ps, vp.camera, depth, o, vp.grid()); },
                   [&](ViewOutcome& o) {
                     count_view(scene, tracer, reference, job, vp.sampling, tiles[vp.tile].name, vp.camera, nullptr,
                                0, res, acc, o);
                     if (vp.pass == 0 && write_files && job.write_view_images)  // packed here, on the worker
                       o.packed_ids = pack_bytes(o.image.ids.data(), o.image.ids.size() * sizeof(uint32_t));
                   });
    pipeline.drain();
  }

  // Per building: views framed on each building, counting its own triangles.
  Buildings buildings;
  bool per_building = job.per_building == PerBuilding::On;
  if (job.per_building != PerBuilding::Off) {
    buildings = find_buildings(scene);
    // Auto: only files whose names say they hold buildings; a model whose
    // 1,000 groups are just parts (no '/') is one building, not 1,000.
    if (job.per_building == PerBuilding::Auto) per_building = buildings.named >= 2;
  }
  if (per_building) {
    std::vector<uint32_t> owner(nt);
    Bounds none;
    none.lo = {INFINITY, INFINITY, INFINITY};
    none.hi = {-INFINITY, -INFINITY, -INFINITY};
    std::vector<Bounds> box(buildings.names.size(), none);
    for (size_t t = 0; t < nt; ++t) {
      owner[t] = buildings.of_component[scene.component_of(t)];
      Bounds& bb = box[owner[t]];
      for (int k = 0; k < 3; ++k) {
        const float* p = &scene.positions[3 * size_t(scene.indices[3 * t + k])];
        for (int a = 0; a < 3; ++a) bb.lo[a] = std::min(bb.lo[a], p[a]), bb.hi[a] = std::max(bb.hi[a], p[a]);
      }
    }
    // A view framed on one building may put its eye inside a neighbour's
    // box (a kiosk beside a hall): it sees that neighbour from inside, and
    // the building's labels come from its other views. Counted per building.
    auto eye_inside_other = [&](const Camera& cam, uint32_t b) {
      for (uint32_t k = 0; k < box.size(); ++k) {
        if (k == b) continue;
        bool in = true;
        for (int a = 0; a < 3 && in; ++a) in = cam.eye[a] >= box[k].lo[a] && cam.eye[a] <= box[k].hi[a];
        if (in) return true;
      }
      return false;
    };
    nlohmann::json per = nlohmann::json::array();
    size_t views = 0;  // of the building being labelled
    double seconds = 0;
    size_t first = 0;  // the pipeline's item number of the building's first pass
    std::vector<ViewPass> own_passes;  // of the building being labelled
    std::vector<std::string> own_names;
    ViewPipeline pipeline(job.overlap, [](size_t, ViewOutcome&) {},
                          [&](size_t k, ViewOutcome& o) {
                            views += own_passes[k - first].pass == 0;
                            for (const auto& [key, v] : o.report["seconds"].items()) seconds += v.get<double>();
                          });
    for (uint32_t b = 0; b < buildings.names.size(); ++b) {
      if (!(box[b].lo[0] <= box[b].hi[0])) continue;  // a building without triangles
      views = 0;
      seconds = 0;
      size_t eyes_inside = 0;
      own_passes.clear();
      own_names.clear();
      std::map<std::string, size_t> own_chosen;
      for (const auto& view : job.views)
        for (const ViewTile& tile : frame_view(box[b], job.up, view, job.distance, job.display)) {
          eyes_inside += eye_inside_other(tile.camera, b);
          const Camera window = perception_window(tile.camera, box[b], ps);
          const ViewSampling vs = sampling_of(job, tile.camera, window, nt);
          if (automatic) ++own_chosen[sampling_name(vs)];
          add_view_passes(own_names.size(), tile.camera, window, vs, own_passes);
          own_names.push_back(tile.name);
        }
      for (const ViewPass& vp : own_passes)
        pipeline.add([&](ViewOutcome& o) { see_view(renderer, ps, vp.camera, depth, o, vp.grid()); },
                     [&](ViewOutcome& o) {
                       count_view(scene, tracer, nullptr, job, vp.sampling, own_names[vp.tile], vp.camera, &owner, b,
                                  res, acc, o);
                     });
      pipeline.drain();
      first += own_passes.size();
      per.push_back({{"building", buildings.names[b]},
                     {"views", views},
                     {"eyes_inside_other_buildings", eyes_inside},
                     {"seconds", seconds}});
      if (automatic) per.back()["sampling_chosen"] = own_chosen;
      if (progress) {
        std::ostringstream ss;
        ss.precision(3);
        ss << "  building " << b + 1 << "/" << buildings.names.size() << " " << buildings.names[b] << ": " << views
           << " views, " << seconds << " s";
        if (eyes_inside) ss << "; " << eyes_inside << " with the eye inside another building's box";
        progress(ss.str());
      }
    }
    res.report["per_building"] = per;
  }

  res.labels = std::move(acc.combined);
  // Pooled: the totals hold every view's samples of a triangle (a building's
  // own views count only its own triangles, as combined above), and traced
  // is 0 exactly where every view left it undisplayable.
  if (job.combine == CombineViews::Pooled) res.labels = label_triangles(res.totals, job.ratio);
  for (size_t t = 0; t < nt; ++t) {
    if (res.labels[t] == Label::Undisplayable && !acc.in_frustum[t]) {
      res.labels[t] = Label::Imperceptible;  // no view could have seen it: the view set was incomplete
      ++res.outside_views;
    }
  }
  res.report["labels"] = to_json(count_labels(res.labels));
  res.report["outside_views"] = res.outside_views;
  return res;
}

void write_label_outputs(Renderer& renderer, const Scene& scene, LabelResult& result, const LabelJob& job) {
  LabelFile lf{result.labels, result.totals.traced, result.totals.imperceptible, {}};
  for (const auto& v : result.views) lf.views.emplace_back(v.view, job.distance);
  const int samples = effective_samples(job);
  lf.samples = samples == kAutoSamples ? kAutoCountUnit : samples;  // what a pixel counts in the totals
  lf.has_model = true;
  lf.model_triangles = scene.triangle_count();
  lf.model_hash = model_fingerprint(scene);
  std::string path = job.out.labels(job.distance);
  write_labels(path, lf);
  result.report["labels_file"] = path;
  result.report["marking_renders"] = write_marking_images(renderer, scene, result.labels, result.id_buffers, job);
  result.id_buffers.clear();
}

nlohmann::json label_model(const Scene& scene, const LabelJob& job, TracerKind kind, const Progress& progress) {
  std::optional<OutputDirectoryLock> lock;
  if (!job.out.dir.empty()) lock.emplace(job.out.dir);
  check_framing(scene, job, job.views, {job.distance});  // before any work
  std::unique_ptr<Tracer> tracer = make_tracer(scene, kind);
  if (progress) progress(tracer_summary(*tracer));
  Renderer renderer;
  LabelResult r = label_scene(renderer, scene, *tracer, job, progress);
  write_label_outputs(renderer, scene, r, job);
  r.report["tracer_build_seconds"] = tracer->build_seconds();
  write_text_atomic(job.out.label_report(job.distance), r.report.dump(2) + "\n");
  return r.report;
}

PerceptionSettings perception_for(const LabelJob& job) {
  PerceptionSettings ps = job.perception;
  ps.ppd = job.display.pixels_per_degree();
  return ps;
}

void check_framing(const Scene& scene, const LabelJob& job, const std::vector<std::string>& views,
                   const std::vector<double>& distances) {
  const Bounds b = scene_bounds(scene);
  for (double d : distances)
    for (const auto& v : views) frame_view(b, job.up, v, d, job.display);
}

std::string tracer_summary(const Tracer& tracer) {
  char line[160];
  std::snprintf(line, sizeof line, "%s built in %.0f ms, %zu KiB", tracer.name(), tracer.build_seconds() * 1e3,
                tracer.memory_bytes() / 1024);
  return line;
}

}  // namespace perclod
