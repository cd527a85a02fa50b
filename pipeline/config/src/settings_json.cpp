// settings_json: the settings that decide a model's outputs, by the table of
// config keys (perclod/settings.h), hashed to tell whether an output is up to
// date. Kept apart from the YAML reader (config.cpp).
#include <cmath>
#include <cstring>
#include <map>
#include <stdexcept>
#include <string>

#include "perclod/config.h"
#include "perclod/label.h"
#include "perclod/settings.h"

namespace perclod {

namespace {

// The value a hashed key enters settings_json with: config_settings()'s
// hashed keys each have one (nested keys inside their mapping's), none
// other. A writer may leave its key out; the JSON types of the values are
// part of the hash.
using HashWriter = void (*)(const BatchConfig&, nlohmann::json&);
using json = nlohmann::json;

// The display profile's values, not its path, by display_settings()'s keys.
void write_display(const BatchConfig& c, json& s) {
  const DisplayProfile d = c.display.empty() ? default_display_profile() : load_display_profile(c.display);
  const std::map<std::string, json> values = {{"name", d.name},
                                              {"width", d.width},
                                              {"height", d.height},
                                              {"dpi", d.dpi},
                                              {"viewer_distance_m", d.viewer_distance},
                                              {"fov_y_deg", d.fov_y_override_deg}};
  json& out = s["display"] = json::object();
  for (const SettingSpec& k : display_settings())
    if (k.hashed) out[k.key] = values.at(k.key);
}

const std::map<std::string, HashWriter>& hash_writers() {
  static const std::map<std::string, HashWriter> writers = {
      {"up", [](const BatchConfig& c, json& s) { s["up"] = c.up == UpAxis::Z ? "z" : "y"; }},
      {"scale", [](const BatchConfig& c, json& s) { s["scale"] = c.scale; }},
      {"display", write_display},
      {"distances", [](const BatchConfig& c, json& s) { s["distances"] = c.distances; }},
      {"views", [](const BatchConfig& c, json& s) { s["views"] = c.views; }},
      {"samples", [](const BatchConfig& c, json& s) { s["samples"] = samples_json(c.samples); }},
      {"spins", [](const BatchConfig& c, json& s) { s["spins"] = c.spins; }},
      {"keep_unsampled_surface",
       [](const BatchConfig& c, json& s) { s["keep_unsampled_surface"] = c.keep_unsampled_surface; }},
      // Joins when on, so the hashes of older configs stay.
      {"mask_per_sample", [](const BatchConfig& c, json& s) { if (c.mask_per_sample) s["mask_per_sample"] = true; }},
      {"per_building", [](const BatchConfig& c, json& s) { s["per_building"] = c.per_building; }},
      // Joins when set, so the hashes of older configs stay.
      {"group_span", [](const BatchConfig& c, json& s) { if (c.group_span != 0) s["group_span"] = c.group_span; }},
      {"own_views_alone", [](const BatchConfig& c, json& s) { s["own_views_alone"] = c.own_views_alone; }},
      // Left out when it is the paper's rule; the default (pooled) joins, so
      // a manifest redoes models labelled before the key existed.
      {"combine_views",
       [](const BatchConfig& c, json& s) {
         if (c.combine_views != "any") s["combine_views"] = c.combine_views;
       }},
      {"tracer", [](const BatchConfig& c, json& s) { s["tracer"] = c.tracer; }},
      {"verify", [](const BatchConfig& c, json& s) { s["verify"] = c.verify; }},
      {"ratio", [](const BatchConfig& c, json& s) { s["ratio"] = c.ratio; }},
      {"simplify", [](const BatchConfig& c, json& s) { s["simplify"] = c.simplify; }},
      {"e_perceptible", [](const BatchConfig& c, json& s) { s["e_perceptible"] = c.e_perceptible; }},
      {"e_imperceptible", [](const BatchConfig& c, json& s) { s["e_imperceptible"] = c.e_imperceptible; }},
      {"e_undisplayable",
       [](const BatchConfig& c, json& s) {
         if (std::isfinite(c.e_undisplayable)) s["e_undisplayable"] = c.e_undisplayable;
       }},
      // true and false stay booleans, so the hashes of configs that named
      // one stay what they were before auto.
      {"keep_undisplayable",
       [](const BatchConfig& c, json& s) {
         s["keep_undisplayable"] = c.keep_undisplayable == "auto" ? json("auto") : json(c.keep_undisplayable == "true");
       }},
      {"k", [](const BatchConfig& c, json& s) { s["k"] = c.k; }},
      {"target", [](const BatchConfig& c, json& s) { s["target"] = c.target; }},
      {"format", [](const BatchConfig& c, json& s) { s["format"] = c.format; }},
      {"judge_views", [](const BatchConfig& c, json& s) { s["judge_views"] = c.judge_views; }},
      {"judge_buildings_alone",
       [](const BatchConfig& c, json& s) { s["judge_buildings_alone"] = c.judge_buildings_alone; }},
      {"max_changed", [](const BatchConfig& c, json& s) { s["max_changed"] = c.max_changed; }},
      {"max_silhouette", [](const BatchConfig& c, json& s) { s["max_silhouette"] = c.max_silhouette; }},
      // Joins only when set, so the hashes of configs without it (and the
      // batches a manifest resumes) stay what they were before the key.
      {"min_ssim", [](const BatchConfig& c, json& s) { if (c.min_ssim > 0) s["min_ssim"] = c.min_ssim; }},
      {"max_visible", [](const BatchConfig& c, json& s) { if (c.max_visible > 0) s["max_visible"] = c.max_visible; }},
      // Joins when set, so the hashes of configs without it stay.
      {"max_visible_local",
       [](const BatchConfig& c, json& s) {
         if (c.max_visible_local > 0) s["max_visible_local"] = c.max_visible_local;
       }},
      // Joins in fidelity mode, where it decides: a manifest redoes fidelity
      // LODs made before tightening existed (some would now be tighter).
      {"tighten_to_limits",
       [](const BatchConfig& c, json& s) {
         if (c.simplify == "fidelity") s["tighten_to_limits"] = c.tighten_to_limits;
       }},
      // Joins in fidelity mode, where it decides: a manifest redoes fidelity
      // LODs made before it existed.
      {"free_topology",
       [](const BatchConfig& c, json& s) {
         if (c.simplify == "fidelity") s["free_topology"] = c.free_topology;
       }},
      // Only the report changes; joins when on, so older hashes stay.
      {"explain", [](const BatchConfig& c, json& s) { if (c.explain) s["explain"] = true; }},
      {"fidelity_target",
       [](const BatchConfig& c, json& s) {
         json target = nullptr;
         if (c.fidelity_target) {
           target = {{"max_changed", c.target_max_changed}, {"max_silhouette", c.target_max_silhouette}};
           if (c.target_min_ssim > 0) target["min_ssim"] = c.target_min_ssim;
           if (c.target_max_visible > 0) target["max_visible"] = c.target_max_visible;
           if (c.target_max_visible_local > 0) target["max_visible_local"] = c.target_max_visible_local;
         }
         s["fidelity_target"] = target;
       }},
      {"cityjson_lod", [](const BatchConfig& c, json& s) { s["cityjson_lod"] = c.cityjson_lod; }},
      // Joins when set, so the hashes of configs without it stay.
      {"crs", [](const BatchConfig& c, json& s) { if (!c.crs.empty()) s["crs"] = c.crs; }},
      {"crs_origin",
       [](const BatchConfig& c, json& s) {
         s["crs_origin"] = c.crs_origin ? json{{"lat", c.origin_lat}, {"lon", c.origin_lon}, {"height", c.origin_height}}
                                        : json(nullptr);
       }},
      {"tileset", [](const BatchConfig& c, json& s) { s["tileset"] = c.tileset; }},
      {"debug_images", [](const BatchConfig& c, json& s) { s["debug_images"] = c.debug_images; }},
      {"marking_near", [](const BatchConfig& c, json& s) { s["marking_near"] = c.marking_near; }},
  };
  return writers;
}

// The hashed keys of config_settings() that settings_json writes: not an
// old name, not a key inside a mapping.
bool written_by_settings_json(const SettingSpec& k) { return k.hashed && !k.alias_of && !std::strchr(k.key, '.'); }

}  // namespace

nlohmann::json settings_json(const BatchConfig& c) {
  static const bool checked = [] {
    for (const auto& [key, writer] : hash_writers()) {
      const SettingSpec* k = find_setting(config_settings(), key);
      if (!k || !written_by_settings_json(*k))
        throw std::logic_error("settings_json writes '" + key + "', which config_settings() does not hash");
    }
    return true;
  }();
  (void)checked;
  json s = json::object();
  for (const SettingSpec& k : config_settings()) {
    if (!written_by_settings_json(k)) continue;
    const auto w = hash_writers().find(k.key);
    if (w == hash_writers().end())
      throw std::logic_error(std::string("config key '") + k.key + "' is hashed but settings_json has no value for it");
    w->second(c, s);
  }
  return s;
}

}  // namespace perclod
