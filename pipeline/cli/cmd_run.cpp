// perclod run CONFIG: the whole method as a batch job (configs/demo.yaml).
#include <cstdio>
#include <stdexcept>

#include "commands.h"
#include "common.h"
#include "perclod/config.h"
#include "perclod/pipeline.h"

namespace perclod::cli {

void register_run(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "run", "Run the whole method from a YAML config (see configs/demo.yaml): one LOD per distance");
  auto config = std::make_shared<std::string>();
  auto json = std::make_shared<bool>(false);
  auto views = std::make_shared<std::string>();
  auto samples = std::make_shared<int>(0);
  auto strict = std::make_shared<bool>(false);
  cmd->add_option("CONFIG", *config, "Batch config YAML")->required()->check(kNotEmpty);
  cmd->add_option("--views", *views, "View set: presets facades obliques top ring<N>[el<E>/...] and views +x -x ... az<A>el<E>, comma separated (README, Views); overrides the config's views)");
  cmd->add_option("--samples", *samples, "Samples per pixel: 1, 2, 4 or 8 (overrides the config's samples)")
      ->check(CLI::IsMember({1, 2, 4, 8}));
  cmd->add_flag("--strict", *strict,
                "Fail (exit 1, after every output is written) when a LOD exceeds the config's max_changed or\n"
                "max_silhouette in any judged view (also 'strict: true' in the config)");
  cmd->add_flag("--json", *json, "Print the run report (also written to OUT/<model>_report.json) on stdout");
  cmd->footer(
      "Writes to OUT: <model>_lod_<d>m.obj, <model>_labels_<d>m.txt, per view <model>_<view>_<d>m.png,\n"
      "_simulated/_difference/_mask.png, _marking.png and _marking_near.png, <model>_report.json and\n"
      "its offline page <model>_report.html (figures, charts and the renders beside them).\n"
      "Each LOD is judged from its labelling views and the config's judge_views (default held_out);\n"
      "figures over max_changed / max_silhouette are warned about on stderr.");
  cmd->callback([=] {
    set_error_files({*config});
    BatchConfig c = load_batch_config(*config);  // the whole config, checked before any work
    if (!views->empty()) views_option(*views, c.up);  // a bad --views fails before any work
    if (!views->empty()) c.views = {*views};
    if (*samples) c.samples = *samples;
    LodJob job = lod_job(c);
    set_error_files({c.model, *config});
    LoadReport rep;
    Scene s = load_model(c.model, LoadOptions{c.scale}, &rep);
    nlohmann::json report = make_lods(s, job, print_progress);
    report["model"] = c.model;
    report["load"] = to_json(rep);
    if (report.contains("warnings"))
      for (const auto& w : report["warnings"])
        std::fprintf(stderr, "perclod: warning: %s\n", w.get<std::string>().c_str());
    if (*json) print_json(report);
    const size_t over = report.value("over_limits", size_t(0));
    if ((*strict || c.strict) && over > 0)
      throw std::runtime_error(c.model + ": " + std::to_string(over) +
                               " view figures exceed the fidelity limits (the warnings above; strict mode)");
  });
}

}  // namespace perclod::cli
