// perclod simplify: one LOD of a model from its per-triangle labels.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <stdexcept>

#include "commands.h"
#include "common.h"
#include "perclod/export.h"
#include "perclod/labels_io.h"
#include "perclod/lod.h"
#include "perclod/simplify.h"

namespace perclod::cli {
namespace {

struct SimplifyArgs {
  ModelArgs model;
  DisplayArgs display;
  std::string labels;
  double distance = 0;
  std::string mode = "paper";
  size_t target = 0;
  std::string out;
  bool json = false;
  bool keep_undisplayable = false;
  SimplifyOptions opt;
};

// Footprint of one pixel at distance d: p(d) = 2 d tan(fov_y / 2) / H.
double pixel_footprint(const DisplayProfile& d, double distance) {
  return 2.0 * distance * std::tan(0.5 * d.fov_y()) / d.height;
}

void run_simplify(SimplifyArgs a) {
  a.opt.mode = parse_simplify_mode(a.mode.c_str());
  const bool labelled = a.opt.mode == SimplifyMode::Paper || a.opt.mode == SimplifyMode::Bounded;
  if (labelled && a.labels.empty())
    throw std::invalid_argument("--mode " + a.mode + " needs --labels FILE (from perclod label)");
  if (a.opt.mode == SimplifyMode::Qem && a.target == 0)
    throw std::invalid_argument("--mode qem needs --target N (triangles)");
  if (!(a.distance > 0) || !std::isfinite(a.distance))
    throw std::invalid_argument("--distance must be positive metres");

  Scene scene = a.model.load(nullptr, a.json);
  std::vector<Label> labels(scene.triangle_count(), Label::Imperceptible);
  if (!a.labels.empty()) {
    LabelFile lf = read_labels(a.labels);
    if (lf.labels.size() != scene.triangle_count())
      throw std::invalid_argument(a.labels + " has " + std::to_string(lf.labels.size()) + " labels but " +
                                  a.model.path + " has " + std::to_string(scene.triangle_count()) +
                                  " triangles (labels from another model or loader settings?)");
    labels = std::move(lf.labels);
  }
  const DisplayProfile display = a.display.profile();
  a.opt.pixel_footprint = pixel_footprint(display, a.distance);
  a.opt.target_triangles = a.target;
  a.opt.delete_undisplayable = !a.keep_undisplayable;
  if (a.out.empty()) a.out = file_stem(a.model.path) + "_" + a.mode + "_" + distance_tag(a.distance) + ".obj";

  SimplifyStats st;
  Scene out = simplify(scene, labels, a.opt, &st);
  auto t0 = std::chrono::steady_clock::now();
  export_scene(out, a.out);
  double t_write = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  if (a.json) {
    nlohmann::json j = {{"model", a.model.path},
                        {"labels", a.labels.empty() ? nlohmann::json(nullptr) : nlohmann::json(a.labels)},
                        {"output", a.out},
                        {"mode", a.mode},
                        {"distance", a.distance},
                        {"pixel_footprint", a.opt.pixel_footprint},
                        {"k", a.opt.k},
                        {"target_triangles", a.target},
                        {"seconds_write", t_write}};
    j.update(simplify_stats_json(st));
    print_json(j);
    return;
  }
  std::printf("output       %s\n", a.out.c_str());
  std::printf("mode         %s at %.1f m (p(d) = %.4f m", a.mode.c_str(), a.distance, a.opt.pixel_footprint);
  if (st.tolerance > 0)
    std::printf(", %s %.4f m", a.opt.mode == SimplifyMode::Cluster ? "cell" : "tolerance", st.tolerance);
  std::printf(")\n");
  std::printf("             %12s %12s %12s %12s\n", "perceptible", "impercept.", "undisplay.", "total");
  std::printf("before       %12zu %12zu %12zu %12zu\n", st.triangles_before[0], st.triangles_before[1],
              st.triangles_before[2], st.total_before());
  std::printf("after        %12zu %12zu %12zu %12zu\n", st.triangles_after[0], st.triangles_after[1],
              st.triangles_after[2], st.total_after());
  std::printf("removed      %zu components, %zu undisplayable triangles, %zu leftover pieces (%zu triangles), "
              "%zu collapses\n",
              st.components_removed, st.undisplayable_faces_deleted, st.pieces_removed, st.pieces_triangles_removed,
              st.collapses);
  if (st.nonmanifold_faces_duplicated || st.degenerate_faces)
    std::printf("input        %zu non-manifold faces and %zu degenerate faces kept on their own vertices\n",
                st.nonmanifold_faces_duplicated, st.degenerate_faces);
  std::printf("displacement max %.3g, mean %.3g of the bounding-box diagonal (%.2f m)\n",
              st.max_displacement_rel, st.mean_displacement_rel, st.bbox_diagonal);
  std::printf("time         %.3f s simplify, %.3f s write\n", st.seconds, t_write);
}

}  // namespace

void register_simplify(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "simplify",
      "Simplify a model for one viewing distance. paper: undisplayable triangles are deleted,\n"
      "then quadric half-edge collapses remove imperceptible triangles until none can go;\n"
      "perceptible triangles stay bit-identical. bounded: collapses of imperceptible and\n"
      "undisplayable triangles, refusing those whose error exceeds k x p(d) (p(d): one\n"
      "pixel's footprint at the distance). qem: plain quadric\n"
      "simplification to --target triangles. cluster: Rossignac-Borrel vertex clustering\n"
      "with cells of k x p(d). Components no view displays are removed outright.");
  auto a = std::make_shared<SimplifyArgs>();
  a->model.add(cmd);
  a->display.add(cmd);
  cmd->add_option("--labels", a->labels, "Labels file written by 'perclod label' (needed by paper and bounded)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--distance", a->distance, "Viewing distance of this LOD (m)")->required();
  cmd->add_option("--mode", a->mode, "paper, bounded, qem or cluster")
      ->check(CLI::IsMember({"paper", "bounded", "qem", "cluster"}))
      ->capture_default_str();
  cmd->add_option("--target", a->target, "qem: triangles to keep");
  cmd->add_option("-k,--k", a->opt.k, "bounded: tolerance, cluster: cell size, in pixels at the distance")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_flag("--constraint-lines", a->opt.constraint_lines,
                "Never collapse edges sharper than --feature-angle (seed 002's constraint lines)");
  cmd->add_option("--feature-angle", a->opt.feature_angle_deg, "Dihedral angle of a feature edge (degrees)")
      ->check(CLI::Range(0.0, 180.0))
      ->capture_default_str();
  cmd->add_flag("--keep-undisplayable", a->keep_undisplayable,
                "paper: collapse undisplayable triangles as the paper does and keep those collapses\n"
                "cannot reach, so closed surfaces stay closed (default: delete them; no pixel of any\n"
                "labelling view reaches them)");
  cmd->add_flag("--preserve-bbox", a->opt.preserve_bbox,
                "cluster: cluster each component alone and keep its bounding box (Belblidia)");
  cmd->add_option("-o,--out", a->out, "Output file, .obj or .glb (default: <model>_<mode>_<D>m.obj)");
  cmd->add_flag("--json", a->json, "Print a JSON report on stdout");
  cmd->callback([a] { run_simplify(*a); });
}

}  // namespace perclod::cli
