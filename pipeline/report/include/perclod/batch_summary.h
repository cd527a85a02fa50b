// perclod/batch_summary.h - what `perclod run` did with each model of a
// batch, as run_batch returns it, and its JSON (<out>/batch_<i>_of_<n>.json,
// `perclod run BATCH --json`).
#pragma once

#include <cstddef>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "perclod/judge.h"

namespace perclod {

// One LOD of a model's manifest: its distance, triangles and worst figures.
struct LodSummary {
  double distance = 0;
  size_t triangles = 0;
  std::optional<WorstFigures> worst;  // absent when the manifest has none
};

enum class ModelStatus { Done, Skipped, Failed };
const char* model_status_name(ModelStatus s);  // "done", "skipped", "failed"

// One model of the batch.
struct ModelOutcome {
  std::string name;   // its output folder under the batch's out
  std::string model;  // its file
  std::string dir;    // its folder, relative to out
  ModelStatus status = ModelStatus::Failed;
  std::string error;                   // failed: why
  std::vector<LodSummary> lods;        // done or skipped: from its manifest
  std::string report_html;             // relative to out ("" when none)
  std::vector<std::string> warnings;   // done: the run's warnings, "[name] ..."
  size_t over_limits = 0;              // done: view figures over the limits
  double seconds = 0;
};

// This shard's models, in list order, and the counts by status.
struct BatchSummary {
  std::vector<ModelOutcome> models;
  int done = 0, skipped = 0, failed = 0;
  std::string shard;  // "i/n"
  std::string config;
  std::string perclod_version;
  double seconds = 0;
};

nlohmann::json batch_summary_json(const BatchSummary& summary);

}  // namespace perclod
