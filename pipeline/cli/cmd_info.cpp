// perclod info MODEL: what the loader sees.
#include <cstdio>

#include "commands.h"
#include "common.h"

namespace perclod::cli {

void register_info(CLI::App& app) {
  auto* cmd = app.add_subcommand("info", "Load a model and print its statistics");
  auto model = std::make_shared<ModelArgs>();
  auto json = std::make_shared<bool>(false);
  model->add(cmd);
  cmd->add_flag("--json", *json, "Print JSON on stdout");
  cmd->callback([=] {
    set_error_files({model->path});
    LoadReport rep;
    Scene s = model->load(&rep, true);
    SceneInfo info = analyse_scene(s);
    if (*json) {
      nlohmann::json j = {{"file", model->path},
                          {"triangles", info.triangles},
                          {"vertices", info.vertices},
                          {"components", info.components},
                          {"materials", info.materials},
                          {"degenerate_triangles", info.degenerate_triangles},
                          {"non_manifold_edges", info.non_manifold_edges},
                          {"boundary_edges", info.boundary_edges},
                          {"bounds_min", {info.bounds.lo[0] + info.offset[0], info.bounds.lo[1] + info.offset[1],
                                          info.bounds.lo[2] + info.offset[2]}},
                          {"bounds_max", {info.bounds.hi[0] + info.offset[0], info.bounds.hi[1] + info.offset[1],
                                          info.bounds.hi[2] + info.offset[2]}},
                          {"size", {info.bounds.hi[0] - info.bounds.lo[0], info.bounds.hi[1] - info.bounds.lo[1],
                                    info.bounds.hi[2] - info.bounds.lo[2]}},
                          {"offset", info.offset},
                          {"load", load_report_json(rep)}};
      print_json(j);
      return;
    }
    std::printf("file                 %s\n", model->path.c_str());
    std::printf("triangles            %zu (%zu polygons, %zu triangulated)\n", info.triangles, rep.polygons,
                rep.polygons_triangulated);
    if (rep.polygons_fanned)
      std::printf("fanned polygons      %zu (ear clipping could not finish them: the rest is a fan that may "
                  "overlap)\n", rep.polygons_fanned);
    std::printf("vertices             %zu\n", info.vertices);
    std::printf("components           %zu%s\n", info.components,
                rep.components_from_connectivity ? " (connected parts: the file has no groups)" : "");
    std::printf("materials            %zu\n", info.materials);
    std::printf("degenerate triangles %zu (kept)\n", info.degenerate_triangles);
    std::printf("non-manifold edges   %zu\n", info.non_manifold_edges);
    std::printf("boundary edges       %zu\n", info.boundary_edges);
    std::printf("size                 %.3f x %.3f x %.3f\n", info.bounds.hi[0] - info.bounds.lo[0],
                info.bounds.hi[1] - info.bounds.lo[1], info.bounds.hi[2] - info.bounds.lo[2]);
    std::printf("bounds min           %.3f %.3f %.3f\n", info.bounds.lo[0] + info.offset[0],
                info.bounds.lo[1] + info.offset[1], info.bounds.lo[2] + info.offset[2]);
    std::printf("bounds max           %.3f %.3f %.3f\n", info.bounds.hi[0] + info.offset[0],
                info.bounds.hi[1] + info.offset[1], info.bounds.hi[2] + info.offset[2]);
    std::printf("offset (recentred)   %.3f %.3f %.3f\n", info.offset[0], info.offset[1], info.offset[2]);
    std::printf("load time            %.3f s\n", rep.seconds);
  });
}

}  // namespace perclod::cli
