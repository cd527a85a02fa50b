// One model's run (`perclod run` on a one-model config, or a batch entry):
// load, make_lods, the report page and the viewer exports; and the hashes
// that tell whether its outputs are up to date.
#include "perclod/run_model.h"

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
#include "perclod/load.h"
#include "perclod/model_exports.h"
#include "perclod/report_html.h"
#include "perclod/report_json.h"

#ifndef PERCLOD_VERSION
#define PERCLOD_VERSION "unknown"
#endif

namespace perclod {
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

}  // namespace

namespace detail {

void relocate(nlohmann::json& j, const std::string& from, const std::string& to) {
  if (j.is_string()) {
    const std::string& s = j.get_ref<const std::string&>();
    if (s.compare(0, from.size(), from) == 0) j = to + s.substr(from.size());
  } else if (j.is_structured()) {
    for (auto& e : j) relocate(e, from, to);
  }
}

std::string leaf(const std::string& path) { return fs::path(path).filename().string(); }

bool process_alive(long pid) { return pid > 0 && (::kill(pid_t(pid), 0) == 0 || errno != ESRCH); }

}  // namespace detail

using detail::leaf;

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

ModelRun model_run(const ModelEntry& model, const std::string& config_file) {
  ModelRun run;
  run.name = model.name;
  run.config_file = config_file;
  run.input_hash = hash_file(model.config.model);
  run.settings_hash = hash_text(settings_json(model.config).dump());
  return run;
}

ModelReport run_model(const BatchConfig& config, const ModelRun& run, const std::string& dir,
                      ModelProgress* progress, nlohmann::json* manifest) {
  BatchConfig c = config;
  c.out = dir;
  LodJob job = lod_job(c);
  LoadOptions lo;
  lo.scale = c.scale;
  lo.cityjson_lod = c.cityjson_lod;
  ModelReport r;
  r.model = c.model;
  Scene scene = load_scene(c.model, lo, &r.load);
  // Placed before the long work: a CRS PROJ cannot place fails now, naming the file.
  const std::optional<CrsFrame> frame = model_crs_frame(c, r.load, scene);
  if (progress) progress->model_loaded(c.model, scene);
  std::vector<Scene> lods;
  r.lods = make_lods(scene, job, progress, &lods);
  write_text_atomic(job.label.out.report(), lod_set_json(r.lods).dump(2) + "\n");
  r.manifest_file = leaf(job.label.out.manifest());
  const nlohmann::json report = model_report_json(r);
  write_model_report_html(report, job.label.out);
  nlohmann::json m = write_model_exports(scene, lods, job, c, run, r, frame);
  if (manifest) *manifest = std::move(m);
  return r;
}

}  // namespace perclod
