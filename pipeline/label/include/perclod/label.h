// perclod/label.h - `perclod label`: every triangle of a model labelled
// perceptible, imperceptible or undisplayable from its views at one distance
// (render -> perceive -> ray-cast; docs/method.md section 4), and the label
// settings that choose how.
#pragma once

#include <cstddef>
#include <map>
#include <memory>
#include <optional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "perclod/display.h"
#include "perclod/image_io.h"
#include "perclod/outputs.h"
#include "perclod/perception.h"
#include "perclod/raycast.h"
#include "perclod/render.h"
#include "perclod/runtime.h"
#include "perclod/view_record.h"
#include "perclod/views.h"

namespace perclod {

enum class TracerKind { Octree, Embree };
TracerKind parse_tracer(const std::string& s);  // "octree" | "embree"
// The production tracer of that kind (Embree in its fast packet mode).
std::unique_ptr<Tracer> make_tracer(const Scene& scene, TracerKind kind);

// LabelJob::group_span of `perclod run` and `perclod label`: each building
// alone, since groups delete facades their own members hide
// (BENCHMARKS.md#building-groups).
constexpr double kDefaultGroupSpan = 0;
// Whether a building's own views show it alone (LabelJob::own_views_alone)
// unless told otherwise: since 0.5.0 (BENCHMARKS.md#building-groups).
constexpr bool kDefaultOwnViewsAlone = true;

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

// Buildings put in groups for labelling (LabelJob::group_span): the boxes
// split at the median of their centres across the longer side, until a
// part's boxes together span at most `span` across (the plane across `up`;
// span 0: every box alone). Empty boxes belong to no group. Returns each
// group's box indices, in the order of their first box.
std::vector<std::vector<uint32_t>> group_boxes(const std::vector<Bounds>& boxes, UpAxis up, double span);

// LabelJob::samples for "auto": each view picks how it is sampled
// (choose_sampling).
constexpr int kAutoSamples = 0;
// Samples per pixel `perclod run` and `label` take unless told otherwise
// (BENCHMARKS.md#5-stability-and-the-inputs-where-methods-fail says how it
// was chosen): auto.
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
// scene's, `box_pixels` the frame's pixels the scene's box covers (without
// the window's margin, which is most of a small building's window). The steadiest setting whose estimated work stays within that of
// one render of the frame (docs/usage.md#choosing-the-samples-per-view):
//  * triangles > frame / 16: the renders and the traced samples cost in
//    proportion to the triangles, and one render with 4 samples is taken;
//  * else a box of at least kSparseViewPixels pixels per triangle: one
//    sample (a sparse view, such as a LoD2 house's own view at 56 m);
//  * else 16 x window <= frame: the 16-sample grid (one render at 4x of the
//    window, no more pixels than the frame);
//  * else 4 x window <= 2 x frame: 4 samples with a mask per sample (four
//    renders of the window);
//  * else one render of the frame with 4 samples.
ViewSampling choose_sampling(size_t window_pixels, size_t frame_pixels, size_t triangles, size_t box_pixels);
// A view whose model's box covers at least this many pixels per triangle
// is traced at one sample per pixel (0.9.1). Its triangles are mostly far
// larger than a pixel, whose labels pool tens to hundreds of samples
// whatever the pattern, and tracing 4 to 16 samples per pixel was two
// thirds of labelling a LoD2 district: the Delft tile runs in 4 min 42 s
// instead of 7 min 33 s, every building's LOD within its floor from its
// held-out views, and labels at 1.5 times the resolution flip about as
// often (BENCHMARKS.md#sparse-views). 256 saved half as much for the same
// stability; no model of more than frame / 64 triangles (20,480 at 1280 x
// 1024) is ever sparse.
constexpr size_t kSparseViewPixels = 64;
// How `perclod run` and `label` combine views unless told otherwise
// (docs/usage.md#combining-views says how it was chosen): "pooled".
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
  // sample offset, each perceived on its own (docs/usage.md#grids-of-samples).
  int samples = 1;
  // With samples > 1: a triangle smaller than a pixel that no sample and no
  // pixel centre hit, lying on the drawn surface at its centroid's pixel
  // (within half a pixel footprint of the depth drawn there) and not under
  // the triangle drawn at that pixel's centre, is not undisplayable when
  // such triangles would leave at least half of that pixel open: it takes
  // the pixel's decision with one sample's weight
  // (docs/usage.md#unsampled-surface). false: the paper's rule, unsampled =
  // undisplayable.
  bool keep_unsampled_surface = false;
  // false: one render and perception mask per view, read by all of its
  // samples. true: each sample offset gets a render and mask of its own
  // (the camera shifted by that offset, one ray per pixel), so a sample reads
  // the mask of the picture drawn at its own position: `samples` renders per
  // view, and labels that a sub-pixel move of the model hardly changes
  // (BENCHMARKS.md#5-stability-and-the-inputs-where-methods-fail).
  bool mask_per_sample = false;
  // Also label each building from views framed on it (its neighbours drawn
  // and occluding); Auto = when find_buildings finds two or more.
  PerBuilding per_building = PerBuilding::Off;
  // Per building: neighbours whose boxes together span at most this many
  // times the distance across (the plane across `up`) share one set of
  // views framed on the group, each view counting the group's triangles;
  // 0 labels each building alone (docs/usage.md#building-groups).
  double group_span = 0;  // run and label take kDefaultGroupSpan
  // Per building: each building's own views render, perceive and trace the
  // building alone (its walls that only neighbours hide are seen), and
  // sample as its own triangles ask (choose_sampling). A group's views, with
  // group_span, stay in the district; its hidden members' own views are
  // alone too. false: own views in place, neighbours drawn and occluding.
  bool own_views_alone = kDefaultOwnViewsAlone;
  // When every building is labelled from its own views alone (per building,
  // own_views_alone, group_span 0), whether the whole-model views count
  // towards the labels too (0.5.0's labels; tests compare). false: they are
  // drawn only for the pictures a job writes (and with `verify`, the
  // octree-Embree agreement), and count nothing: every
  // triangle is seen from `distance` in its building's own views, where the
  // whole-model views see all but the front row from farther away, and
  // they and their judging took two fifths of a district's run
  // (docs/usage.md#own-views-of-the-building-alone).
  bool model_views_beside_alone = false;
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
  // A building's own views (and a group's members' own views) draw and
  // read only their window on the building (perception_window), with the
  // whole frame's projection: the same labels as drawing the whole frame,
  // for the pixels that matter. false draws the whole frame (tests compare).
  bool own_views_window_only = true;
  // Threads that label buildings alone at once (own_views_alone without
  // groups): each its own OpenGL context and pipeline; the labels do not
  // depend on it. 0: one per CPU this process may run on.
  int building_threads = 0;
};

// The threads job.building_threads asks for (0: the CPUs this process may
// run on).
size_t building_lanes(const LabelJob& job);

// How one labelling view (or tile) went: its first pass, with the pixels and
// timings of its later passes added.
struct ViewLabelling {
  std::string view;
  size_t rendered_pixels = 0;          // every pass's render (a grid's at its resolution)
  long long covered_pixels = 0;        // drawn pixels of the first pass
  double imperceptible_fraction = 0;   // of the covered pixels
  int levels = 0;                      // DWT levels of the perception
  LabelCounts labels;                  // this view's own labels
  size_t unsampled_surface = 0;        // triangles keep_unsampled_surface counted
  // Seconds per step: "render", "perceive", "trace" and with verify
  // "trace_embree_verify", summed over the passes.
  std::map<std::string, double> seconds;
  std::optional<Agreement> rays_vs_id_buffer;  // traced against the renderer, at the pixel centres
  std::optional<Agreement> octree_vs_embree;   // with verify
  std::string sampling;                // samples auto: what this view took ("" otherwise)
  size_t passes = 0;                   // with a render per sample: how many (0: one)
};

// How one building's own views went (per-building labelling), or one
// group's (job.group_span): `building` is then its first building's name
// and `buildings` how many it holds.
struct BuildingLabelling {
  std::string building;
  size_t buildings = 1;
  size_t views = 0;
  size_t eyes_inside_other_buildings = 0;
  double seconds = 0;
  std::map<std::string, size_t> sampling_chosen;  // samples auto: views per setting
  // A group's: views framed on one member (in a direction where the
  // group's views saw it poorly), and members with such views.
  size_t own_views = 0, members_alone = 0;
  size_t rendered_pixels = 0;  // drawn and read back, every pass (ViewLabelling::rendered_pixels)
};

// What labelling at one distance did, as the reports give it.
struct LabelReport {
  double distance = 0;
  std::string tracer;
  int samples = 1;                     // samples per pixel, or kAutoSamples
  std::string combine_views;           // "pooled" or "any"
  bool keep_unsampled_surface = false;
  bool mask_per_sample = false;        // a render per sample (or a grid)
  int sample_grid = 0;                 // 3 or 4 for the ordered grids
  bool automatic = false;              // samples auto (sampling_chosen applies)
  bool view_images = false;            // each view's render <stem>_<view>_<d>m.png was written
  std::map<std::string, size_t> sampling_chosen;  // samples auto: views per setting
  std::vector<ViewLabelling> views;    // whole-model views and tiles, in order
  bool per_building = false;           // buildings below were labelled from their own views
  // Whether `views` counted towards the labels (false: each building's own
  // views alone made them, and `views` were drawn for their pictures only).
  bool model_views_counted = true;
  std::vector<BuildingLabelling> buildings;
  LabelCounts labels;                  // the combined labels
  size_t outside_views = 0;
  std::string labels_file;             // written by write_label_outputs ("" before)
  bool markings_written = false;
  std::vector<std::string> marking_renders;
  double tracer_build_seconds = -1;    // label_model: its tracer's build (< 0: not given)
  double seconds = 0;                  // label_scene's wall time
  double seconds_buildings = 0;        // of it, the per-building (or group) views'
  // "render", "perceive", "trace" summed over every view and pass, whole-
  // model and per-building: thread time (a render overlaps a trace).
  std::map<std::string, double> step_seconds;
};

// What labelling tells while it works; perclod/progress_text.h's
// TextProgress turns it into the progress lines `perclod` prints.
class LabelProgress {
 public:
  virtual ~LabelProgress() = default;
  virtual void tracer_built(const Tracer& tracer) = 0;
  // A whole-model view (or tile) `view` at `distance` is labelled, all its passes.
  virtual void view_labelled(const std::string& view, double distance, const ViewLabelling& v) = 0;
  // A building (or group) is labelled from its own views, the index-th of
  // `count` to finish (buildings alone on several threads finish out of
  // model order; b names it).
  virtual void building_labelled(size_t index, size_t count, const BuildingLabelling& b) = 0;
};

struct LabelResult {
  std::vector<Label> labels;               // combined over views
  std::vector<IdBuffer> id_buffers;        // per labelling view and tile, when view images are written
  TriangleCounts totals;                   // summed over views, in samples (samples auto: in 1/16 px)
  std::vector<ViewRecord> views;           // whole-model views (and tiles) that counted, in job.views order
  size_t outside_views = 0;                // triangles in no view's frustum (labelled imperceptible)
  LabelReport report;                      // per view: pixels, fractions, agreement, timings
};

// The part of `cam`'s frame a mask-per-sample pass renders: where `box`
// projects, widened by 12 x 2^L pixels (more than the reach of the L-level
// DWT of `ps`, its CSF filters and its inverse) and with its corner on the
// DWT's 2^L grid, so its perception equals the whole frame's over the box.
// With `alone` (nothing is drawn outside `box`: a building's own view of it
// alone) by 6 x 2^L, which gives the same perception there. The whole
// camera when a box corner is behind the eye.
Camera perception_window(const Camera& cam, const Bounds& box, const PerceptionSettings& ps, bool alone = false);

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
//    its own framed views, counting only its own triangles; when each is
//    labelled from views of it alone (own_views_alone, group_span 0), its
//    own views alone make its labels, and the whole-model views are drawn
//    only for the files they write (unless model_views_beside_alone).
// Uploads `scene` to `renderer`, where it stays for write_label_outputs.
// Writes the renders and perception images of each whole-model view when
// job.out.dir is set.
// `verify_tracer` (job.verify only): an Embree tracer of `scene` in Verify
// mode kept by the caller for several distances; else one is built per call.
LabelResult label_scene(Renderer& renderer, const Scene& scene, const Tracer& tracer, const LabelJob& job,
                        LabelProgress* progress = nullptr, const EmbreeTracer* verify_tracer = nullptr);

// Writes out.labels(d) and, with job.write_view_images, the marking colours of
// the combined labels: per labelling view and tile from its own render's ID
// buffer (out.view(tile, d, "_marking.png"), no second render), and with
// job.marking_near a render of each view from d * closer_factor
// ("_marking_near.png"); records their paths in result.report (labels_file,
// marking_renders) and releases result.id_buffers. `renderer` must hold
// `scene` (as label_scene leaves it).
void write_label_outputs(Renderer& renderer, const Scene& scene, LabelResult& result, const LabelJob& job);


// Where the job's eye stands: its up axis, display and distance.
Framing framing_of(const LabelJob& job);

// The job's perception settings at its display's pixel density.
PerceptionSettings perception_for(const LabelJob& job);

}  // namespace perclod
