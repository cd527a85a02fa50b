// perclod/lods.h - `perclod run` for one model: label, simplify and judge,
// one LOD per distance.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "perclod/fidelity_search.h"
#include "perclod/judge.h"
#include "perclod/label.h"
#include "perclod/runtime.h"
#include "perclod/simplify.h"

namespace perclod {

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
