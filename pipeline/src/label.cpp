// Labelling (the method's sections 2-4 for one distance): per facade view
// render -> perceive -> trace -> count; labels from the counts, combined over
// views; the labels file and marking renders.
#include <cstdio>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "perclod/image_io.h"
#include "perclod/labels_io.h"
#include "pipeline_internal.h"

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
          {"real_disagreements", a.real_disagreements},
          {"identical_rate", a.identical_rate()}};
}

// Marking-colour renders of `labels` from each facade at the job's distance and
// at distance * closer_factor.
std::vector<std::string> write_marking_renders(Renderer& renderer, const Scene& scene,
                                               const std::vector<Label>& labels, const LabelJob& job) {
  std::vector<std::string> files;
  if (job.out.dir.empty()) return files;
  Bounds bounds = scene_bounds(scene);
  RenderOptions opt;
  opt.triangle_colors = marking_colors(labels);
  opt.want_ids = false;
  for (const auto& facade : job.facades)
    for (auto [d, suffix] : {std::pair{job.distance, "_marking.png"},
                             std::pair{job.distance * job.closer_factor, "_marking_near.png"}}) {
      RenderOutput o = renderer.render(facade_camera(bounds, job.up, facade, d, job.display), opt);
      files.push_back(job.out.view(facade, job.distance, suffix));
      write_png(files.back(), o.width, o.height, 3, o.rgb.data());
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

LabelResult label_scene(Renderer& renderer, const Scene& scene, const Tracer& tracer, const LabelJob& job,
                        const Progress& progress) {
  if (job.facades.empty()) throw std::invalid_argument("no facade views to label from");
  const size_t nt = scene.triangle_count();
  Bounds bounds = scene_bounds(scene);
  const PerceptionSettings ps = perception_for(job);
  std::unique_ptr<EmbreeTracer> reference;
  if (job.verify) reference = std::make_unique<EmbreeTracer>(scene, EmbreeMode::Verify);
  const bool write_files = !job.out.dir.empty();
  if (write_files) ensure_directory(job.out.dir);
  renderer.set_scene(scene);

  LabelResult res;
  res.totals.traced.assign(nt, 0);
  res.totals.imperceptible.assign(nt, 0);
  res.report = {{"distance", job.distance}, {"tracer", tracer.name()}, {"views", nlohmann::json::array()}};
  std::vector<uint32_t> rays;
  std::vector<uint8_t> background;
  PerceptionResult pr;  // reused across views: perceive_into allocates only once
  for (const auto& facade : job.facades) {
    Camera cam = facade_camera(bounds, job.up, facade, job.distance, job.display);
    auto t0 = Clock::now();
    RenderOutput img = renderer.render(cam);
    double t_render = since(t0);

    background_of(img, background);
    t0 = Clock::now();
    perceive_into(img.rgb.data(), img.width, img.height, ps, background.data(), pr);
    double t_perceive = since(t0);

    rays.resize(size_t(img.width) * img.height);
    t0 = Clock::now();
    tracer.trace(cam, rays.data());
    double t_trace = since(t0);

    TriangleCounts counts = count_triangles(rays.data(), pr.mask.data(), rays.size(), nt);
    for (size_t t = 0; t < nt; ++t) {
      res.totals.traced[t] += counts.traced[t];
      res.totals.imperceptible[t] += counts.imperceptible[t];
    }
    res.per_view.push_back(label_triangles(counts, job.ratio));
    res.views.push_back({facade, cam, pr.simulated, background});

    nlohmann::json v = {{"facade", facade},
                        {"covered_pixels", pr.counted_pixels},
                        {"imperceptible_fraction", pr.imperceptible_fraction},
                        {"levels", pr.levels},
                        {"labels", to_json(count_labels(res.per_view.back()))},
                        {"rays_vs_id_buffer", to_json(compare_with_id_buffer(scene, cam, rays.data(), img.ids.data()))},
                        {"seconds", {{"render", t_render}, {"perceive", t_perceive}, {"trace", t_trace}}}};
    if (reference) {
      std::vector<uint32_t> ref(rays.size());
      t0 = Clock::now();
      reference->trace(cam, ref.data());
      v["seconds"]["trace_embree_verify"] = since(t0);
      v["octree_vs_embree"] = to_json(compare_traced(scene, cam, rays.data(), ref.data()));
    }
    if (write_files) {
      auto file = [&](const char* suffix) { return job.out.view(facade, job.distance, suffix); };
      write_png(file(".png"), img.width, img.height, 3, img.rgb.data());
      if (job.write_perception_images) {
        write_png(file("_simulated.png"), img.width, img.height, 1, simulated_view(pr).data());
        write_png(file("_difference.png"), img.width, img.height, 1, difference_view(pr).data());
        write_png(file("_mask.png"), img.width, img.height, 1, mask_view(pr).data());
      }
    }
    res.report["views"].push_back(v);
    if (progress) {
      std::ostringstream ss;
      ss.precision(3);
      ss << "  " << facade << " at " << job.distance << " m: " << pr.counted_pixels << " px, "
         << 100 * pr.imperceptible_fraction << "% imperceptible; render " << 1e3 * t_render << " ms, perceive "
         << 1e3 * t_perceive << " ms, trace " << 1e3 * t_trace << " ms";
      progress(ss.str());
    }
  }
  res.labels = combine_views(res.per_view);
  res.report["labels"] = to_json(count_labels(res.labels));
  return res;
}

void write_label_outputs(Renderer& renderer, const Scene& scene, LabelResult& result, const LabelJob& job) {
  LabelFile lf{result.labels, result.totals.traced, result.totals.imperceptible, {}};
  for (const auto& f : job.facades) lf.views.emplace_back(f, job.distance);
  lf.has_model = true;
  lf.model_triangles = scene.triangle_count();
  lf.model_hash = model_fingerprint(scene);
  std::string path = job.out.labels(job.distance);
  write_labels(path, lf);
  result.report["labels_file"] = path;
  result.report["marking_renders"] = write_marking_renders(renderer, scene, result.labels, job);
}

nlohmann::json label_model(const Scene& scene, const LabelJob& job, TracerKind kind, const Progress& progress) {
  std::optional<OutputDirectoryLock> lock;
  if (!job.out.dir.empty()) lock.emplace(job.out.dir);
  std::unique_ptr<Tracer> tracer = make_tracer(scene, kind);
  if (progress) progress(tracer_summary(*tracer));
  Renderer renderer;
  LabelResult r = label_scene(renderer, scene, *tracer, job, progress);
  write_label_outputs(renderer, scene, r, job);
  r.report["tracer_build_seconds"] = tracer->build_seconds();
  write_text_atomic(job.out.label_report(job.distance), r.report.dump(2) + "\n");
  return r.report;
}

std::string detail::tracer_summary(const Tracer& tracer) {
  char line[160];
  std::snprintf(line, sizeof line, "%s built in %.0f ms, %zu KiB", tracer.name(), tracer.build_seconds() * 1e3,
                tracer.memory_bytes() / 1024);
  return line;
}

}  // namespace perclod
