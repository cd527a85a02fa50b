// Helpers the batch's files share (private to perclod_batch).
#pragma once

#include <nlohmann/json.hpp>
#include <string>

namespace perclod::detail {

// Names in the manifest and tileset are relative to the model's folder.
std::string leaf(const std::string& path);

// Replaces the prefix `from` of every string in `j` by `to` (report paths
// written in the partial folder, made relative to the model's folder).
void relocate(nlohmann::json& j, const std::string& from, const std::string& to);

// Whether process `pid` of this host still runs.
bool process_alive(long pid);

}  // namespace perclod::detail
