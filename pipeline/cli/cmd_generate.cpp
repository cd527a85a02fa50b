// perclod generate facade: writes the parametric test building to a file.
#include <chrono>
#include <cstdio>
#include <memory>

#include "commands.h"
#include "common.h"
#include "perclod/export.h"
#include "perclod/facade.h"

namespace perclod::cli {
namespace {

struct GenerateFacadeArgs {
  FacadeParams p;
  size_t triangles = 0;
  std::string out;
  bool json = false;
  bool no_frames = false, no_mullions = false, no_sills = false, no_cornices = false,
       no_columns = false, no_balusters = false;
};

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

nlohmann::json params_json(const FacadeParams& p) {
  return {{"floors", p.floors},
          {"bays", p.bays},
          {"sides", p.sides},
          {"floor_height", p.floor_height},
          {"bay_width", p.bay_width},
          {"depth", p.depth},
          {"frames", p.frames},
          {"mullions", p.mullions},
          {"sills", p.sills},
          {"cornices", p.cornices},
          {"columns", p.columns},
          {"balusters", p.balusters},
          {"mullions_per_window", p.mullions_per_window},
          {"transoms_per_window", p.transoms_per_window},
          {"column_segments", p.column_segments},
          {"balusters_per_bay", p.balusters_per_bay},
          {"baluster_segments", p.baluster_segments},
          {"hidden_interior", p.hidden_interior},
          {"coplanar_panels", p.coplanar_panels},
          {"subpixel_ornaments", p.subpixel_ornaments},
          {"ornament_detail", p.ornament_detail}};
}

void run_generate_facade(GenerateFacadeArgs a) {
  set_error_files({a.out});
  if (a.triangles > 0) {
    // Pick the building's size and tessellation for the budget; the other
    // options (switches, sizes, bars) apply on top and may move the count.
    FacadeParams picked = facade_params_for_triangles(a.triangles);
    a.p.floors = picked.floors;
    a.p.bays = picked.bays;
    a.p.sides = picked.sides;
    a.p.column_segments = picked.column_segments;
    a.p.ornament_detail = picked.ornament_detail;
  }
  a.p.frames = !a.no_frames;
  a.p.mullions = !a.no_mullions;
  a.p.sills = !a.no_sills;
  a.p.cornices = !a.no_cornices;
  a.p.columns = !a.no_columns;
  a.p.balusters = !a.no_balusters;

  auto t0 = std::chrono::steady_clock::now();
  Scene s = generate_facade(a.p);
  double t_generate = seconds_since(t0);
  std::fprintf(stderr, "generated %zu triangles in %.3f s; writing %s\n", s.triangle_count(),
               t_generate, a.out.c_str());
  t0 = std::chrono::steady_clock::now();
  export_scene(s, a.out);
  double t_write = seconds_since(t0);

  Bounds b = scene_bounds(s);
  if (a.json) {
    print_json({{"file", a.out},
                {"triangles", s.triangle_count()},
                {"vertices", s.vertex_count()},
                {"components", s.component_count()},
                {"materials", s.materials.size()},
                {"size", {b.hi[0] - b.lo[0], b.hi[1] - b.lo[1], b.hi[2] - b.lo[2]}},
                {"offset", s.offset},
                {"target_triangles", a.triangles},
                {"params", params_json(a.p)},
                {"seconds_generate", t_generate},
                {"seconds_write", t_write}});
    return;
  }
  std::printf("file        %s\n", a.out.c_str());
  std::printf("building    %d floors x %d bays, %d decorated side%s, column segments %d, "
              "ornament detail %d\n",
              a.p.floors, a.p.bays, a.p.sides, a.p.sides == 1 ? "" : "s", a.p.column_segments,
              a.p.ornament_detail);
  std::printf("triangles   %zu\n", s.triangle_count());
  std::printf("vertices    %zu\n", s.vertex_count());
  std::printf("components  %zu\n", s.component_count());
  std::printf("size        %.2f x %.2f x %.2f m\n", b.hi[0] - b.lo[0], b.hi[1] - b.lo[1],
              b.hi[2] - b.lo[2]);
  std::printf("time        %.3f s generate, %.3f s write\n", t_generate, t_write);
}

void register_generate_facade(CLI::App* generate) {
  auto* cmd = generate->add_subcommand(
      "facade",
      "A box building whose facade has floors x bays windows (frames, mullions, transoms,\n"
      "sills), cornices, columns with capitals and a balustrade; switches add hidden interior\n"
      "parts, coplanar overlapping plaques and sub-pixel ornaments. Z up, metres, main facade\n"
      "facing -y. Every part is its own OBJ group; materials carry colours.");
  auto a = std::make_shared<GenerateFacadeArgs>();
  FacadeParams& p = a->p;
  auto* floors = cmd->add_option("--floors", p.floors, "Storeys")->capture_default_str();
  auto* bays = cmd->add_option("--bays", p.bays, "Window bays per wall")->capture_default_str();
  auto* sides = cmd->add_option("--sides", p.sides, "1: main facade only; 4: all walls decorated")
                    ->check(CLI::IsMember({1, 4}))
                    ->capture_default_str();
  cmd->add_option("--floor-height", p.floor_height, "Storey height (m)")->capture_default_str();
  cmd->add_option("--bay-width", p.bay_width, "Bay width (m)")->capture_default_str();
  cmd->add_option("--depth", p.depth, "Building depth (m) when --sides 1")->capture_default_str();
  auto* segments = cmd->add_option("--column-segments", p.column_segments,
                                   "Tessellation of columns and capitals")
                       ->capture_default_str();
  cmd->add_option("--mullions", p.mullions_per_window, "Mullions per window")->capture_default_str();
  cmd->add_option("--transoms", p.transoms_per_window, "Transoms per window")->capture_default_str();
  cmd->add_option("--balusters-per-bay", p.balusters_per_bay, "Balusters per bay on the roof edge")
      ->capture_default_str();
  cmd->add_option("--baluster-segments", p.baluster_segments, "Tessellation of a baluster")
      ->capture_default_str();
  auto* detail = cmd->add_option("--ornament-detail", p.ornament_detail,
                                 "Extra rings on every turned part (scales the count)")
                     ->capture_default_str();
  cmd->add_flag("--hidden-interior", p.hidden_interior,
                "Add floor slabs and partitions, never visible from outside");
  cmd->add_flag("--coplanar-panels", p.coplanar_panels,
                "Add two overlapping plaques in the wall plane above each window");
  cmd->add_flag("--subpixel-ornaments", p.subpixel_ornaments,
                "Add 1.5 cm studs above each window (under a pixel at 56 m)");
  cmd->add_flag("--no-frames", a->no_frames, "Leave out window frames");
  cmd->add_flag("--no-mullions", a->no_mullions, "Leave out mullions and transoms");
  cmd->add_flag("--no-sills", a->no_sills, "Leave out sills");
  cmd->add_flag("--no-cornices", a->no_cornices, "Leave out cornices");
  cmd->add_flag("--no-columns", a->no_columns, "Leave out columns and capitals");
  cmd->add_flag("--no-balusters", a->no_balusters, "Leave out the roof balustrade");
  auto* target = cmd->add_option("--triangles", a->triangles,
                                 "Pick floors, bays, sides, column segments and ornament detail "
                                 "for about this many triangles (1000 .. millions)")
                     ->check(CLI::Validator(
                         [](std::string& v) -> std::string {
                           bool digits = !v.empty() && v.find_first_not_of("0123456789") == std::string::npos;
                           return digits && v.find_first_not_of('0') != std::string::npos
                                      ? ""
                                      : "must be a positive number of triangles, got '" + v + "'";
                         },
                         "N"));
  for (auto* o : {floors, bays, sides, segments, detail}) target->excludes(o);
  cmd->add_option("FILE", a->out, "Output model file (.obj with .mtl, or .glb)")->required()->check(kNotEmpty);
  cmd->add_flag("--json", a->json, "Print a JSON summary on stdout");
  cmd->callback([a] { run_generate_facade(*a); });
}

}  // namespace

void register_generate(CLI::App& app) {
  auto* generate = app.add_subcommand("generate", "Generate a test scene");
  generate->require_subcommand(1);
  register_generate_facade(generate);
}

}  // namespace perclod::cli
