// `perclod run` for one model (the method's section 5 and the judging of its
// result): labels, simplifies, exports and compares each LOD with the
// original, one distance at a time.
#include "perclod/lods.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <iterator>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <sstream>
#include <stdexcept>

#include "perclod/export.h"
#include "perclod/image_io.h"
#include "perclod/labels_io.h"
#include "perclod/simplify_model.h"

namespace perclod {
using namespace detail;
namespace {

// What every distance of a job shares: the tracers, the OpenGL context and
// the thread that encodes debug images.
struct JobTools {
  std::unique_ptr<Tracer> tracer;
  // verify: one Embree reference scene for the whole job, not one per distance.
  std::unique_ptr<EmbreeTracer> verify_tracer;
  Renderer renderer;
  // Debug images are encoded on a thread of their own while the next view
  // renders and traces; every one is on disk before make_lods returns.
  ImageWriter images;
};

// The LodSet's description of the model and of the job's tools.
LodSet describe_job(const Scene& scene, const LodJob& job, const Tracer& tracer) {
  LodSet set;
  set.triangles = scene.triangle_count();
  set.components = scene.component_count();
  set.display_name = job.label.display.name;
  set.display_ppd = job.label.display.pixels_per_degree();
  set.display_f_max = job.label.display.f_max();
  set.tracer_name = tracer.name();
  set.tracer_build_seconds = tracer.build_seconds();
  set.tracer_memory_bytes = tracer.memory_bytes();
  set.simplify_mode = simplify_mode_name(job.simplify.mode);
  set.judge_views = job.judge_views;
  return set;
}

// One distance of make_lods: label, then make and judge LODs at the bounds
// the job asks for (or a search or tightening tries), then write the kept one.
class DistanceRun {
 public:
  DistanceRun(const Scene& scene, const LodJob& job, JobTools& tools, LodProgress* progress, double d)
      : scene_(scene), job_(job), tools_(tools), progress_(progress), d_(d) {
    lj_ = job.label;
    lj_.distance = d;
    lj_.images = job.label.overlap ? &tools.images : nullptr;
    // Without held-out views there is nothing to record after the first LOD.
    held_out_recorded_ = job.judge_views.empty();
  }

  LodResult run(LodSet& set, Scene* lod_out);

 private:
  void label();
  void choose_bounds();
  Judgement attempt(const SimplifyOptions& o);
  bool log_try(const Judgement& f, const char* what);
  void search_target();
  void search_buildings();
  SimplifyOptions bounds_per_building(const Buildings& bs, const std::vector<FidelitySearchStep>& step_of,
                                      double kept_within) const;
  SimplifyOptions bounds_per_building(const Buildings& bs, const std::vector<SimplifyOptions>& bounds_of,
                                      double kept_within) const;
  void tighten();
  void write_lod(LodSet& set);
  void judge_written(LodSet& set);
  void keep_telling_views();
  void make_lod(const SimplifyOptions& o);
  void measure_model_floors();
  void compare_model_views();
  void judge_buildings(const std::vector<uint8_t>* only);
  std::vector<ViewFigures> remake_flagged(const SimplifyOptions& o, const std::vector<uint8_t>& flagged);
  void append_building_views();
  void tighten_buildings();
  void finish_buildings(const SimplifyOptions& o, std::vector<BuildingJudged> judged);
  void warn(LodSet& set, const std::string& what) const { set.warnings.push_back(what); }

  const Scene& scene_;
  const LodJob& job_;
  JobTools& tools_;
  LodProgress* progress_;
  const double d_;
  LabelJob lj_;
  LabelResult lr_;
  bool buildings_alone_ = false;  // judge each building alone (LodJob::judge_buildings_alone)
  std::vector<BuildingJudged> buildings_;  // their figures for the LOD in lod_
  BuildingFloors floors_;  // each building's floors, measured at its first judging
  std::vector<ViewRecord> judged_;  // the labelling views, then the held-out ones
  bool held_out_recorded_ = false;
  SimplifyOptions asked_, so_;
  double exposure_ = -1;
  SimplifyStats st_;
  Scene lod_;
  std::vector<ViewFigures> views_;
  std::vector<Rgb8Image> pictures_;  // per judged view: original | LOD | changes
  LodResult r_;
  size_t kept_try_ = 0;     // the try whose LOD is written
  bool try_kept_ = true;    // false: the LOD written is none of the tries (tighten_buildings)
  bool searching_ = false;  // fidelity_target in the fidelity mode
  bool target_met_ = false;
  Clock::time_point started_;
};

LodResult DistanceRun::run(LodSet& set, Scene* lod_out) {
  started_ = Clock::now();
  r_.distance = d_;
  label();
  choose_bounds();
  searching_ = job_.fidelity_target && so_.mode == SimplifyMode::Fidelity;
  if (searching_ && buildings_alone_ && asked_.bound_perceptible_px > 0 && asked_.bound_imperceptible_px > 0)
    search_buildings();
  else if (searching_) search_target();
  else tighten();
  write_lod(set);
  judge_written(set);
  if (lod_out) *lod_out = std::move(lod_);
  return std::move(r_);
}

// Labels the scene at this distance and writes the labels and markings.
void DistanceRun::label() {
  const auto t0 = Clock::now();
  lr_ = label_scene(tools_.renderer, scene_, *tools_.tracer, lj_, progress_, tools_.verify_tracer.get());
  write_label_outputs(tools_.renderer, scene_, lr_, lj_);
  release_free_memory();  // the ID buffers of the marking images
  judged_ = std::move(lr_.views);
  lr_.views.clear();
  r_.seconds_label = since(t0);
  // Buildings labelled from their own views alone are judged so too: the
  // held-out views framed on the model would see all but its front row
  // from further than the distance.
  buildings_alone_ = job_.judge_buildings_alone && !job_.judge_views.empty() && lr_.report.per_building &&
                     !lr_.report.model_views_counted;
  held_out_recorded_ = held_out_recorded_ || buildings_alone_;
  // Labels made by each building's own views alone leave no whole-model
  // view to judge from: without held-out views, the labelling view set
  // framed on the model judges (as it did when those views counted).
  if (judged_.empty() && job_.judge_views.empty()) {
    const auto t_record = Clock::now();
    judged_ = record_views(tools_.renderer, scene_, lj_.views, framing_of(lj_), "labelling");
    r_.seconds_compare += since(t_record);
  }
}

// The asked bounds at this distance, with keep_undisplayable: auto decided.
void DistanceRun::choose_bounds() {
  so_ = job_.simplify;
  so_.pixel_footprint = display_pixel_footprint(lj_.display, d_);
  if (job_.undisplayable_auto && undisplayable_auto_applies(so_)) {
    exposure_ = choose_undisplayable(so_, scene_, *tools_.tracer, lr_.labels, framing_of(lj_));
    if (progress_) progress_->undisplayable_decided(exposure_, undisplayable_rule_of(so_));
  }
  asked_ = so_;
}

// The LOD at the bounds `o` into lod_ (so_, st_ and the time with it).
void DistanceRun::make_lod(const SimplifyOptions& o) {
  so_ = o;
  const auto t_simplify = Clock::now();
  lod_ = simplify(scene_, lr_.labels, so_, &st_);
  release_free_memory();  // the simplifier's mesh
  r_.seconds_simplify += since(t_simplify);
}

// Every judged view's floor, the labelling views' too when there are no
// held-out views (judge_views: none): once, before the first comparison (a
// record's floor is < 0 until measured).
void DistanceRun::measure_model_floors() {
  if (std::none_of(judged_.begin(), judged_.end(), [](const ViewRecord& v) { return v.visible_floor < 0; })) return;
  const auto t_floor = Clock::now();
  measure_floors(tools_.renderer, scene_, judged_, judge_settings_of(lj_));
  r_.seconds_compare += since(t_floor);
}

// lod_ against the model's recorded views (judged_) into views_, with
// their pictures when the job writes view images.
void DistanceRun::compare_model_views() {
  pictures_.clear();
  const bool pictures = !job_.label.out.dir.empty() && lj_.write_view_images;
  views_ = compare_lod_views(tools_.renderer, lod_, judged_, judge_settings_of(lj_), pictures ? &pictures_ : nullptr);
}

// One LOD at the bounds `o`, judged from every judged view against the
// search's target (or the job's limits).
Judgement DistanceRun::attempt(const SimplifyOptions& o) {
  make_lod(o);
  // The held-out views of the original are recorded after the first
  // simplification, so the simplifier's memory and theirs are not needed
  // at once (at 1M triangles each is a few hundred MB).
  if (!held_out_recorded_) {
    const auto t_record = Clock::now();
    std::vector<ViewRecord> held = record_views(tools_.renderer, scene_, job_.judge_views, framing_of(lj_), "held_out");
    std::move(held.begin(), held.end(), std::back_inserter(judged_));
    held_out_recorded_ = true;
    r_.seconds_compare += since(t_record);
  }
  measure_model_floors();
  const auto t_cmp = Clock::now();
  compare_model_views();
  if (buildings_alone_) {
    judge_buildings(nullptr);
    append_building_views();
  }
  r_.seconds_compare += since(t_cmp);
  return judge_views(views_, searching_ ? job_.target : job_.limits);
}

// Lists the try just judged (`f`) in the tries and on the progress line;
// returns whether it met its goal.
bool DistanceRun::log_try(const Judgement& f, const char* what) {
  LodTry t;
  t.e_imperceptible = so_.bound_imperceptible_px;
  t.e_perceptible = so_.bound_perceptible_px;
  t.undisplayable = undisplayable_rule_of(so_);
  t.triangles = st_.total_after();
  t.seconds_simplify = st_.seconds;
  t.worst = f.worst;
  t.met = f.met();
  r_.tries.push_back(t);
  if (progress_) progress_->lod_tried(what, d_, t);
  return t.met;
}

// fidelity_target: down the steps to the first that meets the target, then,
// when that is the loosest, looser bounds while they meet it.
void DistanceRun::search_target() {
  r_.tries_kind = LodTries::FidelitySearch;
  const TargetSearch s = search_fidelity_target([&](const FidelitySearchStep& step, bool looser) {
    const char* what = looser ? "fidelity target, looser" : "fidelity target";
    const bool met = log_try(attempt(fidelity_bounds(asked_, step)), what);
    return std::make_pair(met, st_.total_after());
  });
  target_met_ = s.met;
  kept_try_ = s.kept;
  if (s.remake) {
    if (progress_) progress_->looser_remade();
    attempt(fidelity_bounds(asked_, s.step));
  }
}

// The asked bounds with each building's triangles bounded as
// fidelity_bounds(asked_, step_of[building]) bounds them (bound_scale by
// label); where a building's step keeps undisplayable triangles that the
// asked bounds delete, its own are kept (keep_undisplayable_of) within
// kept_within px, the one bound all such steps share.
SimplifyOptions DistanceRun::bounds_per_building(const Buildings& bs, const std::vector<FidelitySearchStep>& step_of,
                                                 double kept_within) const {
  std::vector<SimplifyOptions> at(step_of.size());
  for (size_t b = 0; b < step_of.size(); ++b) at[b] = fidelity_bounds(asked_, step_of[b]);
  return bounds_per_building(bs, at, kept_within);
}

// The same with each building's bounds given (bounds_of[building]: asked_
// for a building at the asked bounds).
SimplifyOptions DistanceRun::bounds_per_building(const Buildings& bs, const std::vector<SimplifyOptions>& bounds_of,
                                                 double kept_within) const {
  SimplifyOptions o = asked_;
  const size_t nt = scene_.triangle_count();
  o.bound_scale.assign(nt, 1.f);
  std::vector<uint8_t> keep(nt, 0);
  for (size_t t = 0; t < nt; ++t) {
    const SimplifyOptions& a = bounds_of[bs.of_component[scene_.component_of(t)]];
    o.bound_scale[t] = lr_.labels[t] == Label::Perceptible
                           ? float(a.bound_perceptible_px / asked_.bound_perceptible_px)
                           : float(a.bound_imperceptible_px / asked_.bound_imperceptible_px);
    keep[t] = asked_.delete_undisplayable && !a.delete_undisplayable;
  }
  if (kept_within >= 0 && std::count(keep.begin(), keep.end(), 1)) {
    o.keep_undisplayable_of = std::move(keep);
    o.bound_undisplayable_px = kept_within;
  }
  return o;
}

// fidelity_target for buildings judged alone: each building takes the
// loosest bounds that meet the target in every one of its views, as
// search_fidelity_target finds them for a whole model: kFidelitySearch's
// steps in turn for the buildings not yet within the target, then, for
// those within at the loosest, e doubled while they stay within and lose
// triangles (search_looser's rule, building by building). Where the asked
// bounds delete undisplayable triangles, the steps that keep them share the
// first such step's bound (as tighten_buildings). A building within at no
// step keeps the tightest tried. r_.tries lists each pass, its figures over
// the buildings it judged; the LOD is made once more with every building's
// own bounds (components are simplified apart, so each building's LOD is
// the one judged).
void DistanceRun::search_buildings() {
  r_.tries_kind = LodTries::FidelitySearch;
  const Buildings bs = find_buildings(scene_);
  const size_t nb = bs.names.size();
  std::vector<uint8_t> open(nb, 0), loosen(nb, 0);
  for (size_t t = 0; t < scene_.triangle_count(); ++t) open[bs.of_component[scene_.component_of(t)]] = 1;
  std::vector<FidelitySearchStep> step_of(nb, kFidelitySearch[0]);
  std::vector<BuildingJudged> best(nb);
  // Per building: the step that last failed the target (for midway_step).
  std::vector<std::optional<FidelitySearchStep>> failed(nb);
  double kept_within = -1;
  // One pass: the flagged buildings made at their steps and judged; each
  // judged building is handed to `judged`. Logged as a try at step `e`.
  auto pass = [&](const std::vector<uint8_t>& flagged, const FidelitySearchStep& step, const char* what,
                  const std::function<void(const BuildingJudged&, bool)>& judged) {
    const std::vector<ViewFigures> tried = remake_flagged(bounds_per_building(bs, step_of, kept_within), flagged);
    for (const BuildingJudged& b : buildings_) judged(b, judge_views(b.views, job_.target).met());
    const SimplifyOptions o = fidelity_bounds(asked_, step);
    LodTry t;
    t.e_imperceptible = o.bound_imperceptible_px;
    t.e_perceptible = o.bound_perceptible_px;
    // Undisplayable triangles as bounds_per_building treats them.
    t.undisplayable = !asked_.delete_undisplayable ? undisplayable_rule_of(asked_)
                      : step.keep_undisplayable    ? UndisplayableRule{false, kept_within, -1}
                                                   : undisplayable_rule_of(o);
    t.triangles = st_.total_after();
    t.seconds_simplify = st_.seconds;
    const Judgement all = judge_views(tried, job_.target);
    t.worst = all.worst;
    t.met = all.met();
    r_.tries.push_back(t);
    if (progress_) progress_->lod_tried(what, d_, t);
  };
  bool first = true;
  for (const FidelitySearchStep& step : kFidelitySearch) {
    if (std::none_of(open.begin(), open.end(), [](uint8_t o) { return o != 0; })) break;
    const bool keeps = asked_.delete_undisplayable && step.keep_undisplayable;
    const double within = step.e_undisplayable >= 0 ? step.e_undisplayable : step.e;
    if (keeps && kept_within >= 0 && within != kept_within) continue;
    if (keeps) kept_within = within;
    for (size_t b = 0; b < nb; ++b)
      if (open[b]) step_of[b] = step;
    pass(open, step, "fidelity target, building by building", [&](const BuildingJudged& b, bool met) {
      best[b.index] = b;  // the tightest tried stays when none meets the target
      if (!met) {
        failed[b.index] = step;
        return;
      }
      open[b.index] = 0;
      loosen[b.index] = first;
    });
    first = false;
  }
  // Looser bounds for the buildings within the target at the loosest step.
  for (double e = 2 * kFidelitySearch[0].e; e <= kFidelitySearchLoosestPx; e *= 2) {
    if (std::none_of(loosen.begin(), loosen.end(), [](uint8_t l) { return l != 0; })) break;
    const FidelitySearchStep looser{e, false};
    std::vector<FidelitySearchStep> kept = step_of;
    for (size_t b = 0; b < nb; ++b)
      if (loosen[b]) step_of[b] = looser;
    const std::vector<uint8_t> trying = loosen;
    pass(trying, looser, "fidelity target, building by building, looser", [&](const BuildingJudged& b, bool met) {
      const size_t k = b.index;
      if (met && b.lod_triangles <= best[k].lod_triangles) {
        loosen[k] = b.lod_triangles < best[k].lod_triangles;  // as many: kept, and no looser
        best[k] = b;
        return;
      }
      step_of[k] = kept[k];  // over the target, or more triangles: the last kept step
      loosen[k] = 0;
      if (!met) failed[k] = looser;
    });
  }
  // Midway between each building's kept step and the one that failed it,
  // one pass per midway bound.
  std::map<double, std::vector<size_t>> midway;
  for (size_t b = 0; b < nb; ++b)
    if (!open[b] && failed[b] && !best[b].building.empty())
      if (const auto mid = midway_step(step_of[b], *failed[b])) midway[mid->e].push_back(b);
  for (const auto& [e, members] : midway) {
    const FidelitySearchStep mid{e, false};
    std::vector<FidelitySearchStep> kept = step_of;
    std::vector<uint8_t> trying(nb, 0);
    for (size_t b : members) trying[b] = 1, step_of[b] = mid;
    pass(trying, mid, "fidelity target, building by building, midway", [&](const BuildingJudged& b, bool met) {
      const size_t k = b.index;
      if (met && b.lod_triangles <= best[k].lod_triangles)
        best[k] = b;
      else
        step_of[k] = kept[k];
    });
  }
  r_.buildings_unmet = size_t(std::count(open.begin(), open.end(), 1));
  target_met_ = r_.buildings_unmet == 0;
  try_kept_ = false;  // the LOD written mixes the passes' bounds
  std::vector<BuildingJudged> judged;
  r_.buildings_searched.clear();
  for (size_t b = 0; b < nb; ++b) {
    if (best[b].building.empty()) continue;  // no triangles
    ++r_.buildings_searched[{step_of[b].e, step_of[b].keep_undisplayable || !asked_.delete_undisplayable}];
    judged.push_back(std::move(best[b]));
  }
  finish_buildings(bounds_per_building(bs, step_of, kept_within), std::move(judged));
}

// The LOD written when buildings were made at bounds of their own: made at
// `o` (each building's LOD is the one `judged` judged, components being
// simplified apart), `judged` as its buildings' figures, then compared from
// the model's recorded views.
void DistanceRun::finish_buildings(const SimplifyOptions& o, std::vector<BuildingJudged> judged) {
  make_lod(o);
  buildings_ = std::move(judged);
  measure_model_floors();  // measured already unless no LOD was attempted
  const auto t_cmp = Clock::now();
  compare_model_views();
  r_.seconds_compare += since(t_cmp);
  append_building_views();
}

// tighten_to_limits: the asked bounds, then tighter ones while the LOD is
// over the job's limits but within reach of them.
void DistanceRun::tighten() {
  const Judgement f = attempt(asked_);
  if (buildings_alone_) {
    if (job_.tighten_to_limits && !f.met()) tighten_buildings();
    return;
  }
  if (!job_.tighten_to_limits) return;
  const TighteningResult t =
      tighten_to_limits(asked_, f, job_.limits, [&](const SimplifyOptions& o, bool midway) {
        if (r_.tries.empty()) log_try(f, "tighten to limits");  // the asked LOD first, while it is so_ and st_
        const bool met = log_try(attempt(o), midway ? "tighten to limits, midway" : "tighten to limits");
        return std::pair<bool, size_t>(met, st_.total_after());
      });
  if (t.outcome == Tightening::NotTried) return;
  r_.tries_kind = LodTries::TightenToLimits;
  kept_try_ = 1 + t.kept_try;  // r_.tries begins with the asked LOD
  if (progress_ && t.outcome == Tightening::NoneWithin) progress_->tightening_failed();
  if (progress_ && t.outcome == Tightening::Met && t.remake) progress_->tightening_midway_missed();
  // The kept LOD made again rather than held through the tries (its
  // comparison pictures take up to 1.4 MB per judged view, 88 views for the
  // million-triangle facade at 56 m): the simplifier and the judge are
  // deterministic, so it is the same.
  if (t.remake) attempt(t.kept);
}

// Exports the kept LOD and records how it was made.
void DistanceRun::write_lod(LodSet& set) {
  r_.lod_file = job_.label.out.lod(d_, job_.lod_format);
  const auto t_export = Clock::now();
  export_scene(lod_, r_.lod_file, ExportOptions{job_.label.up == UpAxis::Z});
  r_.seconds_export = since(t_export);
  r_.labelling = std::move(lr_.report);
  r_.pixel_footprint = so_.pixel_footprint;
  r_.simplify = st_;
  r_.fidelity_mode = so_.mode == SimplifyMode::Fidelity;
  r_.bound_perceptible_px = so_.bound_perceptible_px;
  r_.bound_imperceptible_px = so_.bound_imperceptible_px;
  r_.undisplayable = undisplayable_rule_of(so_, exposure_);
  if (!r_.tries.empty() && try_kept_) r_.tries[kept_try_].kept = true;
  if (searching_ && !target_met_ && r_.buildings_unmet) {
    std::ostringstream ss;
    ss << r_.lod_file << ": " << r_.buildings_unmet << " of " << r_.buildings_judged
       << " buildings meet the fidelity target at no bound at " << d_ << " m; they keep the tightest tried";
    warn(set, ss.str());
  } else if (searching_ && !target_met_) {
    std::ostringstream ss;
    ss << r_.lod_file << ": no bound meets the fidelity target at " << d_ << " m; kept the tightest (e_imperceptible "
       << so_.bound_imperceptible_px << " px, undisplayable " << undisplayable_rule_text(undisplayable_rule_of(so_)) << ")";
    warn(set, ss.str());
  }
  if (st_.total_after() == 0) {
    // Nothing displayable at this distance: the LOD file holds no triangle.
    r_.empty = true;
    std::ostringstream ss;
    ss << r_.lod_file << ": the LOD at " << d_ << " m is empty (no triangle of the model is displayable there)";
    warn(set, ss.str());
  }
}

// The written LOD's pictures and figures against the job's limits, a warning
// per view and measure over them, and the progress line.
void DistanceRun::judge_written(LodSet& set) {
  for (size_t k = 0; k < pictures_.size(); ++k) {
    const std::string file = job_.label.out.view(views_[k].view, d_, "_lod_vs_original.png");
    write_png_via(lj_.images, file, pictures_[k].width, pictures_[k].height, 3, std::move(pictures_[k].pixels));
    views_[k].comparison_image = file;
  }
  r_.views = std::move(views_);
  r_.fidelity = judge_views(r_.views, job_.limits);
  if (buildings_alone_) keep_telling_views();
  for (const OverLimit& o : r_.fidelity.over_limits) {
    std::ostringstream ss;
    ss.precision(3);
    const bool figure = o.measure == "ssim_covered" || o.measure == "visible_ratio" ||
                        o.measure == "visible_local_ratio";  // not a fraction
    ss << r_.lod_file << ": from view " << o.view << " (" << o.set << ") " << o.measure << " is ";
    if (figure) ss << std::setprecision(4) << o.value << " (limit " << o.limit << ")";
    else ss << 100 * o.value << "% (limit " << 100 * o.limit << "%)";
    // How visible the change is beside moving the original a quarter pixel,
    // so a reader can tell a real change from aliasing.
    if (o.measure != "visible_ratio" && o.measure != "visible_local_ratio")
      for (const ViewFigures& v : r_.views)
        if (v.view == o.view && v.set == o.set && v.visible_floor >= 0)
          ss << std::setprecision(2) << "; visible difference " << v.visible_ratio << "x the quarter-pixel floor";
    warn(set, ss.str());
    ++set.over_limits;
  }
  r_.seconds = since(started_);
  if (progress_) progress_->lod_made(r_);
}

// Each building of the LOD in lod_ judged alone (all, or those `only`
// flags) into buildings_.
void DistanceRun::judge_buildings(const std::vector<uint8_t>* only) {
  const double max_visible = (searching_ ? job_.target : job_.limits).max_visible;
  buildings_ = judge_buildings_alone(
      scene_, lod_, job_.judge_views, framing_of(lj_), judge_settings_of(lj_), building_lanes(lj_),
      [&](size_t k, size_t n, const BuildingJudged& b) {
        if (progress_) progress_->building_judged(k, n, b, max_visible);
      },
      only, &floors_);
}

// The LOD made at `o` and the `flagged` buildings judged alone into
// buildings_ (their judging counted in the LOD's); returns all their views.
std::vector<ViewFigures> DistanceRun::remake_flagged(const SimplifyOptions& o, const std::vector<uint8_t>& flagged) {
  make_lod(o);
  const auto t_judge = Clock::now();
  judge_buildings(&flagged);
  r_.seconds_compare += since(t_judge);
  std::vector<ViewFigures> views;
  for (const BuildingJudged& b : buildings_) views.insert(views.end(), b.views.begin(), b.views.end());
  return views;
}

// buildings_' views after the model's in views_, and their counts.
void DistanceRun::append_building_views() {
  r_.buildings_judged = buildings_.size();
  r_.buildings_within = 0;
  r_.buildings_unchanged = 0;
  r_.building_views = 0;
  for (const BuildingJudged& b : buildings_) {
    r_.buildings_within += judge_views(b.views, job_.limits).met();
    r_.buildings_unchanged += b.unchanged;
    r_.building_views += b.views.size();
    views_.insert(views_.end(), b.views.begin(), b.views.end());
  }
}

// tighten_to_limits for buildings judged alone: the buildings over the
// limits are made again at each of tighten_steps in turn (their triangles
// bounded as tightened_bounds bounds them: bounds_per_building), and judged
// again; each keeps the first that brings it within the limits in every
// view, or the tightest it was tried at when none does. The steps below
// kTightenHalvingsTo are tried only for the buildings within reach of the
// limits at the asked bounds (worth_tightening). The other buildings'
// bounds, and so their LODs, stay as asked: components are simplified
// apart. r_.tries lists the asked LOD and each step's, their figures over
// the buildings tried.
void DistanceRun::tighten_buildings() {
  const std::vector<FidelitySearchStep> steps = tighten_steps(asked_);
  if (steps.empty() || !(asked_.bound_imperceptible_px > 0)) return;
  const Buildings bs = find_buildings(scene_);
  const size_t nb = bs.names.size();
  std::vector<uint8_t> trying(nb, 0);
  std::vector<uint8_t> in_reach(nb, 0);  // worth_tightening: may take the steps that need it
  std::vector<size_t> at(nb, 0);  // building -> its entry of buildings_
  std::vector<ViewFigures> over;  // the views of the buildings to tighten
  for (size_t k = 0; k < buildings_.size(); ++k) {
    const size_t b = buildings_[k].index;
    const Judgement j = judge_views(buildings_[k].views, job_.limits);
    at[b] = k;
    in_reach[b] = worth_tightening(j, job_.limits);
    if (j.met() || (!in_reach[b] && tighten_step_needs_reach(steps.front()))) continue;
    trying[b] = 1;
    over.insert(over.end(), buildings_[k].views.begin(), buildings_[k].views.end());
  }
  if (over.empty()) return;
  // A try as the tried buildings were made: their bounds, and their undisplayable rule.
  auto log = [&](const SimplifyOptions& o, const UndisplayableRule& rule, const WorstFigures& w, bool met) {
    LodTry t;
    t.e_imperceptible = o.bound_imperceptible_px;
    t.e_perceptible = o.bound_perceptible_px;
    t.undisplayable = rule;
    t.triangles = st_.total_after();
    t.seconds_simplify = st_.seconds;
    t.worst = w;
    t.met = met;
    r_.tries.push_back(t);
    if (progress_) progress_->lod_tried("tighten the buildings over the limits", d_, t);
  };
  r_.tries_kind = LodTries::TightenToLimits;
  log(asked_, undisplayable_rule_of(asked_), judge_views(over, job_.limits).worst, false);
  std::vector<BuildingJudged> best = buildings_;
  std::vector<SimplifyOptions> bounds(nb, asked_);  // each building's, as made now
  // Where the asked bounds delete undisplayable triangles, a step that keeps
  // them keeps the tried buildings' (keep_undisplayable_of), within the
  // first such step's bound: a later step's other bound would move those of
  // the buildings that met the limits before it.
  double kept_within = -1;
  size_t fixed = 0;
  std::vector<double> met_at(nb, 0);  // the step's e a building met the limits at
  for (const FidelitySearchStep& step : steps) {
    if (tighten_step_needs_reach(step)) {  // the buildings out of reach stop at the tightest halving
      for (size_t b = 0; b < nb; ++b)
        if (trying[b] && !in_reach[b]) trying[b] = 0;
      if (std::none_of(trying.begin(), trying.end(), [](uint8_t t) { return t != 0; })) break;
    }
    const SimplifyOptions at_step = tightened_bounds(asked_, step);
    const bool keeps = asked_.delete_undisplayable && !at_step.delete_undisplayable;
    if (keeps && kept_within >= 0 && at_step.bound_undisplayable_px != kept_within) continue;
    if (keeps) kept_within = at_step.bound_undisplayable_px;
    for (size_t b = 0; b < nb; ++b)
      if (trying[b]) bounds[b] = at_step;
    const std::vector<ViewFigures> tried = remake_flagged(bounds_per_building(bs, bounds, kept_within), trying);
    for (const BuildingJudged& b : buildings_) {
      best[at[b.index]] = b;  // the one within, or the tightest so far
      if (!judge_views(b.views, job_.limits).met()) continue;
      trying[b.index] = 0;
      met_at[b.index] = step.e;
      ++fixed;
    }
    const Judgement all = judge_views(tried, job_.limits);
    log(at_step, keeps ? UndisplayableRule{false, kept_within, -1} : undisplayable_rule_of(asked_), all.worst,
        all.met());
    if (all.met()) break;
  }
  // Each building tried keeps in bounds[] the bounds it met the limits at
  // or, when it met them at none, the tightest it was tried at (a building
  // stops being tried, and its bounds stop changing, at either). When every
  // building tried met the limits at the last step, the LOD written is that
  // try's; otherwise it is none of them.
  kept_try_ = r_.tries.size() - 1;
  try_kept_ = r_.tries.back().met;
  // The buildings that met the limits at a halving: once more at the
  // midway step (tighten_midway), all in one pass (each its own bounds),
  // each keeping it when within the limits with no more triangles.
  std::vector<uint8_t> midway(nb, 0);
  const std::vector<SimplifyOptions> before_midway = bounds;
  SimplifyOptions shown;  // logged: the first midway building's bounds
  size_t n_midway = 0;
  for (size_t b = 0; b < nb; ++b)
    if (met_at[b] > 0)
      if (const auto mid = tighten_midway(asked_, met_at[b])) {
        bounds[b] = tightened_bounds(asked_, *mid);
        if (!n_midway++) shown = bounds[b];
        midway[b] = 1;
      }
  if (n_midway) {
    const std::vector<ViewFigures> tried = remake_flagged(bounds_per_building(bs, bounds, kept_within), midway);
    size_t kept = 0;
    for (const BuildingJudged& b : buildings_) {
      if (judge_views(b.views, job_.limits).met() && b.lod_triangles <= best[at[b.index]].lod_triangles) {
        best[at[b.index]] = b;
        ++kept;
      } else {
        bounds[b.index] = before_midway[b.index];
      }
    }
    const Judgement all = judge_views(tried, job_.limits);
    log(shown, undisplayable_rule_of(asked_), all.worst, all.met());
    // The midway try's LOD is the one written when every building took it
    // and every other building tried had met the limits before.
    const bool all_midway = try_kept_ && kept == n_midway;
    if (all_midway) kept_try_ = r_.tries.size() - 1;
    try_kept_ = all_midway;
  }
  // The LOD is made once more with every building's own bounds.
  r_.buildings_tightened = fixed;
  if (progress_ && !fixed) progress_->tightening_failed();
  finish_buildings(bounds_per_building(bs, bounds, kept_within), std::move(best));
}

// Of the views of buildings judged alone (after the model's), r_.views
// keeps each building's with the highest visible_ratio and every one over a
// limit: a district's report lists its buildings, not nine views of each.
void DistanceRun::keep_telling_views() {
  std::set<std::string> over;
  for (const OverLimit& o : r_.fidelity.over_limits) over.insert(o.view);
  std::map<std::string, size_t> worst;  // building -> index of its worst view
  for (size_t k = 0; k < r_.views.size(); ++k) {
    const ViewFigures& v = r_.views[k];
    if (v.building.empty()) continue;
    auto [it, added] = worst.emplace(v.building, k);
    if (!added && v.visible_ratio > r_.views[it->second].visible_ratio) it->second = k;
  }
  std::vector<uint8_t> keep(r_.views.size(), 0);
  for (const auto& [building, k] : worst) keep[k] = 1;
  std::vector<ViewFigures> kept;
  for (size_t k = 0; k < r_.views.size(); ++k)
    if (r_.views[k].building.empty() || keep[k] || over.count(r_.views[k].view))
      kept.push_back(std::move(r_.views[k]));
  r_.views = std::move(kept);
}

}  // namespace

LodSet make_lods(const Scene& scene, const LodJob& job, LodProgress* progress, std::vector<Scene>* lods) {
  if (job.distances.empty()) throw std::invalid_argument("no viewing distance given");
  if (job.lod_format != "obj" && job.lod_format != "glb")
    throw std::invalid_argument("LOD format must be obj or glb, not '" + job.lod_format + "'");
  OutputDirectoryLock lock(job.label.out.dir);
  const auto t_all = Clock::now();
  // Labelling and held-out views at every distance, before any work.
  const Bounds bounds = scene_bounds(scene);
  check_framing(bounds, job.label.up, job.label.display, job.label.views, job.distances);
  check_framing(bounds, job.label.up, job.label.display, job.judge_views, job.distances);
  JobTools tools;
  tools.tracer = make_tracer(scene, job.tracer);
  if (job.label.verify) tools.verify_tracer = std::make_unique<EmbreeTracer>(scene, EmbreeMode::Verify);
  if (progress) progress->tracer_built(*tools.tracer);
  LodSet set = describe_job(scene, job, *tools.tracer);
  for (double d : job.distances) {
    if (progress) progress->distance_started(d);
    Scene lod;
    set.lods.push_back(DistanceRun(scene, job, tools, progress, d).run(set, lods ? &lod : nullptr));
    if (lods) lods->push_back(std::move(lod));
  }
  tools.images.finish();
  set.seconds = since(t_all);
  return set;
}

}  // namespace perclod
