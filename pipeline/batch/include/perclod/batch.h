// perclod/batch.h - `perclod run` over one model or a whole batch, and the
// files a viewer loads: manifest, all-LOD GLB, 3D Tiles tileset.
//
// run_model is the whole job for one model: load, make_lods, then
// write_model_exports. run_batch runs run_model for every model of a config
// with `models:` (README, "Batches"):
//  * each model is written to <out>/.<name>.partial-<host>-<pid>/ and renamed to
//    <out>/<name>/ when complete, so a folder under its final name is whole;
//  * a model whose manifest records the same input hash, settings hash and
//    perclod version is skipped (options.force redoes it);
//  * a model that fails is reported with its error and the batch goes on;
//    other models' outputs are untouched;
//  * options.shard / shards takes models i, i + n, i + 2n, ... of the list, so
//    shards 0..n-1 partition it exactly (one per machine or Slurm array task);
//  * up to `jobs` models at a time, each started only while the memory
//    estimates of the running ones and its own fit memory_budget_mb.
#pragma once

#include <array>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "perclod/config.h"
#include "perclod/lods.h"

namespace perclod {

// perclod's version (CMake's project version): part of every output's identity.
const char* perclod_version();

// "fnv1a64:<16 hex digits>" of a file's bytes or of a string: cheap identity
// for up-to-date checks (not a cryptographic hash). Throws naming an unreadable file.
std::string hash_file(const std::string& path);
std::string hash_text(const std::string& text);

// Everything run_model needs to know besides the settings.
struct ModelRun {
  std::string name;          // output folder name in a batch (the file stem otherwise)
  std::string config_file;   // named in the manifest
  std::string input_hash, settings_hash;  // hash_file(model), hash_text(settings_json(config).dump())
};

// The identity of `model` of the config file `config_file`: its name and
// both hashes (reads the model file).
ModelRun model_run(const ModelEntry& model, const std::string& config_file);

// load + make_lods (job from lod_job(config), outputs in `dir` named after the
// model) + the report page + write_model_exports. Returns the report, with
// "model", "load" and "manifest" (the manifest's file name) added; `manifest`,
// when given, receives the manifest itself. Throws on any failure (naming the file).
nlohmann::json run_model(const BatchConfig& config, const ModelRun& run, const std::string& dir,
                         const Progress& progress = {}, nlohmann::json* manifest = nullptr);

// The serving range of each LOD (sorted by distance; README, "Manifest"):
// vd = its largest vertex displacement (metres), its switch distance
// d_th = vd / (pixel angle) (Belblidia's d_th = f * vd / ps), serving from
// min(d, d_th) (never before the previous LOD's start) up to the next LOD's
// start (the last: no end, to = infinity).
struct LodRange {
  double distance = 0, displacement = 0, switch_distance = 0, from = 0, to = 0;
  double screen_coverage = 0;  // model diagonal / screen height at `to` (0 for the last)
  double geometric_error = 0;  // tileset: largest displacement of this LOD and every finer one (finest: 0)
};
std::vector<LodRange> lod_ranges(const std::vector<double>& distances, const std::vector<double>& displacements,
                                 double pixel_angle, double fov_y, double diagonal);

// The local east-north-up frame at a WGS84 point, as the column-major 4x4
// transform (ENU metres -> ECEF metres) 3D Tiles takes.
std::array<double, 16> enu_to_ecef(double lat_deg, double lon_deg, double height);

// Writes beside the report in job.label.out: a GLB per LOD (when the LODs are
// OBJ), <stem>_lods.glb (MSFT_lod), <stem>_tileset.json (3D Tiles 1.1) when
// config.tileset, and always <stem>_manifest.json (last: its presence marks
// the outputs complete). File names in them are relative to the folder.
nlohmann::json write_model_exports(const Scene& scene, const std::vector<Scene>& lods, const LodJob& job,
                                   const BatchConfig& config, const ModelRun& run, const nlohmann::json& report);

struct BatchOptions {
  bool force = false;      // redo models whose outputs are up to date
  int shard = 0, shards = 1;
  int jobs = 0;            // 0: the config's
  double memory_budget_mb = -1;  // < 0: the config's
};

// "i/n" -> {i, n}; throws std::invalid_argument unless 0 <= i < n.
std::pair<int, int> parse_shard(const std::string& spec);
// The list positions shard i of n takes: i, i + n, i + 2n, ...
std::vector<size_t> shard_indices(size_t count, int shard, int shards);

// A rough peak-memory estimate (MiB) for one model, from its file size
// (README, "Batches": fitted to measured runs of single buildings; a block
// framed in many tiles needs far more, and its entry's memory_mb says so).
double estimate_memory_mb(const std::string& model_file);

// Runs the batch; `log` receives progress lines ("[i/n name] ..."; with an
// estimate of the time left when `eta` is set). Returns the summary:
// {"models": [{"name", "model", "status": "done"|"skipped"|"failed",
// "error", "dir", "seconds", "lods": [...]}], "done", "skipped", "failed",
// "shard", "seconds"}, also written to <out>/batch_<shard>.json, with
// <out>/tileset.json referencing every complete model's tileset.
nlohmann::json run_batch(const ConfigFile& config, const BatchOptions& options,
                         const std::function<void(const std::string&)>& log, bool eta = false);

}  // namespace perclod
