// perclod run CONFIG: the whole method as a batch job (configs/demo.yaml).
#include <cstdio>

#include "commands.h"
#include "common.h"
#include "perclod/lod.h"

namespace perclod::cli {

void register_run(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "run", "Run the whole method from a YAML config (see configs/demo.yaml): one LOD per distance");
  auto config = std::make_shared<std::string>();
  auto json = std::make_shared<bool>(false);
  cmd->add_option("CONFIG", *config, "Batch config YAML")->required()->check(CLI::ExistingFile);
  cmd->add_flag("--json", *json, "Print the run report (also written to OUT/<model>_report.json) on stdout");
  cmd->footer(
      "Writes to OUT: <model>_lod_<d>m.obj, <model>_labels_<d>m.txt, per facade <model>_<f>_<d>m.png,\n"
      "_simulated/_difference/_mask.png, _marking.png and _marking_near.png, and <model>_report.json.");
  cmd->callback([=] {
    BatchConfig c = load_batch_config(*config);
    LoadReport rep;
    Scene s = load_scene(c.model, LoadOptions{c.scale}, &rep);
    std::fprintf(stderr, "loaded %s: %zu triangles, %zu components in %.2f s\n", c.model.c_str(), s.triangle_count(),
                 s.component_count(), rep.seconds);
    LodJob job;
    job.label.up = c.up;
    job.label.display = c.display.empty() ? default_display_profile() : load_display_profile(c.display);
    job.label.perception = perception_settings_for(job.label.display);
    job.label.facades = parse_facades(c.facades, c.up);
    job.label.ratio = c.ratio;
    job.label.verify = c.verify;
    job.label.out_dir = c.out;
    job.label.stem = file_stem(c.model);
    job.distances = c.distances;
    job.tracer = parse_tracer(c.tracer);
    job.simplify.mode = parse_simplify_mode(c.simplify.c_str());
    job.simplify.k = c.k;
    job.simplify.delete_undisplayable = !c.keep_undisplayable;
    job.lod_format = c.format;
    nlohmann::json report = make_lods(s, job, [](const std::string& m) { std::fprintf(stderr, "%s\n", m.c_str()); });
    report["model"] = c.model;
    report["load"] = to_json(rep);
    if (*json) print_json(report);
  });
}

}  // namespace perclod::cli
