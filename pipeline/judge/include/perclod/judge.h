// perclod/judge.h - a LOD against the original: both rendered from the same
// views (labelling and held-out), with changed pixels, SSIM and silhouette
// per view, and the worst of them against the limits.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "perclod/image_io.h"
#include "perclod/label.h"
#include "perclod/render.h"
#include "perclod/view_record.h"

namespace perclod {

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

}  // namespace perclod
