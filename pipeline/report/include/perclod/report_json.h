// perclod/report_json.h - the stages' results as the JSON reports give them:
// the run report (<stem>_report.json, `perclod run --json`) and the parts
// `perclod simplify --json` prints. The one place a result becomes JSON.
#pragma once

#include <array>
#include <cstddef>
#include <nlohmann/json.hpp>

#include "perclod/judge.h"
#include "perclod/label.h"
#include "perclod/load.h"
#include "perclod/lods.h"
#include "perclod/simplify.h"
#include "perclod/undisplayable.h"

namespace perclod {

// SimplifyStats: triangles per label before and after, vertices, what was
// removed, timings, and with explain the refused half-edges.
nlohmann::json simplify_stats_json(const SimplifyStats& stats);
// Triangles per label (SimplifyStats::triangles_before/after):
// {"perceptible", "imperceptible", "undisplayable", "total"}.
nlohmann::json triangles_per_label_json(const std::array<size_t, 3>& n);

// Adds "undisplayable": "deleted" | "collapsed", "e_undisplayable" (a finite
// bound of kept ones) and, when auto measured it, "undisplayable_exposure".
void add_undisplayable_rule(nlohmann::json& j, const UndisplayableRule& rule);

// Label counts {"perceptible", "imperceptible", "undisplayable"}.
nlohmann::json label_counts_json(const LabelCounts& c);
// What labelling at one distance did: the settings it ran with, per view
// its pixels, labels, timings and agreement, per building its views, and the
// combined labels ("labels_file" and "marking_renders" once written).
nlohmann::json label_report_json(const LabelReport& r);

// One judged view: its name, set and figures ("comparison_image" when written).
nlohmann::json view_figures_json(const ViewFigures& v);
// {"worst": {...}, "limits": {...}, "over_limits": [{"view", "set", "measure", "value", "limit"}]}
nlohmann::json judgement_json(const Judgement& j);
// {"changed_fraction", "ssim_covered", "silhouette_mismatch"}
nlohmann::json worst_figures_json(const WorstFigures& w);
// {"max_changed", "max_silhouette", "min_ssim"}
nlohmann::json fidelity_limits_json(const FidelityLimits& l);

// The run report of make_lods: the model, display, tracer, and per LOD its
// labelling report, bounds, tries, figures per view and judgement.
nlohmann::json lod_set_json(const LodSet& set);

// One model's run as `perclod run` returns it: its file, how it loaded, its
// LODs, and the name of its manifest (beside the LODs).
struct ModelReport {
  std::string model;
  LoadReport load;
  std::string manifest_file;
  LodSet lods;
};
// lod_set_json with "model", "load" and "manifest" added.
nlohmann::json model_report_json(const ModelReport& report);

}  // namespace perclod
