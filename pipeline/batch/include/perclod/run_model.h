// perclod/run_model.h - `perclod run` for one model: load, make_lods, the
// report page and the viewer exports, and the identity (version, input and
// settings hashes) that tells whether its outputs are up to date.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "perclod/config.h"
#include "perclod/lods.h"
#include "perclod/progress_text.h"
#include "perclod/report_json.h"

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
// model) + the report file and page + write_model_exports. Returns what it
// did (model_report_json gives it as JSON); `manifest`, when given, receives
// the manifest itself. Throws on any failure (naming the file).
ModelReport run_model(const BatchConfig& config, const ModelRun& run, const std::string& dir,
                      ModelProgress* progress = nullptr, nlohmann::json* manifest = nullptr);

}  // namespace perclod
