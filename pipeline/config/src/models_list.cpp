// A batch's `models:` list (models_list.h).
#include "models_list.h"

#include <glob.h>

#include <algorithm>
#include <cctype>
#include <cstring>
#include <filesystem>
#include <map>
#include <set>
#include <stdexcept>

#include "perclod/outputs.h"

namespace perclod::detail {
namespace {

std::runtime_error list_error(const std::string& where, const std::string& what) {
  return std::runtime_error(where + ": " + what);
}

bool is_glob(const std::string& s) { return s.find_first_of("*?[") != std::string::npos; }

// A file a folder item takes: a model format's extension. Of JSON files only
// CityJSON's names (.city.json, .cityjson): a folder may hold reports.
bool is_model_file(const std::filesystem::path& p) {
  std::string name = p.filename().string();
  for (auto& ch : name) ch = char(std::tolower(static_cast<unsigned char>(ch)));
  const auto ends = [&](const char* e) {
    const size_t n = std::strlen(e);
    return name.size() > n && name.compare(name.size() - n, n, e) == 0;
  };
  for (const char* e : {".obj", ".ply", ".glb", ".gltf", ".stl", ".dae", ".fbx", ".ifc", ".city.json", ".cityjson"})
    if (ends(e)) return true;
  return false;
}

}  // namespace

std::vector<std::string> expand_models(const std::string& item, const std::string& shown, const std::string& where) {
  namespace fs = std::filesystem;
  std::vector<std::string> files;
  std::error_code ec;
  if (is_glob(item)) {
    glob_t g{};
    const int rc = ::glob(item.c_str(), 0, nullptr, &g);
    if (rc == 0)
      for (size_t i = 0; i < g.gl_pathc; ++i)
        if (fs::is_regular_file(g.gl_pathv[i], ec)) files.push_back(g.gl_pathv[i]);
    globfree(&g);
    if (files.empty()) throw list_error(where, "'" + shown + "' matches no model file");
  } else if (fs::is_directory(item, ec)) {
    for (const auto& e : fs::recursive_directory_iterator(item, fs::directory_options::skip_permission_denied, ec))
      if (e.is_regular_file(ec) && is_model_file(e.path())) files.push_back(e.path().string());
    std::sort(files.begin(), files.end());
    if (files.empty()) throw list_error(where, "folder '" + shown + "' holds no model file");
  } else {
    files.push_back(item);  // parse_model says if it does not exist
  }
  return files;
}

void name_models(std::vector<ModelEntry>& models) {
  namespace fs = std::filesystem;
  std::map<std::string, int> stems;
  for (const auto& m : models) ++stems[model_stem(m.config.model)];
  std::set<std::string> used;
  for (auto& m : models) {
    const fs::path p(m.config.model);
    std::string name = model_stem(m.config.model);
    if (stems[name] > 1 && p.has_parent_path()) name = p.parent_path().filename().string() + "_" + name;
    std::string unique = name;
    for (int k = 2; used.count(unique); ++k) unique = name + "_" + std::to_string(k);
    used.insert(unique);
    m.name = unique;
  }
}

void check_model_names(const std::vector<ModelEntry>& models, const std::vector<std::string>& where,
                       const std::string& out) {
  for (size_t i = 0; i < models.size(); ++i)
    if (is_batch_file_name(models[i].name))
      throw list_error(where[i], "'" + models[i].config.model + "' would be written to the folder '" + out + "/" +
                                       models[i].name + "', a name the batch's own files use (index.html, " +
                                       "tileset.json, batch_<i>_of_<n>.json, names starting with '.'); " +
                                       "rename the model file");
}

}  // namespace perclod::detail
