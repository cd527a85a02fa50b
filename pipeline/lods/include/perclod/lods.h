// perclod/lods.h - `perclod run` for one model: label, simplify and judge,
// one LOD per distance.
#pragma once

#include <nlohmann/json.hpp>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "perclod/fidelity_search.h"
#include "perclod/judge.h"
#include "perclod/label.h"
#include "perclod/runtime.h"
#include "perclod/simplify.h"
#include "perclod/undisplayable.h"

namespace perclod {

struct LodJob {
  LabelJob label;                      // views, samples, display, perception, ratio, output names
  std::vector<double> distances;
  TracerKind tracer = TracerKind::Octree;
  SimplifyOptions simplify;            // mode, bounds, k, ...; pixel_footprint is set per distance
  std::string lod_format = "obj";      // "obj" or "glb"
  // Held-out views every LOD is also judged from (empty: labelling views only).
  std::vector<std::string> judge_views;
  // When each building was labelled from its own views alone: each
  // building's LOD is judged alone from judge_views framed on it
  // (judge_buildings_alone), not from judge_views framed on the model.
  bool judge_buildings_alone = true;
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

// One try of a fidelity_target search or of tighten_to_limits.
struct LodTry {
  double e_imperceptible = 0, e_perceptible = 0;  // the bounds tried, px
  UndisplayableRule undisplayable;
  size_t triangles = 0;
  double seconds_simplify = 0;
  WorstFigures worst;  // over every judged view
  bool met = false;    // within the search's target (or tighten_to_limits' limits)
  bool kept = false;   // this try's LOD is the one written
};

// What a LOD's tries were.
enum class LodTries { None, TightenToLimits, FidelitySearch };

// One LOD of make_lods: how it was labelled, simplified and judged.
struct LodResult {
  double distance = 0;
  // label_scene's report for this distance (per view: pixels, fractions,
  // agreement, timings; the labels file and marking renders).
  LabelReport labelling;
  double pixel_footprint = 0;  // metres a pixel covers at this distance
  std::string lod_file;
  SimplifyStats simplify;
  bool fidelity_mode = false;  // the bounds below are the fidelity mode's
  double bound_perceptible_px = 0, bound_imperceptible_px = 0;
  UndisplayableRule undisplayable;  // as written, with auto's exposure
  LodTries tries_kind = LodTries::None;
  std::vector<LodTry> tries;
  bool empty = false;               // no triangle of the model displayable here
  std::vector<ViewFigures> views;   // labelling views, then held-out ones
  Judgement fidelity;               // views against the job's limits
  // Judged building by building (LodJob::judge_buildings_alone): how many
  // buildings, how many of them within the limits in every view, how many
  // of them the LOD leaves as they are (BuildingJudged::unchanged: no views)
  // and the views judged. `views` then keeps each building's view with the
  // highest visible_ratio and every view over a limit; `fidelity` is over
  // them all.
  size_t buildings_judged = 0, buildings_within = 0, buildings_unchanged = 0, building_views = 0;
  size_t buildings_tightened = 0;  // of them, made at tighter bounds (tighten_to_limits)
  // fidelity_target with buildings judged alone: how many buildings took
  // each step's bounds (e_imperceptible, undisplayable kept), and how many
  // met the target at none.
  std::map<std::pair<double, bool>, size_t> buildings_searched;
  size_t buildings_unmet = 0;
  // Wall time of the distance, and of its stages: labelling (its steps in
  // labelling.step_seconds), every try's simplification, judging (the
  // held-out views' records, the floors and every try's comparison) and
  // writing the LOD.
  double seconds_compare = 0, seconds = 0;
  double seconds_label = 0, seconds_simplify = 0, seconds_export = 0;
};

// make_lods' result: the model, the job's tools, one LodResult per distance.
struct LodSet {
  size_t triangles = 0, components = 0;
  std::string display_name;
  double display_ppd = 0, display_f_max = 0;
  std::string tracer_name;
  double tracer_build_seconds = 0;
  size_t tracer_memory_bytes = 0;
  std::string simplify_mode;
  std::vector<std::string> judge_views;
  size_t over_limits = 0;  // (view, measure) pairs over a limit, over every LOD
  std::vector<LodResult> lods;  // in job.distances order
  std::vector<std::string> warnings;  // for the caller to print
  double seconds = 0;
};

// What make_lods tells while it works, besides labelling's events;
// perclod/progress_text.h's TextProgress prints them.
class LodProgress : public LabelProgress {
 public:
  virtual void distance_started(double distance) = 0;
  // keep_undisplayable: auto measured `exposure` and chose `rule`.
  virtual void undisplayable_decided(double exposure, const UndisplayableRule& rule) = 0;
  // A try of a search or of tightening (`what` names which) is judged.
  virtual void lod_tried(const char* what, double distance, const LodTry& t) = 0;
  // The LOD of the loosest bounds that met the target is made again.
  virtual void looser_remade() = 0;
  // No tighter bounds were within the limits: the tightest tried is kept.
  virtual void tightening_failed() = 0;
  // Tightening's midway try missed: the LOD of the bounds that met the limits is made again.
  virtual void tightening_midway_missed() = 0;
  // A building's LOD is judged alone (the k-th of n to finish).
  virtual void building_judged(size_t k, size_t n, const BuildingJudged& b, double max_visible) = 0;
  // A LOD is written and judged.
  virtual void lod_made(const LodResult& r) = 0;
};

// One LOD per distance: out.lod(d), out.labels(d), renders and marking
// renders. Each LOD is judged from its labelling views and job.judge_views
// (LodResult::views, and LodResult::fidelity against job.limits).
// A LOD without triangles (nothing displayable at its distance) is still
// written, marked empty and warned about; a LOD over a limit in some view
// adds a warning per view and measure, counted in LodSet::over_limits.
// `lods`, when given, receives each LOD's scene in job.distances order.
// The report (out.report(), perclod/report_json.h) is the caller's to write.
LodSet make_lods(const Scene& scene, const LodJob& job, LodProgress* progress = nullptr,
                 std::vector<Scene>* lods = nullptr);

}  // namespace perclod
