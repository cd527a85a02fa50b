// The viewer-facing exports of one model: its manifest (which distances each
// LOD serves), the all-LOD GLB (MSFT_lod) and a 3D Tiles tileset.
#include "perclod/model_exports.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/file.h>
#include <stdio.h>
#include <unistd.h>
#include <algorithm>
#include <atomic>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <sstream>
#include <stdexcept>
#include <thread>

#include "batch_util.h"
#include "perclod/export.h"
#include "perclod/report_json.h"
#include "perclod/run_model.h"

namespace perclod {
using detail::leaf;
namespace fs = std::filesystem;
namespace {

// Source point -> the 3D Tiles frame (+Z up). The GLB holds Y-up glTF (a Z-up
// source turned by export), which 3D Tiles turns back to +Z up; so a Z-up
// source keeps its axes and a Y-up source goes (x, y, z) -> (x, -z, y).
std::array<double, 3> to_tiles_frame(const std::array<double, 3>& p, UpAxis up) {
  return up == UpAxis::Z ? p : std::array<double, 3>{p[0], -p[2], p[1]};
}

nlohmann::json box_volume(const Bounds& b, const std::array<double, 3>& offset, UpAxis up) {
  std::array<double, 3> lo, hi;
  for (int a = 0; a < 3; ++a) lo[a] = b.lo[a] + offset[a], hi[a] = b.hi[a] + offset[a];
  const auto l = to_tiles_frame(lo, up), h = to_tiles_frame(hi, up);
  std::array<double, 3> c, half;
  for (int a = 0; a < 3; ++a) c[a] = 0.5 * (l[a] + h[a]), half[a] = std::max(0.5 * std::abs(h[a] - l[a]), 1e-3);
  return {{"box", {c[0], c[1], c[2], half[0], 0, 0, 0, half[1], 0, 0, 0, half[2]}}};
}

}  // namespace

std::vector<LodRange> lod_ranges(const std::vector<double>& distances, const std::vector<double>& displacements,
                                 double pixel_angle, double fov_y, int height_px, double diagonal) {
  if (distances.size() != displacements.size()) throw std::invalid_argument("one displacement per distance");
  std::vector<size_t> order(distances.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return distances[a] < distances[b]; });
  const double view_height_per_metre = 2 * std::tan(fov_y / 2);
  // Metres of geometric error per metre of distance at the switch: a tile
  // of error e shows e * height_px / (d * view_height_per_metre) pixels.
  const double error_per_metre = kTilesetMaxScreenSpaceError * view_height_per_metre / std::max(1, height_px);
  std::vector<LodRange> r;
  for (size_t i : order) {
    LodRange x;
    x.distance = distances[i];
    x.displacement = displacements[i];
    x.switch_distance = pixel_angle > 0 ? displacements[i] / pixel_angle : 0;
    x.from = r.empty() ? std::min(x.distance, x.switch_distance) : x.distance;
    x.geometric_error = r.empty() ? 0.0 : x.from * error_per_metre;
    r.push_back(x);
  }
  for (size_t i = 0; i < r.size(); ++i) {
    r[i].to = i + 1 < r.size() ? r[i + 1].from : INFINITY;
    r[i].screen_coverage =
        std::isfinite(r[i].to) && r[i].to > 0 ? std::min(1.0, diagonal / (r[i].to * view_height_per_metre)) : 0.0;
  }
  return r;
}

std::array<double, 16> enu_to_ecef(double lat_deg, double lon_deg, double height) {
  constexpr double kA = 6378137.0, kF = 1 / 298.257223563;  // WGS84
  const double e2 = kF * (2 - kF);
  const double lat = lat_deg * kPi / 180, lon = lon_deg * kPi / 180;
  const double sl = std::sin(lat), cl = std::cos(lat), so = std::sin(lon), co = std::cos(lon);
  const double n = kA / std::sqrt(1 - e2 * sl * sl);
  const double x = (n + height) * cl * co, y = (n + height) * cl * so, z = (n * (1 - e2) + height) * sl;
  return {-so,      co,       0,  0,   // east
          -sl * co, -sl * so, cl, 0,   // north
          cl * co,  cl * so,  sl, 0,   // up
          x,        y,        z,  1};
}

std::optional<CrsFrame> model_crs_frame(const BatchConfig& config, const LoadReport& load, const Scene& scene) {
  if (config.crs_origin || config.crs == "none") return std::nullopt;
  const bool from_file = config.crs.empty();
  if (from_file && load.reference_system.empty()) return std::nullopt;
  const std::string code = from_file ? epsg_code(load.reference_system) : config.crs;
  const std::string what = from_file ? "its metadata.referenceSystem '" + load.reference_system + "'" : "crs";
  if (code.empty())
    throw std::runtime_error(config.model + ": " + what +
                             " is no EPSG code perclod reads; set 'crs' in the config (or 'crs: none' to keep source "
                             "coordinates)");
  try {
    return crs_frame(code, scene.offset, config.scale);
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(config.model + ": " + what + ": " + e.what());
  }
}

std::array<double, 16> crs_transform(const CrsFrame& f, const std::array<double, 3>& centre, UpAxis up) {
  // The source axis and sign of each tileset axis (to_tiles_frame): Z up
  // keeps them; Y up has tileset (x, y, z) = source (x, -z, y).
  using Axis = std::pair<int, double>;
  const std::array<Axis, 3> from = up == UpAxis::Z ? std::array<Axis, 3>{Axis{0, 1}, Axis{1, 1}, Axis{2, 1}}
                                                   : std::array<Axis, 3>{Axis{0, 1}, Axis{2, -1}, Axis{1, 1}};
  std::array<double, 16> m{};
  for (int k = 0; k < 3; ++k)
    for (int r = 0; r < 3; ++r) m[4 * k + r] = from[k].second * f.axes[from[k].first][r];
  // The centre lands on the frame's origin: origin + J (p - centre).
  for (int r = 0; r < 3; ++r) {
    m[12 + r] = f.origin[r];
    for (int i = 0; i < 3; ++i) m[12 + r] -= f.axes[i][r] * centre[i];
  }
  m[15] = 1;
  return m;
}

namespace {

// The manifest's record of where the CRS placed the model: the code, where it
// came from, the centre in source coordinates and in WGS84, and PROJ's
// transformations (position, accuracy; heights).
nlohmann::json crs_json(const CrsFrame& f, const BatchConfig& config, const std::array<double, 3>& centre) {
  nlohmann::json j = {
      {"code", f.code},
      {"name", f.name},
      {"from", config.crs.empty() ? "model file" : "config"},
      {"centre", centre},
      {"wgs84", {{"lat", f.lat}, {"lon", f.lon}, {"height", f.height}}},
      {"operation", f.operation},
      {"accuracy_m", f.accuracy_m >= 0 ? nlohmann::json(f.accuracy_m) : nlohmann::json(nullptr)},
      {"ballpark", f.ballpark},
      {"heights_as_ellipsoidal", f.height_ballpark}};
  if (!f.height_operation.empty()) j["height_operation"] = f.height_operation;
  if (!f.height_fallback.empty()) j["height_fallback"] = f.height_fallback;
  return j;
}

// The length of a bounding box's diagonal.
double bounds_diagonal(const Bounds& bounds) {
  double diagonal = 0;
  for (int a = 0; a < 3; ++a) diagonal += double(bounds.hi[a] - bounds.lo[a]) * double(bounds.hi[a] - bounds.lo[a]);
  return std::sqrt(diagonal);
}

// Each LOD's largest displacement in metres, in the job's distance order.
std::vector<double> lod_displacements(const std::vector<LodResult>& lods) {
  std::vector<double> displacements;
  for (const LodResult& r : lods)
    displacements.push_back(r.simplify.max_displacement_rel * r.simplify.bbox_diagonal);
  return displacements;
}

// Where distance d is in the job's distances (the index of its LOD).
size_t distance_index(const std::vector<double>& distances, double d) {
  return size_t(std::find(distances.begin(), distances.end(), d) - distances.begin());
}

// A GLB per LOD (written unless the LODs are GLBs already) into glb, and the
// all-LOD GLB (MSFT_lod, finest first), named in files.
void write_lod_glbs(const std::vector<Scene>& lods, const LodJob& job, const std::vector<LodRange>& ranges,
                    const ExportOptions& eo, std::vector<std::string>& glb, nlohmann::json& files) {
  const OutputNames& out = job.label.out;
  for (size_t i = 0; i < job.distances.size(); ++i) {
    glb[i] = out.lod(job.distances[i], "glb");
    if (job.lod_format != "glb") export_scene(lods.at(i), glb[i], eo);
  }
  std::vector<const Scene*> ordered;
  std::vector<std::string> names;
  std::vector<double> coverage;
  for (const LodRange& r : ranges) {
    ordered.push_back(&lods.at(distance_index(job.distances, r.distance)));
    names.push_back("lod_" + distance_tag(r.distance));
    coverage.push_back(r.screen_coverage);
  }
  const std::string all = out.lods_glb();
  export_lods_glb(ordered, names, coverage, all, eo);
  files["lods_glb"] = leaf(all);
}

// The 3D Tiles 1.1 tileset over the per-LOD GLBs, written and named in files.
void write_tileset(const Scene& scene, const std::vector<Scene>& lods, const LodJob& job, const BatchConfig& config,
                   const std::optional<CrsFrame>& frame, const std::vector<LodRange>& ranges,
                   const std::vector<std::string>& glb, const Bounds& bounds, double diagonal, nlohmann::json& files) {
  const OutputNames& out = job.label.out;
  // 3D Tiles 1.1: the coarsest LOD is the root, each finer one its only
  // child (REPLACE refinement); the finest is the leaf (geometricError 0).
  nlohmann::json tile;
  for (size_t i = 0; i < ranges.size(); ++i) {
    const size_t k = distance_index(job.distances, ranges[i].distance);
    nlohmann::json t = {{"boundingVolume", box_volume(scene_bounds(lods[k].triangle_count() ? lods[k] : scene),
                                                      lods[k].offset, job.label.up)},
                        {"geometricError", ranges[i].geometric_error},
                        {"refine", "REPLACE"},
                        {"content", {{"uri", leaf(glb[k])}}}};
    if (i > 0) t["children"] = nlohmann::json::array({tile});
    tile = t;
  }
  // The root's volume must hold every descendant: the original's bounds.
  tile["boundingVolume"] = box_volume(bounds, scene.offset, job.label.up);
  if (frame) {
    const auto m = crs_transform(*frame, scene.offset, job.label.up);
    tile["transform"] = std::vector<double>(m.begin(), m.end());
  } else if (config.crs_origin) {
    const auto m = enu_to_ecef(config.origin_lat, config.origin_lon, config.origin_height);
    tile["transform"] = std::vector<double>(m.begin(), m.end());
  }
  const DisplayProfile& display = job.label.display;
  const nlohmann::json extras = {
      {"perclod",
       {{"maximum_screen_space_error", kTilesetMaxScreenSpaceError},
        {"display", {{"name", display.name}, {"height_px", display.height}, {"fov_y_deg", display.fov_y() * 180 / kPi}}},
        {"geometric_error",
         "distance * maximum_screen_space_error * 2 tan(fov_y / 2) / height_px: a client with this maximum "
         "screen-space error refines a LOD's tile when the camera is closer than the distance the LOD was made "
         "for (docs/usage.md#export-for-viewers)"}}}};
  nlohmann::json tileset = {{"asset",
                             {{"version", "1.1"},
                              {"generator", std::string("perclod ") + perclod_version()},
                              {"extras", extras}}},
                            {"geometricError", std::max(diagonal, tile["geometricError"].get<double>())},
                            {"root", tile}};
  write_text_atomic(out.tileset(), tileset.dump(2) + "\n");
  files["tileset"] = leaf(out.tileset());
}

// One LOD's manifest entry: the distances it serves, its figures, its files
// (glb: its GLB with a tileset, else null) and its times.
nlohmann::json manifest_lod(const LodRange& r, const LodResult& e, const std::string* glb) {
  nlohmann::json views = nlohmann::json::array();
  for (const ViewFigures& v : e.views)
    views.push_back({{"view", v.view}, {"set", v.set}, {"changed_fraction", v.changed_fraction},
                     {"ssim_covered", v.ssim_covered}, {"silhouette_mismatch", v.silhouette_mismatch},
                     {"visible_ratio", v.visible_ratio}, {"visible_local_ratio", v.visible_local_ratio}});
  nlohmann::json l = {
      {"distance", r.distance},
      {"serves", {{"from", r.from}, {"to", std::isfinite(r.to) ? nlohmann::json(r.to) : nlohmann::json(nullptr)}}},
      {"switch_distance", r.switch_distance},
      {"max_displacement_m", r.displacement},
      {"screen_coverage", r.screen_coverage},
      {"geometric_error", r.geometric_error},
      {"pixel_footprint", e.pixel_footprint},
      {"file", leaf(e.lod_file)},
      {"triangles", triangles_per_label_json(e.simplify.triangles_after)},
      {"triangles_before", triangles_per_label_json(e.simplify.triangles_before)},
      {"fidelity", {{"worst", worst_figures_json(e.fidelity.worst)},
                    {"limits", fidelity_limits_json(e.fidelity.limits)},
                    {"over_limits", e.fidelity.over_limits.size()},
                    {"views", views}}},
      {"seconds", {{"total", e.seconds}, {"simplify", e.simplify.seconds}, {"compare", e.seconds_compare}}}};
  if (glb) l["glb"] = leaf(*glb);
  return l;
}

}  // namespace

nlohmann::json write_model_exports(const Scene& scene, const std::vector<Scene>& lods, const LodJob& job,
                                   const BatchConfig& config, const ModelRun& run, const ModelReport& report,
                                   const std::optional<CrsFrame>& frame) {
  const OutputNames& out = job.label.out;
  const auto t0 = Clock::now();
  const ExportOptions eo{job.label.up == UpAxis::Z};
  const Bounds bounds = scene_bounds(scene);
  const double diagonal = bounds_diagonal(bounds);
  const DisplayProfile& display = job.label.display;
  const double pixel_angle = display_pixel_footprint(display, 1.0);  // metres per pixel at 1 m

  const std::vector<LodResult>& entries = report.lods.lods;
  const std::vector<double> displacements = lod_displacements(entries);
  const std::vector<LodRange> ranges =
      lod_ranges(job.distances, displacements, pixel_angle, display.fov_y(), display.height, diagonal);

  nlohmann::json files = {{"report", leaf(out.report())}};
  std::vector<std::string> glb(job.distances.size());
  if (config.tileset) {
    write_lod_glbs(lods, job, ranges, eo, glb, files);
    write_tileset(scene, lods, job, config, frame, ranges, glb, bounds, diagonal, files);
  }
  if (fs::exists(out.report_html())) files["report_html"] = leaf(out.report_html());

  nlohmann::json lod_list = nlohmann::json::array();
  for (const LodRange& r : ranges) {
    const size_t k = distance_index(job.distances, r.distance);
    lod_list.push_back(manifest_lod(r, entries.at(k), config.tileset ? &glb[k] : nullptr));
  }
  std::array<double, 3> lo, hi;
  for (int a = 0; a < 3; ++a) lo[a] = bounds.lo[a] + scene.offset[a], hi[a] = bounds.hi[a] + scene.offset[a];
  nlohmann::json manifest = {
      {"schema", "perclod-manifest/1"},
      {"perclod_version", perclod_version()},
      {"complete", true},
      {"model", {{"name", run.name},
                 {"file", config.model},
                 {"hash", run.input_hash},
                 {"up", config.up == UpAxis::Z ? "z" : "y"},
                 {"triangles", scene.triangle_count()},
                 {"components", scene.component_count()},
                 {"offset", scene.offset},
                 {"bounds", {{"min", lo}, {"max", hi}}}}},
      {"config", {{"file", run.config_file}, {"hash", run.settings_hash}, {"settings", settings_json(config)}}},
      {"display", {{"name", display.name}, {"width", display.width}, {"height", display.height},
                   {"fov_y_deg", display.fov_y() * 180 / kPi}, {"pixel_angle", pixel_angle}}},
      {"lods", lod_list},
      {"files", files},
      {"timings", {{"load", report.load.seconds},
                   {"lods", report.lods.seconds},
                   {"exports", since(t0)}}}};
  if (frame) manifest["crs"] = crs_json(*frame, config, scene.offset);
  if (config.crs_origin)
    manifest["crs_origin"] = {{"lat", config.origin_lat}, {"lon", config.origin_lon}, {"height", config.origin_height}};
  write_manifest(out, manifest);
  return manifest;
}

void write_manifest(const OutputNames& out, nlohmann::json& manifest) {
  const std::string prefix = out.stem + "_", self = leaf(out.manifest());
  std::vector<std::string> names;
  for (const fs::directory_entry& e : fs::directory_iterator(out.dir)) {
    const std::string name = e.path().filename().string();
    if (e.is_regular_file() && name.compare(0, prefix.size(), prefix) == 0 && name != self) names.push_back(name);
  }
  std::sort(names.begin(), names.end());
  nlohmann::json sums = nlohmann::json::object();
  for (const std::string& name : names) sums[name] = hash_file((fs::path(out.dir) / name).string());
  manifest["checksums"] = std::move(sums);
  write_text_atomic(out.manifest(), manifest.dump(2) + "\n");
}

}  // namespace perclod
