// perclod/pipeline.h - the method for one model, as the commands run it.
//
// One library call per command (the CLI only maps options onto these jobs):
//   render_views    perclod render    shaded views, ID and depth buffers
//   label_model     perclod label     render -> perceive -> ray-cast -> labels, marking renders
//   simplify_model  perclod simplify  one LOD from a labels file
//   make_lods       perclod run       label + simplify + judge, one LOD per distance
// and the steps they are made of (label_scene, write_label_outputs,
// compare_lod_views) for tests and benchmarks. Every file they write is named
// by OutputNames (perclod/outputs.h) and written atomically.
#pragma once

#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "perclod/display.h"
#include "perclod/image_io.h"
#include "perclod/labels_io.h"
#include "perclod/outputs.h"
#include "perclod/perception.h"
#include "perclod/raycast.h"
#include "perclod/render.h"
#include "perclod/simplify.h"
#include "perclod/views.h"

namespace perclod {

// Progress lines for stderr (may be empty).
using Progress = std::function<void(const std::string& message)>;

// ---- perclod render -------------------------------------------------------

struct ViewFiles {
  std::string view;
  double distance = 0;
  std::string color, ids, depth;  // paths written ("" = not requested)
  size_t covered_pixels = 0;      // pixels showing geometry
  size_t drawn_triangles = 0;     // sent to OpenGL after culling what lies outside the view
  double render_seconds = 0;
};

struct RenderViewsJob {
  OutputNames out;
  UpAxis up = UpAxis::Y;
  std::vector<std::string> views;     // view names (tiled like labelling views)
  std::vector<double> distances;
  DisplayProfile display;
  bool write_ids = false, write_depth = false;
  ColorBy color_by = ColorBy::Material;
};

// out.view(view, d, ".png") per view and tile, plus "_ids.tif" (uint32, triangle index + 1)
// and "_depth.tif" (float eye depth, metres) on request. `progress` (may be
// empty) is called after each view.
std::vector<ViewFiles> render_views(const Scene& scene, const RenderViewsJob& job,
                                    const std::function<void(const ViewFiles&, size_t done, size_t total)>& progress);

// ---- perclod label --------------------------------------------------------

enum class TracerKind { Octree, Embree };
TracerKind parse_tracer(const std::string& s);  // "octree" | "embree"
// The production tracer of that kind (Embree in its fast packet mode).
std::unique_ptr<Tracer> make_tracer(const Scene& scene, TracerKind kind);

// How a model is split into buildings for per-building labelling.
// Auto: on when component names give two or more buildings by their
// "<building>/" prefix (CityGML-derived OBJ and CityJSON files).
enum class PerBuilding { Off, On, Auto };
PerBuilding parse_per_building(const std::string& s);  // "false" | "true" | "auto"

// How the views of one distance combine perceptible and imperceptible
// (undisplayable is the same in both: no sample of any view hit it).
//   AnyView  perceptible in any view wins (the paper)
//   Pooled   imperceptible / traced >= ratio over the samples of every view
//            together (LabelResult::totals)
enum class CombineViews { AnyView, Pooled };
CombineViews parse_combine_views(const std::string& s);  // "any" | "pooled"

// Buildings of a scene: component names "<building>/<part>/..." (CityGML-
// derived OBJ groups) share a building when their text before the first '/'
// is the same; a component without '/' is a building of its own. Returns the
// building of each component and the buildings' names.
struct Buildings {
  std::vector<uint32_t> of_component;
  std::vector<std::string> names;
  size_t named = 0;  // buildings named by a "<building>/" prefix (PerBuilding::Auto needs two)
};
Buildings find_buildings(const Scene& scene);

// LabelJob::samples for "auto": each view picks how it is sampled
// (choose_sampling).
constexpr int kAutoSamples = 0;
// Samples per pixel `perclod run` and `label` take unless told otherwise
// (README, "Stable labels", says how it was chosen): auto.
constexpr int kDefaultSamples = kAutoSamples;
// "auto" -> kAutoSamples, or one of 1, 2, 4, 8, 9, 16; throws
// std::invalid_argument naming the text otherwise.
int parse_samples(const std::string& s);
std::string samples_name(int samples);  // "auto" or the number
// In reports and settings: "auto", or the number (as it always was).
nlohmann::json samples_json(int samples);
// The samples a job labels with: its own, but 4 for auto with
// mask_per_sample or keep_unsampled_surface (each fixes how a view is
// sampled, as they did with 4 samples before auto).
struct LabelJob;
int effective_samples(const LabelJob& job);

// How one view is sampled: `samples` per pixel, with a render and mask of
// its own per sample (mask_per_sample, or a grid: samples 9 and 16) or one
// render that every sample reads.
struct ViewSampling {
  int samples = 1;
  bool mask_per_sample = false;
  bool operator==(const ViewSampling& o) const { return samples == o.samples && mask_per_sample == o.mask_per_sample; }
};
// What samples: auto gives a view, from what labelling it would cost, with
// no clock involved (the same model, views and display always give the same
// labels): `window_pixels` is the size of the view's window on the model
// (perception_window), `frame_pixels` the whole frame's, `triangles` the
// scene's. The steadiest setting whose estimated work stays within that of
// one render of the frame (README, "Choosing the samples per view"):
//  * triangles > frame / 16: the renders and the traced samples cost in
//    proportion to the triangles, and one render with 4 samples is taken;
//  * else 16 x window <= frame: the 16-sample grid (one render at 4x of the
//    window, no more pixels than the frame);
//  * else 4 x window <= 2 x frame: 4 samples with a mask per sample (four
//    renders of the window);
//  * else one render of the frame with 4 samples.
ViewSampling choose_sampling(size_t window_pixels, size_t frame_pixels, size_t triangles);
// How `perclod run` and `label` combine views unless told otherwise
// (README, "Combining views", says how it was chosen): "pooled".
constexpr const char* kDefaultCombineViews = "pooled";

struct LabelJob {
  UpAxis up = UpAxis::Y;
  DisplayProfile display;
  PerceptionSettings perception;      // ppd is taken from `display`
  std::vector<std::string> views;     // view names, e.g. parse_views("facades", up)
  // Samples per pixel (1, 2, 4, 8; see sample_offsets), or kAutoSamples:
  // per view, choose_sampling (mask_per_sample is then the choice's). 9 and 16 are the
  // ordered 3 x 3 and 4 x 4 grids, a mask per sample from one render: the
  // view's window (perception_window) drawn at 3 or 4 times its resolution
  // per axis, whose fine pixels are the samples, split into one picture per
  // sample offset, each perceived on its own (README, Grids of samples).
  int samples = 1;
  // With samples > 1: a triangle smaller than a pixel that no sample and no
  // pixel centre hit, lying on the drawn surface at its centroid's pixel
  // (within half a pixel footprint of the depth drawn there) and not under
  // the triangle drawn at that pixel's centre, is not undisplayable when
  // such triangles would leave at least half of that pixel open: it takes
  // the pixel's decision with one sample's weight (README, "Unsampled
  // surface"). false: the paper's rule, unsampled = undisplayable.
  bool keep_unsampled_surface = false;
  // false: one render and perception mask per view, read by all of its
  // samples. true: each sample offset gets a render and mask of its own
  // (the camera shifted by that offset, one ray per pixel), so a sample reads
  // the mask of the picture drawn at its own position: `samples` renders per
  // view, and labels that a sub-pixel move of the model hardly changes
  // (README, "Stable labels").
  bool mask_per_sample = false;
  // Also label each building from views framed on it (its neighbours drawn
  // and occluding); Auto = when find_buildings finds two or more.
  PerBuilding per_building = PerBuilding::Off;
  double distance = 56;
  double ratio = 0.5;                 // imperceptible / traced >= ratio -> imperceptible
  CombineViews combine = CombineViews::AnyView;  // the paper's; run and label take kDefaultCombineViews
  bool verify = false;                // also trace with Embree (tie-rule mode) and compare
  double closer_factor = 0.25;        // marking render from d * closer_factor too
  OutputNames out;                    // out.dir "" = write no files
  // With out.dir set: per view its render and its marking (coloured from the
  // labelling render's ID buffer), and the simulated/difference/mask images.
  bool write_view_images = true;
  bool write_perception_images = true;
  bool marking_near = true;           // also the marking from d * closer_factor (a full render per view)
  ImageWriter* images = nullptr;      // encodes the PNGs on its own thread (else each is written at once)
  // Render view k+1 while view k is traced (labelling) or compared (judging),
  // on a second thread; false runs them one after another (same results).
  bool overlap = true;
};

// What the original looked like from one view, kept to judge a LOD from the
// same view: a labelling view, or a held-out view (record_views). Only the
// rectangle the original draws, widened by kRecordMargin pixels, is kept
// (a building at 427 m covers a few thousand of a view's million pixels);
// outside it the original drew nothing: background, background_rgb. The
// render's colours are kept, not its perception: the judge rebuilds the
// whole render from them and perceives it again, with the same figures to
// the last bit. The colours are packed losslessly (zlib): at 56 m a
// 1M-triangle model is judged from 86 tiles that its records nearly fill,
// 3.9 MB each at 3 bytes a pixel, 22-240 KB packed.
constexpr int kRecordMargin = 16;
struct ViewRecord {
  std::string view;  // view name (with "_t<i>" for a tile)
  Camera camera;
  int x0 = 0, y0 = 0, w = 0, h = 0;       // the kept rectangle of the camera's image
  std::vector<uint8_t> packed_rgb;         // the render's colours, w x h x 3, row 0 top, packed (zlib)
  std::vector<bool> background;            // true where no triangle was drawn (a bit each)
  uint8_t background_rgb[3] = {255, 255, 255};  // the colour of an undrawn pixel
  std::string set = "labelling";           // "labelling" or "held_out"

  // Index into the kept arrays of image pixel (x, y), or -1 outside them.
  long kept(int x, int y) const {
    return x >= x0 && x < x0 + w && y >= y0 && y < y0 + h ? long(y - y0) * w + (x - x0) : -1;
  }
  bool background_at(int x, int y) const {
    const long k = kept(x, y);
    return k < 0 || background[size_t(k)];
  }
  // The kept rectangle's colours, w x h x 3, unpacked.
  void rgb_into(std::vector<uint8_t>& rgb) const;
  // The whole render, camera.width x camera.height x 3: the kept rectangle
  // over the undrawn colour.
  void render_into(std::vector<uint8_t>& image) const;
};

// A labelling render's triangle IDs, kept to colour its marking image once
// the labels are final (shade_ids).
struct IdBuffer {
  std::string view;  // view name (with "_t<i>" for a tile)
  Camera camera;
  std::vector<uint8_t> packed_ids;  // camera.width x camera.height IDs (triangle + 1, 0 = none), packed (zlib)
  void ids_into(std::vector<uint32_t>& ids) const;
};

struct LabelResult {
  std::vector<Label> labels;               // combined over views
  std::vector<IdBuffer> id_buffers;        // per labelling view and tile, when view images are written
  TriangleCounts totals;                   // summed over views, in samples (samples auto: in 1/16 px)
  std::vector<ViewRecord> views;           // whole-model views (and tiles), in job.views order
  size_t outside_views = 0;                // triangles in no view's frustum (labelled imperceptible)
  nlohmann::json report;                   // per view: pixels, fractions, agreement, timings
};

// The part of `cam`'s frame a mask-per-sample pass renders: where `box`
// projects, widened by 12 x 2^L pixels (more than the reach of the L-level
// DWT of `ps`, its CSF filters and its inverse) and with its corner on the
// DWT's 2^L grid, so its perception equals the whole frame's over the box.
// The whole camera when a box corner is behind the eye.
Camera perception_window(const Camera& cam, const Bounds& box, const PerceptionSettings& ps);

// Labels every triangle of `scene` from the job's views at one distance
// (docs/method.md section 4):
//  * each view is framed (frame_view: tiled when the model overfills it),
//    rendered, perceived and traced at job.samples samples per pixel (auto:
//    as choose_sampling picks for that view); a
//    sample counts for the triangle it hits, and is imperceptible when its
//    pixel is in the perception mask (with a mask per sample each sample
//    offset is a render, mask and trace of its own, cropped to the model);
//  * traced == 0 over every view -> undisplayable; else job.combine decides:
//    pooled (the default) sums every view's samples and calls a triangle
//    imperceptible when imperceptible / traced >= ratio; any (the paper)
//    applies that rule per view and perceptible in any view wins;
//  * a triangle no view's frustum contains is never undisplayable: it is
//    labelled imperceptible and counted in outside_views;
//  * per building (job.per_building): each building is also labelled from
//    its own framed views, counting only its own triangles.
// Uploads `scene` to `renderer`, where it stays for write_label_outputs.
// Writes the renders and perception images of each whole-model view when
// job.out.dir is set.
// `verify_tracer` (job.verify only): an Embree tracer of `scene` in Verify
// mode kept by the caller for several distances; else one is built per call.
LabelResult label_scene(Renderer& renderer, const Scene& scene, const Tracer& tracer, const LabelJob& job,
                        const Progress& progress = {}, const EmbreeTracer* verify_tracer = nullptr);

// Writes out.labels(d) and, with job.write_view_images, the marking colours of
// the combined labels: per labelling view and tile from its own render's ID
// buffer (out.view(tile, d, "_marking.png"), no second render), and with
// job.marking_near a render of each view from d * closer_factor
// ("_marking_near.png"); records their paths in result.report ("labels_file",
// "marking_renders") and releases result.id_buffers. `renderer` must hold
// `scene` (as label_scene leaves it).
void write_label_outputs(Renderer& renderer, const Scene& scene, LabelResult& result, const LabelJob& job);

// label_scene + write_label_outputs with a tracer of `tracer` kind, and the
// report written to out.label_report(d). Returns that report.
nlohmann::json label_model(const Scene& scene, const LabelJob& job, TracerKind tracer,
                           const Progress& progress = {});

// ---- perclod simplify -----------------------------------------------------

struct SimplifyJob {
  std::string labels_file;       // from perclod label; "" only for qem and cluster
  std::string model_file;        // named in errors when the labels belong to another model
  const LabelFile* labels = nullptr;  // already read from labels_file (else simplify_model reads it)
  double distance = 0;           // metres: p(d) for bounded and cluster
  DisplayProfile display;
  SimplifyOptions options;       // pixel_footprint is set from distance and display
  OutputNames out;               // the LOD goes to out.lod(distance, format)
  std::string format = "obj";    // "obj" or "glb"
  UpAxis up = UpAxis::Y;         // a Z-up model's GLB is turned to glTF's +Y up
  // keep_undisplayable: auto (fidelity mode, when options.delete_undisplayable):
  // choose_undisplayable decides from the labels' exposure.
  bool undisplayable_auto = true;
};

struct SimplifyRun {
  SimplifyStats stats;
  std::string lod_file;
  double pixel_footprint = 0;
  double write_seconds = 0;
  double undisplayable_exposure = -1;  // measured for keep_undisplayable: auto; -1 = not measured
  SimplifyOptions options;             // what simplified: the job's, with auto resolved
};

// Reads and checks the labels against `scene`, simplifies, exports.
SimplifyRun simplify_model(const Scene& scene, const SimplifyJob& job);

// SimplifyStats as the reports print them (`run` and `simplify --json`).
nlohmann::json simplify_stats_json(const SimplifyStats& stats);

// Why a LOD stopped (SimplifyStats::refused), in words: "N half-edges left:
// X locked or over their bound, ...", as `simplify --explain` and `run`
// with explain print it.
std::string refused_text(const SimplifyStats::Refused& why);

// ---- perclod run ----------------------------------------------------------

// The views `perclod run` judges every LOD from besides its labelling views
// (the "held_out" preset of perclod/views.h: none of them is a labelling view
// of the default set).
constexpr const char* kDefaultJudgeViews = "held_out";

// Renders `scene` from `views` (framed like labelling views, cameras from the
// scene's own bounding box, at job.distance) and records each for
// compare_lod_views, marked with `set`. Uploads `scene` to `renderer`.
std::vector<ViewRecord> record_views(Renderer& renderer, const Scene& scene, const std::vector<std::string>& views,
                                     const LabelJob& job, const std::string& set = "held_out");

// How a LOD looks from recorded views of the original: each view is rendered
// from `lod`. Per view:
//  * changed_fraction: pixels (drawn in either render) whose vision-simulated
//    luminance differs by more than the perception threshold, over those
//    drawn pixels;
//  * ssim_covered: mean SSIM (ssim_mean) of the two renders' luminance over
//    the pixels drawn in either;
//  * silhouette_mismatch: pixels drawn in exactly one of the two, over the
//    pixels the original draws (coverage_changed_pixels counts them).
// Uploads `lod` to `renderer`.
// `pictures`, when given, receives per view a picture of the region either
// render draws (scaled to 240-400 px): the original's luminance | the LOD's |
// the LOD's with changed pixels red and silhouette changes blue (make_lods
// writes them as _lod_vs_original.png).
nlohmann::json compare_lod_views(Renderer& renderer, const Scene& lod, const std::vector<ViewRecord>& original,
                                 const LabelJob& job, std::vector<Rgb8Image>* pictures = nullptr);
// The same from the labelling views of a LabelResult.
nlohmann::json compare_lod_views(Renderer& renderer, const Scene& lod, const LabelResult& original,
                                 const LabelJob& job);

// Limits a LOD is held to in every judged view (README, "Judging a LOD").
struct FidelityLimits {
  double max_changed = 0.02;      // changed_fraction
  double max_silhouette = 0.01;   // silhouette_mismatch
  double min_ssim = 0;            // ssim_covered (0: no limit)
};

// The worst figures of compare_lod_views' views and the views over a limit:
// {"worst": {"changed_fraction", "ssim_covered" (lowest), "silhouette_mismatch"},
//  "over_limits": [{"view", "set", "measure", "value", "limit"}, ...]} (an
// SSIM is over its limit when it is below min_ssim).
nlohmann::json judge_views(const nlohmann::json& views, const FidelityLimits& limits);

struct LodJob {
  LabelJob label;                      // views, samples, display, perception, ratio, output names
  std::vector<double> distances;
  TracerKind tracer = TracerKind::Octree;
  SimplifyOptions simplify;            // mode, bounds, k, ...; pixel_footprint is set per distance
  std::string lod_format = "obj";      // "obj" or "glb"
  // Held-out views every LOD is also judged from (empty: labelling views only).
  std::vector<std::string> judge_views;
  FidelityLimits limits;
  // Fidelity mode: try the steps of kFidelitySearch (loosest first) and keep
  // the first LOD that meets these limits in every judged view (when that is
  // the first step, the loosest of it and the looser bounds above it up to
  // kFidelitySearchLoosestPx that meet them and still remove triangles); the
  // tightest is kept when none does (and warned about).
  bool fidelity_target = false;
  FidelityLimits target;
  // Fidelity mode, no fidelity_target: a LOD over job.limits is tried again
  // at tighter bounds (tighten_steps, worth_tightening).
  bool tighten_to_limits = true;
  // keep_undisplayable: auto (choose_undisplayable, per distance).
  bool undisplayable_auto = true;
};

// One try of a fidelity_target search (or of tighten_to_limits):
// e_imperceptible = e pixels, the perceptible bound tightened to e where e is
// the tighter, and undisplayable triangles treated as asked or, with
// keep_undisplayable, collapsed within e_undisplayable (e when not given; the
// asked e_undisplayable where tighter) instead of deleted.
struct FidelitySearchStep {
  double e;
  bool keep_undisplayable;
  double e_undisplayable = -1;  // with keep_undisplayable: their bound, px (< 0: e)
};

// The tries, in order. Tightening e_I alone cannot help where e_P or the
// deleted undisplayable triangles hold a LOD over the target: on the
// million-triangle facade at 56 m (perclod run, 2026-12-03) every e_I from
// 16 down to 0.5 px at e_P = 0.5 px leaves 2.8-3.0% of the worst judged view
// changed, 0.25 px for both 2.1%; 0.125 px with undisplayable triangles kept
// within it meets 2% (0.98%). The last try moves nothing and deletes nothing:
// only collapses of zero error remain.
constexpr FidelitySearchStep kFidelitySearch[] = {
    {16, false}, {8, false}, {4, false}, {2, false}, {1, false}, {0.5, false},  // undisplayable deleted
    {0.25, false}, {0.25, true}, {0.125, true}, {0, true}};                     // then kept
// When the first try already meets the target, looser bounds may too: e_I
// then doubles, up to this, while the target holds and each try removes
// triangles, and the loosest LOD that met it is kept (han at 56 m: 16 and
// 32 px meet a 2% target, 64 px does not). 1024 px is more than a whole
// display at the paper's profile (1280 x 1024).
constexpr double kFidelitySearchLoosestPx = 1024;

// The looser half of a fidelity_target search, for `run` and its tests: the
// first step (kFidelitySearch[0]) met the target, leaving `triangles`.
// `try_step(step)` makes and judges the LOD at each looser step in turn (e
// doubled, up to kFidelitySearchLoosestPx) and returns whether it met the
// target and its triangle count. A try that meets it with fewer triangles is
// kept and the next tried; one with as many is kept and ends the search;
// one that fails, or keeps more, ends it with the last kept step, whose LOD
// the caller makes again (the simplifier and judge are deterministic).
struct LooserSearch {
  FidelitySearchStep step;  // the bounds of the LOD to write
  int tries = 0;            // looser tries made
  int kept = -1;            // which of them is `step` (from 0); -1: kFidelitySearch[0]
  bool remake = false;      // the last try is not `step`: make its LOD again
};
LooserSearch search_looser(size_t triangles,
                           const std::function<std::pair<bool, size_t>(const FidelitySearchStep&)>& try_step);

SimplifyOptions fidelity_bounds(SimplifyOptions so, const FidelitySearchStep& step);

// ---- undisplayable triangles: deleted or kept (`keep_undisplayable: auto`) --

// The views undisplayable_exposure looks from: az22.5el30, az67.5el30, ...,
// az337.5el30, between the default labelling azimuths at the labelling
// ring's elevation. None is a view of the default labelling set, of the
// `held_out` preset or of the benchmarks' 17 held-out views.
std::vector<std::string> exposure_views();

// How much of what a viewer sees from between the labelling views the
// triangles labelled undisplayable are: over exposure_views() framed at
// job.distance (tiles included), the nearest hits on undisplayable triangles
// over all hits, each pixel traced once at its centre. What deleting them
// would open from those views.
double undisplayable_exposure(const Scene& scene, const Tracer& tracer, const std::vector<Label>& labels,
                              const LabelJob& job);

// keep_undisplayable: auto (fidelity mode) deletes undisplayable triangles
// when their exposure is at most kKeepUndisplayableExposure, and otherwise
// keeps them, collapsed within kAutoUndisplayableBoundPx (an asked
// e_undisplayable keeps them anyway: auto has nothing to decide). README,
// "Keeping undisplayable triangles", has the measurements that chose both.
constexpr double kKeepUndisplayableExposure = 0.004;
constexpr double kAutoUndisplayableBoundPx = 4;

// Whether keep_undisplayable: auto has anything to decide for `so`: the
// fidelity mode, undisplayable triangles not already kept.
inline bool undisplayable_auto_applies(const SimplifyOptions& so) {
  return so.mode == SimplifyMode::Fidelity && so.delete_undisplayable;
}
// What keep_undisplayable: auto makes of `so` for an exposure (above): `so`
// unchanged unless the rule applies and the exposure is over
// kKeepUndisplayableExposure; then undisplayable triangles are kept and
// collapsed within kAutoUndisplayableBoundPx.
SimplifyOptions choose_undisplayable(SimplifyOptions so, double exposure);
// The same from the labels: measures undisplayable_exposure (framed by
// `framing`'s up, display and distance), applies it to `so`, returns it.
double choose_undisplayable(SimplifyOptions& so, const Scene& scene, const Tracer& tracer,
                            const std::vector<Label>& labels, const LabelJob& framing);

// How `so` treats undisplayable triangles, as reports give it:
// "undisplayable": "deleted" | "collapsed", "e_undisplayable" (a finite
// bound of kept ones) and, when auto measured it (exposure >= 0),
// "undisplayable_exposure".
void add_undisplayable_rule(nlohmann::json& j, const SimplifyOptions& so, double exposure = -1);

// ---- tightening a LOD that misses its limits (`tighten_to_limits`) ----------

// Fidelity mode without a fidelity_target: when the LOD at the asked bounds
// is over job.limits in a judged view, but by no more than kTightenReach
// times each limit (worth_tightening), `run` tries tighten_steps in order and
// keeps the first LOD within the limits in every judged view; when none is,
// the LOD at the asked bounds stays, flagged as before. Tightening from 0.5
// to 0.125 px cut the changed pixels by about 3x where it was tried (the
// million-triangle facade at 56 m: 2.97% -> 0.98%, perclod run 2026-12-03),
// so a LOD further over than that is left alone rather than tried at every
// step for nothing: the default LODs at 427 m are within the limits (the
// block) or 3.8-19x over 2% (README, Fidelity), where moving the original
// by a quarter pixel changes 19-65% of a view.
constexpr double kTightenReach = 3;

// The tries, in order: e_imperceptible 0.25 px (undisplayable triangles as
// asked), then undisplayable triangles kept within kAutoUndisplayableBoundPx
// at 0.25 and 0.125 px, then within 0.125 px too. Kept within 4 px they
// cost far fewer triangles than within the step's own bound, for nearly the
// same figures (bench_fidelity, 2026-12-04: Sponza at 132 m 21,810 triangles
// and 2.02% of the worst held-out view changed, against 34,036 and 1.84%;
// the million-triangle facade at 56 m 186,397 and 1.60% against 194,765
// and 1.55%).
constexpr FidelitySearchStep kTightenSteps[] = {{0.25, false},
                                                {0.25, true, kAutoUndisplayableBoundPx},
                                                {0.125, true, kAutoUndisplayableBoundPx},
                                                {0.125, true}};

// The steps of kTightenSteps that tighten `so` (fidelity mode): e at most
// its e_imperceptible, and fidelity_bounds changes some bound (a step that
// would change nothing, or only what the step before changed, is left out).
std::vector<FidelitySearchStep> tighten_steps(const SimplifyOptions& so);

// Whether `judged` (judge_views' result) is over `limits` and no worst
// figure is beyond kTightenReach times its limit (an SSIM's shortfall from 1
// against min_ssim's).
bool worth_tightening(const nlohmann::json& judged, const FidelityLimits& limits);

// tighten_to_limits itself, for `run` and for the benchmarks that must do as
// it does. `judged` is judge_views' result (against `limits`) for the LOD
// at `asked`. When worth_tightening says so and tighten_steps has steps,
// `try_step(bounds)` makes and judges the LOD at each step's bounds in order
// and returns whether it is within `limits`, until one is.
enum class Tightening { NotTried, Met, NoneWithin };
Tightening tighten_to_limits(const SimplifyOptions& asked, const nlohmann::json& judged, const FidelityLimits& limits,
                             const std::function<bool(const SimplifyOptions&)>& try_step);

// One LOD per distance: out.lod(d), out.labels(d), renders and marking
// renders, and out.report() (returned too) with its HTML page out.report_html()
// (perclod/report_html.h). Each LOD is judged from its
// labelling views and job.judge_views (entry "lod_vs_original", per view, and
// "fidelity", judge_views' summary against job.limits).
// A LOD without triangles (nothing displayable at its distance) is still
// written; its entry gets "empty": true and the report a "warnings" list
// (absent when there is nothing to warn about) for the caller to print; a
// LOD over a limit in some view adds a warning per view and measure, and
// the report's "over_limits" counts them (0 when every LOD is within).
// `lods`, when given, receives each LOD's scene in job.distances order.
nlohmann::json make_lods(const Scene& scene, const LodJob& job, const Progress& progress = {},
                         std::vector<Scene>* lods = nullptr);

}  // namespace perclod
