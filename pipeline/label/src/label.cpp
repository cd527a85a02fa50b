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
#include "view_pass.h"

namespace perclod {
using namespace detail;
namespace {

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

}  // namespace perclod
