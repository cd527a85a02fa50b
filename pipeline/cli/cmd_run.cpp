// perclod run CONFIG: the whole method as a batch job (configs/demo.yaml), for
// one model ('model:') or many ('models:', docs/usage.md#batches).
#include <unistd.h>

#include <cstdio>
#include <map>
#include <stdexcept>

#include "commands.h"
#include "common.h"
#include "perclod/batch.h"
#include "perclod/run_model.h"
#include "perclod/config.h"
#include "perclod/lods.h"
#include "perclod/report_json.h"

namespace perclod::cli {
namespace {

struct RunArgs {
  std::string config, views, shard, combine_views;
  std::string samples;  // "" = the config's
  int jobs = 0;
  double memory_budget_mb = -1;
  bool json = false, strict = false, force = false, keep_unsampled_surface = false, mask_per_sample = false;
  bool explain = false;
};

void print_warnings(const std::vector<std::string>& warnings) {
  for (const std::string& w : warnings) std::fprintf(stderr, "perclod: warning: %s\n", w.c_str());
}

void run_one(const RunArgs& a, const ConfigFile& f) {
  const BatchConfig& c = f.models.front().config;
  if (!a.shard.empty() || a.force || a.jobs || a.memory_budget_mb >= 0)
    throw OptionError("--shard, --force, --jobs and --memory-budget-mb apply to a batch config ('models:'); " +
                      f.path + " names one model");
  set_error_files({c.model, a.config});
  TextProgress progress(print_progress);
  const ModelReport report = run_model(c, model_run(f.models.front(), f.path), c.out, &progress);
  print_warnings(report.lods.warnings);
  if (a.json) print_json(model_report_json(report));
  const size_t over = report.lods.over_limits;
  if ((a.strict || c.strict) && over > 0)
    throw std::runtime_error(c.model + ": " + std::to_string(over) +
                             " view figures exceed the fidelity limits (the warnings above; strict mode)");
}

void run_many(const RunArgs& a, const ConfigFile& f) {
  BatchOptions o;
  o.force = a.force;
  if (!a.shard.empty()) try {
      std::tie(o.shard, o.shards) = parse_shard(a.shard);
    } catch (const std::invalid_argument& e) {
      throw OptionError(e.what());
    }
  o.jobs = a.jobs;
  o.memory_budget_mb = a.memory_budget_mb;
  set_error_files({a.config});
  const BatchSummary summary = run_batch(f, o, print_progress, ::isatty(2) == 1);
  std::map<std::string, bool> strict;  // each model's own 'strict' (an entry may override it)
  for (const auto& e : f.models) strict[e.name] = e.config.strict;
  size_t over = 0;
  for (const ModelOutcome& m : summary.models) {
    print_warnings(m.warnings);
    if (m.status == ModelStatus::Done && (a.strict || strict[m.name])) over += m.over_limits;
  }
  std::fprintf(stderr, "perclod: batch %s: %d done, %d skipped, %d failed of %zu models in %.0f s\n",
               summary.shard.c_str(), summary.done, summary.skipped, summary.failed, summary.models.size(),
               summary.seconds);
  if (a.json) print_json(batch_summary_json(summary));
  if (summary.failed > 0) {
    std::string names;
    for (const ModelOutcome& m : summary.models)
      if (m.status == ModelStatus::Failed) names += (names.empty() ? "" : ", ") + m.name;
    throw std::runtime_error(std::to_string(summary.failed) + " of " + std::to_string(summary.models.size()) +
                             " models failed (" + names + "); the others' outputs are complete");
  }
  if (over > 0)
    throw std::runtime_error(std::to_string(over) +
                             " view figures exceed the fidelity limits (the warnings above; strict mode)");
}

}  // namespace

void register_run(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "run", "Run the whole method from a YAML config (see configs/demo.yaml): one LOD per distance,\n"
             "for one model or a batch of many ('models:' in the config; docs/usage.md#batches)");
  auto a = std::make_shared<RunArgs>();
  cmd->add_option("CONFIG", a->config, "Batch config YAML")->required()->check(kNotEmpty);
  // The options that set a config key take its help from the table of settings.
  cmd->add_option("--views", a->views, key_help("views", "overrides the config's views"));
  cmd->add_option("--samples", a->samples, key_help("samples", "overrides the config's samples"))
      ->check(samples_check());
  CLI::Option* keep = cmd->add_flag("--keep-unsampled-surface", a->keep_unsampled_surface,
                                    key_help("keep_unsampled_surface", "sets the config's keep_unsampled_surface"));
  cmd->add_flag("--mask-per-sample", a->mask_per_sample, key_help("mask_per_sample", "sets the config's mask_per_sample"))
      ->excludes(keep);
  cmd->add_option("--combine-views", a->combine_views,
                  key_help("combine_views", "overrides the config's combine_views"))
      ->check(CLI::IsMember({"any", "pooled"}));
  cmd->add_flag("--strict", a->strict, key_help("strict", "sets the config's strict"));
  cmd->add_flag("--explain", a->explain, key_help("explain", "sets the config's explain"));
  cmd->add_option("--shard", a->shard,
                  "Batch: process only shard i of n (0-based, e.g. 2/8): models i, i+n, i+2n... of the list,\n"
                  "so n machines or Slurm array tasks split a city (scripts/slurm/)");
  cmd->add_flag("--force", a->force, "Batch: redo models whose outputs are up to date (same input, settings, version)");
  cmd->add_option("--jobs", a->jobs, key_help("jobs", "overrides the config's jobs"))
      ->check(CLI::Range(1, 64));
  cmd->add_option("--memory-budget-mb", a->memory_budget_mb,
                  key_help("memory_budget_mb", "overrides the config's memory_budget_mb"))
      ->check(kNonNegative);
  cmd->add_flag("--json", a->json,
                "Print the run report (one model) or the batch summary (many) on stdout");
  cmd->footer(
      "One model: writes to OUT: <model>_lod_<d>m.obj, <model>_labels_<d>m.txt, per view <model>_<view>_<d>m.png,\n"
      "_simulated/_difference/_mask.png, _marking.png and _marking_near.png, <model>_report.json and its\n"
      "offline page <model>_report.html (figures, charts, renders beside them), and for\n"
      "viewers <model>_lod_<d>m.glb, <model>_lods.glb (MSFT_lod), <model>_tileset.json (3D Tiles 1.1) and\n"
      "<model>_manifest.json (docs/usage.md#manifest).\n"
      "A batch writes each model to OUT/<name>/ (complete or absent: built in a partial folder, then renamed),\n"
      "skips models whose manifest matches their input, settings and perclod version, goes on past a model\n"
      "that fails (exit 1 at the end, naming it), and writes OUT/batch_<i>_of_<n>.json and OUT/tileset.json.\n"
      "Each LOD is judged from its labelling views and the config's judge_views (default held_out);\n"
      "a view whose visible difference exceeds max_visible (default 1: its quarter-pixel floor), or that is\n"
      "over max_changed / max_silhouette or under min_ssim when those are set, is warned about on stderr;\n"
      "fidelity_target: {max_visible: 1} searches the bounds for the fewest triangles within it.");
  cmd->callback([a] {
    set_error_files({a->config});
    ConfigFile f = load_config_file(a->config);  // the whole config, checked before any work
    for (auto& m : f.models) {
      if (!a->views.empty()) {
        views_option(a->views, m.config.up);  // a bad --views fails before any work
        m.config.views = {a->views};
      }
      if (!a->samples.empty()) m.config.samples = parse_samples(a->samples);
      if (a->keep_unsampled_surface) m.config.keep_unsampled_surface = true;
      if (a->mask_per_sample) m.config.mask_per_sample = true;
      if (!a->combine_views.empty()) m.config.combine_views = a->combine_views;
      if (a->explain) {
        if (m.config.simplify == "cluster")
          throw OptionError("--explain applies to the collapse modes (fidelity, paper, bounded, qem); " +
                            (f.batch ? "model " + m.name : a->config) + " uses cluster");
        m.config.explain = true;
      }
    }
    if (f.batch) run_many(*a, f);
    else run_one(*a, f);
  });
}

}  // namespace perclod::cli
