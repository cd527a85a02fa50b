// perclod/judge.h - a LOD against the original: both rendered from the same
// views (labelling and held-out), with changed pixels, SSIM and silhouette
// per view, and the worst of them against the limits.
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "perclod/display.h"
#include "perclod/image_io.h"
#include "perclod/perception.h"
#include "perclod/label.h"
#include "perclod/render.h"
#include "perclod/view_record.h"
#include "perclod/views.h"

namespace perclod {

// The views `perclod run` judges every LOD from besides its labelling views
// (the "held_out" preset of perclod/views.h: none of them is a labelling view
// of the default set).
constexpr const char* kDefaultJudgeViews = "held_out";

// How a LOD's render is compared with the original's: the perception
// settings at the display's pixel density (perception_for), and whether the
// LOD's render of view k+1 overlaps the comparison of view k (same figures).
struct JudgeSettings {
  PerceptionSettings perception;
  bool overlap = true;   // renders overlap the work on the views before them
  size_t workers = 1;    // with overlap: threads working on views at once (results do not depend on it)
};
JudgeSettings judge_settings_of(const LabelJob& job);

// Renders `scene` from `views` (framed like labelling views, cameras from the
// scene's own bounding box) and records each for compare_lod_views, marked
// with `set`. Uploads `scene` to `renderer`.
std::vector<ViewRecord> record_views(Renderer& renderer, const Scene& scene, const std::vector<std::string>& views,
                                     const Framing& framing, const std::string& set = "held_out");

// record_views for given cameras (tiles named as frame_view names them).
std::vector<ViewRecord> record_views(Renderer& renderer, const Scene& scene, const std::vector<ViewTile>& tiles,
                                     const std::string& set);

// `views` framed on `box` (frame_view), each camera cropped to its window on
// the box as a building's own view of it alone is (perception_window with
// `alone`): what judging a building alone renders and perceives, not its
// whole frame.
std::vector<ViewTile> framed_windows(const Bounds& box, const std::vector<std::string>& views, const Framing& framing,
                                     const PerceptionSettings& ps);

// The perceptual floor a view's LOD is judged against: the visible
// difference (perclod/perception.h) between the original's render and the
// original's render with the camera moved by this many pixels (along the
// image diagonal) - a change no viewer would call a different model.
constexpr double kFloorShiftPx = 0.25;
// Measures each record's visible_floor: renders `original` (uploading it to
// `renderer`) from each record's camera moved by kFloorShiftPx and compares
// both renders' vision-simulated images over the pixels either draws; no
// floor is below kFloorOfMedian times the median floor of `records` (a
// single flat wall's is near 0: bench_fidelity found Sponza's -x facade at
// 0, its moved original 612-1,457x over it).
constexpr double kFloorOfMedian = 0.5;
void measure_floors(Renderer& renderer, const Scene& original, std::vector<ViewRecord>& records,
                    const JudgeSettings& how);
// A floor below this many thresholds counts as this much: a view where a
// shift changes nothing (a blank or flat one) judges any visible change as
// far over its floor, not as infinitely over.
constexpr double kMinVisibleFloor = 0.01;
// The squares of the local figure (visible_difference_local), pixels: about
// a window at 56 m on the paper's display.
constexpr int kLocalBlockPx = 16;

// One judged view: how the LOD's render differs from the original's.
struct ViewFigures {
  std::string view;                 // view name (with "_t<i>" for a tile)
  std::string set;                  // "labelling" or "held_out"
  std::string building;             // judged alone (judge_buildings_alone): its building, else empty
  size_t drawn_pixels = 0;          // drawn in either render
  size_t changed_pixels = 0;        // of those, perceptibly changed
  double changed_fraction = 0;      // changed_pixels / drawn_pixels
  double ssim_covered = 1;          // mean SSIM of the luminances over the drawn pixels
  size_t covered_pixels_original = 0;
  size_t coverage_changed_pixels = 0;  // drawn in exactly one of the two
  double silhouette_mismatch = 0;   // coverage_changed_pixels / covered_pixels_original
  double visible_difference = 0;    // perclod/perception.h's, over the drawn pixels (thresholds)
  double visible_floor = -1;        // the view's floor (< 0: not measured)
  double visible_ratio = 0;         // visible_difference / max(floor, kMinVisibleFloor); 0 when unmeasured
  double visible_local = 0;         // visible_difference_local (kLocalBlockPx squares)
  double visible_floor_local = -1;
  double visible_local_ratio = 0;   // visible_local over its own floor
  std::string comparison_image;     // the picture's file, when make_lods writes one
  bool operator==(const ViewFigures&) const = default;
};

// How a LOD looks from recorded views of the original: each view is rendered
// from `lod`. Per view:
//  * changed_fraction: pixels (drawn in either render) whose vision-simulated
//    luminance differs by more than the perception threshold, over those
//    drawn pixels;
//  * ssim_covered: mean SSIM (ssim_mean) of the two renders' luminance over
//    the pixels drawn in either;
//  * silhouette_mismatch: pixels drawn in exactly one of the two, over the
//    pixels the original draws (1 when the original draws none and the LOD
//    some).
//  * visible_difference: how visible the two vision-simulated images'
//    difference is over the pixels drawn in either (visible_difference of
//    perclod/perception.h), and visible_ratio, that over the record's floor
//    (measure_floors): 1 = as visible as moving the original a quarter pixel.
// Uploads `lod` to `renderer`.
// `pictures`, when given, receives per view a picture of the region either
// render draws (scaled to 240-400 px): the original's luminance | the LOD's |
// the LOD's with changed pixels red and silhouette changes blue (make_lods
// writes them as _lod_vs_original.png).
std::vector<ViewFigures> compare_lod_views(Renderer& renderer, const Scene& lod,
                                           const std::vector<ViewRecord>& original, const JudgeSettings& how,
                                           std::vector<Rgb8Image>* pictures = nullptr);

// Limits a LOD is held to in every judged view (docs/usage.md#judging-a-lod).
struct FidelityLimits {
  double max_changed = 1;         // changed_fraction (1: no limit)
  double max_silhouette = 1;      // silhouette_mismatch (1: no limit)
  double min_ssim = 0;            // ssim_covered (0: no limit)
  double max_visible = 1;         // visible_ratio (0: no limit): within the quarter-pixel floor
  double max_visible_local = 0;   // visible_local_ratio (0: no limit)
};

// The worst of each figure over the judged views.
struct WorstFigures {
  double changed_fraction = 0;
  double ssim_covered = 1;        // the lowest
  double silhouette_mismatch = 0;
  double visible_ratio = 0;
  double visible_local_ratio = 0;  // held to max_visible_local when that is set
};

// A view's figure over its limit (an SSIM is over when below min_ssim).
struct OverLimit {
  std::string view, set;
  std::string measure;  // "changed_fraction", "ssim_covered", "silhouette_mismatch", "visible_ratio" or "visible_local_ratio"
  double value = 0, limit = 0;
};

// The views of a LOD judged against limits.
struct Judgement {
  WorstFigures worst;
  FidelityLimits limits;
  std::vector<OverLimit> over_limits;  // in view order, each view's measures in the order above
  bool met() const { return over_limits.empty(); }
};

Judgement judge_views(const std::vector<ViewFigures>& views, const FidelityLimits& limits);

// One building's LOD judged alone (judge_buildings_alone).
struct BuildingJudged {
  size_t index = 0;  // of the building in find_buildings' order
  std::string building;
  size_t triangles = 0, lod_triangles = 0;
  // The LOD's triangles are the original's (same corners, materials and
  // order), so every render of it is the original's: not rendered, no views.
  bool unchanged = false;
  std::vector<ViewFigures> views;  // named "<building>/<view>", building set
};

// Each building of `original` (find_buildings) judged alone, as `perclod
// judge` judges a file holding only it: its triangles of `original` and of
// `lod` (a simplification of it: the same component names, each triangle's
// component in the same building) as scenes of their own, rendered from
// `views` framed on the building at framing.distance, only the window
// framed_windows keeps; floors and figures as measure_floors and
// compare_lod_views give them, worked out view by view (the original's
// render perceived once for both; how.overlap is not used). Buildings
// without triangles are skipped, and
// with `only` (one flag per building of find_buildings) those not flagged;
// a building whose LOD is its original is `unchanged`, without views.
// `lanes` threads, each with its own OpenGL context, take the next building
// when done with one; the result (in building order) does not depend on
// them. done(k, n, b), when given, is called (one call at a time) as each
// building is judged, in the order they finish. `floors`, when given, keeps
// each building's floors between calls for the same `original`, views and
// framing (the LODs judged may differ): a building judged again measures
// none, and its figures are the same.
using BuildingFloors = std::vector<std::vector<std::pair<double, double>>>;  // per building, per tile
std::vector<BuildingJudged> judge_buildings_alone(
    const Scene& original, const Scene& lod, const std::vector<std::string>& views, const Framing& framing,
    const JudgeSettings& how, size_t lanes,
    const std::function<void(size_t, size_t, const BuildingJudged&)>& done = nullptr,
    const std::vector<uint8_t>* only = nullptr, BuildingFloors* floors = nullptr);

}  // namespace perclod
