// bench_labels: are the labels right for views they never saw, do they hold
// still, and what do they cost. Three sections, each printing a table:
//
//  coverage   For each candidate view set: label the model at each distance,
//             then trace a held-out view set (azimuths offset from every
//             labelling azimuth, at 15 and 45 degrees of elevation, and
//             az0el75) and report the fraction of drawn pixels that show a
//             triangle labelled undisplayable: what a LOD that deletes
//             undisplayable triangles loses from those views; before it,
//             the undisplayable_exposure keep_undisplayable: auto decides
//             from (its own eight views between the labelling ones).
//  stability  Move the geometry by +0.25 px and by -0.25 px (of p(d)) along
//             all three axes, so along both screen axes of every horizontal
//             view, keeping the bounding box and so every camera fixed: two
//             zero-area anchor triangles stand at the box corners widened by
//             the shift, and the distance is corrected by the same amount.
//             Relabel and report the fraction of visible triangles whose
//             label changes, by count and weighted by traced samples, P<->I
//             and visible<->U separately, and by count per triangle-size
//             class (projected area in pixels at d: <1, 1-10, 10-100, >=100).
//  cost       Labelling seconds per view (render, perceive, trace) for the
//             paper's set (facades, 1 sample) beside the default (views and
//             samples) and beside a mask per sample (4 and 8 samples; each
//             view's times include all of its passes), medians of R runs,
//             same process.
//
// Models: the demo building (ingolstadt/bldg_4018215.obj), han_ministry.obj,
// the 53-building block and the Delft 3D BAG tile (`delft`; both per
// building), and a generated facade (`facade`, --facade-triangles; the cost
// section always adds it).
//
// Usage: bench_labels [--section coverage|stability|cost|all] [--models demo,han,block]
//                     [--distances 56,132,427] [--samples 1,4] [--views "facades;facades,ring8el30"]
//                     [--runs R] [--facade-triangles N]
//   experiments: [--spins 1|2|4] (perception cycle spinning) [--threshold T] (grey levels)
//                [--keep-unsampled-surface] (LabelJob::keep_unsampled_surface)
//                [--mask-per-sample] (LabelJob::mask_per_sample: a render and mask per sample offset)
//                [--shift-scale 0] (relabel without moving: the noise floor, 0 when deterministic)
//                [--per-building true|false|auto] (the block runs per building unless told otherwise)
//                [--rule any|pooled] (LabelJob::combine: how views combine P and I; see rule_for)
//                [--model-views-beside-alone] (LabelJob::model_views_beside_alone: 0.5.0's per-building labels)
//   [--csv FILE]: the stability section's rows as CSV (flips in percent).
//   [--perturb shift|noise|resolution]: see g_perturb.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <map>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "bench_common.h"
#include "perclod/facade.h"
#include "perclod/load.h"
#include "perclod/label.h"
#include "perclod/report_json.h"
#include "perclod/undisplayable.h"

using namespace perclod;

namespace {

int g_spins = 0;  // 0 = the job's default
bool g_keep_unsampled_surface = false;
bool g_mask_per_sample = false;
double g_shift_scale = 1.0;  // --shift-scale 0: the noise floor (relabel without moving)
std::string g_per_building;  // --per-building true|false|auto: overrides the model's setting
double g_threshold = -1;  // --threshold T: perception threshold (grey levels)
FILE* g_csv = nullptr;    // --csv FILE: the stability rows, one per model, distance, view set and spp
// --perturb: what the stability section changes between the two labellings.
//   shift       the geometry by +-0.25 px (x --shift-scale) along both screen axes
//   noise       every vertex by uniform noise of +-1e-6 of the bounding-box diagonal (x --shift-scale)
//   resolution  the display: 1920x1536 at 1.5x the pixel density (same screen, same field of view)
std::string g_perturb = "shift";
// --rule any|pooled: LabelJob::combine (how the views of a distance combine
// P and I). Unless told: the paper's (any) for the paper's setting (facades,
// one sample), the product's default otherwise.
std::string g_rule;
// --model-views-beside-alone: LabelJob::model_views_beside_alone (the whole-
// model views count beside each building's own views alone: 0.5.0's labels).
bool g_model_views_beside_alone = false;
std::string rule_for(const std::string& views, int samples) {
  if (!g_rule.empty()) return g_rule;
  return views == "facades" && samples == 1 ? "any" : kDefaultCombineViews;
}

// The perturbation as the tables name it: "shift", "shift x4" (one pixel), "noise", "resolution".
// A --rule is named ("shift any"): the CSV's perturb column tells such rows apart.
std::string perturb_name() {
  std::ostringstream ss;
  ss << g_perturb;
  if (g_perturb != "resolution" && g_shift_scale != 1.0) ss << " x" << g_shift_scale;
  if (!g_rule.empty()) ss << " " << g_rule;
  if (g_mask_per_sample) ss << " mps";
  if (g_model_views_beside_alone) ss << " +model views";
  return ss.str();
}

struct Model {
  std::string key, path;
  UpAxis up;
  PerBuilding per_building;
};

using bench::split;

LabelJob make_job(UpAxis up, const std::string& views, int samples, double d, PerBuilding pb) {
  LabelJob job;
  job.up = up;
  job.display = DisplayProfile{};
  job.perception = perception_settings_for(job.display);
  job.views = parse_views(views, up);
  job.samples = samples;
  job.distance = d;
  job.per_building = g_per_building.empty() ? pb : parse_per_building(g_per_building);
  job.write_perception_images = false;
  if (g_spins) job.perception.spins = g_spins;
  job.keep_unsampled_surface = g_keep_unsampled_surface;
  job.mask_per_sample = g_mask_per_sample;
  job.model_views_beside_alone = g_model_views_beside_alone;
  job.combine = parse_combine_views(rule_for(views, samples));
  if (g_threshold >= 0) job.perception.threshold = g_threshold;
  return job;
}

using bench::held_out_views;
using bench::shifted;

void coverage(const Model& m, const Scene& scene, const std::vector<double>& distances,
              const std::vector<std::string>& view_sets, int samples) {
  OctreeTracer tracer(scene);
  Renderer renderer;
  const Bounds b = scene_bounds(scene);
  const DisplayProfile display;
  for (double d : distances)
    for (const auto& set : view_sets) {
      LabelJob job = make_job(m.up, set, samples, d, m.per_building);
      auto t0 = std::chrono::steady_clock::now();
      LabelResult r = label_scene(renderer, scene, tracer, job);
      double sec = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      double worst = 0, sum = 0;
      std::string worst_view;
      size_t n = 0;
      for (const auto& v : held_out_views())
        for (const ViewTile& t : frame_view(b, m.up, v, d, display)) {
          std::vector<uint32_t> ids = tracer.trace(t.camera);
          size_t drawn = 0, undisplayable = 0;
          for (uint32_t id : ids)
            if (id) {
              ++drawn;
              undisplayable += r.labels[id - 1] == Label::Undisplayable;
            }
          double f = drawn ? double(undisplayable) / double(drawn) : 0.0;
          sum += f;
          ++n;
          if (f >= worst) worst = f, worst_view = t.name;
        }
      const auto t_exp = std::chrono::steady_clock::now();
      const double exposure = undisplayable_exposure(scene, tracer, r.labels, framing_of(job));
      std::printf("%-6s %5.0f  undisplayable exposure %.3f%% (%.2f s; labelling %.1f s)\n", m.key.c_str(), d,
                  100 * exposure, std::chrono::duration<double>(std::chrono::steady_clock::now() - t_exp).count(), sec);
      LabelCounts c = count_labels(r.labels);
      std::printf("%-6s %5.0f  %-34s %4zu views %6.1f s  P %6zu I %6zu U %6zu out %5zu  held-out U px: mean %6.2f%% worst %6.2f%% (%s)\n",
                  m.key.c_str(), d, set.c_str(), label_report_json(r.report)["views"].size(), sec, c.perceptible, c.imperceptible,
                  c.undisplayable, r.outside_views, 100 * sum / double(n), 100 * worst, worst_view.c_str());
      std::fflush(stdout);
    }
}

struct Flips {
  double visible = 0, pi = 0, vu = 0, w_visible = 0, w_pi = 0, w_vu = 0;
  double cls_visible[4] = {0, 0, 0, 0}, cls_flip[4] = {0, 0, 0, 0};
};

// Projected area in pixels of triangle t at distance d (facing the viewer).
int size_class(const Scene& s, size_t t, double footprint) {
  const float* p[3];
  for (int k = 0; k < 3; ++k) p[k] = &s.positions[3 * size_t(s.indices[3 * t + k])];
  double e1[3], e2[3];
  for (int k = 0; k < 3; ++k) e1[k] = p[1][k] - p[0][k], e2[k] = p[2][k] - p[0][k];
  const double cx = e1[1] * e2[2] - e1[2] * e2[1], cy = e1[2] * e2[0] - e1[0] * e2[2], cz = e1[0] * e2[1] - e1[1] * e2[0];
  const double px = 0.5 * std::sqrt(cx * cx + cy * cy + cz * cz) / (footprint * footprint);
  return px < 1 ? 0 : px < 10 ? 1 : px < 100 ? 2 : 3;
}

void stability(const Model& m, const Scene& scene, const std::vector<double>& distances, const std::string& views,
               int samples) {
  const size_t nt = scene.triangle_count();
  for (double d : distances) {
    const double p = display_pixel_footprint(DisplayProfile{}, d);
    const double s = 0.25 * p;
    Scene ref = shifted(scene, 0.0, s);
    LabelJob job = make_job(m.up, views, samples, d - s, m.per_building);
    Renderer renderer;
    auto label = [&](const Scene& sc) {
      OctreeTracer tracer(sc);
      return label_scene(renderer, sc, tracer, job);
    };
    LabelResult base = label(ref);
    Flips f;
    double weight_scale = 1.0;  // the moved labelling's samples in the base's units
    for (double sign : {1.0, -1.0}) {
      LabelResult moved;
      if (g_perturb == "noise") {
        Scene noisy = ref;
        const double diag = scene_bounds(scene).diagonal();
        std::mt19937 rng(sign > 0 ? 1 : 2);
        std::uniform_real_distribution<double> u(-1.0, 1.0);
        const size_t n = 3 * (noisy.positions.size() / 3 - 2);  // the two anchors stay
        for (size_t i = 0; i < n; ++i)
          noisy.positions[i] = float(double(noisy.positions[i]) + g_shift_scale * 1e-6 * diag * u(rng));
        moved = label(noisy);
      } else if (g_perturb == "resolution") {
        if (sign < 0) break;  // one other display, not two
        LabelJob hi = job;
        hi.display.width = 1920, hi.display.height = 1536, hi.display.dpi *= 1.5;
        hi.display.name += "-x1.5";
        hi.perception.ppd = perception_settings_for(hi.display).ppd;
        OctreeTracer tracer(ref);
        moved = label_scene(renderer, ref, tracer, hi);
        weight_scale = (1280.0 * 1024.0) / (1920.0 * 1536.0);
      } else {
        moved = label(shifted(scene, g_shift_scale * sign * s, s));
      }
      for (size_t t = 0; t < nt; ++t) {
        const Label a = base.labels[t], b = moved.labels[t];
        const bool va = a != Label::Undisplayable, vb = b != Label::Undisplayable;
        if (!va && !vb) continue;
        const double w = std::max(double(base.totals.traced[t]), weight_scale * double(moved.totals.traced[t]));
        const int c = size_class(scene, t, p);
        f.visible += 1, f.w_visible += w, f.cls_visible[c] += 1;
        if (a == b) continue;
        f.cls_flip[c] += 1;
        if (va && vb)
          f.pi += 1, f.w_pi += w;
        else
          f.vu += 1, f.w_vu += w;
      }
    }
    const double pairs = g_perturb == "resolution" ? 1 : 2;  // labellings compared with the base
    auto pct = [](double a, double b) { return b > 0 ? 100 * a / b : 0.0; };
    std::printf("%-6s %-10s %5.0f  %-28s spp %s  visible %7.0f  flips by count: P<->I %5.2f%% vis<->U %5.2f%% all %5.2f%%  "
                "by samples: P<->I %5.2f%% vis<->U %5.2f%% all %5.2f%%  by size <1/1-10/10-100/>=100 px: "
                "%5.1f%% %5.1f%% %5.1f%% %5.1f%% (of %.0f/%.0f/%.0f/%.0f)\n",
                m.key.c_str(), perturb_name().c_str(), d, views.c_str(), samples_name(samples).c_str(), f.visible / pairs,
                pct(f.pi, f.visible), pct(f.vu, f.visible), pct(f.pi + f.vu, f.visible), pct(f.w_pi, f.w_visible),
                pct(f.w_vu, f.w_visible), pct(f.w_pi + f.w_vu, f.w_visible), pct(f.cls_flip[0], f.cls_visible[0]),
                pct(f.cls_flip[1], f.cls_visible[1]), pct(f.cls_flip[2], f.cls_visible[2]),
                pct(f.cls_flip[3], f.cls_visible[3]), f.cls_visible[0] / pairs, f.cls_visible[1] / pairs,
                f.cls_visible[2] / pairs, f.cls_visible[3] / pairs);
    std::fflush(stdout);
    if (g_csv) {
      std::fprintf(g_csv, "%s,%s,%g,\"%s\",%s,%.0f,%.4f,%.4f,%.4f,%.4f", m.key.c_str(), perturb_name().c_str(), d,
                   views.c_str(), samples_name(samples).c_str(), f.visible / pairs, pct(f.pi, f.visible), pct(f.vu, f.visible), pct(f.w_pi, f.w_visible),
                   pct(f.w_vu, f.w_visible));
      for (int c = 0; c < 4; ++c)
        std::fprintf(g_csv, ",%.0f,%.4f", f.cls_visible[c] / pairs, pct(f.cls_flip[c], f.cls_visible[c]));
      std::fprintf(g_csv, "\n");
      std::fflush(g_csv);
    }
  }
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0 : v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

void cost(const std::string& key, const Scene& scene, UpAxis up, double d, int runs) {
  OctreeTracer tracer(scene);
  Renderer renderer;
  struct Setup {
    const char* name;
    std::string views;
    int samples;
    bool mask_per_sample;
  } setups[] = {{"paper: facades, 1 spp", "facades", 1, false},
                {"facades, 4 spp", "facades", 4, false},
                {"default views, 4 spp", kDefaultViews, 4, false},
                {"default: views, auto spp", kDefaultViews, kAutoSamples, false},
                {"default views, 4 spp, mps", kDefaultViews, 4, true},
                {"default views, 8 spp, mps", kDefaultViews, 8, true},
                {"default views, 9 spp grid", kDefaultViews, 9, false},
                {"default views, 16 spp grid", kDefaultViews, 16, false}};
  // One untimed labelling first: the first setup timed would otherwise pay
  // for the process's first renders, allocations and worker threads.
  label_scene(renderer, scene, tracer, make_job(up, setups[0].views, setups[0].samples, d, PerBuilding::Off));
  double paper_per_view = 0;
  for (const auto& st : setups) {
    std::vector<double> per_view, render, perceive, trace;
    size_t views = 0;
    for (int r = 0; r < runs; ++r) {
      LabelJob job = make_job(up, st.views, st.samples, d, PerBuilding::Off);
      job.mask_per_sample = st.mask_per_sample;
      auto t0 = std::chrono::steady_clock::now();
      LabelResult res = label_scene(renderer, scene, tracer, job);
      double sec = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      views = label_report_json(res.report)["views"].size();
      per_view.push_back(sec / double(views));
      double a = 0, b = 0, c = 0;
      for (const ViewLabelling& v : res.report.views) {
        a += v.seconds.at("render");
        b += v.seconds.at("perceive");
        c += v.seconds.at("trace");
      }
      render.push_back(a / double(views));
      perceive.push_back(b / double(views));
      trace.push_back(c / double(views));
    }
    const double pv = median(per_view);
    if (paper_per_view == 0) paper_per_view = pv;
    std::printf("%-8s %5.0f m  %-26s %3zu views  per view %7.1f ms (render %6.1f, perceive %6.1f, trace %6.1f)  x%.2f of paper\n",
                key.c_str(), d, st.name, views, 1e3 * pv, 1e3 * median(render), 1e3 * median(perceive),
                1e3 * median(trace), pv / paper_per_view);
    std::fflush(stdout);
  }
}

}  // namespace

int main(int argc, char** argv) {
  std::string section = "all", models_arg = "demo,han,block", views_arg = std::string("facades;") + kDefaultViews;
  std::vector<double> distances = {56, 132, 427};
  std::vector<int> samples = {1, kDefaultSamples};
  int runs = 5;
  size_t facade_triangles = 1000000;
  for (int i = 1; i < argc; ++i) {
    auto next = [&]() -> std::string {
      if (i + 1 >= argc) {
        std::fprintf(stderr, "bench_labels: %s needs a value\n", argv[i]);
        std::exit(2);
      }
      return argv[++i];
    };
    std::string a = argv[i];
    if (a == "--section") section = next();
    else if (a == "--models") models_arg = next();
    else if (a == "--views") views_arg = next();
    else if (a == "--runs") runs = std::stoi(next());
    else if (a == "--spins") g_spins = std::stoi(next());
    else if (a == "--keep-unsampled-surface") g_keep_unsampled_surface = true;
    else if (a == "--mask-per-sample") g_mask_per_sample = true;
    else if (a == "--model-views-beside-alone") g_model_views_beside_alone = true;
    else if (a == "--shift-scale") g_shift_scale = std::stod(next());
    else if (a == "--threshold") g_threshold = std::stod(next());
    else if (a == "--rule") {
      g_rule = next();
      if (g_rule != "any" && g_rule != "pooled") {
        std::fprintf(stderr, "bench_labels: --rule must be any or pooled\n");
        return 2;
      }
    }
    else if (a == "--per-building") g_per_building = next();
    else if (a == "--facade-triangles") facade_triangles = std::stoul(next());
    else if (a == "--perturb") {
      g_perturb = next();
      if (g_perturb != "shift" && g_perturb != "noise" && g_perturb != "resolution") {
        std::fprintf(stderr, "bench_labels: --perturb must be shift, noise or resolution\n");
        return 2;
      }
    } else if (a == "--csv") {
      const std::string path = next();
      g_csv = std::fopen(path.c_str(), "w");
      if (!g_csv) {
        std::perror(path.c_str());
        return 1;
      }
      std::fprintf(g_csv, "model,perturb,distance,views,samples,visible,flip_pi_count,flip_vu_count,flip_pi_weighted,"
                          "flip_vu_weighted,visible_lt1px,flip_lt1px,visible_1_10px,flip_1_10px,visible_10_100px,"
                          "flip_10_100px,visible_ge100px,flip_ge100px\n");
    }
    else if (a == "--distances") {
      distances.clear();
      for (auto& s : split(next(), ',')) distances.push_back(std::stod(s));
    } else if (a == "--samples") {
      samples.clear();
      for (auto& s : split(next(), ',')) samples.push_back(parse_samples(s));
    } else {
      std::fprintf(stderr, "usage: bench_labels [--section coverage|stability|cost|all] [--models demo,han,block]\n"
                           "  [--distances 56,132,427] [--samples 1,4] [--views \"facades;facades,ring8el30\"]\n"
                           "  [--runs R] [--facade-triangles N] [--spins S] [--threshold T] [--shift-scale F]\n"
                           "  [--keep-unsampled-surface] [--mask-per-sample] [--model-views-beside-alone]\n"
                           "  [--per-building true|false|auto] [--rule any|pooled] [--csv FILE] (stability rows)\n"
                           "  [--perturb shift|noise|resolution] (what the stability section changes)\n");
      return 2;
    }
  }
  const std::string data = PERCLOD_SHARED_DATA;
  const std::vector<Model> all = {
      {"demo", data + "/ingolstadt/bldg_4018215.obj", UpAxis::Z, PerBuilding::Off},
      {"han", data + "/han/han_ministry.obj", UpAxis::Y, PerBuilding::Off},
      {"sponza", data + "/sponza/sponza.obj", UpAxis::Y, PerBuilding::Off},
      {"sibenik", data + "/sibenik/sibenik.obj", UpAxis::Y, PerBuilding::Off},
      {"block", data + "/ingolstadt/ingolstadt_lod3_all53.obj", UpAxis::Z, PerBuilding::On},
      {"delft", data + "/cityjson/3dbag_5910_delft.city.json", UpAxis::Z, PerBuilding::On},
      {"facade", "", UpAxis::Z, PerBuilding::Off}};  // generated, --facade-triangles
  const std::vector<std::string> view_sets = split(views_arg, ';');
  for (const auto& key : split(models_arg, ',')) {
    auto it = std::find_if(all.begin(), all.end(), [&](const Model& m) { return m.key == key; });
    if (it == all.end()) {
      std::fprintf(stderr, "bench_labels: unknown model '%s' (demo, han, sponza, sibenik, block, delft, facade)\n",
                   key.c_str());
      return 2;
    }
    Scene scene = it->path.empty() ? generate_facade(facade_params_for_triangles(facade_triangles))
                                   : load_scene(it->path);
    std::printf("# %s: %s, %zu triangles\n", it->key.c_str(), it->path.empty() ? "generated" : it->path.c_str(),
                scene.triangle_count());
    if (section == "coverage" || section == "all")
      for (int spp : samples) coverage(*it, scene, distances, view_sets, spp);
    if (section == "stability" || section == "all")
      for (const auto& set : view_sets)
        for (int spp : samples) stability(*it, scene, distances, set, spp);
    if ((section == "cost" || section == "all") && it->key == "demo")
      for (double d : distances) cost("demo", scene, it->up, d, runs);
  }
  if (section == "cost" || section == "all") {
    Scene f = generate_facade(facade_params_for_triangles(facade_triangles));
    std::printf("# generated facade: %zu triangles\n", f.triangle_count());
    for (double d : distances) cost("facade", f, UpAxis::Z, d, std::max(1, runs / 2));
  }
  if (g_csv) std::fclose(g_csv);
  return 0;
}
