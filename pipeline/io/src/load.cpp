// Model loading. OBJ: perclod's own double-precision reader. Other formats:
// assimp. Both end in build_scene(), which recentres in double and only then
// converts to float.
#include "perclod/load.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>

#include <nlohmann/json.hpp>

#include "perclod/outputs.h"
#include "perclod/simplify.h"
#include "readers.h"

namespace perclod {
namespace fs = std::filesystem;
using namespace detail;

namespace detail {

[[noreturn]] void fail(const std::string& path, const std::string& what, size_t line) {
  if (line) throw LoadError(path + ":" + std::to_string(line) + ": " + what);
  throw LoadError(path + ": " + what);
}

std::string read_file(const std::string& path) {
  std::error_code ec;
  if (!fs::exists(path, ec)) fail(path, "no such file");
  if (fs::is_directory(path, ec)) fail(path, "is a directory, not a model file");
  std::ifstream f(path, std::ios::binary);
  if (!f) fail(path, "cannot open (permission?)");
  std::ostringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

}  // namespace detail

namespace {


Scene build_scene(RawModel&& m, const std::string& path, const LoadOptions& opt, LoadReport& rep) {
  if (m.indices.empty()) fail(path, "no triangles (empty model)");
  if (!(opt.scale > 0) || !std::isfinite(opt.scale)) fail(path, "unit scale must be a positive number");
  double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  for (uint32_t i : m.indices)
    for (int a = 0; a < 3; ++a) {
      double v = m.positions[3 * size_t(i) + a] * opt.scale;
      lo[a] = std::min(lo[a], v);
      hi[a] = std::max(hi[a], v);
    }
  auto num = [](double v) {
    char buf[32];
    return std::string(buf, std::to_chars(buf, buf + sizeof buf, v).ptr);
  };
  const std::string scale_note = opt.scale == 1 ? "" : " (times unit scale " + num(opt.scale) + ")";
  for (int a = 0; a < 3; ++a)
    if (!std::isfinite(lo[a]) || !std::isfinite(hi[a]))
      fail(path, "coordinates overflow" + scale_note + ": the model is too large or the unit scale is wrong");
  Scene s;
  for (int a = 0; a < 3; ++a) s.offset[a] = opt.centre ? (*opt.centre)[a] : 0.5 * (lo[a] + hi[a]);
  s.positions.resize(m.positions.size());
  for (size_t i = 0; i < m.positions.size(); ++i) {
    const double v = m.positions[i] * opt.scale - s.offset[i % 3];
    // Positions are float after recentring: a coordinate beyond float's range
    // (about 3.4e38) would become infinite.
    if (!(std::fabs(v) <= double(std::numeric_limits<float>::max())))
      fail(path, "vertex " + std::to_string(i / 3 + 1) + " coordinate " + num(m.positions[i]) + scale_note +
                     " is too far from the model's centre for float precision (beyond 3.4e38): the model is "
                     "too large or the unit scale is wrong");
    s.positions[i] = float(v);
  }
  const double span = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]});
  if (span > kMaxModelSpan)
    fail(path, "the model spans " + num(span) + " m" + (opt.scale == 1 ? "" : " after the unit scale " + num(opt.scale)) +
                   ", more than the " + num(kMaxModelSpan) +
                   " m perclod renders and traces in float precision: the model is too large or the unit scale "
                   "is wrong");
  s.indices = std::move(m.indices);
  s.material = std::move(m.material);
  s.materials = std::move(m.materials);
  // Components: the file's groups, or connectivity where it has at most one.
  if (m.component_names.size() <= 1 && !m.objects_are_components) {
    uint32_t n = connected_parts(s, s.component);
    s.component_names.resize(n);
    for (uint32_t c = 0; c < n; ++c) s.component_names[c] = "part" + std::to_string(c);
    rep.components_from_connectivity = true;
  } else {
    s.component = std::move(m.component);
    s.component_names = std::move(m.component_names);
  }
  for (size_t t = 0; t < s.triangle_count(); ++t) rep.degenerate_triangles += is_degenerate(s, t);
  try {
    validate(s);  // e.g. a coordinate that overflows float after recentring and scaling
  } catch (const std::invalid_argument& e) {
    fail(path, e.what());
  }
  return s;
}

}  // namespace

bool is_degenerate(const Scene& s, size_t t) {
  uint32_t a = s.indices[3 * t], b = s.indices[3 * t + 1], c = s.indices[3 * t + 2];
  if (a == b || b == c || a == c) return true;
  const float* A = &s.positions[3 * size_t(a)];
  const float* B = &s.positions[3 * size_t(b)];
  const float* C = &s.positions[3 * size_t(c)];
  double u[3], v[3];
  for (int k = 0; k < 3; ++k) u[k] = double(B[k]) - A[k], v[k] = double(C[k]) - A[k];
  double cx = u[1] * v[2] - u[2] * v[1], cy = u[2] * v[0] - u[0] * v[2], cz = u[0] * v[1] - u[1] * v[0];
  return cx == 0 && cy == 0 && cz == 0;
}

Scene load_scene(const std::string& path, const LoadOptions& options, LoadReport* report) {
  auto t0 = std::chrono::steady_clock::now();
  LoadReport rep;
  std::string ext = lower_extension(path);
  RawModel raw;
  if (ext == ".obj" || (ext.empty() && looks_like_obj(path))) raw = read_obj(path, rep);
  // .json and .city.json: the content decides (read_cityjson refuses other JSON).
  else if (ext == ".json" || ext == ".cityjson" || (ext.empty() && looks_like_cityjson(path)))
    raw = read_cityjson(path, options, rep);
  else raw = read_assimp(path, rep);
  Scene s = build_scene(std::move(raw), path, options, rep);
  rep.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (report) *report = rep;
  return s;
}

SceneInfo analyse_scene(const Scene& s) {
  SceneInfo info;
  info.triangles = s.triangle_count();
  info.vertices = s.vertex_count();
  info.components = s.component_count();
  info.materials = s.materials.size();
  info.bounds = scene_bounds(s);
  info.offset = s.offset;
  const std::vector<uint32_t> weld = weld_exact(s);  // per corner
  std::vector<uint64_t> edges;
  edges.reserve(s.indices.size());
  for (size_t t = 0; t < s.triangle_count(); ++t) {
    info.degenerate_triangles += is_degenerate(s, t);
    for (int k = 0; k < 3; ++k) {
      uint64_t a = weld[3 * t + k], b = weld[3 * t + (k + 1) % 3];
      if (a == b) continue;
      edges.push_back(std::min(a, b) << 32 | std::max(a, b));
    }
  }
  std::sort(edges.begin(), edges.end());
  for (size_t i = 0; i < edges.size();) {
    size_t j = i;
    while (j < edges.size() && edges[j] == edges[i]) ++j;
    if (j - i == 1) ++info.boundary_edges;
    if (j - i > 2) ++info.non_manifold_edges;
    i = j;
  }
  return info;
}

nlohmann::json load_report_json(const LoadReport& r) {
  nlohmann::json j = {{"polygons", r.polygons},
                      {"polygons_triangulated", r.polygons_triangulated},
                      {"degenerate_triangles", r.degenerate_triangles},
                      {"components_from_connectivity", r.components_from_connectivity},
                      {"seconds", r.seconds}};
  // Counts of what could not be used as it was: only when it happened.
  for (const auto& [key, n] : {std::pair<const char*, size_t>{"polygons_fanned", r.polygons_fanned},
                               {"polygons_with_holes", r.polygons_with_holes},
                               {"polygons_holes_failed", r.polygons_holes_failed},
                               {"polygons_skipped", r.polygons_skipped},
                               {"cityjson_objects_without_lod", r.cityjson_objects_without_lod},
                               {"cityjson_geometries_unsupported", r.cityjson_geometries_unsupported}})
    if (n) j[key] = n;
  if (!r.reference_system.empty()) j["reference_system"] = r.reference_system;
  return j;
}

}  // namespace perclod