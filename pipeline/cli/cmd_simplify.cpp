// perclod simplify: one LOD of a model from its per-triangle labels.
#include <cstdio>
#include <memory>
#include <sstream>
#include <string>

#include "commands.h"
#include "common.h"
#include "perclod/labels_io.h"
#include "perclod/report_json.h"
#include "perclod/simplify_model.h"

namespace perclod::cli {
namespace {

struct SimplifyArgs {
  ModelArgs model;
  DisplayArgs display;
  std::string mode = "fidelity", out = "out";
  size_t target = 0;
  bool json = false;
  bool keep_undisplayable = false, delete_undisplayable = false;  // neither: auto
  double e_undisplayable = -1;  // fidelity: bound of kept undisplayable triangles; < 0 = not given
  SimplifyJob job;
};

void print_table(const SimplifyArgs& a, const SimplifyRun& r) {
  const SimplifyStats& st = r.stats;
  std::printf("output       %s\n", r.lod_file.c_str());
  std::printf("mode         %s at %.1f m (p(d) = %.4f m", a.mode.c_str(), a.job.distance, r.pixel_footprint);
  if (a.job.options.mode == SimplifyMode::Fidelity)
    std::printf(", bounds %.4f m perceptible, %.4f m imperceptible", st.tolerance_perceptible, st.tolerance);
  else if (st.tolerance > 0)
    std::printf(", %s %.4f m", a.job.options.mode == SimplifyMode::Cluster ? "cell" : "tolerance", st.tolerance);
  std::printf(")\n");
  std::printf("             %12s %12s %12s %12s\n", "perceptible", "impercept.", "undisplay.", "total");
  std::printf("before       %12zu %12zu %12zu %12zu\n", st.triangles_before[0], st.triangles_before[1],
              st.triangles_before[2], st.total_before());
  std::printf("after        %12zu %12zu %12zu %12zu\n", st.triangles_after[0], st.triangles_after[1],
              st.triangles_after[2], st.total_after());
  if (r.undisplayable_exposure >= 0)
    std::printf("undisplay.   %.3f%% of the pixels between the labelling views (auto keeps them above %.1f%%): %s\n",
                100 * r.undisplayable_exposure, 100 * kKeepUndisplayableExposure,
                r.options.delete_undisplayable ? "deleted" : "kept, collapsed within the bound");
  std::printf("removed      %zu components, %zu undisplayable triangles, %zu leftover pieces (%zu triangles), "
              "%zu collapses\n",
              st.components_removed, st.undisplayable_faces_deleted, st.pieces_removed, st.pieces_triangles_removed,
              st.collapses);
  if (st.nonmanifold_faces_duplicated || st.degenerate_faces)
    std::printf("input        %zu non-manifold faces and %zu degenerate faces kept on their own vertices\n",
                st.nonmanifold_faces_duplicated, st.degenerate_faces);
  if (st.refused_counted) std::printf("stopped      %s\n", refused_text(st.refused).c_str());
  std::printf("displacement max %.3g, mean %.3g of the bounding-box diagonal (%.2f m)\n",
              st.max_displacement_rel, st.mean_displacement_rel, st.bbox_diagonal);
  std::printf("time         %.3f s simplify, %.3f s write\n", st.seconds, r.write_seconds);
}

void run_simplify(SimplifyArgs a) {
  set_error_files({a.model.path});
  a.job.options.mode = parse_simplify_mode(a.mode.c_str());
  a.job.options.target_triangles = a.target;
  if (a.delete_undisplayable && (a.keep_undisplayable || a.e_undisplayable >= 0))
    throw OptionError("--delete-undisplayable deletes what --keep-undisplayable and --e-undisplayable keep: give one");
  a.job.options.delete_undisplayable = !a.keep_undisplayable && a.e_undisplayable < 0;
  a.job.undisplayable_auto = !a.delete_undisplayable;
  if (a.e_undisplayable >= 0) {
    if (a.job.options.mode != SimplifyMode::Fidelity)
      throw OptionError("--e-undisplayable applies only to --mode fidelity");
    a.job.options.bound_undisplayable_px = a.e_undisplayable;
  }
  a.job.display = a.display.profile();
  a.job.out = output_names_for(a.out, a.model.path);
  a.job.model_file = a.model.path;
  a.job.up = a.model.up_axis();
  if (a.job.options.mode == SimplifyMode::Qem && a.target == 0)
    throw OptionError("--mode qem needs --target N (the number of triangles to keep)");
  if (a.job.options.mode == SimplifyMode::Cluster && a.job.options.explain_stop)
    throw OptionError("--explain applies to the collapse modes (fidelity, paper, bounded, qem), not cluster");
  if (a.job.options.mode != SimplifyMode::Qem && a.target != 0)
    throw OptionError("--target applies only to --mode qem");
  if (simplify_mode_uses_labels(a.job.options.mode) && a.job.labels_file.empty())
    throw OptionError("--mode " + a.mode + " needs --labels FILE (from perclod label)");
  // The labels are read (and checked) before the model loads.
  LabelFile labels;
  if (!a.job.labels_file.empty()) {
    require_file(a.job.labels_file);
    labels = read_labels(a.job.labels_file);
    a.job.labels = &labels;
  }
  Scene scene = a.model.load(nullptr, a.json);
  SimplifyRun r = simplify_model(scene, a.job);
  const bool empty = r.stats.total_after() == 0;
  if (!r.stats.target_reached)
    std::fprintf(stderr, "perclod: warning: %s: qem stopped at %zu triangles, not the target %zu: %s\n",
                 r.lod_file.c_str(), r.stats.total_after(), a.target, r.stats.stop_reason.c_str());
  if (empty)
    std::fprintf(stderr, "perclod: warning: %s: the LOD is empty (no triangle is displayable at %g m)\n",
                 r.lod_file.c_str(), a.job.distance);
  if (!a.json) return print_table(a, r);
  nlohmann::json j = {{"model", a.model.path},
                      {"labels", a.job.labels_file.empty() ? nlohmann::json(nullptr) : nlohmann::json(a.job.labels_file)},
                      {"output", r.lod_file},
                      {"mode", a.mode},
                      {"distance", a.job.distance},
                      {"pixel_footprint", r.pixel_footprint},
                      {"k", a.job.options.k},
                      {"target_triangles", a.target},
                      {"seconds_write", r.write_seconds}};
  if (empty) j["empty"] = true;
  if (r.options.mode == SimplifyMode::Fidelity || r.options.mode == SimplifyMode::Paper)
    add_undisplayable_rule(j, undisplayable_rule_of(r.options, r.undisplayable_exposure));
  j.update(simplify_stats_json(r.stats));
  print_json(j);
}

std::string number(double v) {
  std::ostringstream ss;
  ss << v;
  return ss.str();
}
std::string percent(double fraction) { return number(100 * fraction) + "%"; }

}  // namespace

void register_simplify(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "simplify",
      "Simplify a model for one viewing distance. fidelity (default): quadric half-edge collapses\n"
      "of any triangle, each vertex bounded by its faces' labels: no surface moves more than\n"
      "--e-perceptible (perceptible) or --e-imperceptible (imperceptible) pixels at the distance,\n"
      "nor changes more than a square pixel of area; undisplayable triangles are deleted, unless\n"
      "deleting them would open more than " + percent(kKeepUndisplayableExposure) +
      " of what views between the labelling ones see: then\n"
      "they are kept and collapsed within " + number(kAutoUndisplayableBoundPx) +
      " pixels (--e-undisplayable: always kept, within that many).\n"
      "paper: undisplayable triangles are deleted,\n"
      "then quadric half-edge collapses remove imperceptible triangles until none can go;\n"
      "perceptible triangles stay bit-identical. bounded: collapses of imperceptible and\n"
      "undisplayable triangles, refusing those whose error exceeds k x p(d) (p(d): one\n"
      "pixel's footprint at the distance). qem: plain quadric\n"
      "simplification to --target triangles. cluster: Rossignac-Borrel vertex clustering\n"
      "with cells of k x p(d). Components no view displays are removed outright.");
  auto a = std::make_shared<SimplifyArgs>();
  a->model.add(cmd);
  a->display.add(cmd);
  cmd->add_option("--labels", a->job.labels_file,
                  "Labels file written by 'perclod label' (needed by fidelity, paper and bounded)")
      ->check(kNotEmpty);
  cmd->add_option("--distance,-d", a->job.distance, "Viewing distance of this LOD in metres")
      ->required()
      ->check(kPositive);
  // The options that set a config key take its help from the table of settings.
  cmd->add_option("--mode", a->mode, key_help("simplify", "the config key simplify"))
      ->check(CLI::IsMember({"fidelity", "paper", "bounded", "qem", "cluster"}))
      ->capture_default_str();
  cmd->add_option("--target", a->target,
                  key_help("target", "when it cannot get there, a warning and the JSON's stop_reason say why"));
  cmd->add_option("--e-perceptible", a->job.options.bound_perceptible_px, key_help("e_perceptible"))
      ->check(kNonNegative)
      ->capture_default_str();
  cmd->add_option("--e-imperceptible", a->job.options.bound_imperceptible_px, key_help("e_imperceptible"))
      ->check(kNonNegative)
      ->capture_default_str();
  cmd->add_option("--e-undisplayable", a->e_undisplayable, key_help("e_undisplayable", "default: auto, see above"))
      ->check(kNonNegative);
  cmd->add_option("-k,--k", a->job.options.k, key_help("k"))
      ->check(kPositive)
      ->capture_default_str();
  cmd->add_flag("--constraint-lines", a->job.options.constraint_lines,
                "Never collapse edges sharper than --feature-angle (Shi, Yang, Li's constraint lines)");
  cmd->add_option("--feature-angle", a->job.options.feature_angle_deg, "Dihedral angle of a feature edge (degrees)")
      ->check(in_range(0, 180))
      ->capture_default_str();
  cmd->add_flag("--free-topology,!--manifold", a->job.options.free_topology,
                key_help("free_topology", "--manifold: stop where the half-edge collapses stop"));
  cmd->add_flag("--keep-undisplayable", a->keep_undisplayable,
                key_help("keep_undisplayable", "this flag: true; --delete-undisplayable: false; neither: auto"));
  cmd->add_flag("--delete-undisplayable", a->delete_undisplayable,
                "fidelity: always delete undisplayable triangles (the rule before auto)");
  cmd->add_flag("--preserve-bbox", a->job.options.preserve_bbox,
                "cluster: cluster each component alone and keep its bounding box (Belblidia)");
  cmd->add_option("--out,-o", a->out, "Output directory (created); the LOD is OUT/<model>_lod_<D>m.<format>")
      ->check(kNotEmpty);
  cmd->add_option("--format", a->job.format, key_help("format"))
      ->check(CLI::IsMember({"obj", "glb"}))
      ->capture_default_str();
  cmd->add_flag("--explain", a->job.options.explain_stop,
                key_help("explain", "the table's 'stopped' line, the JSON's 'refused'; one more pass over the mesh"));
  cmd->add_flag("--json", a->json, "Print a JSON report on stdout");
  cmd->callback([a] { run_simplify(*a); });
}

}  // namespace perclod::cli
