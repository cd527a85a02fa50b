// `perclod run` for one model and for a batch, and the viewer-facing exports
// (manifest, all-LOD GLB, 3D Tiles tileset). Design notes in perclod/batch.h.
#include "perclod/batch.h"

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

#include "perclod/export.h"
#include "perclod/load.h"
#include "perclod/outputs.h"
#include "perclod/report_html.h"
#include "perclod/lods.h"
#include "perclod/runtime.h"

#ifndef PERCLOD_VERSION
#define PERCLOD_VERSION "unknown"
#endif

namespace perclod {
using detail::Clock;
using detail::since;
namespace fs = std::filesystem;
namespace {

constexpr uint64_t kFnvBasis = 14695981039346656037ull, kFnvPrime = 1099511628211ull;
uint64_t fnv1a(uint64_t h, const char* data, size_t n) {
  for (size_t i = 0; i < n; ++i) h = (h ^ uint8_t(data[i])) * kFnvPrime;
  return h;
}
std::string hash_name(uint64_t h) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "fnv1a64:%016llx", static_cast<unsigned long long>(h));
  return buf;
}

// Replaces the prefix `from` of every string in `j` by `to` (report paths
// written in the partial folder, made relative to the model's folder).
void relocate(nlohmann::json& j, const std::string& from, const std::string& to) {
  if (j.is_string()) {
    const std::string& s = j.get_ref<const std::string&>();
    if (s.compare(0, from.size(), from) == 0) j = to + s.substr(from.size());
  } else if (j.is_structured()) {
    for (auto& e : j) relocate(e, from, to);
  }
}

// Names in the manifest and tileset are relative to the model's folder.
std::string leaf(const std::string& path) { return fs::path(path).filename().string(); }

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

nlohmann::json label_counts(const nlohmann::json& per_label) {
  return {{"perceptible", per_label.at("perceptible")},
          {"imperceptible", per_label.at("imperceptible")},
          {"undisplayable", per_label.at("undisplayable")},
          {"total", per_label.at("total")}};
}

bool process_alive(long pid) { return pid > 0 && (::kill(pid_t(pid), 0) == 0 || errno != ESRCH); }

}  // namespace

const char* perclod_version() { return PERCLOD_VERSION; }

std::string hash_text(const std::string& text) { return hash_name(fnv1a(kFnvBasis, text.data(), text.size())); }

std::string hash_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(path + ": cannot open to hash");
  uint64_t h = kFnvBasis;
  std::vector<char> buf(1 << 20);
  while (in) {
    in.read(buf.data(), std::streamsize(buf.size()));
    h = fnv1a(h, buf.data(), size_t(in.gcount()));
  }
  if (in.bad()) throw std::runtime_error(path + ": read error while hashing");
  return hash_name(h);
}

std::vector<LodRange> lod_ranges(const std::vector<double>& distances, const std::vector<double>& displacements,
                                 double pixel_angle, double fov_y, double diagonal) {
  if (distances.size() != displacements.size()) throw std::invalid_argument("one displacement per distance");
  std::vector<size_t> order(distances.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return distances[a] < distances[b]; });
  std::vector<LodRange> r;
  for (size_t i : order) {
    LodRange x;
    x.distance = distances[i];
    x.displacement = displacements[i];
    x.switch_distance = pixel_angle > 0 ? displacements[i] / pixel_angle : 0;
    x.from = std::min(x.distance, x.switch_distance);
    if (!r.empty()) x.from = std::max(x.from, r.back().from);
    r.push_back(x);
  }
  const double view_height_per_metre = 2 * std::tan(fov_y / 2);
  double finer_error = 0;
  for (size_t i = 0; i < r.size(); ++i) {
    r[i].to = i + 1 < r.size() ? r[i + 1].from : INFINITY;
    r[i].screen_coverage =
        std::isfinite(r[i].to) && r[i].to > 0 ? std::min(1.0, diagonal / (r[i].to * view_height_per_metre)) : 0.0;
    finer_error = std::max(finer_error, r[i].displacement);
    r[i].geometric_error = i == 0 ? 0.0 : finer_error;
  }
  return r;
}

std::array<double, 16> enu_to_ecef(double lat_deg, double lon_deg, double height) {
  constexpr double kA = 6378137.0, kF = 1 / 298.257223563;  // WGS84
  const double e2 = kF * (2 - kF);
  const double lat = lat_deg * M_PI / 180, lon = lon_deg * M_PI / 180;
  const double sl = std::sin(lat), cl = std::cos(lat), so = std::sin(lon), co = std::cos(lon);
  const double n = kA / std::sqrt(1 - e2 * sl * sl);
  const double x = (n + height) * cl * co, y = (n + height) * cl * so, z = (n * (1 - e2) + height) * sl;
  return {-so,      co,       0,  0,   // east
          -sl * co, -sl * so, cl, 0,   // north
          cl * co,  cl * so,  sl, 0,   // up
          x,        y,        z,  1};
}

nlohmann::json write_model_exports(const Scene& scene, const std::vector<Scene>& lods, const LodJob& job,
                                   const BatchConfig& config, const ModelRun& run, const nlohmann::json& report) {
  const OutputNames& out = job.label.out;
  const auto t0 = Clock::now();
  const ExportOptions eo{job.label.up == UpAxis::Z};
  const Bounds bounds = scene_bounds(scene);
  double diagonal = 0;
  for (int a = 0; a < 3; ++a) diagonal += double(bounds.hi[a] - bounds.lo[a]) * double(bounds.hi[a] - bounds.lo[a]);
  diagonal = std::sqrt(diagonal);
  const DisplayProfile& display = job.label.display;
  const double pixel_angle = display_pixel_footprint(display, 1.0);  // metres per pixel at 1 m

  const nlohmann::json& entries = report.at("lods");
  std::vector<double> displacements;
  for (const auto& e : entries) {
    const auto& s = e.at("simplify");
    displacements.push_back(s.at("max_displacement_rel").get<double>() * s.at("bbox_diagonal").get<double>());
  }
  const std::vector<LodRange> ranges = lod_ranges(job.distances, displacements, pixel_angle, display.fov_y(), diagonal);
  auto index_of = [&](double d) {
    return size_t(std::find(job.distances.begin(), job.distances.end(), d) - job.distances.begin());
  };

  nlohmann::json files = {{"report", leaf(out.report())}};
  std::vector<std::string> glb(job.distances.size());
  if (config.tileset) {
    for (size_t i = 0; i < job.distances.size(); ++i) {
      glb[i] = out.lod(job.distances[i], "glb");
      if (job.lod_format != "glb") export_scene(lods.at(i), glb[i], eo);
    }
    std::vector<const Scene*> ordered;
    std::vector<std::string> names;
    std::vector<double> coverage;
    for (const LodRange& r : ranges) {
      ordered.push_back(&lods.at(index_of(r.distance)));
      names.push_back("lod_" + distance_tag(r.distance));
      coverage.push_back(r.screen_coverage);
    }
    const std::string all = out.file("_lods.glb");
    export_lods_glb(ordered, names, coverage, all, eo);
    files["lods_glb"] = leaf(all);

    // 3D Tiles 1.1: the coarsest LOD is the root, each finer one its only
    // child (REPLACE refinement); the finest is the leaf (geometricError 0).
    nlohmann::json tile;
    for (size_t i = 0; i < ranges.size(); ++i) {
      const size_t k = index_of(ranges[i].distance);
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
    if (config.crs_origin) {
      const auto m = enu_to_ecef(config.origin_lat, config.origin_lon, config.origin_height);
      tile["transform"] = std::vector<double>(m.begin(), m.end());
    }
    nlohmann::json tileset = {{"asset", {{"version", "1.1"}, {"generator", std::string("perclod ") + perclod_version()}}},
                              {"geometricError", std::max(diagonal, tile["geometricError"].get<double>())},
                              {"root", tile}};
    write_text_atomic(out.file("_tileset.json"), tileset.dump(2) + "\n");
    files["tileset"] = leaf(out.file("_tileset.json"));
  }
  if (fs::exists(out.report_html())) files["report_html"] = leaf(out.report_html());

  nlohmann::json lod_list = nlohmann::json::array();
  for (const LodRange& r : ranges) {
    const size_t k = index_of(r.distance);
    const nlohmann::json& e = entries.at(k);
    nlohmann::json views = nlohmann::json::array();
    for (const auto& v : e.at("lod_vs_original"))
      views.push_back({{"view", v.at("view")}, {"set", v.at("set")}, {"changed_fraction", v.at("changed_fraction")},
                       {"ssim_covered", v.at("ssim_covered")}, {"silhouette_mismatch", v.at("silhouette_mismatch")}});
    nlohmann::json l = {
        {"distance", r.distance},
        {"serves", {{"from", r.from}, {"to", std::isfinite(r.to) ? nlohmann::json(r.to) : nlohmann::json(nullptr)}}},
        {"switch_distance", r.switch_distance},
        {"max_displacement_m", r.displacement},
        {"screen_coverage", r.screen_coverage},
        {"geometric_error", r.geometric_error},
        {"pixel_footprint", e.at("pixel_footprint")},
        {"file", leaf(e.at("lod_file").get<std::string>())},
        {"triangles", label_counts(e.at("simplify").at("triangles_after"))},
        {"triangles_before", label_counts(e.at("simplify").at("triangles_before"))},
        {"fidelity", {{"worst", e.at("fidelity").at("worst")},
                      {"limits", e.at("fidelity").at("limits")},
                      {"over_limits", e.at("fidelity").at("over_limits").size()},
                      {"views", views}}},
        {"seconds", {{"total", e.value("seconds", 0.0)},
                     {"simplify", e.at("simplify").value("seconds", 0.0)},
                     {"compare", e.value("seconds_compare", 0.0)}}}};
    if (config.tileset) l["glb"] = leaf(glb[k]);
    lod_list.push_back(l);
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
                   {"fov_y_deg", display.fov_y() * 180 / M_PI}, {"pixel_angle", pixel_angle}}},
      {"lods", lod_list},
      {"files", files},
      {"timings", {{"load", report.contains("load") ? report["load"].value("seconds", 0.0) : 0.0},
                   {"lods", report.value("seconds", 0.0)},
                   {"exports", since(t0)}}}};
  if (config.crs_origin)
    manifest["crs_origin"] = {{"lat", config.origin_lat}, {"lon", config.origin_lon}, {"height", config.origin_height}};
  write_text_atomic(out.file("_manifest.json"), manifest.dump(2) + "\n");
  return manifest;
}

ModelRun model_run(const ModelEntry& model, const std::string& config_file) {
  ModelRun run;
  run.name = model.name;
  run.config_file = config_file;
  run.input_hash = hash_file(model.config.model);
  run.settings_hash = hash_text(settings_json(model.config).dump());
  return run;
}

nlohmann::json run_model(const BatchConfig& config, const ModelRun& run, const std::string& dir,
                         const Progress& progress, nlohmann::json* manifest) {
  BatchConfig c = config;
  c.out = dir;
  LodJob job = lod_job(c);
  LoadOptions lo;
  lo.scale = c.scale;
  lo.cityjson_lod = c.cityjson_lod;
  LoadReport rep;
  Scene scene = load_scene(c.model, lo, &rep);
  if (progress) {
    std::ostringstream ss;
    ss << c.model << ": " << scene.triangle_count() << " triangles, " << scene.component_count() << " components";
    progress(ss.str());
  }
  std::vector<Scene> lods;
  nlohmann::json report = make_lods(scene, job, progress, &lods);
  report["model"] = c.model;
  report["load"] = load_report_json(rep);
  report["manifest"] = leaf(job.label.out.file("_manifest.json"));
  write_model_report_html(report, job.label.out);
  nlohmann::json m = write_model_exports(scene, lods, job, c, run, report);
  if (manifest) *manifest = std::move(m);
  return report;
}

std::pair<int, int> parse_shard(const std::string& spec) {
  const size_t slash = spec.find('/');
  auto num = [&](const std::string& s) {
    size_t used = 0;
    long v = -1;
    try {
      v = std::stol(s, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != s.size() || s.empty()) throw std::invalid_argument("--shard must be i/n (e.g. 0/3), got '" + spec + "'");
    return v;
  };
  if (slash == std::string::npos) throw std::invalid_argument("--shard must be i/n (e.g. 0/3), got '" + spec + "'");
  const long i = num(spec.substr(0, slash)), n = num(spec.substr(slash + 1));
  if (n < 1 || n > 1000000 || i < 0 || i >= n)
    throw std::invalid_argument("--shard i/n needs 0 <= i < n, got '" + spec + "'");
  return {int(i), int(n)};
}

std::vector<size_t> shard_indices(size_t count, int shard, int shards) {
  std::vector<size_t> r;
  for (size_t i = size_t(shard); i < count; i += size_t(shards)) r.push_back(i);
  return r;
}

// An upper bound for `perclod run` with the default settings, fitted to its
// peak resident memory on generated facades and the demo building, with
// about 10% to spare (README, Batches: "Models at a time").
double estimate_memory_mb(const std::string& model_file) {
  std::error_code ec;
  const double mb = double(fs::file_size(model_file, ec)) / (1024.0 * 1024.0);
  return 500.0 + 10.0 * (ec ? 0.0 : mb);
}

namespace {

struct Slot {
  size_t index = 0;      // in config.models
  nlohmann::json result;
};

// A JSON file (a manifest, a tileset, a summary), or null when it is missing
// or unreadable.
nlohmann::json read_json_file(const std::string& path) {
  std::ifstream in(path);
  if (!in) return nullptr;
  try {
    return nlohmann::json::parse(in);
  } catch (const std::exception&) {
    return nullptr;
  }
}

// Per LOD of a manifest: distance, total triangles, worst figures.
nlohmann::json summary_lods(const nlohmann::json& manifest) {
  nlohmann::json r = nlohmann::json::array();
  const nlohmann::json lods = manifest.is_object() ? manifest.value("lods", nlohmann::json::array()) : nlohmann::json();
  if (lods.is_array())
    for (const auto& l : lods) {
      if (!l.is_object()) continue;
      r.push_back({{"distance", l.value("distance", 0.0)},
                   {"triangles", l.value("triangles", nlohmann::json::object()).value("total", size_t(0))},
                   {"worst", l.value("fidelity", nlohmann::json::object()).value("worst", nlohmann::json::object())}});
    }
  return r;
}

std::string manifest_path(const std::string& dir, const BatchConfig& c) {
  return output_names_for(dir, c.model).file("_manifest.json");
}

std::string host_name() {
  char buf[256] = {0};
  if (::gethostname(buf, sizeof buf - 1) != 0 || !buf[0]) return "host";
  std::string h = buf;
  for (auto& ch : h)
    if (ch == '/' || ch == '-' || ch == '.') ch = '_';
  return h;
}

// The folder a model is built in: .<name>.partial-<host>-<pid> beside its
// final folder (the host too: several machines may share `out`).
std::string partial_dir(const std::string& out, const std::string& name) {
  return (fs::path(out) / ("." + name + ".partial-" + host_name() + "-" + std::to_string(::getpid()))).string();
}

// Partial folders of `name` left by processes of this host that are gone
// (another host's are left alone: its process cannot be asked).
void remove_stale_partials(const std::string& out, const std::string& name) {
  std::error_code ec;
  const std::string prefix = "." + name + ".partial-" + host_name() + "-";
  for (fs::directory_iterator it(out, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string f = it->path().filename().string();
    if (f.compare(0, prefix.size(), prefix) != 0) continue;
    long pid = 0;
    try {
      pid = std::stol(f.substr(prefix.size()));
    } catch (const std::exception&) {
      continue;
    }
    if (!process_alive(pid)) fs::remove_all(it->path(), ec);
  }
}

// Moves the finished `partial` folder to `final_dir`; an older complete
// folder there is swapped out in one step (renameat2 RENAME_EXCHANGE) and
// removed, so `final_dir` always holds one whole set of outputs.
void publish(const std::string& partial, const std::string& final_dir) {
  std::error_code ec;
  if (!fs::exists(final_dir, ec)) {
    fs::rename(partial, final_dir, ec);
    if (ec) throw std::runtime_error(final_dir + ": cannot move the finished outputs into place: " + ec.message());
    return;
  }
  if (::renameat2(AT_FDCWD, partial.c_str(), AT_FDCWD, final_dir.c_str(), RENAME_EXCHANGE) == 0) {
    fs::remove_all(partial, ec);  // now the old outputs
    return;
  }
  if (errno != EINVAL && errno != ENOSYS && errno != ENOTSUP)
    throw std::runtime_error(final_dir + ": cannot replace the old outputs: " + std::strerror(errno));
  // Filesystems without an exchanging rename (NFS, some FUSE): the old folder
  // goes aside, the new one in; only between the two is `final_dir` absent.
  const std::string aside = partial + ".old";
  fs::rename(final_dir, aside, ec);
  if (ec) throw std::runtime_error(final_dir + ": cannot move the old outputs aside: " + ec.message());
  fs::rename(partial, final_dir, ec);
  if (ec) {
    std::error_code back;
    fs::rename(aside, final_dir, back);
    throw std::runtime_error(final_dir + ": cannot move the finished outputs into place: " + ec.message());
  }
  fs::remove_all(aside, ec);
}

std::string format_seconds(double s) {
  char buf[32];
  if (s < 90) std::snprintf(buf, sizeof buf, "%.0fs", s);
  else if (s < 5400) std::snprintf(buf, sizeof buf, "%dm%02ds", int(s) / 60, int(s) % 60);
  else std::snprintf(buf, sizeof buf, "%dh%02dm", int(s) / 3600, (int(s) % 3600) / 60);
  return buf;
}

// Holds an exclusive flock on a file for its lifetime (waits for it).
class FileLock {
 public:
  explicit FileLock(const std::string& path) : fd_(::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0666)) {
    if (fd_ >= 0) ::flock(fd_, LOCK_EX);
  }
  ~FileLock() {
    if (fd_ >= 0) ::close(fd_);
  }
  FileLock(const FileLock&) = delete;
  FileLock& operator=(const FileLock&) = delete;

 private:
  int fd_;
};

// <out>/tileset.json: one child per complete model folder (external tilesets).
void write_batch_tileset(const std::string& out) {
  nlohmann::json children = nlohmann::json::array();
  double error = 0;
  std::error_code ec;
  std::vector<fs::path> dirs;
  for (fs::directory_iterator it(out, ec), end; !ec && it != end; it.increment(ec))
    if (it->is_directory(ec) && it->path().filename().string()[0] != '.') dirs.push_back(it->path());
  std::sort(dirs.begin(), dirs.end());
  for (const auto& d : dirs)
    for (const auto& f : fs::directory_iterator(d, ec)) {
      const std::string name = f.path().filename().string();
      if (name.size() < 13 || name.compare(name.size() - 13, 13, "_tileset.json") != 0) continue;
      nlohmann::json t = read_json_file(f.path().string());
      if (!t.is_object() || !t.contains("root")) continue;
      nlohmann::json root = t["root"];
      nlohmann::json child = {{"boundingVolume", root["boundingVolume"]},
                              {"geometricError", t["geometricError"]},
                              {"content", {{"uri", (d.filename() / name).string()}}}};
      // The model's own transform (crs_origin) applies inside its tileset;
      // the child's volume must be in this tileset's frame, so place a
      // transformed model by a sphere around its box.
      if (root.contains("transform")) {
        const auto& m = root["transform"];
        const auto& b = root["boundingVolume"]["box"];
        double c[3], r = 0;
        for (int a = 0; a < 3; ++a)
          c[a] = m[a].get<double>() * b[0].get<double>() + m[4 + a].get<double>() * b[1].get<double>() +
                 m[8 + a].get<double>() * b[2].get<double>() + m[12 + a].get<double>();
        for (int k = 0; k < 3; ++k) {
          double l = 0;
          for (int a = 0; a < 3; ++a) l += b[3 + 3 * k + a].get<double>() * b[3 + 3 * k + a].get<double>();
          r += std::sqrt(l);
        }
        child["boundingVolume"] = {{"sphere", {c[0], c[1], c[2], r}}};
      }
      error = std::max(error, t["geometricError"].get<double>());
      children.push_back(child);
    }
  if (children.empty()) return;
  // The root's volume: a sphere around every child's box or sphere.
  double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  for (const auto& ch : children) {
    const auto& v = ch["boundingVolume"];
    double c[3], r;
    if (v.contains("sphere")) {
      for (int a = 0; a < 3; ++a) c[a] = v["sphere"][a].get<double>();
      r = v["sphere"][3].get<double>();
    } else {
      const auto& b = v["box"];
      for (int a = 0; a < 3; ++a) c[a] = b[a].get<double>();
      r = std::abs(b[3].get<double>()) + std::abs(b[7].get<double>()) + std::abs(b[11].get<double>());
    }
    for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], c[a] - r), hi[a] = std::max(hi[a], c[a] + r);
  }
  double c[3], r = 0;
  for (int a = 0; a < 3; ++a) c[a] = 0.5 * (lo[a] + hi[a]), r += 0.25 * (hi[a] - lo[a]) * (hi[a] - lo[a]);
  nlohmann::json ts = {{"asset", {{"version", "1.1"}, {"generator", std::string("perclod ") + perclod_version()}}},
                       {"geometricError", 2 * std::sqrt(r)},
                       {"root", {{"boundingVolume", {{"sphere", {c[0], c[1], c[2], std::sqrt(r)}}}},
                                 {"geometricError", std::max(error, 2 * std::sqrt(r))},
                                 {"refine", "ADD"},
                                 {"children", children}}}};
  write_text_atomic((fs::path(out) / "tileset.json").string(), ts.dump(2) + "\n");
}

// <out>/index.html from every shard's summary batch_<i>_of_<n>.json on disk
// (the shards of one split: each lists its own models).
void write_batch_index(const std::string& out, int shards) {
  nlohmann::json all = {{"models", nlohmann::json::array()}, {"done", 0}, {"skipped", 0}, {"failed", 0}, {"seconds", 0.0}};
  for (int i = 0; i < shards; ++i) {
    const nlohmann::json s = read_json_file(
        (fs::path(out) / ("batch_" + std::to_string(i) + "_of_" + std::to_string(shards) + ".json")).string());
    if (!s.is_object()) continue;
    for (const auto& m : s["models"]) all["models"].push_back(m);
    for (const char* k : {"done", "skipped", "failed"}) all[k] = all[k].get<int>() + s.value(k, 0);
    all["seconds"] = std::max(all["seconds"].get<double>(), s.value("seconds", 0.0));
  }
  write_text_atomic((fs::path(out) / "index.html").string(), batch_index_html(all));
}

}  // namespace

nlohmann::json run_batch(const ConfigFile& config, const BatchOptions& options,
                         const std::function<void(const std::string&)>& log, bool eta) {
  const auto t0 = Clock::now();
  ensure_directory(config.out);
  const std::vector<size_t> mine = shard_indices(config.models.size(), options.shard, options.shards);
  const int jobs = std::max(1, options.jobs > 0 ? options.jobs : config.jobs);
  const double budget = options.memory_budget_mb >= 0 ? options.memory_budget_mb : config.memory_budget_mb;
  const size_t total = mine.size();

  std::vector<Slot> slots(total);
  double weight_total = 0;
  std::vector<double> weight(total);
  for (size_t i = 0; i < total; ++i) {
    slots[i].index = mine[i];
    std::error_code ec;
    const auto bytes = fs::file_size(config.models[mine[i]].config.model, ec);
    weight[i] = 1.0 + (ec ? 0.0 : double(bytes) / 1e6);  // MB + 1
    weight_total += weight[i];
  }

  std::mutex mu;
  std::condition_variable cv;
  size_t next = 0;
  double running_mb = 0, weight_done = 0;
  auto say = [&](size_t i, const std::string& what) {
    const ModelEntry& m = config.models[slots[i].index];
    std::ostringstream ss;
    ss << "[" << i + 1 << "/" << total << " " << m.name << "] " << what;
    std::lock_guard<std::mutex> g(mu);
    if (eta && weight_done > 0) {
      const double elapsed = since(t0);
      ss << "  (about " << format_seconds(elapsed / weight_done * (weight_total - weight_done)) << " left)";
    }
    if (log) log(ss.str());
  };

  auto work = [&](size_t i) {
    const ModelEntry& m = config.models[slots[i].index];
    const BatchConfig& c = m.config;
    const std::string final_dir = (fs::path(config.out) / m.name).string();
    const auto t = Clock::now();
    nlohmann::json r = {{"name", m.name}, {"model", c.model}, {"dir", m.name}};
    try {
      const ModelRun run = model_run(m, config.path);
      const nlohmann::json old = read_json_file(manifest_path(final_dir, c));
      const auto field = [&](const char* part) {  // old[part]["hash"], "" when absent
        return old.is_object() ? old.value(part, nlohmann::json::object()).value("hash", std::string()) : std::string();
      };
      if (!options.force && old.is_object() && old.value("complete", false) &&
          old.value("perclod_version", "") == perclod_version() && field("model") == run.input_hash &&
          field("config") == run.settings_hash) {
        r["status"] = "skipped";
        r["lods"] = summary_lods(old);
        const nlohmann::json files = old.value("files", nlohmann::json::object());
        if (files.contains("report_html")) r["report_html"] = m.name + "/" + files["report_html"].get<std::string>();
        say(i, "up to date, skipped (--force redoes it)");
      } else {
        remove_stale_partials(config.out, m.name);
        const std::string partial = partial_dir(config.out, m.name);
        std::error_code ec;
        fs::remove_all(partial, ec);
        say(i, "start: " + c.model);
        try {
          // Messages name the folder the files will be in once complete.
          auto moved = [&](std::string s) {
            for (size_t at; (at = s.find(partial + "/")) != std::string::npos;)
              s.replace(at, partial.size(), final_dir);
            return s;
          };
          nlohmann::json man;
          nlohmann::json report =
              run_model(c, run, partial, [&](const std::string& s) { say(i, moved(s)); }, &man);
          // Paths in the report and outputs become relative to the model's folder.
          nlohmann::json rel = report;
          relocate(rel, partial + "/", "");
          write_text_atomic(output_names_for(partial, c.model).report(), rel.dump(2) + "\n");
          publish(partial, final_dir);
          r["status"] = "done";
          r["lods"] = summary_lods(man);
          const nlohmann::json& files = man.at("files");
          if (files.contains("report_html"))
            r["report_html"] = m.name + "/" + files["report_html"].get<std::string>();
          if (report.contains("warnings"))
            for (const auto& w : report["warnings"])
              r["warnings"].push_back("[" + m.name + "] " + moved(w.get<std::string>()));
          r["over_limits"] = report.value("over_limits", 0);
        } catch (...) {
          fs::remove_all(partial, ec);
          throw;
        }
        say(i, "done in " + format_seconds(since(t)) + ": " + final_dir);
      }
    } catch (const std::exception& e) {
      r["status"] = "failed";
      r["error"] = e.what();
      say(i, std::string("FAILED: ") + e.what());
    }
    r["seconds"] = since(t);
    std::lock_guard<std::mutex> g(mu);
    slots[i].result = r;
    weight_done += weight[i];
  };

  // Workers take models in list order; a model starts only while its memory
  // estimate fits beside the running ones (the first always starts).
  auto worker = [&] {
    for (;;) {
      size_t i;
      double need;
      {
        std::unique_lock<std::mutex> lk(mu);
        if (next >= total) return;
        i = next;
        const BatchConfig& c = config.models[slots[i].index].config;
        need = c.memory_mb > 0 ? c.memory_mb : estimate_memory_mb(c.model);
        cv.wait(lk, [&] { return running_mb == 0 || budget <= 0 || running_mb + need <= budget; });
        if (i != next) continue;  // another worker took it meanwhile
        ++next;
        running_mb += need;
      }
      work(i);
      {
        std::lock_guard<std::mutex> g(mu);
        running_mb -= need;
      }
      cv.notify_all();
    }
  };
  std::vector<std::thread> pool;
  for (int k = 0; k < std::min<int>(jobs, int(total)); ++k) pool.emplace_back(worker);
  for (auto& th : pool) th.join();

  nlohmann::json summary = {{"models", nlohmann::json::array()}, {"done", 0}, {"skipped", 0}, {"failed", 0},
                            {"shard", std::to_string(options.shard) + "/" + std::to_string(options.shards)},
                            {"config", config.path}, {"perclod_version", perclod_version()}};
  for (const Slot& s : slots) {
    summary["models"].push_back(s.result);
    const std::string st = s.result.value("status", "failed");
    summary[st] = summary[st].get<int>() + 1;
  }
  summary["seconds"] = since(t0);
  write_text_atomic((fs::path(config.out) / ("batch_" + std::to_string(options.shard) + "_of_" +
                                             std::to_string(options.shards) + ".json"))
                        .string(),
                    summary.dump(2) + "\n");
  {
    // Shards finishing together take turns, so the last one's scan sees every
    // folder and summary published before it.
    FileLock lock((fs::path(config.out) / ".batch.lock").string());
    write_batch_tileset(config.out);
    write_batch_index(config.out, options.shards);
  }
  return summary;
}

}  // namespace perclod
