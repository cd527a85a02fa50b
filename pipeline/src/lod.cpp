// The whole method for one model (method.md sections 2-5):
//   per distance: per facade view: render -> perceive -> trace -> count;
//   labels from the counts, combined over views; marking renders;
//   label-constrained simplification; export.
#include "perclod/lod.h"

#include <chrono>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "perclod/batch.h"
#include "perclod/export.h"
#include "perclod/image_io.h"
#include "perclod/labels_io.h"

namespace perclod {
namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

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

// The job's perception settings at its display's pixel density.
PerceptionSettings perception_for(const LabelJob& job) {
  PerceptionSettings ps = job.perception;
  ps.ppd = job.display.pixels_per_degree();
  return ps;
}

// 1 where the render drew no triangle (from its ID buffer).
void background_of(const RenderOutput& img, std::vector<uint8_t>& background) {
  background.resize(img.ids.size());
  for (size_t i = 0; i < img.ids.size(); ++i) background[i] = img.ids[i] == 0;
}

std::string tagged(const LabelJob& job, const std::string& facade, const std::string& suffix) {
  return view_file_base(job.out_dir, job.stem, facade, job.distance) + suffix;
}

}  // namespace

nlohmann::json simplify_stats_json(const SimplifyStats& s) {
  auto per_label = [](const std::array<size_t, 3>& n) {
    return nlohmann::json{{"perceptible", n[0]}, {"imperceptible", n[1]}, {"undisplayable", n[2]},
                          {"total", n[0] + n[1] + n[2]}};
  };
  return {{"triangles_before", per_label(s.triangles_before)},
          {"triangles_after", per_label(s.triangles_after)},
          {"total_before", s.total_before()},
          {"total_after", s.total_after()},
          {"vertices_before", s.vertices_before},
          {"vertices_after", s.vertices_after},
          {"components_removed", s.components_removed},
          {"pieces_removed", s.pieces_removed},
          {"pieces_triangles_removed", s.pieces_triangles_removed},
          {"undisplayable_faces_deleted", s.undisplayable_faces_deleted},
          {"nonmanifold_faces_duplicated", s.nonmanifold_faces_duplicated},
          {"degenerate_faces", s.degenerate_faces},
          {"collapses", s.collapses},
          {"tolerance", s.tolerance},
          {"max_error", s.max_error},
          {"cluster_dangling_edges", s.cluster_dangling_edges},
          {"cluster_isolated_points", s.cluster_isolated_points},
          {"max_displacement_rel", s.max_displacement_rel},
          {"mean_displacement_rel", s.mean_displacement_rel},
          {"bbox_diagonal", s.bbox_diagonal},
          {"seconds", s.seconds}};
}

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
  if (!job.out_dir.empty()) ensure_directory(job.out_dir);

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
    if (!job.out_dir.empty()) {
      write_png(tagged(job, facade, ".png"), img.width, img.height, 3, img.rgb.data());
      if (job.write_perception_images) {
        write_png(tagged(job, facade, "_simulated.png"), img.width, img.height, 1, simulated_view(pr).data());
        write_png(tagged(job, facade, "_difference.png"), img.width, img.height, 1, difference_view(pr).data());
        write_png(tagged(job, facade, "_mask.png"), img.width, img.height, 1, mask_view(pr).data());
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

nlohmann::json compare_lod_views(Renderer& renderer, const Scene& lod, const LabelResult& original,
                                 const LabelJob& job) {
  const PerceptionSettings ps = perception_for(job);
  renderer.set_scene(lod);
  nlohmann::json views = nlohmann::json::array();
  PerceptionResult pr;
  std::vector<uint8_t> background;
  for (const ViewRecord& v : original.views) {
    RenderOutput img = renderer.render(v.camera);
    background_of(img, background);
    perceive_into(img.rgb.data(), img.width, img.height, ps, background.data(), pr);
    if (pr.simulated.size() != v.simulated.size())
      throw std::logic_error("compare_lod_views: view size changed between labelling and comparison");
    size_t drawn = 0, changed = 0, coverage_changed = 0;
    for (size_t i = 0; i < background.size(); ++i) {
      if (background[i] && v.background[i]) continue;
      ++drawn;
      changed += std::abs(pr.simulated[i] - v.simulated[i]) > ps.threshold;
      coverage_changed += background[i] != v.background[i];
    }
    views.push_back({{"facade", v.facade},
                     {"drawn_pixels", drawn},
                     {"changed_pixels", changed},
                     {"changed_fraction", drawn ? double(changed) / double(drawn) : 0.0},
                     {"coverage_changed_pixels", coverage_changed}});
  }
  return views;
}

std::vector<std::string> write_marking_renders(Renderer& renderer, const Scene& scene,
                                               const std::vector<Label>& labels, const LabelJob& job) {
  std::vector<std::string> files;
  if (job.out_dir.empty()) return files;
  Bounds bounds = scene_bounds(scene);
  RenderOptions opt;
  opt.triangle_colors = marking_colors(labels);
  opt.want_ids = false;
  for (const auto& facade : job.facades)
    for (auto [d, suffix] : {std::pair{job.distance, "_marking.png"},
                             std::pair{job.distance * job.closer_factor, "_marking_near.png"}}) {
      RenderOutput o = renderer.render(facade_camera(bounds, job.up, facade, d, job.display), opt);
      files.push_back(tagged(job, facade, suffix));
      write_png(files.back(), o.width, o.height, 3, o.rgb.data());
    }
  return files;
}

void write_label_outputs(Renderer& renderer, const Scene& scene, LabelResult& result, const LabelJob& job) {
  LabelFile lf{result.labels, result.totals.traced, result.totals.imperceptible, {}};
  for (const auto& f : job.facades) lf.views.emplace_back(f, job.distance);
  std::string path = distance_file(job.out_dir, job.stem, "labels", job.distance, ".txt");
  write_labels(path, lf);
  result.report["labels_file"] = path;
  result.report["marking_renders"] = write_marking_renders(renderer, scene, result.labels, job);
}

nlohmann::json make_lods(const Scene& scene, const LodJob& job, const Progress& progress) {
  if (job.distances.empty()) throw std::invalid_argument("no viewing distance given");
  if (job.lod_format != "obj" && job.lod_format != "glb")
    throw std::invalid_argument("LOD format must be obj or glb, not '" + job.lod_format + "'");
  const std::string& out = job.label.out_dir;
  ensure_directory(out);
  auto t_all = Clock::now();

  auto t0 = Clock::now();
  std::unique_ptr<Tracer> tracer = make_tracer(scene, job.tracer);
  double t_build = since(t0);
  Renderer renderer;
  if (progress)
    progress(std::string(tracer->name()) + " built in " + std::to_string(int(t_build * 1e3)) + " ms, " +
             std::to_string(tracer->memory_bytes() / 1024) + " KiB");

  nlohmann::json report = {{"triangles", scene.triangle_count()},
                           {"components", scene.component_count()},
                           {"display", {{"name", job.label.display.name},
                                        {"ppd", job.label.display.pixels_per_degree()},
                                        {"f_max", job.label.display.f_max()}}},
                           {"tracer", {{"name", tracer->name()}, {"build_seconds", t_build},
                                       {"memory_bytes", tracer->memory_bytes()}}},
                           {"simplify_mode", simplify_mode_name(job.simplify.mode)},
                           {"lods", nlohmann::json::array()}};
  for (double d : job.distances) {
    if (progress) {
      std::ostringstream ss;
      ss << "distance " << d << " m";
      progress(ss.str());
    }
    LabelJob lj = job.label;
    lj.distance = d;
    auto t_d = Clock::now();
    renderer.set_scene(scene);  // the previous distance's comparison left its LOD there
    LabelResult lr = label_scene(renderer, scene, *tracer, lj, progress);

    write_label_outputs(renderer, scene, lr, lj);

    SimplifyOptions so = job.simplify;
    // p(d): the footprint of one pixel at the eye depth of the facade plane.
    so.pixel_footprint = facade_camera(scene_bounds(scene), lj.up, lj.facades[0], d, lj.display).pixel_footprint(d);
    SimplifyStats st;
    Scene lod = simplify(scene, lr.labels, so, &st);
    std::string lod_path = distance_file(out, lj.stem, "lod", d, "." + job.lod_format);
    export_scene(lod, lod_path);
    nlohmann::json entry = lr.report;
    entry["pixel_footprint"] = so.pixel_footprint;
    entry["lod_file"] = lod_path;
    entry["simplify"] = simplify_stats_json(st);
    auto t_cmp = Clock::now();
    entry["lod_vs_original"] = compare_lod_views(renderer, lod, lr, lj);
    entry["seconds_compare"] = since(t_cmp);
    if (progress) {
      double worst = 0;
      for (const auto& v : entry["lod_vs_original"]) worst = std::max(worst, v["changed_fraction"].get<double>());
      std::ostringstream ss;
      ss << "  LOD " << d << " m: " << st.total_before() << " -> " << st.total_after() << " triangles ("
         << (st.total_before() ? 100.0 * double(st.total_after()) / double(st.total_before()) : 0.0)
         << "%); per view at most " << 100 * worst
         << "% of drawn pixels differ after vision simulation; " << lod_path;
      progress(ss.str());
    }
    entry["seconds"] = since(t_d);
    report["lods"].push_back(entry);
  }
  report["seconds"] = since(t_all);
  write_text_atomic(out + "/" + job.label.stem + "_report.json", report.dump(2) + "\n");
  return report;
}

}  // namespace perclod
