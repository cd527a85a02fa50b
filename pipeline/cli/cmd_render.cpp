// perclod render MODEL --distance D [--views facades]: shaded renders of views.
#include <cstdio>

#include "commands.h"
#include "common.h"
#include "perclod/render_views.h"

namespace perclod::cli {

void register_render(CLI::App& app) {
  auto* cmd = app.add_subcommand("render", "Render views of a model offscreen (OSMesa)");
  struct Args {
    ModelArgs model;
    DisplayArgs display;
    std::vector<double> distances;
    std::string views = "facades", out = "out";
    bool ids = false, depth = false, by_component = false, json = false;
  };
  auto a = std::make_shared<Args>();
  a->model.add(cmd);
  a->display.add(cmd);
  cmd->add_option("--distance,-d", a->distances, "Viewing distance(s) in metres, e.g. -d 56 -d 132 or -d 56,132")
      ->required()
      ->delimiter(',');
  cmd->add_option("--views,--facade,-f", a->views, key_help("views", "default facades"));
  cmd->add_option("--out,-o", a->out, "Output directory (created)")->check(kNotEmpty);
  cmd->add_flag("--ids", a->ids, "Also write the triangle-ID buffer (<name>_ids.tif, uint32, index + 1, 0 = background)");
  cmd->add_flag("--depth", a->depth, "Also write eye depth (<name>_depth.tif, float metres, 0 = background)");
  cmd->add_flag("--by-component", a->by_component, "Colour by component instead of material");
  cmd->add_flag("--json", a->json, "Print a JSON summary on stdout");
  cmd->footer(
      "Files: OUT/<model>_<view>_<distance>m.png (+ _ids.tif, _depth.tif; <view>_t<i> for the tiles of a view\n"
      "too close to frame the model). Row 0 is the top row.");
  cmd->callback([a] {
    set_error_files({a->model.path});
    // Options and the display profile first: a bad one fails before the model loads.
    RenderViewsJob job;
    job.out = output_names_for(a->out, a->model.path);
    job.up = a->model.up_axis();
    job.views = views_option(a->views, job.up);
    job.distances = check_distances(a->distances);
    job.display = a->display.profile();
    Scene s = a->model.load();
    job.write_ids = a->ids;
    job.write_depth = a->depth;
    job.color_by = a->by_component ? ColorBy::Component : ColorBy::Material;
    auto views = render_views(s, job, [](const ViewFiles& v, size_t done, size_t total) {
      std::fprintf(stderr, "[%zu/%zu] %s (%.0f ms, %zu px covered, %zu triangles drawn)\n", done, total,
                   v.color.c_str(), v.render_seconds * 1e3, v.covered_pixels, v.drawn_triangles);
    });
    if (a->json) {
      nlohmann::json j = {{"model", a->model.path}, {"triangles", s.triangle_count()}, {"views", nlohmann::json::array()}};
      for (const auto& v : views)
        j["views"].push_back({{"view", v.view}, {"distance", v.distance}, {"color", v.color}, {"ids", v.ids},
                              {"depth", v.depth}, {"covered_pixels", v.covered_pixels}, {"drawn_triangles", v.drawn_triangles},
                              {"render_seconds", v.render_seconds}});
      print_json(j);
    }
  });
}

}  // namespace perclod::cli
