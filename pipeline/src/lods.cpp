// LODs (the method's section 5 and the judging of its result): one LOD from
// a labels file, and the whole job of `perclod run`, which labels, simplifies,
// exports and compares each LOD with the original, one distance at a time.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <future>
#include <iomanip>
#include <iterator>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "perclod/export.h"
#include "perclod/labels_io.h"
#include "perclod/image_io.h"
#include "pipeline_internal.h"

namespace perclod {
using namespace detail;

nlohmann::json simplify_stats_json(const SimplifyStats& s) {
  auto per_label = [](const std::array<size_t, 3>& n) {
    return nlohmann::json{{"perceptible", n[0]}, {"imperceptible", n[1]}, {"undisplayable", n[2]},
                          {"total", n[0] + n[1] + n[2]}};
  };
  nlohmann::json j = {{"triangles_before", per_label(s.triangles_before)},
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
                      {"chunks", s.chunks},
                      {"tolerance", s.tolerance},
                      {"tolerance_perceptible", s.tolerance_perceptible},
                      {"target_reached", s.target_reached},
                      {"stop_reason", s.stop_reason},
                      {"max_error", s.max_error},
                      {"cluster_dangling_edges", s.cluster_dangling_edges},
                      {"cluster_isolated_points", s.cluster_isolated_points},
                      {"max_displacement_rel", s.max_displacement_rel},
                      {"mean_displacement_rel", s.mean_displacement_rel},
                      {"bbox_diagonal", s.bbox_diagonal},
                      {"seconds", s.seconds}};
  if (s.refused_counted) {
    const SimplifyStats::Refused& r = s.refused;
    j["refused"] = {{"bound_or_locked", r.bound_or_locked}, {"valence", r.valence}, {"topology", r.topology},
                    {"shape", r.shape}, {"legal", r.legal}, {"total", r.total()}};
  }
  return j;
}

std::string refused_text(const SimplifyStats::Refused& why) {
  std::string s = std::to_string(why.total()) + " half-edges left: " + std::to_string(why.bound_or_locked) +
                  " locked or over their bound, " + std::to_string(why.shape) +
                  " refused by shape (normal change, sliver, area), " + std::to_string(why.topology) +
                  " by topology, " + std::to_string(why.valence) + " by the valence cap";
  if (why.legal) s += ", " + std::to_string(why.legal) + " legal only after the last pass";
  return s;
}

SimplifyRun simplify_model(const Scene& scene, const SimplifyJob& job) {
  const SimplifyMode mode = job.options.mode;
  if (simplify_mode_uses_labels(mode) && job.labels_file.empty())
    throw std::invalid_argument(std::string(simplify_mode_name(mode)) +
                                " mode needs a labels file (from perclod label)");
  if (!(job.distance > 0) || !std::isfinite(job.distance))
    throw std::invalid_argument("the viewing distance must be positive metres");
  if (job.format != "obj" && job.format != "glb")
    throw std::invalid_argument("LOD format must be obj or glb, not '" + job.format + "'");
  std::vector<Label> labels(scene.triangle_count(), Label::Imperceptible);
  if (!job.labels_file.empty()) {
    LabelFile lf = job.labels ? *job.labels : read_labels(job.labels_file);
    const std::string model = job.model_file.empty() ? std::string("the model") : job.model_file;
    if (lf.labels.size() != scene.triangle_count())
      throw std::invalid_argument(job.labels_file + ": has " + std::to_string(lf.labels.size()) +
                                  " labels but " + model + " has " + std::to_string(scene.triangle_count()) +
                                  " triangles (labels from another model or loader settings?)");
    if (lf.has_model && lf.model_hash != model_fingerprint(scene)) {
      char hash[40];
      std::snprintf(hash, sizeof hash, "%016llx", static_cast<unsigned long long>(model_fingerprint(scene)));
      throw std::invalid_argument(job.labels_file + ": labels of another model: its fingerprint does not match " +
                                  model + " (" + hash + "; another file, or loaded with another --scale?)");
    }
    labels = std::move(lf.labels);
  }
  OutputDirectoryLock lock(job.out.dir);  // a busy directory is refused before the work, not after
  SimplifyRun run;
  SimplifyOptions so = job.options;
  so.pixel_footprint = run.pixel_footprint = display_pixel_footprint(job.display, job.distance);
  if (job.undisplayable_auto && undisplayable_auto_applies(so)) {
    LabelJob framing;
    framing.up = job.up;
    framing.display = job.display;
    framing.distance = job.distance;
    run.undisplayable_exposure = choose_undisplayable(so, scene, OctreeTracer(scene), labels, framing);
  }
  run.options = so;
  Scene lod = simplify(scene, labels, so, &run.stats);
  run.lod_file = job.out.lod(job.distance, job.format);
  auto t0 = Clock::now();
  export_scene(lod, run.lod_file, ExportOptions{job.up == UpAxis::Z});
  run.write_seconds = since(t0);
  return run;
}

std::vector<ViewRecord> record_views(Renderer& renderer, const Scene& scene, const std::vector<std::string>& views,
                                     const LabelJob& job, const std::string& set) {
  const Bounds bounds = scene_bounds(scene);
  renderer.set_scene(scene);
  std::vector<ViewRecord> records;
  std::vector<uint8_t> background;
  RenderOutput img;  // one set of buffers for every view
  for (const auto& view : views)
    for (const ViewTile& tile : frame_view(bounds, job.up, view, job.distance, job.display)) {
      renderer.render(tile.camera, img);
      background_of(img, background);
      records.push_back(view_record(tile.name, tile.camera, img.rgb, background, set));
    }
  return records;
}

void ViewRecord::rgb_into(std::vector<uint8_t>& rgb) const {
  rgb.resize(3 * size_t(w) * size_t(h));
  if (!rgb.empty()) unpack_bytes(packed_rgb, rgb.data(), rgb.size());
}

void ViewRecord::render_into(std::vector<uint8_t>& image) const {
  thread_local std::vector<uint8_t> kept;
  rgb_into(kept);
  const size_t W = size_t(camera.width), H = size_t(camera.height);
  image.resize(W * H * 3);
  for (size_t i = 0; i < W * H; ++i) std::copy_n(background_rgb, 3, &image[3 * i]);
  for (int y = 0; y < h; ++y)
    std::copy_n(&kept[3 * size_t(y) * size_t(w)], 3 * size_t(w), &image[3 * ((size_t(y0 + y) * W) + size_t(x0))]);
}

void IdBuffer::ids_into(std::vector<uint32_t>& ids) const {
  ids.resize(size_t(camera.width) * size_t(camera.height));
  if (!ids.empty()) unpack_bytes(packed_ids, ids.data(), ids.size() * sizeof(uint32_t));
}

namespace {

// One picture of a judged view: the original's luminance | the LOD's | the
// LOD's with perceptibly changed pixels red and pixels drawn by only one of
// the two blue. Each panel is the region either render draws (8 px margin),
// shrunk by a whole factor (box filter; a block is red or blue if any pixel
// in it is) to at most 400 px, or enlarged by one (nearest) to about 240 px,
// so a building far away is as readable as one close by.
Rgb8Image side_by_side(const ViewRecord& v, const std::vector<float>& original_luminance,
                       const std::vector<float>& lod_luminance, const std::vector<uint8_t>& lod_background,
                       const std::vector<uint8_t>& changed, int w, int h) {
  int x0 = w, y0 = h, x1 = -1, y1 = -1;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y) * size_t(w) + size_t(x);
      if (v.background_at(x, y) && lod_background[i]) continue;
      x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
    }
  if (x1 < 0) x0 = 0, y0 = 0, x1 = w - 1, y1 = h - 1;  // nothing drawn: the whole view
  constexpr int kMargin = 8;
  x0 = std::max(0, x0 - kMargin), y0 = std::max(0, y0 - kMargin);
  x1 = std::min(w - 1, x1 + kMargin), y1 = std::min(h - 1, y1 + kMargin);
  const int cw = x1 - x0 + 1, ch = y1 - y0 + 1, side = std::max(cw, ch);
  const int shrink = std::max(1, (side + 399) / 400), grow = shrink > 1 ? 1 : std::clamp(240 / side, 1, 8);
  const int pw = std::max(1, cw * grow / shrink), ph = std::max(1, ch * grow / shrink);
  constexpr int kGap = 4;
  Rgb8Image img;
  img.width = 3 * pw + 2 * kGap, img.height = ph;
  img.pixels.assign(size_t(img.width) * size_t(ph) * 3, 255);
  for (int y = 0; y < ph; ++y)
    for (int x = 0; x < pw; ++x) {
      // Source block of this output pixel.
      const int sx0 = x0 + x * shrink / grow, sy0 = y0 + y * shrink / grow;
      const int sx1 = std::min(x1 + 1, sx0 + std::max(1, shrink)), sy1 = std::min(y1 + 1, sy0 + std::max(1, shrink));
      double a = 0, b = 0;
      bool red = false, blue = false;
      int n = 0;
      for (int yy = sy0; yy < sy1; ++yy)
        for (int xx = sx0; xx < sx1; ++xx, ++n) {
          const size_t i = size_t(yy) * size_t(w) + size_t(xx);
          a += original_luminance[i], b += lod_luminance[i];
          red |= changed[i] != 0;
          blue |= (lod_background[i] != 0) != v.background_at(xx, yy);
        }
      n = std::max(n, 1);
      const auto put = [&](int panel, double l, uint8_t r, uint8_t g, uint8_t bl) {
        uint8_t* p = &img.pixels[(size_t(y) * size_t(img.width) + size_t(panel * (pw + kGap) + x)) * 3];
        const double k = l / n / 255.0;
        p[0] = uint8_t(std::lround(r * k)), p[1] = uint8_t(std::lround(g * k)), p[2] = uint8_t(std::lround(bl * k));
      };
      put(0, a, 255, 255, 255);
      put(1, b, 255, 255, 255);
      if (blue) put(2, std::max(b, 96.0 * n), 64, 96, 255);
      else if (red) put(2, std::max(b, 96.0 * n), 255, 48, 48);
      else put(2, b, 255, 255, 255);
    }
  for (int y = 0; y < ph; ++y)  // grey gaps between the panels
    for (int g = 0; g < kGap; ++g)
      for (int panel : {1, 2}) {
        uint8_t* p = &img.pixels[(size_t(y) * size_t(img.width) + size_t(panel * (pw + kGap) - kGap + g)) * 3];
        p[0] = p[1] = p[2] = 160;
      }
  return img;
}

// One judged view's figures from the LOD's render of it (and its picture).
struct ViewComparer {
  PerceptionSettings ps;
  PerceptionResult pr, original;
  std::vector<uint8_t> background, drawn_mask, changed_mask, original_rgb;
  SsimScratch ssim_scratch;

  nlohmann::json operator()(const ViewRecord& v, RenderOutput& img, Rgb8Image* picture) {
    const size_t kept = size_t(v.w) * size_t(v.h);
    if (img.width != v.camera.width || img.height != v.camera.height || v.background.size() != kept)
      throw std::logic_error("compare_lod_views: view size changed between recording and comparison");
    background_of(img, background);
    perceive_into(img.rgb.data(), img.width, img.height, ps, background.data(), pr);
    // The original's render rebuilt from its record and perceived as it was
    // when recorded (same pixels, same settings: the same floats).
    v.render_into(original_rgb);
    perceive_into(original_rgb.data(), img.width, img.height, ps, nullptr, original);
    const size_t n = background.size();
    size_t drawn = 0, changed = 0, coverage_changed = 0, covered_original = 0;
    drawn_mask.assign(n, 0);
    changed_mask.assign(picture ? n : 0, 0);
    for (int y = 0; y < img.height; ++y)
      for (int x = 0; x < img.width; ++x) {
        const size_t i = size_t(y) * size_t(img.width) + size_t(x);
        const long k = v.kept(x, y);
        const bool original_background = k < 0 || v.background[size_t(k)];
        covered_original += !original_background;
        if (background[i] && original_background) continue;
        drawn_mask[i] = 1;
        ++drawn;
        // Beyond the kept rectangle the original drew nothing within
        // kRecordMargin pixels: a LOD drawing there changes what is seen.
        const bool c = k < 0 || std::abs(pr.simulated[i] - original.simulated[i]) > ps.threshold;
        changed += c;
        if (picture) changed_mask[i] = c;
        coverage_changed += (background[i] != 0) != original_background;
      }
    // Both luminances on the same 8-bit grid, so an unchanged LOD scores 1.
    for (auto* lum : {&original.luminance, &pr.luminance})
      for (float& l : *lum) l = std::round(std::clamp(l, 0.f, 255.f));
    const double ssim = ssim_mean(original.luminance.data(), pr.luminance.data(), img.width, img.height,
                                  drawn_mask.data(), &ssim_scratch);
    if (picture)
      *picture = side_by_side(v, original.luminance, pr.luminance, background, changed_mask, img.width, img.height);
    return {{"view", v.view},
            {"set", v.set},
            {"drawn_pixels", drawn},
            {"changed_pixels", changed},
            {"changed_fraction", drawn ? double(changed) / double(drawn) : 0.0},
            {"ssim_covered", ssim},
            {"covered_pixels_original", covered_original},
            {"coverage_changed_pixels", coverage_changed},
            {"silhouette_mismatch", covered_original ? double(coverage_changed) / double(covered_original)
                                                     : (coverage_changed ? 1.0 : 0.0)}};
  }
};

}  // namespace

// The LOD's render of view k+1 (on this thread, which owns the OpenGL
// context) overlaps the comparison of view k on a worker; the figures are
// those of one view after another.
nlohmann::json compare_lod_views(Renderer& renderer, const Scene& lod, const std::vector<ViewRecord>& original,
                                 const LabelJob& job, std::vector<Rgb8Image>* pictures) {
  renderer.set_scene(lod);
  nlohmann::json views = nlohmann::json::array();
  std::vector<Rgb8Image> shots(pictures ? original.size() : 0);
  ViewComparer compare{perception_for(job), {}, {}, {}, {}, {}, {}, {}};
  RenderOutput img[2];
  // Declared after the buffers it works on: an exception ends the worker
  // (finishing the comparison in flight) before they are freed.
  std::optional<Worker> worker;
  if (job.overlap) worker.emplace();
  std::future<nlohmann::json> pending;
  for (size_t k = 0; k < original.size(); ++k) {
    renderer.render(original[k].camera, img[k % 2]);  // reuses the buffers of view k-2, compared by now
    if (pending.valid()) views.push_back(pending.get());
    auto work = [&, k] { return compare(original[k], img[k % 2], pictures ? &shots[k] : nullptr); };
    if (worker) pending = worker->submit(work);
    else views.push_back(work());
  }
  if (pending.valid()) views.push_back(pending.get());
  if (pictures)
    for (auto& p : shots) pictures->push_back(std::move(p));
  return views;
}

nlohmann::json compare_lod_views(Renderer& renderer, const Scene& lod, const LabelResult& original,
                                 const LabelJob& job) {
  return compare_lod_views(renderer, lod, original.views, job);
}

nlohmann::json judge_views(const nlohmann::json& views, const FidelityLimits& limits) {
  double changed = 0, silhouette = 0, ssim = 1;
  nlohmann::json over = nlohmann::json::array();
  for (const auto& v : views) {
    const double c = v.at("changed_fraction").get<double>(), s = v.at("silhouette_mismatch").get<double>();
    const double q = v.at("ssim_covered").get<double>();
    changed = std::max(changed, c);
    silhouette = std::max(silhouette, s);
    ssim = std::min(ssim, q);
    auto flag = [&](const char* measure, double value, double limit, bool over_limit) {
      if (over_limit)
        over.push_back({{"view", v.at("view")}, {"set", v.at("set")}, {"measure", measure}, {"value", value},
                        {"limit", limit}});
    };
    flag("changed_fraction", c, limits.max_changed, c > limits.max_changed);
    flag("ssim_covered", q, limits.min_ssim, q < limits.min_ssim);
    flag("silhouette_mismatch", s, limits.max_silhouette, s > limits.max_silhouette);
  }
  return {{"worst", {{"changed_fraction", changed}, {"ssim_covered", ssim}, {"silhouette_mismatch", silhouette}}},
          {"limits",
           {{"max_changed", limits.max_changed}, {"max_silhouette", limits.max_silhouette}, {"min_ssim", limits.min_ssim}}},
          {"over_limits", over}};
}

SimplifyOptions fidelity_bounds(SimplifyOptions so, const FidelitySearchStep& step) {
  so.bound_imperceptible_px = step.e;
  so.bound_perceptible_px = std::min(so.bound_perceptible_px, step.e);
  if (step.keep_undisplayable) {
    const double e_u = step.e_undisplayable >= 0 ? step.e_undisplayable : step.e;
    so.bound_undisplayable_px = so.delete_undisplayable ? e_u : std::min(so.bound_undisplayable_px, e_u);
    so.delete_undisplayable = false;
  }
  return so;
}

std::vector<FidelitySearchStep> tighten_steps(const SimplifyOptions& so) {
  std::vector<FidelitySearchStep> steps;
  if (so.mode != SimplifyMode::Fidelity) return steps;
  auto same = [](const SimplifyOptions& a, const SimplifyOptions& b) {
    return a.bound_imperceptible_px == b.bound_imperceptible_px && a.bound_perceptible_px == b.bound_perceptible_px &&
           a.delete_undisplayable == b.delete_undisplayable &&
           (a.delete_undisplayable || a.bound_undisplayable_px == b.bound_undisplayable_px);
  };
  SimplifyOptions last = so;
  for (const FidelitySearchStep& step : kTightenSteps) {
    if (step.e > so.bound_imperceptible_px) continue;
    const SimplifyOptions t = fidelity_bounds(so, step);
    if (same(t, last)) continue;
    steps.push_back(step);
    last = t;
  }
  return steps;
}

bool worth_tightening(const nlohmann::json& judged, const FidelityLimits& limits) {
  if (judged.at("over_limits").empty()) return false;
  const nlohmann::json& w = judged.at("worst");
  const bool ssim_within =
      limits.min_ssim <= 0 || 1 - w.at("ssim_covered").get<double>() <= kTightenReach * (1 - limits.min_ssim);
  return w.at("changed_fraction").get<double>() <= kTightenReach * limits.max_changed &&
         w.at("silhouette_mismatch").get<double>() <= kTightenReach * limits.max_silhouette && ssim_within;
}

Tightening tighten_to_limits(const SimplifyOptions& asked, const nlohmann::json& judged, const FidelityLimits& limits,
                             const std::function<bool(const SimplifyOptions&)>& try_step) {
  const std::vector<FidelitySearchStep> steps = tighten_steps(asked);
  if (steps.empty() || !worth_tightening(judged, limits)) return Tightening::NotTried;
  for (const FidelitySearchStep& step : steps)
    if (try_step(fidelity_bounds(asked, step))) return Tightening::Met;
  return Tightening::NoneWithin;
}

LooserSearch search_looser(size_t triangles,
                           const std::function<std::pair<bool, size_t>(const FidelitySearchStep&)>& try_step) {
  LooserSearch r{kFidelitySearch[0]};
  for (FidelitySearchStep looser{2 * r.step.e, false}; looser.e <= kFidelitySearchLoosestPx; looser.e *= 2) {
    const auto [met, left] = try_step(looser);
    ++r.tries;
    if (!met || left > triangles) {
      r.remake = true;
      break;
    }
    r.step = looser;
    r.kept = r.tries - 1;
    if (left == triangles) break;  // looser bounds removed nothing more
    triangles = left;
  }
  return r;
}

std::vector<std::string> exposure_views() {
  std::vector<std::string> v;
  for (int i = 0; i < 8; ++i) {
    std::ostringstream ss;
    ss << "az" << 22.5 + 45.0 * i << "el30";
    v.push_back(ss.str());
  }
  return v;
}

double undisplayable_exposure(const Scene& scene, const Tracer& tracer, const std::vector<Label>& labels,
                              const LabelJob& job) {
  if (labels.size() != scene.triangle_count())
    throw std::invalid_argument("undisplayable_exposure: labels and scene differ in size");
  const Bounds b = scene_bounds(scene);
  size_t hits = 0, undisplayable = 0;
  std::vector<uint32_t> ids;
  for (const std::string& v : exposure_views())
    for (const ViewTile& t : frame_view(b, job.up, v, job.distance, job.display)) {
      ids.resize(size_t(t.camera.width) * size_t(t.camera.height));
      tracer.trace(t.camera, ids.data());
      for (uint32_t id : ids)
        if (id) {
          ++hits;
          undisplayable += labels[id - 1] == Label::Undisplayable;
        }
    }
  return hits ? double(undisplayable) / double(hits) : 0.0;
}

SimplifyOptions choose_undisplayable(SimplifyOptions so, double exposure) {
  if (undisplayable_auto_applies(so) && exposure > kKeepUndisplayableExposure) {
    so.delete_undisplayable = false;
    so.bound_undisplayable_px = kAutoUndisplayableBoundPx;
  }
  return so;
}

double choose_undisplayable(SimplifyOptions& so, const Scene& scene, const Tracer& tracer,
                            const std::vector<Label>& labels, const LabelJob& framing) {
  const double exposure = undisplayable_exposure(scene, tracer, labels, framing);
  so = choose_undisplayable(so, exposure);
  return exposure;
}

void add_undisplayable_rule(nlohmann::json& j, const SimplifyOptions& so, double exposure) {
  j["undisplayable"] = so.delete_undisplayable ? "deleted" : "collapsed";
  if (!so.delete_undisplayable && std::isfinite(so.bound_undisplayable_px))
    j["e_undisplayable"] = so.bound_undisplayable_px;
  if (exposure >= 0) j["undisplayable_exposure"] = exposure;  // keep_undisplayable: auto decided
}

namespace {

// The same in words, for progress lines and warnings.
std::string undisplayable_rule_text(const SimplifyOptions& so) {
  if (so.delete_undisplayable) return "deleted";
  if (!std::isfinite(so.bound_undisplayable_px)) return "collapsed, unbounded";
  std::ostringstream ss;
  ss << "collapsed within " << so.bound_undisplayable_px << " px";
  return ss.str();
}

}  // namespace

nlohmann::json make_lods(const Scene& scene, const LodJob& job, const Progress& progress, std::vector<Scene>* lods) {
  if (job.distances.empty()) throw std::invalid_argument("no viewing distance given");
  if (job.lod_format != "obj" && job.lod_format != "glb")
    throw std::invalid_argument("LOD format must be obj or glb, not '" + job.lod_format + "'");
  const OutputNames& out = job.label.out;
  OutputDirectoryLock lock(out.dir);
  auto t_all = Clock::now();

  // Labelling and held-out views at every distance, before any work.
  check_framing(scene, job.label, job.label.views, job.distances);
  check_framing(scene, job.label, job.judge_views, job.distances);
  std::unique_ptr<Tracer> tracer = make_tracer(scene, job.tracer);
  // verify: one Embree reference scene for the whole job, not one per distance.
  std::unique_ptr<EmbreeTracer> verify_tracer;
  if (job.label.verify) verify_tracer = std::make_unique<EmbreeTracer>(scene, EmbreeMode::Verify);
  Renderer renderer;
  // Debug images are encoded on a thread of their own while the next view
  // renders and traces; every one is on disk before the report is written.
  ImageWriter images;
  if (progress) progress(tracer_summary(*tracer));

  nlohmann::json report = {{"triangles", scene.triangle_count()},
                           {"components", scene.component_count()},
                           {"display", {{"name", job.label.display.name},
                                        {"ppd", job.label.display.pixels_per_degree()},
                                        {"f_max", job.label.display.f_max()}}},
                           {"tracer", {{"name", tracer->name()}, {"build_seconds", tracer->build_seconds()},
                                       {"memory_bytes", tracer->memory_bytes()}}},
                           {"simplify_mode", simplify_mode_name(job.simplify.mode)},
                           {"judge_views", job.judge_views},
                           {"over_limits", 0},
                           {"lods", nlohmann::json::array()}};
  auto warn = [&report](const std::string& what) {
    if (!report.contains("warnings")) report["warnings"] = nlohmann::json::array();
    report["warnings"].push_back(what);
  };
  for (double d : job.distances) {
    if (progress) {
      std::ostringstream ss;
      ss << "distance " << d << " m";
      progress(ss.str());
    }
    LabelJob lj = job.label;
    lj.distance = d;
    lj.images = job.label.overlap ? &images : nullptr;
    auto t_d = Clock::now();
    LabelResult lr = label_scene(renderer, scene, *tracer, lj, progress, verify_tracer.get());

    write_label_outputs(renderer, scene, lr, lj);
    release_free_memory();  // the ID buffers of the marking images
    std::vector<ViewRecord> judged = std::move(lr.views);
    lr.views.clear();
    // The held-out views of the original are recorded after the first
    // simplification, so the simplifier's memory and theirs are not needed
    // at once (at 1M triangles each is a few hundred MB).
    bool held_out_recorded = job.judge_views.empty();

    SimplifyOptions so = job.simplify;
    so.pixel_footprint = display_pixel_footprint(lj.display, d);
    double exposure = -1;
    if (job.undisplayable_auto && undisplayable_auto_applies(so)) {
      exposure = choose_undisplayable(so, scene, *tracer, lr.labels, lj);
      if (progress) {
        std::ostringstream ss;
        ss << std::setprecision(3) << "  undisplayable triangles: " << 100 * exposure
           << "% of the pixels between the labelling views -> "
           << undisplayable_rule_text(so);
        progress(ss.str());
      }
    }
    SimplifyStats st;
    Scene lod;
    nlohmann::json views, tries = nlohmann::json::array();  // a search's or tightening's tries
    std::vector<Rgb8Image> pictures;  // per judged view: original | LOD | changes
    double seconds_compare = 0;
    const bool searching = job.fidelity_target && so.mode == SimplifyMode::Fidelity;
    const FidelityLimits& goal = searching ? job.target : job.limits;
    const SimplifyOptions asked = so;
    // One LOD at the bounds `o`, judged from every judged view against `goal`.
    auto attempt = [&](const SimplifyOptions& o) {
      so = o;
      lod = simplify(scene, lr.labels, so, &st);
      release_free_memory();  // the simplifier's mesh
      if (!held_out_recorded) {
        std::vector<ViewRecord> held = record_views(renderer, scene, job.judge_views, lj, "held_out");
        std::move(held.begin(), held.end(), std::back_inserter(judged));
        held_out_recorded = true;
      }
      const auto t_cmp = Clock::now();
      pictures.clear();
      views = compare_lod_views(renderer, lod, judged, lj,
                                out.dir.empty() || !lj.write_view_images ? nullptr : &pictures);
      seconds_compare += since(t_cmp);
      return judge_views(views, goal);
    };
    // Lists the try just judged (`f`) in `tries` and on the progress line;
    // returns whether it met `goal`.
    auto log_try = [&](const nlohmann::json& f, const char* what) {
      const bool met = f["over_limits"].empty();
      nlohmann::json t = {{"e_imperceptible", so.bound_imperceptible_px},
                          {"e_perceptible", so.bound_perceptible_px},
                          {"triangles", st.total_after()},
                          {"seconds_simplify", st.seconds},
                          {"worst", f["worst"]},
                          {"met", met}};
      add_undisplayable_rule(t, so);
      tries.push_back(std::move(t));
      if (progress) {
        std::ostringstream ss;
        ss << "  " << what << " at " << d << " m: e_imperceptible " << so.bound_imperceptible_px
           << " px, e_perceptible " << so.bound_perceptible_px << " px, undisplayable "
           << undisplayable_rule_text(so) << " -> " << st.total_after()
           << " triangles, worst " << 100 * f["worst"]["changed_fraction"].get<double>() << "% changed, SSIM "
           << f["worst"]["ssim_covered"].get<double>() << ", silhouette "
           << 100 * f["worst"]["silhouette_mismatch"].get<double>() << "%" << (met ? " (met)" : "");
        progress(ss.str());
      }
      return met;
    };
    bool tightened = false;  // tighten_to_limits tried tighter bounds
    bool target_met = false;
    size_t kept_try = 0;  // the try whose LOD is written (marked "kept" in the report)
    if (searching) {
      size_t first_met = 0;  // down the steps to the first that meets the target
      while (first_met < std::size(kFidelitySearch) &&
             !log_try(attempt(fidelity_bounds(asked, kFidelitySearch[first_met])), "fidelity target"))
        ++first_met;
      target_met = first_met < std::size(kFidelitySearch);
      kept_try = tries.size() - 1;  // the first that met, or the tightest
      if (first_met == 0) {  // the loosest step met it: so may looser bounds
        const LooserSearch l = search_looser(st.total_after(), [&](const FidelitySearchStep& step) {
          const bool met = log_try(attempt(fidelity_bounds(asked, step)), "fidelity target, looser");
          return std::make_pair(met, st.total_after());
        });
        kept_try += size_t(l.kept + 1);
        if (l.remake) {
          if (progress) progress("  fidelity target: back to the loosest bounds that met it");
          attempt(fidelity_bounds(asked, l.step));
        }
      }
    } else {
      const nlohmann::json f = attempt(asked);
      Tightening t = Tightening::NotTried;
      if (job.tighten_to_limits)
        t = tighten_to_limits(asked, f, job.limits, [&](const SimplifyOptions& o) {
          if (tries.empty()) log_try(f, "tighten to limits");  // the asked LOD first, while it is so and st
          return log_try(attempt(o), "tighten to limits");
        });
      tightened = t != Tightening::NotTried;
      kept_try = t == Tightening::Met ? tries.size() - 1 : 0;  // the one within, or the asked bounds
      if (t == Tightening::NoneWithin) {
        // The LOD at the asked bounds, made again rather than held through
        // the tries (its comparison pictures take up to 1.4 MB per judged
        // view, 88 views for the million-triangle facade at 56 m): the
        // simplifier and the judge are deterministic, so it is the same.
        if (progress) progress("  tighten to limits: none within; the asked bounds again");
        attempt(asked);
      }
    }
    std::string lod_path = out.lod(d, job.lod_format);
    export_scene(lod, lod_path, ExportOptions{job.label.up == UpAxis::Z});
    nlohmann::json entry = lr.report;
    entry["pixel_footprint"] = so.pixel_footprint;
    entry["lod_file"] = lod_path;
    entry["simplify"] = simplify_stats_json(st);
    if (so.mode == SimplifyMode::Fidelity) {
      entry["bounds_px"] = {{"perceptible", so.bound_perceptible_px}, {"imperceptible", so.bound_imperceptible_px}};
      add_undisplayable_rule(entry["bounds_px"], so, exposure);
    }
    if (!tries.empty()) tries[kept_try]["kept"] = true;
    if (tightened) entry["tighten_to_limits"] = tries;
    if (searching) {
      entry["fidelity_search"] = tries;
      if (!target_met) {
        std::ostringstream ss;
        ss << lod_path << ": no bound meets the fidelity target at " << d << " m; kept the tightest (e_imperceptible "
           << so.bound_imperceptible_px << " px, undisplayable " << undisplayable_rule_text(so) << ")";
        warn(ss.str());
      }
    }
    if (st.total_after() == 0) {
      // Nothing displayable at this distance: the LOD file holds no triangle.
      entry["empty"] = true;
      std::ostringstream ss;
      ss << lod_path << ": the LOD at " << d << " m is empty (no triangle of the model is displayable there)";
      warn(ss.str());
    }
    for (size_t k = 0; k < pictures.size(); ++k) {
      const std::string file = out.view(views[k]["view"].get<std::string>(), d, "_lod_vs_original.png");
      write_png_via(lj.images, file, pictures[k].width, pictures[k].height, 3, std::move(pictures[k].pixels));
      views[k]["comparison_image"] = file;
    }
    entry["lod_vs_original"] = std::move(views);
    entry["fidelity"] = judge_views(entry["lod_vs_original"], job.limits);
    entry["seconds_compare"] = seconds_compare;
    for (const auto& o : entry["fidelity"]["over_limits"]) {
      std::ostringstream ss;
      ss.precision(3);
      const bool ssim = o["measure"] == "ssim_covered";  // a figure, not a fraction
      ss << lod_path << ": from view " << o["view"].get<std::string>() << " (" << o["set"].get<std::string>()
         << ") " << o["measure"].get<std::string>() << " is ";
      if (ssim) ss << std::setprecision(4) << o["value"].get<double>() << " (limit " << o["limit"].get<double>() << ")";
      else ss << 100 * o["value"].get<double>() << "% (limit " << 100 * o["limit"].get<double>() << "%)";
      warn(ss.str());
      report["over_limits"] = report["over_limits"].get<size_t>() + 1;
    }
    if (progress) {
      const auto& w = entry["fidelity"]["worst"];
      std::ostringstream ss;
      ss << "  LOD " << d << " m: " << st.total_before() << " -> " << st.total_after() << " triangles ("
         << (st.total_before() ? 100.0 * double(st.total_after()) / double(st.total_before()) : 0.0)
         << "%); worst of " << entry["lod_vs_original"].size() << " views: "
         << 100 * w["changed_fraction"].get<double>() << "% changed, SSIM "
         << w["ssim_covered"].get<double>() << ", silhouette " << 100 * w["silhouette_mismatch"].get<double>()
         << "%; " << lod_path;
      progress(ss.str());
      if (st.refused_counted) {  // explain: true
        std::ostringstream stop;
        stop << "  LOD " << d << " m stopped: " << refused_text(st.refused);
        progress(stop.str());
      }
    }
    entry["seconds"] = since(t_d);
    report["lods"].push_back(entry);
    if (lods) lods->push_back(std::move(lod));
  }
  images.finish();
  report["seconds"] = since(t_all);
  write_text_atomic(out.report(), report.dump(2) + "\n");
  return report;
}

}  // namespace perclod
