// perclod run CONFIG: a batch job from a YAML config (configs/demo.yaml).
#include <cstdio>

#include "commands.h"
#include "common.h"
#include "perclod/batch.h"

namespace perclod::cli {

void register_run(CLI::App& app) {
  auto* cmd = app.add_subcommand("run", "Run a batch job described by a YAML config (see configs/demo.yaml)");
  auto config = std::make_shared<std::string>();
  auto json = std::make_shared<bool>(false);
  cmd->add_option("CONFIG", *config, "Batch config YAML")->required()->check(CLI::ExistingFile);
  cmd->add_flag("--json", *json, "Print a JSON summary on stdout");
  cmd->callback([=] {
    BatchConfig c = load_batch_config(*config);
    LoadReport rep;
    Scene s = load_scene(c.model, LoadOptions{c.scale}, &rep);
    std::fprintf(stderr, "loaded %s: %zu triangles, %zu components in %.2f s\n", c.model.c_str(), s.triangle_count(),
                 s.component_count(), rep.seconds);
    RenderViewsJob job;
    job.out_dir = c.out;
    job.stem = file_stem(c.model);
    job.up = c.up;
    job.facades = parse_facades(c.facades, c.up);
    job.distances = c.distances;
    job.display = c.display.empty() ? default_display_profile() : load_display_profile(c.display);
    Renderer renderer;
    auto views = render_views(renderer, s, job, [](const ViewFiles& v, size_t done, size_t total) {
      std::fprintf(stderr, "[%zu/%zu] %s (%.0f ms)\n", done, total, v.color.c_str(), v.render_seconds * 1e3);
    });
    if (*json) {
      nlohmann::json j = {{"config", *config}, {"model", c.model}, {"views", views.size()}};
      print_json(j);
    }
  });
}

}  // namespace perclod::cli
