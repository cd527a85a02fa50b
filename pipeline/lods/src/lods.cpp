// `perclod run` for one model (the method's section 5 and the judging of its
// result): labels, simplifies, exports and compares each LOD with the
// original, one distance at a time.
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


#include "perclod/lods.h"

#include "perclod/export.h"
#include "perclod/image_io.h"
#include "perclod/labels_io.h"
#include "perclod/simplify_model.h"
#include "perclod/undisplayable.h"

namespace perclod {
using namespace detail;

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
