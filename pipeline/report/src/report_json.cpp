// The stages' results as JSON (perclod/report_json.h). Keys are written as
// the reports have always named them; nlohmann::json keeps them sorted.
#include "perclod/report_json.h"

#include <array>
#include <cmath>
#include <string>

namespace perclod {
namespace {

nlohmann::json agreement_json(const Agreement& a) {
  return {{"covered", a.covered},
          {"identical", a.identical},
          {"ties", a.ties},
          {"edge_grazes", a.edge_grazes},
          {"real_disagreements", a.real_disagreements},
          {"identical_rate", a.identical_rate()}};
}

nlohmann::json view_labelling_json(const ViewLabelling& v) {
  nlohmann::json seconds = nlohmann::json::object();
  for (const auto& [step, s] : v.seconds) seconds[step] = s;
  nlohmann::json j = {{"view", v.view},
                      {"rendered_pixels", v.rendered_pixels},
                      {"covered_pixels", v.covered_pixels},
                      {"imperceptible_fraction", v.imperceptible_fraction},
                      {"levels", v.levels},
                      {"labels", label_counts_json(v.labels)},
                      {"unsampled_surface", v.unsampled_surface},
                      {"seconds", std::move(seconds)}};
  if (v.rays_vs_id_buffer) j["rays_vs_id_buffer"] = agreement_json(*v.rays_vs_id_buffer);
  if (v.octree_vs_embree) j["octree_vs_embree"] = agreement_json(*v.octree_vs_embree);
  if (!v.sampling.empty()) j["sampling"] = v.sampling;
  if (v.passes) j["passes"] = v.passes;
  return j;
}

nlohmann::json building_labelling_json(const BuildingLabelling& b, bool automatic) {
  nlohmann::json j = {{"building", b.building},
                      {"views", b.views},
                      {"rendered_pixels", b.rendered_pixels},
                      {"eyes_inside_other_buildings", b.eyes_inside_other_buildings},
                      {"seconds", b.seconds}};
  if (b.buildings > 1) {  // a group, named by its first building
    j["buildings"] = b.buildings;
    j["own_views"] = b.own_views;
    j["members_alone"] = b.members_alone;
  }
  if (automatic) j["sampling_chosen"] = b.sampling_chosen;
  return j;
}

nlohmann::json try_json(const LodTry& t) {
  nlohmann::json j = {{"e_imperceptible", t.e_imperceptible},
                      {"e_perceptible", t.e_perceptible},
                      {"triangles", t.triangles},
                      {"seconds_simplify", t.seconds_simplify},
                      {"worst", worst_figures_json(t.worst)},
                      {"met", t.met}};
  add_undisplayable_rule(j, t.undisplayable);
  if (t.kept) j["kept"] = true;
  return j;
}

nlohmann::json lod_json(const LodResult& r) {
  nlohmann::json entry = label_report_json(r.labelling);
  entry["pixel_footprint"] = r.pixel_footprint;
  entry["lod_file"] = r.lod_file;
  entry["simplify"] = simplify_stats_json(r.simplify);
  if (r.fidelity_mode) {
    entry["bounds_px"] = {{"perceptible", r.bound_perceptible_px}, {"imperceptible", r.bound_imperceptible_px}};
    add_undisplayable_rule(entry["bounds_px"], r.undisplayable);
  }
  if (r.tries_kind != LodTries::None) {
    nlohmann::json tries = nlohmann::json::array();
    for (const LodTry& t : r.tries) tries.push_back(try_json(t));
    entry[r.tries_kind == LodTries::FidelitySearch ? "fidelity_search" : "tighten_to_limits"] = std::move(tries);
  }
  if (r.empty) entry["empty"] = true;
  nlohmann::json views = nlohmann::json::array();
  for (const ViewFigures& v : r.views) views.push_back(view_figures_json(v));
  entry["lod_vs_original"] = std::move(views);
  entry["fidelity"] = judgement_json(r.fidelity);
  if (r.buildings_judged)
    entry["judged_alone"] = {{"buildings", r.buildings_judged},
                             {"within_limits", r.buildings_within},
                             {"unchanged", r.buildings_unchanged},
                             {"tightened", r.buildings_tightened},
                             {"views", r.building_views}};
  if (!r.buildings_searched.empty()) {
    // Loosest first, as the search went.
    nlohmann::json steps = nlohmann::json::array();
    for (auto it = r.buildings_searched.rbegin(); it != r.buildings_searched.rend(); ++it)
      steps.push_back({{"e_imperceptible", it->first.first},
                       {"keep_undisplayable", it->first.second},
                       {"buildings", it->second}});
    entry["judged_alone"]["searched"] = {{"steps", std::move(steps)}, {"unmet", r.buildings_unmet}};
  }
  entry["seconds_compare"] = r.seconds_compare;
  entry["seconds"] = r.seconds;
  // Wall time per stage; render, perceive and trace are thread time summed
  // over the labelling views (a render overlaps the previous view's trace).
  nlohmann::json stages = {{"label", r.seconds_label},
                           {"label_buildings", r.labelling.seconds_buildings},
                           {"simplify", r.seconds_simplify},
                           {"judge", r.seconds_compare},
                           {"export", r.seconds_export}};
  for (const auto& [step, s] : r.labelling.step_seconds) stages[step] = s;
  entry["stage_seconds"] = std::move(stages);
  return entry;
}

}  // namespace

nlohmann::json simplify_stats_json(const SimplifyStats& s) {
  nlohmann::json j = {{"triangles_before", triangles_per_label_json(s.triangles_before)},
                      {"triangles_after", triangles_per_label_json(s.triangles_after)},
                      {"total_before", s.total_before()},
                      {"total_after", s.total_after()},
                      {"vertices_before", s.vertices_before},
                      {"vertices_after", s.vertices_after},
                      {"components_removed", s.components_removed},
                      {"pieces_removed", s.pieces_removed},
                      {"pieces_triangles_removed", s.pieces_triangles_removed},
                      {"undisplayable_faces_deleted", s.undisplayable_faces_deleted},
                      {"nonmanifold_faces_duplicated", s.nonmanifold_faces_duplicated},
                      {"degenerate_faces", s.degenerate_faces},
                      {"collapses", s.collapses},
                      {"free_collapses", s.free_collapses},
                      {"chunks", s.chunks},
                      {"tolerance", s.tolerance},
                      {"tolerance_perceptible", s.tolerance_perceptible},
                      {"target_reached", s.target_reached},
                      {"stop_reason", s.stop_reason},
                      {"max_error", s.max_error},
                      {"cluster_dangling_edges", s.cluster_dangling_edges},
                      {"cluster_isolated_points", s.cluster_isolated_points},
                      {"max_displacement_rel", s.max_displacement_rel},
                      {"mean_displacement_rel", s.mean_displacement_rel},
                      {"bbox_diagonal", s.bbox_diagonal},
                      {"seconds", s.seconds}};
  if (s.refused_counted) {
    const SimplifyStats::Refused& r = s.refused;
    j["refused"] = {{"bound_or_locked", r.bound_or_locked}, {"valence", r.valence}, {"topology", r.topology},
                    {"shape", r.shape}, {"legal", r.legal}, {"total", r.total()}};
  }
  return j;
}

nlohmann::json label_counts_json(const LabelCounts& c) {
  return {{"perceptible", c.perceptible}, {"imperceptible", c.imperceptible}, {"undisplayable", c.undisplayable}};
}

nlohmann::json label_report_json(const LabelReport& r) {
  nlohmann::json j = {{"distance", r.distance},
                      {"tracer", r.tracer},
                      {"samples_per_pixel", samples_json(r.samples)},
                      {"combine_views", r.combine_views},
                      {"keep_unsampled_surface", r.keep_unsampled_surface},
                      {"view_images", r.view_images},
                      {"views", nlohmann::json::array()},
                      {"labels", label_counts_json(r.labels)},
                      {"outside_views", r.outside_views}};
  if (r.mask_per_sample) j["mask_per_sample"] = true;
  if (r.sample_grid) j["sample_grid"] = r.sample_grid;
  if (r.automatic) j["sampling_chosen"] = r.sampling_chosen;
  for (const ViewLabelling& v : r.views) j["views"].push_back(view_labelling_json(v));
  if (r.per_building) {
    j["model_views_counted"] = r.model_views_counted;
    j["per_building"] = nlohmann::json::array();
    for (const BuildingLabelling& b : r.buildings) j["per_building"].push_back(building_labelling_json(b, r.automatic));
  }
  if (!r.labels_file.empty()) j["labels_file"] = r.labels_file;
  if (r.markings_written) j["marking_renders"] = r.marking_renders;
  if (r.tracer_build_seconds >= 0) j["tracer_build_seconds"] = r.tracer_build_seconds;
  return j;
}

void add_undisplayable_rule(nlohmann::json& j, const UndisplayableRule& rule) {
  j["undisplayable"] = rule.deleted ? "deleted" : "collapsed";
  if (!rule.deleted && std::isfinite(rule.bound_px)) j["e_undisplayable"] = rule.bound_px;
  if (rule.exposure >= 0) j["undisplayable_exposure"] = rule.exposure;  // keep_undisplayable: auto decided
}

nlohmann::json view_figures_json(const ViewFigures& v) {
  nlohmann::json j = {{"view", v.view},
                      {"set", v.set},
                      {"drawn_pixels", v.drawn_pixels},
                      {"changed_pixels", v.changed_pixels},
                      {"changed_fraction", v.changed_fraction},
                      {"ssim_covered", v.ssim_covered},
                      {"covered_pixels_original", v.covered_pixels_original},
                      {"coverage_changed_pixels", v.coverage_changed_pixels},
                      {"silhouette_mismatch", v.silhouette_mismatch},
                      {"visible_difference", v.visible_difference},
                      {"visible_floor", v.visible_floor},
                      {"visible_ratio", v.visible_ratio},
                      {"visible_local", v.visible_local},
                      {"visible_floor_local", v.visible_floor_local},
                      {"visible_local_ratio", v.visible_local_ratio}};
  if (!v.building.empty()) j["building"] = v.building;
  if (!v.comparison_image.empty()) j["comparison_image"] = v.comparison_image;
  return j;
}

nlohmann::json triangles_per_label_json(const std::array<size_t, 3>& n) {
  return {{"perceptible", n[0]}, {"imperceptible", n[1]}, {"undisplayable", n[2]}, {"total", n[0] + n[1] + n[2]}};
}

nlohmann::json worst_figures_json(const WorstFigures& w) {
  return {{"changed_fraction", w.changed_fraction},
          {"ssim_covered", w.ssim_covered},
          {"silhouette_mismatch", w.silhouette_mismatch},
          {"visible_ratio", w.visible_ratio},
          {"visible_local_ratio", w.visible_local_ratio}};
}

nlohmann::json fidelity_limits_json(const FidelityLimits& l) {
  return {{"max_changed", l.max_changed},
          {"max_silhouette", l.max_silhouette},
          {"min_ssim", l.min_ssim},
          {"max_visible", l.max_visible},
          {"max_visible_local", l.max_visible_local}};
}

nlohmann::json judgement_json(const Judgement& j) {
  nlohmann::json over = nlohmann::json::array();
  for (const OverLimit& o : j.over_limits)
    over.push_back({{"view", o.view}, {"set", o.set}, {"measure", o.measure}, {"value", o.value}, {"limit", o.limit}});
  return {{"worst", worst_figures_json(j.worst)},
          {"limits", fidelity_limits_json(j.limits)},
          {"over_limits", std::move(over)}};
}

nlohmann::json lod_set_json(const LodSet& set) {
  nlohmann::json report = {
      {"triangles", set.triangles},
      {"components", set.components},
      {"display", {{"name", set.display_name}, {"ppd", set.display_ppd}, {"f_max", set.display_f_max}}},
      {"tracer",
       {{"name", set.tracer_name},
        {"build_seconds", set.tracer_build_seconds},
        {"memory_bytes", set.tracer_memory_bytes}}},
      {"simplify_mode", set.simplify_mode},
      {"judge_views", set.judge_views},
      {"over_limits", set.over_limits},
      {"lods", nlohmann::json::array()}};
  for (const LodResult& r : set.lods) report["lods"].push_back(lod_json(r));
  if (!set.warnings.empty()) report["warnings"] = set.warnings;
  report["seconds"] = set.seconds;
  return report;
}

nlohmann::json model_report_json(const ModelReport& r) {
  nlohmann::json j = lod_set_json(r.lods);
  j["model"] = r.model;
  j["load"] = load_report_json(r.load);
  j["manifest"] = r.manifest_file;
  return j;
}

}  // namespace perclod
