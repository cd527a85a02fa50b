// perclod label MODEL --distance D: render, perceive, cast, label, marking renders.
#include <cstdio>

#include "commands.h"
#include "common.h"
#include "perclod/label.h"
#include "perclod/label_model.h"
#include "perclod/progress_text.h"
#include "perclod/report_json.h"

namespace perclod::cli {

void register_label(CLI::App& app) {
  auto* cmd = app.add_subcommand("label", "Label every triangle perceptible, imperceptible or undisplayable at a distance");
  struct Args {
    ModelArgs model;
    DisplayArgs display;
    double distance = 0;
    std::string views = kDefaultViews, out = "out", tracer = "octree", per_building = "auto",
                own_views_alone = kDefaultOwnViewsAlone ? "true" : "false",
                combine_views = kDefaultCombineViews;
    std::string samples = samples_name(kDefaultSamples);
    int spins = 1;
    bool verify = false, json = false, keep_unsampled_surface = false, mask_per_sample = false;
    double ratio = 0.5, threshold = -1, closer = 0.25, group_span = kDefaultGroupSpan;
  };
  auto a = std::make_shared<Args>();
  a->model.add(cmd);
  a->display.add(cmd);
  cmd->add_option("--distance,-d", a->distance, "Viewing distance in metres")->required()->check(kPositive);
  // The options that set a config key take its help from the table of settings.
  cmd->add_option("--views,--facade,-f", a->views, key_help("views", key_default("views")));
  cmd->add_option("--samples", a->samples, key_help("samples", key_default("samples")))->check(samples_check());
  CLI::Option* keep =
      cmd->add_flag("--keep-unsampled-surface", a->keep_unsampled_surface, key_help("keep_unsampled_surface"));
  cmd->add_flag("--mask-per-sample", a->mask_per_sample, key_help("mask_per_sample"))->excludes(keep);
  cmd->add_option("--spins", a->spins, key_help("spins", key_default("spins")))->check(CLI::IsMember({1, 2, 4}));
  cmd->add_option("--per-building", a->per_building, key_help("per_building", key_default("per_building")))
      ->check(CLI::IsMember({"true", "false", "auto"}));
  cmd->add_option("--group-span", a->group_span, key_help("group_span", key_default("group_span")))
      ->check(in_range(0, 100));
  cmd->add_option("--own-views-alone", a->own_views_alone,
                  key_help("own_views_alone", key_default("own_views_alone")))
      ->check(CLI::IsMember({"true", "false"}));
  cmd->add_option("--tracer", a->tracer, key_help("tracer", key_default("tracer")))
      ->check(CLI::IsMember({"octree", "embree"}));
  cmd->add_flag("--verify", a->verify, key_help("verify"));
  cmd->add_option("--ratio", a->ratio, key_help("ratio", key_default("ratio")))->check(in_range(0, 1));
  cmd->add_option("--combine-views", a->combine_views, key_help("combine_views", key_default("combine_views")))
      ->check(CLI::IsMember({"any", "pooled"}));
  cmd->add_option("--threshold", a->threshold, "Perception threshold T in grey levels (default: calibrated)")
      ->check(kNonNegative);
  cmd->add_option("--closer", a->closer, "Second marking render at distance x this factor (default 0.25)")
      ->check(kPositive);
  cmd->add_option("--out,-o", a->out, "Output directory (created)")->check(kNotEmpty);
  cmd->add_flag("--json", a->json, "Print the JSON summary on stdout");
  cmd->footer(
      "Writes OUT/<model>_labels_<d>m.txt (docs/usage.md#the-labels-file), OUT/<model>_label_<d>m.json,\n"
      "and per view <model>_<view>_<d>m.png, _simulated.png, _difference.png, _mask.png, _marking.png,\n"
      "_marking_near.png (a view too close to frame the model is tiled: <view>_t<i>).");
  cmd->callback([a] {
    set_error_files({a->model.path});
    LabelJob job;
    job.up = a->model.up_axis();
    job.display = a->display.profile();
    job.perception = perception_settings_for(job.display);
    if (a->threshold >= 0) job.perception.threshold = a->threshold;
    job.perception.spins = a->spins;
    job.views = views_option(a->views, job.up);
    job.samples = parse_samples(a->samples);
    job.keep_unsampled_surface = a->keep_unsampled_surface;
    job.mask_per_sample = a->mask_per_sample;
    job.per_building = parse_per_building(a->per_building);
    job.group_span = a->group_span;
    job.own_views_alone = a->own_views_alone == "true";
    job.distance = a->distance;
    job.ratio = a->ratio;
    job.combine = parse_combine_views(a->combine_views);
    job.verify = a->verify;
    job.closer_factor = a->closer;
    job.out = output_names_for(a->out, a->model.path);
    Scene s = a->model.load();
    TextProgress progress(print_progress);
    const LabelReport report = label_model(s, job, parse_tracer(a->tracer), &progress);
    const LabelCounts& l = report.labels;
    std::fprintf(stderr, "labels: %d perceptible, %d imperceptible, %d undisplayable -> %s\n", int(l.perceptible),
                 int(l.imperceptible), int(l.undisplayable), report.labels_file.c_str());
    if (a->json) print_json(label_report_json(report));
  });
}

}  // namespace perclod::cli
