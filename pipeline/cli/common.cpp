#include "common.h"

#include "perclod/outputs.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <sstream>

namespace perclod::cli {

void ModelArgs::add(CLI::App* cmd) {
  cmd->add_option("MODEL", path, "Model file: OBJ, PLY, glTF/GLB, STL, IFC, DAE, FBX")->required();
  cmd->add_option("--up", up, "Up axis of the model: y (default) or z (CityGML-derived data)")
      ->check(CLI::IsMember({"y", "z", "Y", "Z"}));
  cmd->add_option("--scale", scale, "Unit scale to metres (e.g. 0.001 for a model in mm)")
      ->check(CLI::PositiveNumber);
}

Scene ModelArgs::load(LoadReport* report, bool quiet) const { return load_model(path, LoadOptions{scale}, report, quiet); }

Scene load_model(const std::string& path, const LoadOptions& options, LoadReport* report, bool quiet) {
  LoadReport rep;
  Scene s = load_scene(path, options, &rep);
  if (!quiet) {
    std::fprintf(stderr, "loaded %s: %zu triangles, %zu components in %.2f s", path.c_str(), s.triangle_count(),
                 s.component_count(), rep.seconds);
    if (rep.degenerate_triangles) std::fprintf(stderr, " (%zu degenerate triangles kept)", rep.degenerate_triangles);
    if (rep.polygons_fanned)
      std::fprintf(stderr, " (%zu polygons ear clipping could not finish: their rest is a fan that may overlap)",
                   rep.polygons_fanned);
    std::fprintf(stderr, "\n");
  }
  if (report) *report = rep;
  return s;
}

void DisplayArgs::add(CLI::App* cmd) {
  cmd->add_option("--display", path, "Display profile YAML (default: the paper's 1280x1024, 86.27 dpi, 0.5 m)")
      ->check(CLI::ExistingFile);
}

DisplayProfile DisplayArgs::profile() const {
  return path.empty() ? default_display_profile() : load_display_profile(path);
}

std::vector<double> check_distances(const std::vector<double>& d) {
  if (d.empty()) throw std::invalid_argument("give at least one --distance");
  for (double x : d)
    if (!(x > 0) || !std::isfinite(x)) throw std::invalid_argument("distances must be positive metres");
  check_distinct_tags(d);
  return d;
}


void print_progress(const std::string& message) { std::fprintf(stderr, "%s\n", message.c_str()); }

nlohmann::json to_json(const LoadReport& r) {
  nlohmann::json j = {{"polygons", r.polygons},
                      {"polygons_triangulated", r.polygons_triangulated},
                      {"degenerate_triangles", r.degenerate_triangles},
                      {"components_from_connectivity", r.components_from_connectivity},
                      {"seconds", r.seconds}};
  if (r.polygons_fanned) j["polygons_fanned"] = r.polygons_fanned;  // only when it happened
  return j;
}

void print_json(const nlohmann::json& j) { std::cout << j.dump(2) << std::endl; }

}  // namespace perclod::cli
