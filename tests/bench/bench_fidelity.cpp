// bench_fidelity: what a LOD looks like from views its labels never saw, for
// perclod's simplify modes beside meshoptimizer at the same triangle count.
//
// Per model and distance: labels from the default view set (kDefaultViews:
// facades, ring8el30, ring8el60, top; 4 samples per pixel, per building where the file
// holds several);
// the original is recorded from those labelling views and from 17 held-out
// views (every labelling azimuth of ring8 offset by 22.5 degrees, at 15 and
// 45 degrees up, and az0el75). Each LOD is rendered from all of them and
// judged with compare_lod_views: changed fraction (after vision simulation),
// SSIM over the covered region, silhouette mismatch; the table prints the
// worst view of each set, and the sampled Hausdorff distance to the original
// over its bounding-box diagonal (hausdorff.h).
//
// Rows: "original moved 1/4 px" (the judge's noise floor: the unsimplified
// model moved by a quarter of p(d), so every edge lands up to a quarter pixel
// away), fidelity at e_P = 0.5 px and several e_I, paper, bounded (k = 1),
// cluster (k = 1), and plain qem and OpenMesh's stock Decimater (quadric +
// aspect ratio 10, as bench_simplify) at each fidelity row's count;
// meshoptimizer (meshopt_simplify, meshopt_simplifySloppy when it stalls
// above 1.1x the count) at each fidelity row's count; and "meshopt for the
// same SSIM": meshoptimizer swept over target counts (error limit 1, i.e.
// none) and over error limits (1e-4 .. 1e-2 of the mesh extent, no count),
// with the rows at fidelity's counts, the lower envelope of all those
// points interpolated to the fewest triangles whose worst-view SSIM (over
// both sets) matches the fidelity row's, with the ratio fidelity / meshopt
// (< 1: perclod needs fewer).
//
// meshoptimizer welds corners of the same component and material only, so
// every output triangle keeps its colour and the renders compare like with
// like.
//
// Usage: bench_fidelity [--models demo,han,sibenik,sponza,block,facade] [--distances 56,132,427]
//                       [--e-imperceptible 1,2,4] [--e-perceptible 0.5] [--csv FILE]
//                       [--no-meshopt] [--keep-undisplayable [--e-undisplayable E] | --delete-undisplayable] [--dump DIR]
//                       [--facade-triangles N] [--e-area A] [--max-normal-change DEG]
//                       [--dump-view NAME] [--pairs DIR [--pairs-all]] [--set KEY=VALUE ...] [--only-fidelity]
//                       [--label-shift] [--no-tighten] [--no-search]
//   --no-tighten: fidelity rows at the asked bounds only. By default a
//     fidelity LOD over the run's limits is tightened as `perclod run` does
//     (tighten_to_limits), judged from what the run judges: the labelling
//     views and the `held_out` preset, 9 of the 17 held-out views here.
//   --set: a labelling setting for the sweeps of scripts/bench.py: levels (DWT),
//   csf_k, csf (fir|weights|kakadu), threshold (grey levels), ratio (label),
//   samples, keep_unsampled_surface (0|1), mask_per_sample (0|1), views, spins, resolution (a
//   factor: 1.5 = 1920x1536 at 1.5x the pixel density, same screen).
//   --only-fidelity: the fidelity rows only (and the floor search's).
//   --no-search: no "fidelity floor search" row: the LOD `fidelity_target: {}`
//     writes (kFidelitySearch from 16 px down to the first within the
//     perceptual floor in what the run judges, looser while the first is).
//   --label-shift: also fidelity (the first e_I) and paper LODs made from the
//     labels of the model moved by -1/4, 0 and +1/4 px with anchored views
//     (bench_labels' stability shift), each judged against the unmoved model:
//     what label flips change in the LOD (paper LODs from labels combined by
//     the paper's rule, combine_views: any).
//   --pairs DIR: writes DIR/<model>_<d>m_original.png and one
//   <model>_<d>m_<method>.png per row, all from the held-out view az22.5el45
//   and cropped to the same rectangle, for an independent image metric
//   (scripts/bench.py runs butteraugli on them). --pairs-all: also the
//   rows "original moved 1/4 px" (<tag>_moved_quarter_px), "meshopt sweep F"
//   (<tag>_meshopt_sweepF) and "meshopt error E" (<tag>_meshopt_errorE).
//
// Every row also has the judge's perceptual figure (judge.h): visible_ratio,
// each view's visible difference over its quarter-pixel floor
// (measure_floors on the original's records), worst and median over all
// judged views, and kPairView's (with that view's changed fraction and SSIM),
// columns visible_worst, visible_median, pair_visible, pair_changed, pair_ssim;
// pair_image names the row's --pairs file, visible_worst_view the worst
// view and its floor ("<view>/<floor>").
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#ifdef PERCLOD_HAVE_MESHOPTIMIZER
#include <meshoptimizer.h>
#endif

#include "bench_common.h"
#include "decimater.h"
#include "hausdorff.h"
#include "peers.h"
#include "perclod/facade.h"
#include "perclod/image_io.h"
#include "perclod/load.h"
#include "perclod/fidelity_search.h"
#include "perclod/judge.h"
#include "perclod/label.h"
#include "perclod/undisplayable.h"
#include "perclod/simplify.h"

using namespace perclod;

namespace {

using bench::split;

std::vector<double> numbers(const std::string& s) {
  std::vector<double> v;
  for (const auto& x : split(s, ',')) v.push_back(std::atof(x.c_str()));
  return v;
}

using bench::held_out_views;

std::string g_dump;   // --dump DIR: original | LOD | difference of each LOD's worst held-out view
std::string g_dump_view;  // --dump-view NAME: dump this judged view instead of the worst held-out one
const std::vector<Label>* g_dump_labels = nullptr;  // the labels of the distance being judged, for --dump
std::string g_pairs;  // --pairs DIR: original and LOD from kPairView, for butteraugli
bool g_pairs_all = false;  // --pairs-all: also the moved original's and every meshoptimizer sweep LOD's pair
const bench::HausdorffReference* g_hausdorff = nullptr;  // from the model being judged, in run_model
std::vector<std::pair<std::string, std::string>> g_settings;  // --set KEY=VALUE, in order
bool g_only_fidelity = false;
bool g_label_shift = false;  // --label-shift: LODs from labels of the model moved by +-1/4 px
bool g_tighten = true;       // --no-tighten: no tighten_to_limits
bool g_search = true;        // --no-search: no "fidelity floor search" row
double g_label_seconds = 0;  // labelling time of the current model and distance

// Applies --set KEY=VALUE to a labelling job; throws on an unknown key.
void apply_settings(LabelJob& job) {
  for (const auto& [key, value] : g_settings) {
    const double v = std::atof(value.c_str());
    if (key == "resolution") {  // the display's pixels per degree follow
      job.display.width = int(std::lround(job.display.width * v));
      job.display.height = int(std::lround(job.display.height * v));
      job.display.dpi *= v;
      job.perception.ppd = perception_settings_for(job.display).ppd;
    } else if (key == "levels") job.perception.levels = int(v);
    else if (key == "csf_k") job.perception.k = v;
    else if (key == "threshold") job.perception.threshold = v;
    else if (key == "spins") job.perception.spins = int(v);
    else if (key == "ratio") job.ratio = v;
    else if (key == "samples") job.samples = int(v);
    else if (key == "keep_unsampled_surface") job.keep_unsampled_surface = v != 0;
    else if (key == "mask_per_sample") job.mask_per_sample = v != 0;
    else if (key == "combine_views") job.combine = parse_combine_views(value);
    else if (key == "views") job.views = parse_views(value, job.up);
    else if (key == "csf") {
      if (value == "fir") job.perception.csf = PerceptionSettings::CsfMode::Fir;
      else if (value == "weights") job.perception.csf = PerceptionSettings::CsfMode::Weights;
      else if (value == "kakadu") job.perception.csf = PerceptionSettings::CsfMode::Kakadu;
      else throw std::invalid_argument("--set csf=" + value + ": fir, weights or kakadu");
    } else {
      throw std::invalid_argument("--set " + key + ": unknown setting");
    }
  }
}
constexpr const char* kPairView = "az22.5el45";

// Worst figures of one set of views.
struct Worst {
  double changed = 0, ssim = 1, silhouette = 0;
};

struct Judged {
  size_t triangles = 0;
  double seconds = 0;  // simplification
  Worst labelling, held_out;
  double hausdorff = 0;  // sampled, symmetric, / the original's bounding-box diagonal
  // The judge's visible_ratio (the visible difference over the view's
  // quarter-pixel floor, measure_floors) over all judged views: the worst
  // and the median; and kPairView's figures, the view the --pairs images
  // show (NaN where that view is tiled), for checking the judge against an
  // independent metric such as butteraugli on the same images.
  double visible_worst = 0, visible_median = 0;
  double visible_local_worst = 0;  // the worst view's visible_local_ratio (the worst 16 px square's)
  std::string visible_worst_view;  // the view of visible_worst, "<view>/<floor>" (which floor it was over)
  double pair_visible = NAN, pair_changed = NAN, pair_ssim = NAN;
  std::string pair_image;  // the --pairs file of this LOD ("" when none was written)
  double ssim_all() const { return std::min(labelling.ssim, held_out.ssim); }
};

// Writes DIR/<name>.png: the original, the LOD and their difference (x4)
// side by side, from `cam`, cropped to what either draws.
void dump(Renderer& renderer, const Scene& original, const Scene& lod, const Camera& cam, const std::string& name) {
  renderer.set_scene(original);
  RenderOutput a = renderer.render(cam);
  renderer.set_scene(lod);
  RenderOutput b = renderer.render(cam);
  const int w = a.width, h = a.height;
  int x0 = w, x1 = -1, y0 = h, y1 = -1;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      if (a.ids[size_t(y) * w + x] || b.ids[size_t(y) * w + x])
        x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
  if (x1 < 0) return;
  const int cw = x1 - x0 + 1, ch = y1 - y0 + 1;
  std::vector<uint8_t> out(size_t(3) * cw * 3 * ch);
  for (int y = 0; y < ch; ++y)
    for (int x = 0; x < cw; ++x)
      for (int c = 0; c < 3; ++c) {
        const size_t src = (size_t(y + y0) * w + (x + x0)) * 3 + c;
        const int diff = std::min(255, 4 * std::abs(int(a.rgb[src]) - int(b.rgb[src])));
        uint8_t* row = &out[size_t(y) * 3 * cw * 3];
        row[3 * x + c] = a.rgb[src];
        row[3 * (cw + x) + c] = b.rgb[src];
        row[3 * (2 * cw + x) + c] = uint8_t(diff);
      }
  write_png(g_dump + "/" + name + ".png", 3 * cw, ch, 3, out.data());
  if (!g_dump_labels) return;
  // Which label the original's triangle carries where a pixel changed by
  // more than 32 grey levels (summed over RGB).
  size_t by_label[4] = {0, 0, 0, 0};  // P, I, U, background in the original
  size_t changed = 0;
  // <name>_labels.png: the original in grey, each such pixel in the marking
  // colour of the original's label there (green P, red I, blue U; white
  // where the original shows background).
  std::vector<uint8_t> marked(size_t(3) * cw * ch);
  for (int y = 0; y < ch; ++y)
    for (int x = 0; x < cw; ++x) {
      const size_t i = size_t(y + y0) * w + (x + x0);
      uint8_t* m = &marked[(size_t(y) * cw + x) * 3];
      int sum = 0;
      for (int c = 0; c < 3; ++c) sum += std::abs(int(a.rgb[3 * i + c]) - int(b.rgb[3 * i + c]));
      const uint8_t grey = uint8_t((a.rgb[3 * i] + a.rgb[3 * i + 1] + a.rgb[3 * i + 2]) / 6);
      m[0] = m[1] = m[2] = grey;
      if (sum <= 32) continue;
      ++changed;
      const int l = a.ids[i] ? int((*g_dump_labels)[a.ids[i] - 1]) : 3;
      by_label[l] += 1;
      static const uint8_t colour[4][3] = {{0, 255, 0}, {255, 0, 0}, {0, 96, 255}, {255, 255, 255}};
      std::memcpy(m, colour[l], 3);
    }
  write_png(g_dump + "/" + name + "_labels.png", cw, ch, 3, marked.data());
  std::printf("  dump %s: %zu pixels changed by > 32 levels; the original shows there P %zu, I %zu, U %zu, "
              "background %zu\n",
              name.c_str(), changed, by_label[0], by_label[1], by_label[2], by_label[3]);
}

// Crop rectangle of the original's render from kPairView (what it draws,
// plus 8 px), fixed per model and distance so every LOD is cut the same.
struct Crop {
  int x0 = 0, y0 = 0, w = 0, h = 0;
};

// Writes `g_pairs/<name>.png`: the render `r` cut to `crop`.
void write_cropped(const RenderOutput& r, const Crop& crop, const std::string& name) {
  std::vector<uint8_t> out(size_t(3) * crop.w * crop.h);
  for (int y = 0; y < crop.h; ++y)
    std::memcpy(&out[size_t(y) * 3 * crop.w], &r.rgb[(size_t(y + crop.y0) * r.width + crop.x0) * 3],
                size_t(3) * crop.w);
  write_png(g_pairs + "/" + name + ".png", crop.w, crop.h, 3, out.data());
}

// Writes `g_pairs/<name>.png`: `scene` rendered from `cam`, cut to `crop`.
void write_pair(Renderer& renderer, const Scene& scene, const Camera& cam, const Crop& crop, const std::string& name) {
  renderer.set_scene(scene);
  write_cropped(renderer.render(cam), crop, name);
}

// The pair view of the model and distance being judged (camera null: none).
struct PairView {
  const Camera* camera = nullptr;
  Crop crop;
} g_pair;

// What the original's render `r` draws, plus 8 px.
Crop pair_crop(const RenderOutput& r) {
  int x0 = r.width, x1 = -1, y0 = r.height, y1 = -1;
  for (int y = 0; y < r.height; ++y)
    for (int x = 0; x < r.width; ++x)
      if (r.ids[size_t(y) * r.width + x])
        x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
  if (x1 < 0) return Crop{0, 0, r.width, r.height};
  const int m = 8;
  x0 = std::max(0, x0 - m), y0 = std::max(0, y0 - m);
  x1 = std::min(r.width - 1, x1 + m), y1 = std::min(r.height - 1, y1 + m);
  return Crop{x0, y0, x1 - x0 + 1, y1 - y0 + 1};
}

// `views_out` (may be null) receives compare_lod_views' figures per view.
Judged judge(Renderer& renderer, const Scene& lod, const std::vector<ViewRecord>& records, const LabelJob& job,
             const Scene* original = nullptr, const std::string& dump_name = "",
             std::vector<ViewFigures>* views_out = nullptr) {
  Judged j;
  j.triangles = lod.triangle_count();
  if (g_hausdorff) j.hausdorff = g_hausdorff->relative(lod);
  const std::vector<ViewFigures> views = compare_lod_views(renderer, lod, records, judge_settings_of(job));
  if (views_out) *views_out = views;
  if (g_pair.camera && !dump_name.empty()) {
    write_pair(renderer, lod, *g_pair.camera, g_pair.crop, dump_name);
    j.pair_image = dump_name + ".png";
  }
  if (!g_dump.empty() && original) {
    size_t worst = 0;
    double worst_changed = -1;
    for (size_t i = 0; i < views.size(); ++i)
      if (views[i].set == "held_out" && views[i].changed_fraction > worst_changed)
        worst = i, worst_changed = views[i].changed_fraction;
    for (size_t i = 0; i < views.size(); ++i)
      if (records[i].view == g_dump_view) worst = i;
    dump(renderer, *original, lod, records[worst].camera, dump_name + "_" + records[worst].view);
  }
  std::vector<double> ratios;
  for (const auto& v : views) {
    Worst& w = v.set == "labelling" ? j.labelling : j.held_out;
    w.changed = std::max(w.changed, v.changed_fraction);
    w.ssim = std::min(w.ssim, v.ssim_covered);
    w.silhouette = std::max(w.silhouette, v.silhouette_mismatch);
    ratios.push_back(v.visible_ratio);
    j.visible_local_worst = std::max(j.visible_local_worst, v.visible_local_ratio);
    if (v.visible_ratio >= j.visible_worst) {
      j.visible_worst = v.visible_ratio;
      std::ostringstream ss;
      ss << v.view << "/" << v.visible_floor;
      j.visible_worst_view = ss.str();
    }
    if (v.view == kPairView && v.set == "held_out")
      j.pair_visible = v.visible_ratio, j.pair_changed = v.changed_fraction, j.pair_ssim = v.ssim_covered;
  }
  if (!ratios.empty()) {
    std::sort(ratios.begin(), ratios.end());
    const size_t n = ratios.size();
    j.visible_median = n % 2 ? ratios[n / 2] : 0.5 * (ratios[n / 2 - 1] + ratios[n / 2]);
  }
  return j;
}

#ifdef PERCLOD_HAVE_MESHOPTIMIZER
// meshoptimizer on the scene, corners welded per (component, material), so
// each output triangle knows its component and material.
struct MeshoptInput {
  std::vector<float> positions;
  std::vector<uint32_t> key;  // per welded vertex: component and material of its corners
  std::vector<unsigned> indices;
};

MeshoptInput meshopt_input(const Scene& s) {
  const size_t nc = 3 * s.triangle_count();
  std::vector<float> pos(3 * nc);
  std::vector<uint32_t> key(nc);
  const uint32_t nm = uint32_t(std::max<size_t>(1, s.materials.size()));
  for (size_t c = 0; c < nc; ++c) {
    const size_t t = c / 3;
    std::memcpy(&pos[3 * c], &s.positions[3 * size_t(s.indices[c])], 3 * sizeof(float));
    key[c] = uint32_t(s.component_of(t)) * nm + (s.material.empty() ? 0 : s.material[t]);
  }
  std::vector<unsigned> corners(nc);
  for (size_t c = 0; c < nc; ++c) corners[c] = unsigned(c);
  meshopt_Stream streams[2] = {{pos.data(), 3 * sizeof(float), 3 * sizeof(float)},
                               {key.data(), sizeof(uint32_t), sizeof(uint32_t)}};
  std::vector<unsigned> remap(nc);
  const size_t nv = meshopt_generateVertexRemapMulti(remap.data(), nullptr, nc, nc, streams, 2);
  MeshoptInput in;
  in.indices.resize(nc);
  meshopt_remapIndexBuffer(in.indices.data(), static_cast<const unsigned*>(nullptr), nc, remap.data());
  in.positions.resize(3 * nv);
  meshopt_remapVertexBuffer(in.positions.data(), pos.data(), nc, 3 * sizeof(float), remap.data());
  in.key.resize(nv);
  meshopt_remapVertexBuffer(in.key.data(), key.data(), nc, sizeof(uint32_t), remap.data());
  return in;
}

// A LOD of `s` made of triangles over the welded vertices of `in`: each
// triangle takes the component and material its corners were welded by.
Scene lod_from_welded(const Scene& s, const MeshoptInput& in, const std::vector<unsigned>& tris) {
  Scene lod;
  lod.offset = s.offset;
  lod.component_names = s.component_names;
  lod.materials = s.materials;
  lod.positions = in.positions;
  lod.indices.assign(tris.begin(), tris.end());
  const uint32_t nm = uint32_t(std::max<size_t>(1, s.materials.size()));
  for (size_t t = 0; t < tris.size() / 3; ++t) {
    const uint32_t k = in.key[tris[3 * t]];
    if (!s.component.empty()) lod.component.push_back(k / nm);
    if (!s.material.empty()) lod.material.push_back(k % nm);
  }
  return lod;
}

// target_error: meshoptimizer's error limit relative to the mesh extent
// (1 = none: simplify to the count).
Scene meshopt_lod(const Scene& s, const MeshoptInput& in, size_t target, bool sloppy, double& seconds,
                  float target_error = 1.0f) {
  auto t0 = std::chrono::steady_clock::now();
  std::vector<unsigned> out(in.indices.size());
  const size_t nv = in.positions.size() / 3;
  size_t n = sloppy ? meshopt_simplifySloppy(out.data(), in.indices.data(), in.indices.size(), in.positions.data(),
                                             nv, 3 * sizeof(float), 3 * target, target_error, nullptr)
                    : meshopt_simplify(out.data(), in.indices.data(), in.indices.size(), in.positions.data(), nv,
                                       3 * sizeof(float), 3 * target, target_error, 0, nullptr);
  seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  out.resize(n);
  return lod_from_welded(s, in, out);
}

// OpenMesh's stock Decimater (ModQuadric, no error limit, + ModAspectRatio
// 10) to `target` faces, on meshoptimizer's welded input so every face keeps
// its component and material. Faces OpenMesh refuses (non-manifold) are
// added with their own vertices, as its reader does.
using bench::DMesh;

Scene decimater_lod(const Scene& s, const MeshoptInput& in, size_t target, double& seconds) {
  auto t0 = std::chrono::steady_clock::now();
  omerr().disable();
  DMesh mesh;
  std::vector<uint32_t> source;  // DMesh vertex -> welded vertex of `in`
  const size_t nv = in.positions.size() / 3;
  for (size_t i = 0; i < nv; ++i) {
    mesh.add_vertex(DMesh::Point(in.positions[3 * i], in.positions[3 * i + 1], in.positions[3 * i + 2]));
    source.push_back(uint32_t(i));
  }
  for (size_t t = 0; t < in.indices.size() / 3; ++t) {
    const unsigned v[3] = {in.indices[3 * t], in.indices[3 * t + 1], in.indices[3 * t + 2]};
    if (v[0] == v[1] || v[1] == v[2] || v[0] == v[2]) continue;  // degenerate: OpenMesh cannot hold it
    if (!mesh.add_face(DMesh::VertexHandle(int(v[0])), DMesh::VertexHandle(int(v[1])), DMesh::VertexHandle(int(v[2])))
             .is_valid()) {
      DMesh::VertexHandle d[3];
      for (int k = 0; k < 3; ++k) {
        d[k] = mesh.add_vertex(mesh.point(DMesh::VertexHandle(int(v[k]))));
        source.push_back(v[k]);
      }
      mesh.add_face(d[0], d[1], d[2]);
    }
  }
  mesh.update_face_normals();
  bench::decimate_stock(mesh, target);
  seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::vector<unsigned> tris;
  for (auto f : mesh.faces()) {
    if (mesh.status(f).deleted()) continue;
    for (auto v : mesh.fv_range(f)) tris.push_back(source[size_t(v.idx())]);
  }
  return lod_from_welded(s, in, tris);
}
#endif

// judge_views over what `perclod run` judges a LOD from by default: the
// labelling views and the `held_out` preset (tiles named <view>_t<i>), the
// run's default limits (or `limits`). What tighten_to_limits decides from.
Judgement run_judged(const std::vector<ViewFigures>& views, const FidelityLimits& limits = FidelityLimits{}) {
  const std::vector<std::string> preset = parse_views(kDefaultJudgeViews, UpAxis::Z);  // names only
  std::vector<ViewFigures> judged;
  for (const ViewFigures& v : views) {
    std::string name = v.view;
    const size_t tile = name.rfind("_t");
    if (tile != std::string::npos) name.resize(tile);
    if (v.set == "labelling" || std::find(preset.begin(), preset.end(), name) != preset.end()) judged.push_back(v);
  }
  return judge_views(judged, limits);
}

struct Model {
  std::string key;
  Scene scene;
  UpAxis up;
  PerBuilding per_building;
};

FILE* g_csv = nullptr;
bool g_meshopt = true;        // --no-meshopt: perclod rows only
bool g_keep_undisplayable = false;
bool g_delete_undisplayable = false;  // --delete-undisplayable: always, not keep_undisplayable: auto
double g_exposure = 0;                // undisplayable_exposure of the distance's labels
double g_area = kDefaultBoundAreaPx2;  // --e-area: fidelity's area budget, px^2 (inf = none)
  // --keep-undisplayable: fidelity collapses them instead
double g_e_u = INFINITY;  // --e-undisplayable: with --keep-undisplayable, the bound of their collapses, px
double g_max_normal = SimplifyOptions().max_normal_change_deg;  // --max-normal-change: fidelity's limit, degrees

void row(const Model& m, double d, const std::string& method, const Judged& j, const std::string& note = "") {
  std::printf("%-6s %4.0f  %-26s %8zu  %7.3f  | %6.2f%% %6.4f %6.2f%% | %6.2f%% %6.4f %6.2f%% | %7.4f%% | %6.3f "
              "%6.3f %6.3f  %s\n",
              m.key.c_str(), d, method.c_str(), j.triangles, j.seconds, 100 * j.labelling.changed, j.labelling.ssim,
              100 * j.labelling.silhouette, 100 * j.held_out.changed, j.held_out.ssim, 100 * j.held_out.silhouette,
              100 * j.hausdorff, j.visible_worst, j.visible_median, j.pair_visible, note.c_str());
  std::fflush(stdout);
  if (g_csv) {
    std::fprintf(g_csv, "%s,%g,%s,%zu,%.4f,%.5f,%.5f,%.5f,%.5f,%.5f,%.5f,%.6f,%.3f,%.4f,%.4f,%.4f,%.5f,%.5f,%s,%s,%s,%.4f\n",
                 m.key.c_str(), d, method.c_str(), j.triangles, j.seconds, j.labelling.changed, j.labelling.ssim,
                 j.labelling.silhouette, j.held_out.changed, j.held_out.ssim, j.held_out.silhouette, j.hausdorff,
                 g_label_seconds, j.visible_worst, j.visible_median, j.pair_visible, j.pair_changed, j.pair_ssim,
                 j.pair_image.c_str(), j.visible_worst_view.c_str(), note.c_str(), j.visible_local_worst);
    std::fflush(g_csv);
  }
}

// Fidelity mode at e_P / e_I with the command line's other fidelity settings.
SimplifyOptions fidelity_options(double e_p, double e_i) {
  SimplifyOptions so;
  so.mode = SimplifyMode::Fidelity;
  so.bound_perceptible_px = e_p;
  so.bound_imperceptible_px = e_i;
  so.delete_undisplayable = !g_keep_undisplayable;
  so.bound_area_px2 = g_area;
  so.max_normal_change_deg = g_max_normal;
  so.bound_undisplayable_px = g_e_u;
  // keep_undisplayable: auto, as `perclod run` does, unless told otherwise.
  return g_delete_undisplayable ? so : choose_undisplayable(so, g_exposure);
}

#ifdef PERCLOD_HAVE_MESHOPTIMIZER
// A peer's sweep: each LOD's count with its worst-view SSIM and its worst
// visible ratio (the judge's figure over the quarter-pixel floor).
struct Sweep {
  std::vector<bench::SweepPoint> ssim, visible, local;
  void add(const Judged& j) {
    ssim.push_back({j.triangles, j.ssim_all()});
    visible.push_back({j.triangles, j.visible_worst});
    local.push_back({j.triangles, j.visible_local_worst});
  }
};

// The meshoptimizer peers of one model and distance, judged like the
// fidelity rows (records, job) and set beside them.
struct PeerRun {
  Renderer& renderer;
  const Model& m;
  double d;
  const std::string& tag;
  const std::vector<ViewRecord>& records;
  const LabelJob& job;
  const std::vector<Judged>& fidelity;
  const std::vector<double>& e_i;
  const Judged* search = nullptr;        // the floor search's LOD (null: none)
  const Judged* search_local = nullptr;  // the same held to the local floor too

  // meshopt_simplify of `scene` to `target` (and sloppy too where simplify
  // stalls above 1.1x the target), rows named `name`, points into `sweep`.
  void meshopt_at(const Scene& scene, const MeshoptInput& in, size_t target, const std::string& name, Sweep& sweep,
                  const std::string& pair_name) {
    target = std::clamp<size_t>(target, 1, scene.triangle_count());  // a fidelity count above what a cull kept
    for (bool sloppy : {false, true}) {
      double sec = 0;
      Scene lod = meshopt_lod(scene, in, target, sloppy, sec);
      const bool stalled = lod.triangle_count() > target + target / 10 + 1;
      Judged j = judge(renderer, lod, records, job, nullptr, pair_name.empty() ? "" : pair_name + (sloppy ? "_sloppy" : ""));
      j.seconds = sec;
      row(m, d, name, j, sloppy ? "sloppy" : (stalled ? "stalled" : ""));
      sweep.add(j);
      if (!stalled) break;  // sloppy only where simplify stalls
    }
  }

  // meshoptimizer on `scene` (the model, or what the visibility cull kept)
  // at each fidelity row's count, swept over fractions of `scene`'s count,
  // and (with_errors) over error limits: every LOD a point of the sweep
  // (the ones at fidelity's counts too: leaving them out overstated the
  // count meshoptimizer needs where they beat the line between sweep points).
  Sweep meshopt_sweep(const Scene& scene, const std::string& method, bool with_errors) {
    const MeshoptInput in = meshopt_input(scene);
    const std::string file = method == "meshopt" ? "_meshopt" : "_culled_meshopt";
    Sweep sweep;
    for (size_t i = 0; i < fidelity.size(); ++i) {
      std::ostringstream name, pair_name;
      name << method << " @e_I=" << e_i[i];
      pair_name << tag << file << "_eI" << e_i[i];
      meshopt_at(scene, in, fidelity[i].triangles, name.str(), sweep, pair_name.str());
    }
    const size_t nt = scene.triangle_count();
    for (double f : {0.02, 0.05, 0.1, 0.2, 0.35, 0.5, 0.7, 0.85, 1.0}) {
      if (f == 1.0 && with_errors) continue;  // the model itself: the sweep's end already
      std::ostringstream name, pair_name;
      name << method << " sweep " << f;
      pair_name << tag << file << "_sweep" << f;
      meshopt_at(scene, in, size_t(f * double(nt)), name.str(), sweep, g_pairs_all ? pair_name.str() : "");
    }
    if (!with_errors) return sweep;
    // By error limit (no count): meshoptimizer's own notion of quality.
    for (float err : {1e-4f, 3e-4f, 1e-3f, 3e-3f, 1e-2f}) {
      double sec = 0;
      Scene lod = meshopt_lod(scene, in, 1, false, sec, err);
      std::ostringstream name, pair_name;
      pair_name << tag << file << "_error" << err;
      Judged j = judge(renderer, lod, records, job, nullptr, g_pairs_all ? pair_name.str() : "");
      j.seconds = sec;
      name << method << " error " << err;
      row(m, d, name.str(), j);
      sweep.add(j);
    }
    return sweep;
  }

  // For each fidelity row, the fewest triangles the peer's sweep needs for
  // the same worst-view SSIM and for the same worst visible ratio; and for
  // each of them the fewest at the floor (worst visible ratio 1), fidelity's
  // read from its rows at the asked e_I and the floor search's LOD (also set
  // beside the peer at its own visible ratio: "equal_visible <peer> search"). CSV rows "same_ssim e_I=E" (plain
  // meshoptimizer, the name scripts/bench.py reads) or "equal_ssim <peer>
  // e_I=E", "equal_visible <peer> e_I=E" and "equal_visible <peer> floor",
  // the note "<peer> N ratio R".
  void equal_fidelity(const Sweep& peer, const std::string& name, size_t full) {
    auto line = [&](const std::string& method, size_t ours, double goal, double need) {
      const double ratio = need > 0 ? double(ours) / need : 0.0;
      std::printf("%-6s %4.0f  %s: perclod %zu triangles at %.4f, %s about %.0f; ratio %.2f\n", m.key.c_str(), d,
                  method.c_str(), ours, goal, name.c_str(), need, ratio);
      if (g_csv)
        std::fprintf(g_csv, "%s,%g,%s,%zu,,,%.5f,,,,,,,,,,,,,,%s %.0f ratio %.3f\n", m.key.c_str(), d, method.c_str(),
                     ours, goal, name.c_str(), need, ratio);
    };
    Sweep ours;
    for (size_t i = 0; i < fidelity.size(); ++i) {
      ours.add(fidelity[i]);
      std::ostringstream e;
      e << "e_I=" << e_i[i];
      const double ssim = fidelity[i].ssim_all(), vis = fidelity[i].visible_worst;
      line((name == "meshopt" ? "same_ssim " : "equal_ssim " + name + " ") + e.str(), fidelity[i].triangles, ssim,
           bench::fewest_reaching(peer.ssim, ssim, true, full));
      line("equal_visible " + name + " " + e.str(), fidelity[i].triangles, vis,
           bench::fewest_reaching(peer.visible, vis, false, full));
    }
    if (search) {
      ours.add(*search);
      line("equal_visible " + name + " search", search->triangles, search->visible_worst,
           bench::fewest_reaching(peer.visible, search->visible_worst, false, full));
    }
    // The local figure (the worst 16 px square's): the default LOD, and the
    // search held to both floors, beside the peer at the same local figure.
    if (!fidelity.empty())
      line("equal_local " + name + " e_I=" + std::to_string(e_i[0]).substr(0, 4), fidelity[0].triangles,
           fidelity[0].visible_local_worst, bench::fewest_reaching(peer.local, fidelity[0].visible_local_worst, false, full));
    if (search_local)
      line("equal_local " + name + " search_local", search_local->triangles, search_local->visible_local_worst,
           bench::fewest_reaching(peer.local, search_local->visible_local_worst, false, full));
    const double at_floor = bench::fewest_reaching(ours.visible, 1.0, false, full);
    line("equal_visible " + name + " floor", size_t(std::lround(at_floor)), 1.0,
         bench::fewest_reaching(peer.visible, 1.0, false, full));
  }
};
#endif

// The LOD `perclod run` writes with `fidelity_target: {}` (the default
// limits: within the quarter-pixel floor): kFidelitySearch's steps from the
// loosest down to the first within the limits in what the run judges
// (run_judged), then, when the loosest met them, looser steps while they do
// and remove triangles: search_fidelity_target, as `run` does. `make(bounds, suffix, views)`
// simplifies and judges one try. `note` receives the bounds written.
template <class Make>
Judged floor_search(const SimplifyOptions& asked, const FidelityLimits& limits, Make&& make, std::string& note) {
  std::vector<ViewFigures> views;
  std::vector<Judged> tried;  // each try's LOD's figures, in order
  const TargetSearch s = search_fidelity_target([&](const FidelitySearchStep& step, bool) {
    tried.push_back(make(fidelity_bounds(asked, step), "_search", &views));
    return std::make_pair(run_judged(views, limits).met(), tried.back().triangles);
  });
  const SimplifyOptions b = fidelity_bounds(asked, s.step);
  std::ostringstream ss;  // no comma: the CSV does not quote
  ss << (s.met ? "" : "none within; ") << "e_I=" << b.bound_imperceptible_px << " e_P=" << b.bound_perceptible_px
     << (b.delete_undisplayable ? "" : " undisplayable kept") << "; " << s.tries << " tries";
  note = ss.str();
  return tried.at(s.kept);  // deterministic: the kept try's LOD need not be made again
}

void run_model(const Model& m, const std::vector<double>& distances, const std::vector<double>& e_i, double e_p) {
  const Scene& scene = m.scene;
  const bench::HausdorffReference hausdorff(scene);
  g_hausdorff = &hausdorff;
  OctreeTracer tracer(scene);
  Renderer renderer;
  for (double d : distances) {
    LabelJob job;
    job.up = m.up;
    job.display = DisplayProfile{};
    job.perception = perception_settings_for(job.display);
    job.views = parse_views(kDefaultViews, m.up);
    job.samples = kDefaultSamples;
    job.combine = parse_combine_views(kDefaultCombineViews);
    job.per_building = m.per_building;
    job.distance = d;
    job.write_perception_images = false;
    apply_settings(job);
    const auto label_start = std::chrono::steady_clock::now();
    LabelResult lr = label_scene(renderer, scene, tracer, job);
    g_label_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - label_start).count();
    std::vector<ViewRecord> records = std::move(lr.views);
    for (auto& r : record_views(renderer, scene, held_out_views(), framing_of(job), "held_out")) records.push_back(std::move(r));
    // Each view's perceptual floor, so every row has the judge's visible_ratio.
    measure_floors(renderer, scene, records, judge_settings_of(job));
    const double p = display_pixel_footprint(job.display, d);
    g_pair = PairView{};
    std::ostringstream tag_ss;
    tag_ss << m.key << "_" << d << "m";
    const std::string tag = tag_ss.str();
    if (!g_pairs.empty())
      for (const auto& r : records)
        if (r.view == kPairView) {
          renderer.set_scene(scene);
          const RenderOutput original = renderer.render(r.camera);
          g_pair = PairView{&r.camera, pair_crop(original)};
          write_cropped(original, g_pair.crop, tag + "_original");
        }
    LabelCounts lc = count_labels(lr.labels);
    g_dump_labels = &lr.labels;
    g_exposure = undisplayable_exposure(scene, tracer, lr.labels, framing_of(job));
    std::printf("\n%s at %.0f m: %zu triangles (P %zu, I %zu, U %zu), p(d) = %.4f m, %zu labelling + %zu held-out "
                "views; undisplayable exposure %.3f%%: fidelity %s them\n",
                m.key.c_str(), d, scene.triangle_count(), lc.perceptible, lc.imperceptible, lc.undisplayable, p,
                records.size() - held_out_views().size(), held_out_views().size(), 100 * g_exposure,
                fidelity_options(0.5, 0.5).delete_undisplayable ? "deletes" : "keeps");
    std::printf("%-6s %4s  %-26s %8s  %7s  | %-23s | %-23s | %-9s | %s\n", "model", "d", "method", "tris", "simp s",
                "labelling: chg  SSIM  sil", "held-out: chg  SSIM  sil", "Hausdorff", "visible ratio: worst median pair");

    auto simplified = [&](SimplifyOptions so, const std::string& suffix = "", std::vector<ViewFigures>* views = nullptr) {
      so.pixel_footprint = p;
      SimplifyStats st;
      Scene lod = simplify(scene, lr.labels, so, &st);
      std::ostringstream name;
      name << tag << "_" << simplify_mode_name(so.mode);
      if (so.mode == SimplifyMode::Fidelity) name << "_eI" << so.bound_imperceptible_px;
      if (so.mode == SimplifyMode::Fidelity && !so.delete_undisplayable) name << "_kept";
      name << suffix;
      Judged j = judge(renderer, lod, records, job, &scene, name.str(), views);
      j.seconds = st.seconds;
      return j;
    };
    std::vector<Judged> fidelity;
    for (double ei : e_i) {
      // As `perclod run` makes it: the asked bounds, then tighten_to_limits.
      const SimplifyOptions asked = fidelity_options(e_p, ei);
      std::vector<ViewFigures> views;
      Judged j = simplified(asked, "", &views);
      std::string note;
      const Judged at_asked = j;
      std::ostringstream suffix;  // --pairs and --dump files of each try, apart from the asked LOD's
      suffix << "_tightened_from" << ei;
      std::vector<std::pair<Judged, std::string>> tries;  // each try's LOD and note, in order
      auto try_step = [&](const SimplifyOptions& tighter, bool midway) {
        j = simplified(tighter, suffix.str(), &views);
        std::ostringstream ss;  // no comma: the CSV does not quote
        ss << "tightened to e=" << tighter.bound_imperceptible_px << " px" << (midway ? " (midway)" : "")
           << "; undisplayable ";
        if (tighter.delete_undisplayable) ss << "deleted";
        else ss << "kept within " << tighter.bound_undisplayable_px << " px";
        ss << "; asked: " << at_asked.triangles << " tris " << 100 * at_asked.held_out.changed << "% "
           << at_asked.held_out.ssim;
        tries.emplace_back(j, ss.str());
        return std::pair<bool, size_t>(run_judged(views).met(), j.triangles);
      };
      // As `run` keeps it: the try within (or its midway), else the tightest tried.
      if (g_tighten) {
        const TighteningResult t = tighten_to_limits(asked, run_judged(views), FidelityLimits{}, try_step);
        if (t.tries) std::tie(j, note) = tries[t.kept_try];
        if (t.outcome == Tightening::NoneWithin) note += "; over the limits at every step: the tightest kept";
      }
      fidelity.push_back(j);
      std::ostringstream name;
      name << "fidelity e_I=" << ei;
      row(m, d, name.str(), fidelity.back(), note);
    }
    // What `fidelity_target: {}` writes: the search for the perceptual floor.
    // And with the local figure held to its floor too: `fidelity_target: {max_visible_local: 1}`.
    Judged search, search_local;
    if (g_search) {
      std::string note;
      const SimplifyOptions asked = fidelity_options(e_p, kDefaultBoundImperceptiblePx);
      search = floor_search(asked, FidelityLimits{}, simplified, note);
      row(m, d, "fidelity floor search", search, note);
      FidelityLimits both;
      both.max_visible_local = 1;
      search_local = floor_search(asked, both, simplified, note);
      row(m, d, "fidelity floor search local", search_local, note);
    }
    if (g_label_shift) {
      // What label flips do to the LOD: the labelling of bench_labels'
      // stability section (the geometry moved by -1/4, 0 and +1/4 px along
      // each axis, two zero-area anchors holding the views still), each
      // labelling applied to the unmoved model, simplified and judged like
      // any LOD. Rows "<mode> (labels <shift>)". The fidelity LOD takes the
      // labels of `job` (views pooled, the default); the paper LOD the
      // paper's rule over the same views (combine_views: any), as
      // configs/paper.yaml has it.
      const double s = 0.25 * p;
      LabelJob anchored = job;
      anchored.distance = d - s;  // the anchors widen the box by s
      LabelJob anchored_any = anchored;
      anchored_any.combine = CombineViews::AnyView;
      for (double sign : {0.0, 1.0, -1.0}) {
        const Scene moved = bench::shifted(scene, sign * s, s);
        OctreeTracer moved_tracer(moved);
        const char* shift = sign == 0 ? "anchored" : sign > 0 ? "+1/4 px" : "-1/4 px";
        for (SimplifyMode mode : {SimplifyMode::Fidelity, SimplifyMode::Paper}) {
          LabelResult r = label_scene(renderer, moved, moved_tracer,
                                      mode == SimplifyMode::Paper ? anchored_any : anchored);
          r.labels.resize(scene.triangle_count());  // the anchors' two labels go
          SimplifyOptions so;
          if (mode == SimplifyMode::Fidelity) so = fidelity_options(e_p, e_i.front());
          so.mode = mode;
          so.pixel_footprint = p;
          SimplifyStats st;
          Judged j = judge(renderer, simplify(scene, r.labels, so, &st), records, job);
          j.seconds = st.seconds;
          std::ostringstream name;
          name << simplify_mode_name(mode);
          if (mode == SimplifyMode::Fidelity) name << " e_I=" << e_i.front();
          name << " (labels " << shift << ")";  // no comma: the CSV does not quote
          row(m, d, name.str(), j);
        }
      }
    }
    {
      // The noise floor of the judge: the original itself, moved by a quarter
      // of a pixel's footprint (along the diagonal of the axes), judged like
      // any LOD. Nothing is simplified; what it changes is what moving edges
      // by a quarter pixel does to a render with one sample per pixel.
      Scene moved = scene;
      const float step = float(0.25 * p / std::sqrt(3.0));
      for (float& x : moved.positions) x += step;
      row(m, d, "original moved 1/4 px", judge(renderer, moved, records, job, nullptr, g_pairs_all ? tag + "_moved_quarter_px" : ""));
    }
    if (g_only_fidelity) continue;
    {
      SimplifyOptions so;
      so.mode = SimplifyMode::Paper;
      row(m, d, "paper", simplified(so));
      so.mode = SimplifyMode::Bounded;
      so.k = 1;
      row(m, d, "bounded k=1", simplified(so));
      so.mode = SimplifyMode::Cluster;
      row(m, d, "cluster k=1", simplified(so));
      // Plain quadric collapse, labels ignored, at each fidelity row's count.
      for (size_t i = 0; i < fidelity.size(); ++i) {
        so.mode = SimplifyMode::Qem;
        so.target_triangles = fidelity[i].triangles;
        std::ostringstream name;
        name << "qem @e_I=" << e_i[i];
        std::ostringstream suffix;
        suffix << "_eI" << e_i[i];
        row(m, d, name.str(), simplified(so, suffix.str()));
      }
    }
#ifdef PERCLOD_HAVE_MESHOPTIMIZER
    if (!g_meshopt) continue;
    const MeshoptInput welded = meshopt_input(scene);
    for (size_t i = 0; i < fidelity.size(); ++i) {
      double sec = 0;
      Scene lod = decimater_lod(scene, welded, fidelity[i].triangles, sec);
      std::ostringstream name, pair_name;
      name << "decimater @e_I=" << e_i[i];
      pair_name << tag << "_decimater_eI" << e_i[i];
      Judged j = judge(renderer, lod, records, job, nullptr, pair_name.str());
      j.seconds = sec;
      row(m, d, name.str(), j);
    }
    PeerRun peers{renderer, m, d, tag, records, job, fidelity, e_i, g_search ? &search : nullptr,
                  g_search ? &search_local : nullptr};
    const Sweep plain = peers.meshopt_sweep(scene, "meshopt", true);
    size_t seen = 0;
    const Scene culled = bench::visibility_culled(renderer, scene, m.up, job.display, d, 2, &seen);
    std::printf("%-6s %4.0f  visibility cull: %zu of %zu triangles seen from %zu views at 2x\n", m.key.c_str(), d,
                seen, scene.triangle_count(), bench::hemisphere_views().size());
    const Sweep culled_sweep = peers.meshopt_sweep(culled, "culled meshopt", false);
    peers.equal_fidelity(plain, "meshopt", scene.triangle_count());
    peers.equal_fidelity(culled_sweep, "culled", scene.triangle_count());
#endif
  }
  g_hausdorff = nullptr;
}

}  // namespace

int main(int argc, char** argv) {
  std::string models_arg = "demo,han", csv;
  std::vector<double> distances = {56, 132, 427}, e_i = {1, 2, 4};
  size_t facade_triangles = 1000000;
  double e_p = kDefaultBoundPerceptiblePx;
  for (int i = 1; i < argc; ++i) {
    std::string a = argv[i];
    if (a == "--models" && i + 1 < argc) models_arg = argv[++i];
    else if (a == "--distances" && i + 1 < argc) distances = numbers(argv[++i]);
    else if (a == "--e-imperceptible" && i + 1 < argc) e_i = numbers(argv[++i]);
    else if (a == "--e-perceptible" && i + 1 < argc) e_p = std::atof(argv[++i]);
    else if (a == "--csv" && i + 1 < argc) csv = argv[++i];
    else if (a == "--no-meshopt") g_meshopt = false;
    else if (a == "--e-area" && i + 1 < argc) g_area = std::atof(argv[++i]);
    else if (a == "--max-normal-change" && i + 1 < argc) g_max_normal = std::atof(argv[++i]);
    else if (a == "--e-undisplayable" && i + 1 < argc) g_e_u = std::atof(argv[++i]);
    else if (a == "--facade-triangles" && i + 1 < argc) facade_triangles = std::strtoull(argv[++i], nullptr, 10);
    else if (a == "--dump" && i + 1 < argc) g_dump = argv[++i];
    else if (a == "--dump-view" && i + 1 < argc) g_dump_view = argv[++i];
    else if (a == "--pairs" && i + 1 < argc) g_pairs = argv[++i];
    else if (a == "--pairs-all") g_pairs_all = true;
    else if (a == "--only-fidelity") g_only_fidelity = true;
    else if (a == "--label-shift") g_label_shift = true;
    else if (a == "--no-tighten") g_tighten = false;
    else if (a == "--no-search") g_search = false;
    else if (a == "--set" && i + 1 < argc && std::strchr(argv[i + 1], '=')) {
      const std::string kv = argv[++i];
      g_settings.push_back({kv.substr(0, kv.find('=')), kv.substr(kv.find('=') + 1)});
    }
    else if (a == "--keep-undisplayable") g_keep_undisplayable = true;
    else if (a == "--delete-undisplayable") g_delete_undisplayable = true;
    else {
      std::fprintf(stderr, "usage: bench_fidelity [--models demo,han,sibenik,sponza,block,facade] [--distances 56,132,427]\n"
                           "                      [--e-imperceptible 1,2,4] [--e-perceptible 0.5] [--csv FILE]\n"
                           "                      [--no-meshopt] [--keep-undisplayable [--e-undisplayable E] | --delete-undisplayable] [--dump DIR]\n"
                           "                      [--facade-triangles N] [--e-area A] [--max-normal-change DEG]\n"
                           "                      [--dump-view NAME]\n"
                           "                      [--pairs DIR [--pairs-all]] [--set KEY=VALUE ...] [--only-fidelity]\n"
                           "                      [--label-shift] [--no-tighten] [--no-search]\n");
      return 2;
    }
  }
  // The picture folders are made here, before hours of judging, not found
  // missing at the first picture.
  try {
    for (const std::string& dir : {g_dump, g_pairs})
      if (!dir.empty()) ensure_directory(dir);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_fidelity: %s\n", e.what());
    return 1;
  }
  if (!csv.empty()) {
    g_csv = std::fopen(csv.c_str(), "w");
    if (!g_csv) {
      std::perror(csv.c_str());
      return 1;
    }
    std::fprintf(g_csv, "model,distance,method,triangles,seconds,lab_changed,lab_ssim,lab_silhouette,"
                        "held_changed,held_ssim,held_silhouette,hausdorff_rel,label_seconds,visible_worst,"
                        "visible_median,pair_visible,pair_changed,pair_ssim,pair_image,visible_worst_view,note,"
                        "visible_local_worst\n");
  }
#ifndef PERCLOD_HAVE_MESHOPTIMIZER
  std::fprintf(stderr, "bench_fidelity: built without meshoptimizer: perclod rows only\n");
#endif
  const std::string data = PERCLOD_SHARED_DATA;
  for (const auto& key : split(models_arg, ',')) {
    Model m;
    m.key = key;
    if (key == "demo") {
      m.scene = load_scene(data + "/ingolstadt/bldg_4018215.obj");
      m.up = UpAxis::Z, m.per_building = PerBuilding::Off;
    } else if (key == "han") {
      m.scene = load_scene(data + "/han/han_ministry.obj");
      m.up = UpAxis::Y, m.per_building = PerBuilding::Off;
    } else if (key == "sibenik" || key == "sponza") {  // Y-up interiors, judged from outside like a building
      m.scene = load_scene(data + "/" + key + "/" + key + ".obj");
      m.up = UpAxis::Y, m.per_building = PerBuilding::Off;
    } else if (key == "block") {
      m.scene = load_scene(data + "/ingolstadt/ingolstadt_lod3_all53.obj");
      m.up = UpAxis::Z, m.per_building = PerBuilding::On;
    } else if (key == "facade") {
      m.scene = generate_facade(facade_params_for_triangles(facade_triangles));
      m.up = UpAxis::Z, m.per_building = PerBuilding::Off;
    } else {
      std::fprintf(stderr, "bench_fidelity: unknown model '%s' (demo, han, sibenik, sponza, block, facade)\n",
                   key.c_str());
      return 2;
    }
    try {
      run_model(m, distances, e_i, e_p);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "bench_fidelity: error: %s: %s\n", key.c_str(), e.what());
      return 1;
    }
  }
  if (g_csv) std::fclose(g_csv);
  return 0;
}
