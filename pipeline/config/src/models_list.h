// A batch's `models:` list: the files an item names and each model's output
// folder name (private to perclod_config; load_config_file uses them).
#pragma once

#include <string>
#include <vector>

#include "perclod/config.h"

namespace perclod::detail {

// The files a `models:` item names: itself, the sorted matches of a glob, or
// the sorted model files under a directory (recursively). `shown` is the
// item as the config wrote it and `where` the place ("CONFIG: models[i]"),
// for errors.
std::vector<std::string> expand_models(const std::string& item, const std::string& shown, const std::string& where);

// Output folder names: file stems, made unique by the parent folder's name
// and then by a number, in list order (so the same list always maps alike).
void name_models(std::vector<ModelEntry>& models);

// Refuses a model whose folder would take a name of the batch's own files
// in OUT (is_batch_file_name, perclod/outputs.h): found with the rest of the
// list, before any model is built, not when the batch writes that file over
// its folder. where[i]: "CONFIG: models[k]" of models[i].
void check_model_names(const std::vector<ModelEntry>& models, const std::vector<std::string>& where,
                       const std::string& out);

}  // namespace perclod::detail
