// perclod/batch.h - `perclod run` over a whole batch: run_model
// (perclod/run_model.h) for every model of a config with `models:`
// (docs/usage.md#batches):
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

#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "perclod/batch_summary.h"
#include "perclod/config.h"

namespace perclod {

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
// (BENCHMARKS.md#the-memory-estimate: fitted to measured runs of single
// buildings; a block
// framed in many tiles needs far more, and its entry's memory_mb says so).
double estimate_memory_mb(const std::string& model_file);

// Writes <out>/tileset.json (3D Tiles 1.1) over every model folder in out
// that holds a <name>_tileset.json: one child per model, its content that
// tileset (an external tileset), ADD refinement. Its geometricError and its
// root's are the larger of the batch's bounding-sphere diameter and every
// model tileset's geometricError. Writes nothing when no folder has one.
void write_batch_tileset(const std::string& out);

// Runs the batch; `log` receives progress lines ("[i/n name] ..."; with an
// estimate of the time left when `eta` is set). Returns what it did with
// each model, also written (batch_summary_json) to
// <out>/batch_<shard>_of_<shards>.json, with <out>/tileset.json referencing
// every complete model's tileset and <out>/index.html.
BatchSummary run_batch(const ConfigFile& config, const BatchOptions& options,
                       const std::function<void(const std::string&)>& log, bool eta = false);

}  // namespace perclod
