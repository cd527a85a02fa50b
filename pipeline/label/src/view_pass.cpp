// One view labelled: rendered and perceived (see_view), traced and counted
// (count_view), and split into passes by its sampling.
#include "view_pass.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <sstream>

namespace perclod::detail {
namespace {


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
// render's eye depth (0 = background); ids: its ID buffer (triangle + 1);
// both hold `part` of cam's frame.
constexpr double kSurfaceDepthPx = 0.5;
constexpr double kOpenPixelArea = 0.5;



size_t add_unsampled_surface(const Scene& scene, const Camera& cam, const PixelRect& part, const float* depth,
                             const uint32_t* ids, const uint8_t* mask, const std::vector<uint32_t>* owner,
                             uint32_t building, TriangleCounts& counts) {
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
  std::vector<float> open(size_t(part.w) * part.h, 0.f);  // their area per pixel, pixels^2
  for (size_t t = 0; t < nt; ++t) {
    if (counts.traced[t] || (owner && (*owner)[t] != building)) continue;
    double px[3], py[3], z[3];
    if (!project(t, px, py, z)) continue;
    const double area = 0.5 * std::fabs((px[1] - px[0]) * (py[2] - py[0]) - (px[2] - px[0]) * (py[1] - py[0]));
    if (!(area < 1.0)) continue;
    const double cx = (px[0] + px[1] + px[2]) / 3, cy = (py[0] + py[1] + py[2]) / 3;
    const double cz = (z[0] + z[1] + z[2]) / 3;
    if (!(cx >= part.x && cy >= part.y && cx < part.x + part.w && cy < part.y + part.h)) continue;
    const size_t i = (size_t(cy) - part.y) * part.w + (size_t(cx) - part.x);
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

}  // namespace


bool projected_extent(const Camera& cam, const Bounds& box, bool past_near, double lo[2], double hi[2]) {
  lo[0] = lo[1] = INFINITY;
  hi[0] = hi[1] = -INFINITY;
  for (int c = 0; c < 8; ++c) {
    const Eigen::Vector3d p(c & 1 ? box.hi[0] : box.lo[0], c & 2 ? box.hi[1] : box.lo[1], c & 4 ? box.hi[2] : box.lo[2]);
    double px = 0, py = 0, depth = 0;
    if (!cam.project(p, px, py, depth) || (past_near && !(depth > cam.znear))) return false;
    lo[0] = std::min(lo[0], px), hi[0] = std::max(hi[0], px);
    lo[1] = std::min(lo[1], py), hi[1] = std::max(hi[1], py);
  }
  return true;
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

// The first half of labelling a view, on the thread that owns the OpenGL
// context: render and perceive one camera. grid >= 2: render it at grid
// times the resolution and perceive each of the grid x grid sample pictures.
void see_view(Renderer& renderer, const PerceptionSettings& ps, const Camera& cam, bool want_depth, ViewOutcome& out,
              int grid, const PixelRect& part) {
  auto t0 = Clock::now();
  RenderOptions ro;
  ro.want_depth = want_depth;  // add_unsampled_surface reads it
  out.part = {};
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
  if (part.w) {
    ro.part_x = part.x, ro.part_y = part.y, ro.part_w = part.w, ro.part_h = part.h;
    out.part = part;
  }
  renderer.render(cam, out.image, ro);
  out.t_render = since(t0);
  background_of(out.image, out.background);
  t0 = Clock::now();
  perceive_into(out.image.rgb.data(), out.image.width, out.image.height, ps, out.background.data(), out.perception);
  out.t_perceive = since(t0);
}

PixelRect box_rect(const Camera& cam, const Bounds& box) {
  double lo[2], hi[2];
  if (!projected_extent(cam, box, true, lo, hi)) return {0, 0, cam.width, cam.height};
  const int size[2] = {cam.width, cam.height};
  int a[2], b[2];
  for (int k = 0; k < 2; ++k) {
    a[k] = int(std::clamp(std::floor(lo[k]) - 2.0, 0.0, double(size[k])));
    b[k] = int(std::clamp(std::ceil(hi[k]) + 2.0, 0.0, double(size[k])));
  }
  return {a[0], a[1], std::max(0, b[0] - a[0]), std::max(0, b[1] - a[1])};
}

namespace {

// A rectangle's samples placed in `part` (an image of misses): `r` and
// `part` are parts of the same frame, r inside part.
std::vector<uint32_t> spread_rect(const std::vector<uint32_t>& samples, const PixelRect& r, const PixelRect& part) {
  std::vector<uint32_t> out(size_t(part.w) * part.h, 0);
  if (r.w <= 0 || r.h <= 0) return out;  // nothing traced (it may lie outside the part)
  for (int y = 0; y < r.h; ++y)
    std::copy_n(samples.data() + size_t(y) * r.w, r.w,
                out.data() + size_t(r.y - part.y + y) * part.w + (r.x - part.x));
  return out;
}

// How a view's samples are traced: an ordered grid (its sample pictures each
// a mask), one ray per pixel centre (a mask-per-sample pass), or the job's
// samples from one picture; and whether verify's pixel centres ride along.
struct TracePlan {
  int grid = 0;     // sample_grid(vs.samples)
  int samples = 1;  // samples counted per pixel of this render
  bool centre_in_walk = false;
};

// Every sample of the view in one call into out.samples: the octree walks
// its structure once for every eight of them. With a mask per sample this
// render is one sample pass, its camera shifted by the pass's offset: one
// ray per pixel centre.
TracePlan trace_view(const Tracer& tracer, bool verify, bool whole_model, const ViewSampling& vs, const Camera& cam,
                     const Bounds* only, size_t pixels, ViewOutcome& out) {
  TracePlan plan;
  plan.grid = sample_grid(vs.samples);
  plan.samples = plan.grid ? plan.grid * plan.grid : vs.mask_per_sample ? 1 : vs.samples;
  std::vector<std::array<double, 2>> offsets = plan.grid           ? grid_offsets(plan.grid)
                                               : vs.mask_per_sample ? std::vector<std::array<double, 2>>{{0.0, 0.0}}
                                                                    : sample_offsets(vs.samples);
  // verify compares the octree with Embree and with the ID buffer at the
  // pixel centres: with several samples the centre rides along in the same
  // walk, as one more sample, when the walk has room for it.
  plan.centre_in_walk =
      !plan.grid && verify && whole_model && plan.samples > 1 && plan.samples < OctreeTracer::kMaxSamples;
  if (plan.centre_in_walk) offsets.push_back({0.0, 0.0});  // trace(cam): offsets add to cam's own shift
  std::vector<std::vector<uint32_t>>& traced = out.samples;
  traced.resize(offsets.size());
  // The offsets are added to the camera's shift: a whole frame's is 0, a
  // window's is its crop, a mask-per-sample pass's its own offset too (its
  // one offset is zero). The image holds out.part of the frame (all of it
  // when unset), and the samples are placed where it holds them.
  const PixelRect part = held_part(out, cam);
  const PixelRect rect = only ? box_rect(cam, *only) : part;
  if (rect.w > 0 && rect.h > 0 && !inside(rect, part))
    throw std::logic_error("trace_view: the pixels to trace are not all in the part of the frame rendered");
  const bool whole = rect.w == part.w && rect.h == part.h;
  const bool whole_frame = rect.w == cam.width && rect.h == cam.height;
  std::vector<uint32_t*> buffers;
  for (auto& t : traced) {
    if (whole) {
      t.resize(pixels);  // every pixel is written by the trace
    } else {
      t.assign(size_t(rect.w) * rect.h, 0);
    }
    buffers.push_back(t.data());
  }
  if (rect.w > 0 && rect.h > 0)
    tracer.trace_samples(whole_frame ? cam : cropped(cam, rect.x, rect.y, rect.w, rect.h), offsets, buffers.data());
  if (!whole)
    for (auto& t : traced) t = spread_rect(t, rect, part);
  return plan;
}

// Adds the traced samples (of `owner[t] == building` only, when given) to
// `counts`, then the triangles drawn but missed by every sample and, with
// keep_unsampled_surface, the unsampled surface; returns how many of those.
size_t count_samples(const Scene& scene, const LabelJob& job, const TracePlan& plan, const Camera& cam,
                     const std::vector<uint32_t>* owner, uint32_t building, size_t pixels, ViewOutcome& out,
                     TriangleCounts& counts) {
  auto mask_of = [&](size_t k) -> const uint8_t* {
    return plan.grid && k ? out.more_masks[k - 1].data() : out.perception.mask.data();
  };
  for (size_t k = 0; k < size_t(plan.samples); ++k) {
    std::vector<uint32_t>& rays = out.samples[k];
    if (owner)
      for (uint32_t& id : rays)
        if (id && (*owner)[id - 1] != building) id = 0;
    add_counts(counts, rays.data(), mask_of(k), pixels);
  }
  if (plan.grid) {
    for (size_t k = 0; k < size_t(plan.samples); ++k)
      add_drawn_but_missed(k ? out.more_ids[k - 1].data() : out.image.ids.data(), mask_of(k), pixels, owner, building,
                           counts);
  } else if (plan.samples > 1) {
    add_drawn_but_missed(out.image.ids.data(), out.perception.mask.data(), pixels, owner, building, counts);
  }
  if (!finds_unsampled_surface(job)) return 0;
  return add_unsampled_surface(scene, cam, held_part(out, cam), out.image.depth.data(), out.image.ids.data(),
                               out.perception.mask.data(), owner, building, counts);
}

// With samples auto the views' sample counts differ (4 or 16 a pixel): the
// totals count sixteenths of a pixel, so every view weighs by area.
uint32_t count_weight(const LabelJob& job, const ViewSampling& vs) {
  return job.samples == kAutoSamples ? uint32_t(kAutoCountUnit / vs.samples) : 1;
}

}  // namespace

void add_view_counts(const Scene& scene, const LabelJob& job, const ViewSampling& vs, const Camera& cam,
                     const std::vector<uint32_t>* owner, uint32_t building, const TriangleCounts& counts,
                     const std::vector<Label>& labels, LabelResult& res, Accumulator& acc) {
  const size_t nt = scene.triangle_count();
  // The frustum marks a building's view may set are its own triangles'.
  std::vector<uint8_t> seen;
  if (owner) {
    seen.assign(nt, 0);
    mark_in_frustum(scene, cam, seen);
  } else {
    mark_in_frustum(scene, cam, acc.in_frustum);
  }
  const uint32_t weight = count_weight(job, vs);
  for (size_t t = 0; t < nt; ++t) {
    if (owner && (*owner)[t] != building) continue;
    res.totals.traced[t] += weight * counts.traced[t];
    res.totals.imperceptible[t] += weight * counts.imperceptible[t];
    acc.combined[t] = combine_labels(acc.combined[t], labels[t]);
    if (owner) acc.in_frustum[t] |= seen[t];
  }
}

void add_part_counts(const Scene& part, const std::vector<uint32_t>& triangle, const LabelJob& job,
                     const ViewSampling& vs, const Camera& cam, const TriangleCounts& counts, LabelResult& res,
                     Accumulator& acc) {
  std::vector<uint8_t> seen(part.triangle_count(), 0);
  mark_in_frustum(part, cam, seen);
  const std::vector<Label> labels = label_triangles(counts, job.ratio);
  const uint32_t weight = count_weight(job, vs);
  for (size_t i = 0; i < triangle.size(); ++i) {
    const uint32_t t = triangle[i];
    res.totals.traced[t] += weight * counts.traced[i];
    res.totals.imperceptible[t] += weight * counts.imperceptible[i];
    acc.combined[t] = combine_labels(acc.combined[t], labels[i]);
    acc.in_frustum[t] |= seen[i];
  }
}

namespace {

// Rays against the renderer's ID buffer and, with verify, octree against
// Embree: both at the pixel centres, where the rasteriser samples. With one
// sample per pixel that is the trace itself; otherwise verify traces the
// centres once more, and without verify the comparison is left out.
void verify_view(const Scene& scene, const Tracer& tracer, const EmbreeTracer* reference, const TracePlan& plan,
                 const Camera& cam, size_t pixels, ViewOutcome& out) {
  std::vector<uint32_t> traced_centre;
  const uint32_t* centre = nullptr;
  const Camera drawn = kept_picture_camera(cam, plan.grid);  // the camera of out.image
  if (plan.samples == 1 || plan.grid) {
    centre = out.samples[0].data();  // the one sample is the centre (of this pass's camera; with grid, sample 0's)
  } else if (plan.centre_in_walk) {
    centre = out.samples.back().data();
  } else if (reference) {
    traced_centre.resize(pixels);
    tracer.trace(cam, traced_centre.data());
    centre = traced_centre.data();
  }
  if (centre) out.report.rays_vs_id_buffer = compare_with_id_buffer(scene, drawn, centre, out.image.ids.data());
  if (reference) {
    std::vector<uint32_t> ref(pixels);
    const auto t0 = Clock::now();
    reference->trace(drawn, ref.data());
    out.report.seconds["trace_embree_verify"] = since(t0);
    out.report.octree_vs_embree = compare_traced(scene, drawn, centre, ref.data());
  }
}

}  // namespace

void count_view(const Scene& scene, const Tracer& tracer, const EmbreeTracer* reference, const LabelJob& job,
                const ViewSampling& vs, const std::string& name, const Camera& cam,
                const std::vector<uint32_t>* owner, uint32_t building, const Bounds* own_box, LabelResult* res,
                Accumulator* acc, ViewOutcome& out) {
  if ((res == nullptr) != (acc == nullptr)) throw std::logic_error("count_view: res and acc go together");
  const bool add = res != nullptr;
  const size_t nt = scene.triangle_count();
  const double t_render = out.t_render, t_perceive = out.t_perceive;
  const size_t pixels = size_t(out.image.width) * out.image.height;
  TriangleCounts counts;
  counts.traced.assign(nt, 0);
  counts.imperceptible.assign(nt, 0);
  const auto t0 = Clock::now();
  const TracePlan plan = trace_view(tracer, reference != nullptr, owner == nullptr, vs, cam, own_box, pixels, out);
  const size_t unsampled_surface = count_samples(scene, job, plan, cam, owner, building, pixels, out, counts);
  const double t_trace = since(t0);

  const std::vector<Label> labels = label_triangles(counts, job.ratio);
  if (add) add_view_counts(scene, job, vs, cam, owner, building, counts, labels, *res, *acc);
  ViewLabelling& r = out.report;
  r = ViewLabelling{};
  r.view = name;
  r.rendered_pixels = plan.grid ? pixels * size_t(plan.samples) : pixels;
  r.covered_pixels = out.perception.counted_pixels;
  r.imperceptible_fraction = out.perception.imperceptible_fraction;
  r.levels = out.perception.levels;
  r.labels = count_labels(labels);
  r.unsampled_surface = unsampled_surface;
  r.seconds = {{"render", t_render}, {"perceive", t_perceive}, {"trace", t_trace}};
  if (!owner) verify_view(scene, tracer, reference, plan, cam, pixels, out);
  if (!add) out.counts = std::move(counts);
}

ViewSampling sampling_of(const LabelJob& job, const Camera& cam, const Camera& window, size_t triangles,
                         const Bounds& box) {
  if (job.samples != kAutoSamples) return {job.samples, job.mask_per_sample};
  const PixelRect b = box_rect(cam, box);
  return choose_sampling(size_t(window.width) * window.height, size_t(cam.width) * cam.height, triangles,
                         size_t(b.w) * size_t(b.h));
}

// The renders of one view of camera `cam`, whose window on the model is
// `window`: one that every sample reads (the whole frame; a grid's is the
// window at grid times the resolution), or with a mask per sample one
// render of the window per sample offset, its camera shifted by it.
// Appended to `out`.
void add_view_passes(size_t tile, const Camera& cam, const Camera& window, const ViewSampling& vs,
                     std::vector<ViewPass>& out, const PixelRect& part) {
  const int grid = sample_grid(vs.samples);
  if (grid) {
    out.push_back({tile, 0, 1, window, vs, {}});
    return;
  }
  if (!vs.mask_per_sample || vs.samples == 1) {
    out.push_back({tile, 0, 1, cam, vs, part});
    return;
  }
  const auto offsets = sample_offsets(vs.samples);
  for (size_t p = 0; p < offsets.size(); ++p) {
    Camera c = window;
    c.shift_x += offsets[p][0];
    c.shift_y += offsets[p][1];
    out.push_back({tile, p, offsets.size(), c, vs, {}});
  }
}

std::string sampling_name(const ViewSampling& vs) {
  if (sample_grid(vs.samples)) return std::to_string(vs.samples) + " (grid)";
  return std::to_string(vs.samples) + (vs.mask_per_sample && vs.samples > 1 ? " (mask per sample)" : "");
}

// Adds a later pass's timings to the report of the view's first pass.
void add_pass_report(ViewLabelling& first, const ViewLabelling& pass, size_t passes) {
  for (const auto& [k, v] : pass.seconds) first.seconds[k] += v;
  first.rendered_pixels += pass.rendered_pixels;
  first.passes = passes;
}

}  // namespace perclod::detail
