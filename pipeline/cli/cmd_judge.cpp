// perclod judge ORIGINAL LOD -d D: a LOD made by perclod or any other tool,
// judged against the original from views framed on the original.
#include <cstdio>
#include <memory>
#include <stdexcept>
#include <string>

#include "commands.h"
#include "common.h"
#include "perclod/judge.h"
#include "perclod/report_json.h"

namespace perclod::cli {
namespace {

struct JudgeArgs {
  ModelArgs model;
  DisplayArgs display;
  std::string lod;
  std::vector<double> distances;
  std::string views = kDefaultJudgeViews;
  double max_visible = 1;
  bool strict = false, json = false;
};

// Returns whether every view is within max_visible.
bool judge(const JudgeArgs& a) {
  set_error_files({a.model.path, a.lod});
  LabelJob job;  // the framing and perception a run would judge with
  job.up = a.model.up_axis();
  job.display = a.display.profile();
  job.perception = perception_settings_for(job.display);
  const std::vector<std::string> views = views_option(a.views, job.up);
  const std::vector<double> distances = check_distances(a.distances);
  const Scene original = a.model.load();
  LoadOptions lo;  // the LOD in the original's frame: both files' source coordinates agree
  lo.scale = a.model.scale;
  lo.centre = original.offset;
  const Scene lod = load_model(a.lod, lo);
  FidelityLimits limits;
  limits.max_visible = a.max_visible;
  Renderer renderer;
  nlohmann::json out = {{"model", a.model.path}, {"lod", a.lod}, {"triangles", original.triangle_count()},
                        {"lod_triangles", lod.triangle_count()}, {"distances", nlohmann::json::array()}};
  bool within = true;
  for (double d : distances) {
    job.distance = d;
    std::vector<ViewRecord> records = record_views(renderer, original, views, framing_of(job), "judged");
    measure_floors(renderer, original, records, judge_settings_of(job));
    const std::vector<ViewFigures> figures = compare_lod_views(renderer, lod, records, judge_settings_of(job));
    const Judgement j = judge_views(figures, limits);
    within &= j.met();
    std::fprintf(stderr,
                 "%g m: worst of %zu views: visible %.3gx the floor, %.3g%% changed, SSIM %.4f, silhouette %.3g%%%s\n",
                 d, figures.size(), j.worst.visible_ratio, 100 * j.worst.changed_fraction, j.worst.ssim_covered,
                 100 * j.worst.silhouette_mismatch, j.met() ? "" : " (over the limit)");
    nlohmann::json v = nlohmann::json::array();
    for (const ViewFigures& f : figures) v.push_back(view_figures_json(f));
    out["distances"].push_back({{"distance", d}, {"views", std::move(v)}, {"fidelity", judgement_json(j)}});
  }
  if (a.json) print_json(out);
  return within;
}

}  // namespace

void register_judge(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "judge",
      "Judge a LOD (made by perclod or any tool) against the original as run judges its own: from views framed on "
      "the original, changed pixels, SSIM, silhouette and the visible difference over its quarter-pixel floor");
  auto a = std::make_shared<JudgeArgs>();
  a->model.add(cmd);
  cmd->add_option("LOD", a->lod, "The LOD's file, in the original's source coordinates (OBJ, GLB, ...)")
      ->required()
      ->check(CLI::ExistingFile);
  a->display.add(cmd);
  cmd->add_option("--distance,-d", a->distances, "Viewing distance(s) in metres, e.g. -d 56 -d 132 or -d 56,132")
      ->required()
      ->delimiter(',');
  cmd->add_option("--views,-f", a->views,
                  "Views to judge from, framed on the original: presets and views as for --views of run "
                  "(docs/usage.md#view-sets) (default held_out)");
  cmd->add_option("--max-visible", a->max_visible, key_help("max_visible", key_default("max_visible")))
      ->check(kNonNegative);
  cmd->add_flag("--strict", a->strict, "Exit 1 when a view's visible ratio is over --max-visible");
  cmd->add_flag("--json", a->json, "Print every view's figures and the worst on stdout");
  cmd->footer(
      "Prints the worst figures per distance on stderr (docs/usage.md#judging-a-lod-from-elsewhere). Both\n"
      "files are read in their source coordinates, so a LOD written in other units or axes does not line up.");
  cmd->callback([a] {
    if (!judge(*a) && a->strict)
      throw std::runtime_error(a->lod + ": a judged view's visible ratio is over --max-visible (strict mode)");
  });
}

}  // namespace perclod::cli
