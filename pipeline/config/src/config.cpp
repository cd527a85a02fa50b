// YAML display profiles and batch configs.
#include "perclod/config.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <iomanip>
#include <sstream>
#include <map>
#include <filesystem>
#include <set>
#include <stdexcept>
#include <vector>

#include "perclod/crs.h"
#include "models_list.h"
#include "perclod/outputs.h"
#include "perclod/settings.h"
#include "perclod/views.h"

namespace perclod {
namespace {

std::runtime_error config_error(const std::string& path, const std::string& what) {
  return std::runtime_error(path + ": " + what);
}

YAML::Node load_yaml(const std::string& path) {
  if (!std::filesystem::exists(path)) throw config_error(path, "no such file");
  try {
    YAML::Node n = YAML::LoadFile(path);
    if (!n.IsMap()) throw config_error(path, "expected a YAML mapping at the top level");
    return n;
  } catch (const YAML::Exception& e) {
    throw config_error(path, std::string("YAML error: ") + e.what());
  }
}

// Levenshtein distance, for "did you mean" on a misspelt key.
size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<size_t> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    size_t diag = row[0];
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (a[i - 1] != b[j - 1])});
      diag = up;
    }
  }
  return row[b.size()];
}

// Every key of the mapping must be one of `known` and appear once: yaml-cpp
// keeps only one of two equal keys when indexing, so walk the keys themselves.
void check_keys(const YAML::Node& n, const std::string& path, const std::set<std::string>& known) {
  std::set<std::string> seen;
  for (const auto& kv : n) {
    std::string key;
    try {
      key = kv.first.as<std::string>();
    } catch (const YAML::Exception&) {
      throw config_error(path, "a key is not a plain name");
    }
    if (!known.count(key)) {
      for (const auto& k : known)
        if (size_t d = edit_distance(key, k); d <= 2 && 2 * d < key.size())
          throw config_error(path, "unknown key '" + key + "' (did you mean '" + k + "'?)");
      std::string list;
      for (const auto& k : known) list += (list.empty() ? "" : ", ") + k;
      throw config_error(path, "unknown key '" + key + "' (known keys: " + list + ")");
    }
    if (!seen.insert(key).second) throw config_error(path, "key '" + key + "' appears twice");
  }
}

template <class T>
T get(const YAML::Node& n, const std::string& path, const char* key, T fallback) {
  if (!n[key]) return fallback;
  try {
    return n[key].as<T>();
  } catch (const YAML::Exception&) {
    throw config_error(path, std::string("key '") + key + "' has a value of the wrong type");
  }
}

// The keys of one mapping in a table of settings (perclod/settings.h): the
// top level's (parent "": the keys without a dot) or those of the mapping
// `parent` ("crs_origin": lat, lon, height). `top_only` picks the batch's
// own keys instead of the others.
std::set<std::string> keys_in(const std::vector<SettingSpec>& table, const std::string& parent, bool top_only = false) {
  std::set<std::string> keys;
  const std::string prefix = parent.empty() ? "" : parent + ".";
  for (const SettingSpec& s : table) {
    const std::string key = s.key;
    if (s.top_only != top_only || key.rfind(prefix, 0) != 0) continue;
    if (key.find('.', prefix.size()) == std::string::npos) keys.insert(key.substr(prefix.size()));
  }
  return keys;
}

void require_positive(const std::string& path, const char* key, double v) {
  if (!(v > 0) || !std::isfinite(v)) throw config_error(path, std::string("'") + key + "' must be a positive number");
}

// The smallest screen (pixels a side) and the narrowest field of view
// (degrees) a display profile may have: a frame of fewer pixels has no
// room for its margins, and a view of under a degree frames a building only
// in thousands of tiles (refused as "too close", blaming the model).
constexpr int kMinScreenPx = 16, kMaxScreenPx = 16384;
constexpr double kMinFovDeg = 1, kMaxFovDeg = 179;

std::string number(double v) {
  std::ostringstream ss;
  ss << std::setprecision(4) << v;
  return ss.str();
}

// Fails unless the field of view of `d` is kMinFovDeg..kMaxFovDeg high and
// at least kMinFovDeg wide, naming the keys it comes from.
void check_field_of_view(const std::string& path, const DisplayProfile& d) {
  const double deg = 180 / DisplayProfile::kPi, fov_y = d.fov_y();
  const double high = fov_y * deg, wide = 2 * std::atan(double(d.width) / d.height * std::tan(fov_y / 2)) * deg;
  const std::string from = d.fov_y_override_deg > 0 ? "'fov_y_deg' " + number(d.fov_y_override_deg)
                                                     : "'height' " + std::to_string(d.height) + " px at 'dpi' " +
                                                           number(d.dpi) + " seen from 'viewer_distance_m' " +
                                                           number(d.viewer_distance);
  if (!(high >= kMinFovDeg && high <= kMaxFovDeg))
    throw config_error(path, "the field of view is " + number(high) + " degrees high (" + from + "); it must be " +
                                 number(kMinFovDeg) + " to " + number(kMaxFovDeg) + " degrees");
  if (!(wide >= kMinFovDeg))
    throw config_error(path, "the field of view is " + number(wide) + " degrees wide ('width' " +
                                 std::to_string(d.width) + " px beside " + from + "); it must be at least " +
                                 number(kMinFovDeg) + " degree");
}

}  // namespace

DisplayProfile default_display_profile() { return DisplayProfile{}; }

DisplayProfile load_display_profile(const std::string& path) {
  YAML::Node n = load_yaml(path);
  static const std::set<std::string> keys = keys_in(display_settings(), "");
  check_keys(n, path, keys);
  DisplayProfile d;
  d.name = get<std::string>(n, path, "name", std::filesystem::path(path).stem().string());
  d.width = get<int>(n, path, "width", d.width);
  d.height = get<int>(n, path, "height", d.height);
  d.dpi = get<double>(n, path, "dpi", d.dpi);
  d.viewer_distance = get<double>(n, path, "viewer_distance_m", d.viewer_distance);
  d.fov_y_override_deg = get<double>(n, path, "fov_y_deg", 0.0);
  for (auto [key, px] : {std::pair{"width", d.width}, std::pair{"height", d.height}})
    if (px < kMinScreenPx || px > kMaxScreenPx)
      throw config_error(path, std::string("'") + key + "' must be " + std::to_string(kMinScreenPx) + ".." +
                                   std::to_string(kMaxScreenPx) + " pixels, not " + std::to_string(px));
  require_positive(path, "dpi", d.dpi);
  require_positive(path, "viewer_distance_m", d.viewer_distance);
  if (n["fov_y_deg"] && !(d.fov_y_override_deg >= kMinFovDeg && d.fov_y_override_deg <= kMaxFovDeg))
    throw config_error(path, "'fov_y_deg' must be " + number(kMinFovDeg) + " to " + number(kMaxFovDeg) + " degrees");
  // Checked after the values so a present but bad key is reported as such.
  for (const char* key : {"width", "height", "dpi", "viewer_distance_m"})
    if (!n[key]) throw config_error(path, std::string("'") + key + "' is required");
  check_field_of_view(path, d);
  return d;
}

namespace {

// The known keys of a config's mappings come from the table of settings
// (docs/usage.md#config-keys). A model's keys: a config's top level and the
// overrides of a `models:` entry.
const std::set<std::string>& model_keys() {
  static const std::set<std::string> keys = keys_in(config_settings(), "");
  return keys;
}
// The batch's own keys (top level only).
const std::set<std::string>& batch_keys() {
  static const std::set<std::string> keys = keys_in(config_settings(), "", true);
  return keys;
}

std::string relative_to(const std::filesystem::path& dir, const std::string& p) {
  return p.empty() || std::filesystem::path(p).is_absolute() ? p : (dir / p).string();
}

// The settings of one model from a mapping `n` holding model_keys() (and, at
// the top level, the batch's keys), group by group in the order its errors
// are checked. `path` names the place in errors ("cfg.yaml" or
// "cfg.yaml: models[2]"); relative file names are taken from `dir`.

void read_model_file(const YAML::Node& n, const std::string& path, const std::filesystem::path& dir,
                     BatchConfig& c) {
  c.model = relative_to(dir, get<std::string>(n, path, "model", ""));
  if (c.model.empty()) throw config_error(path, "'model' is required");
  try {
    c.up = parse_up_axis(get<std::string>(n, path, "up", "y"));
  } catch (const std::invalid_argument& e) {
    throw config_error(path, e.what());
  }
  c.scale = get<double>(n, path, "scale", 1.0);
  require_positive(path, "scale", c.scale);
  if (n["display"]) {
    c.display = relative_to(dir, get<std::string>(n, path, "display", ""));
    if (c.display.empty()) throw config_error(path, "'display' must name a display profile file");
  }
}

// A view set: one string ("facades,top") or a list of items, checked.
void read_view_set(const YAML::Node& n, const std::string& path, const char* key, std::vector<std::string>& items) {
  const YAML::Node v = n[key];
  if (!v) return;
  items.clear();
  if (v.IsSequence()) {
    for (const auto& item : v) {
      if (!item.IsScalar())
        throw config_error(path, std::string("'") + key + "' must be a list of view names or presets");
      items.push_back(item.Scalar());
    }
  } else if (v.IsScalar()) {
    items.push_back(v.Scalar());
  } else {
    throw config_error(path, std::string("'") + key + "' must be a view set such as \"facades,top\" or a list");
  }
}

void read_views(const YAML::Node& n, const std::string& path, BatchConfig& c) {
  if (n["views"] && n["facades"]) throw config_error(path, "give 'views' or its old name 'facades', not both");
  const char* views_key = n["facades"] ? "facades" : "views";
  read_view_set(n, path, views_key, c.views);
  try {
    parse_views(c.views, c.up);
  } catch (const std::invalid_argument& e) {
    throw config_error(path, std::string("'") + views_key + "': " + e.what());
  }
  read_view_set(n, path, "judge_views", c.judge_views);
  if (c.judge_views == std::vector<std::string>{"none"}) c.judge_views.clear();
  if (!c.judge_views.empty()) try {
      parse_views(c.judge_views, c.up);
    } catch (const std::invalid_argument& e) {
      throw config_error(path, std::string("'judge_views': ") + e.what() + " (or 'none')");
    }
}

void read_sampling(const YAML::Node& n, const std::string& path, BatchConfig& c) {
  if (const YAML::Node sn = n["samples"]) {
    try {
      c.samples = parse_samples(sn.IsScalar() ? sn.Scalar() : std::string("(not a single value)"));
    } catch (const std::invalid_argument& e) {
      throw config_error(path, std::string("'samples': ") + e.what());
    }
  }
  c.spins = get<int>(n, path, "spins", c.spins);
  if (c.spins != 1 && c.spins != 2 && c.spins != 4) throw config_error(path, "'spins' must be 1, 2 or 4");
  c.keep_unsampled_surface = get<bool>(n, path, "keep_unsampled_surface", c.keep_unsampled_surface);
  c.mask_per_sample = get<bool>(n, path, "mask_per_sample", c.mask_per_sample);
  if (c.mask_per_sample && c.keep_unsampled_surface && c.samples != 1)
    throw config_error(path, "'mask_per_sample' and 'keep_unsampled_surface' cannot both be true");
  if (sample_grid(c.samples) && c.keep_unsampled_surface)
    throw config_error(path, "'keep_unsampled_surface' needs 'samples' of 2, 4 or 8 (" + std::to_string(c.samples) +
                                 " samples are a grid with a picture per sample)");
  if (n["per_building"]) {
    const YAML::Node pb = n["per_building"];
    c.per_building = pb.IsScalar() ? pb.Scalar() : std::string("?");
    try {
      parse_per_building(c.per_building);
    } catch (const std::invalid_argument& e) {
      throw config_error(path, std::string("'per_building': ") + e.what());
    }
  }
  c.own_views_alone = get<bool>(n, path, "own_views_alone", c.own_views_alone);
  c.group_span = get<double>(n, path, "group_span", c.group_span);
  if (!(c.group_span >= 0 && c.group_span <= 100)) throw config_error(path, "'group_span' must be within [0, 100]");
}

void read_label_rule(const YAML::Node& n, const std::string& path, BatchConfig& c) {
  c.combine_views = get<std::string>(n, path, "combine_views", c.combine_views);
  try {
    parse_combine_views(c.combine_views);
  } catch (const std::invalid_argument& e) {
    throw config_error(path, std::string("'combine_views': ") + e.what());
  }
  c.tracer = get<std::string>(n, path, "tracer", c.tracer);
  if (c.tracer != "octree" && c.tracer != "embree") throw config_error(path, "'tracer' must be octree or embree");
  c.verify = get<bool>(n, path, "verify", c.verify);
  c.ratio = get<double>(n, path, "ratio", c.ratio);
  if (!(c.ratio >= 0 && c.ratio <= 1)) throw config_error(path, "'ratio' must be within [0, 1]");
}

// A fidelity bound e_*: 0..1000 pixels, and given only in fidelity mode.
void check_bound(const YAML::Node& n, const std::string& path, const BatchConfig& c, const char* key, double v) {
  if (!(v >= 0 && v <= 1000)) throw config_error(path, std::string("'") + key + "' must be 0..1000 pixels");
  if (n[key] && c.simplify != "fidelity")
    throw config_error(path, std::string("'") + key + "' applies only to 'simplify: fidelity'");
}

void read_simplify_mode(const YAML::Node& n, const std::string& path, BatchConfig& c) {
  c.simplify = get<std::string>(n, path, "simplify", c.simplify);
  if (c.simplify != "fidelity" && c.simplify != "paper" && c.simplify != "bounded" && c.simplify != "qem" &&
      c.simplify != "cluster")
    throw config_error(path, "'simplify' must be fidelity, paper, bounded, qem or cluster");
  c.e_perceptible = get<double>(n, path, "e_perceptible", c.e_perceptible);
  c.e_imperceptible = get<double>(n, path, "e_imperceptible", c.e_imperceptible);
  check_bound(n, path, c, "e_perceptible", c.e_perceptible);
  check_bound(n, path, c, "e_imperceptible", c.e_imperceptible);
}

// The limits each judged view is held to, and what a run does about them.
void read_limits(const YAML::Node& n, const std::string& path, BatchConfig& c) {
  c.max_changed = get<double>(n, path, "max_changed", c.max_changed);
  c.max_silhouette = get<double>(n, path, "max_silhouette", c.max_silhouette);
  if (!(c.max_changed >= 0 && c.max_changed <= 1)) throw config_error(path, "'max_changed' must be a fraction in [0, 1]");
  if (!(c.max_silhouette >= 0 && c.max_silhouette <= 1))
    throw config_error(path, "'max_silhouette' must be a fraction in [0, 1]");
  c.min_ssim = get<double>(n, path, "min_ssim", c.min_ssim);
  if (!(c.min_ssim >= 0 && c.min_ssim <= 1)) throw config_error(path, "'min_ssim' must be within [0, 1]");
  c.max_visible = get<double>(n, path, "max_visible", c.max_visible);
  if (!(c.max_visible >= 0 && std::isfinite(c.max_visible)))
    throw config_error(path, "'max_visible' must be a finite number >= 0 (times the perceptual floor; 0: no limit)");
  c.max_visible_local = get<double>(n, path, "max_visible_local", c.max_visible_local);
  if (!(c.max_visible_local >= 0 && std::isfinite(c.max_visible_local)))
    throw config_error(path,
                       "'max_visible_local' must be a finite number >= 0 (times the local perceptual floor; 0: no limit)");
  c.strict = get<bool>(n, path, "strict", c.strict);
  c.tighten_to_limits = get<bool>(n, path, "tighten_to_limits", c.tighten_to_limits);
  c.judge_buildings_alone = get<bool>(n, path, "judge_buildings_alone", c.judge_buildings_alone);
  if (n["tighten_to_limits"] && c.simplify != "fidelity")
    throw config_error(path, "'tighten_to_limits' applies only to 'simplify: fidelity'");
  c.free_topology = get<bool>(n, path, "free_topology", c.free_topology);
  if (n["free_topology"] && c.simplify != "fidelity")
    throw config_error(path, "'free_topology' applies only to 'simplify: fidelity'");
  c.explain = get<bool>(n, path, "explain", c.explain);
  if (c.explain && c.simplify == "cluster")
    throw config_error(path, "'explain' applies to the collapse modes (fidelity, paper, bounded, qem), not cluster");
}

void read_fidelity_target(const YAML::Node& n, const std::string& path, BatchConfig& c) {
  const YAML::Node t = n["fidelity_target"];
  if (!t) return;
  if (!t.IsMap()) throw config_error(path, "'fidelity_target' must be a mapping such as {max_changed: 0.02}");
  if (c.simplify != "fidelity") throw config_error(path, "'fidelity_target' applies only to 'simplify: fidelity'");
  static const std::set<std::string> keys = keys_in(config_settings(), "fidelity_target");
  check_keys(t, path, keys);
  c.fidelity_target = true;
  c.target_max_changed = get<double>(t, path, "max_changed", c.max_changed);
  c.target_max_silhouette = get<double>(t, path, "max_silhouette", c.max_silhouette);
  if (!(c.target_max_changed >= 0 && c.target_max_changed <= 1) ||
      !(c.target_max_silhouette >= 0 && c.target_max_silhouette <= 1))
    throw config_error(path, "'fidelity_target': max_changed and max_silhouette must be fractions in [0, 1]");
  c.target_min_ssim = get<double>(t, path, "min_ssim", c.min_ssim);
  if (!(c.target_min_ssim >= 0 && c.target_min_ssim <= 1))
    throw config_error(path, "'fidelity_target': min_ssim must be within [0, 1]");
  c.target_max_visible = get<double>(t, path, "max_visible", c.max_visible);
  c.target_max_visible_local = get<double>(t, path, "max_visible_local", c.max_visible_local);
  if (!(c.target_max_visible >= 0 && std::isfinite(c.target_max_visible)) ||
      !(c.target_max_visible_local >= 0 && std::isfinite(c.target_max_visible_local)))
    throw config_error(path, "'fidelity_target': max_visible and max_visible_local must be finite numbers >= 0");
}

// The mode's own settings (k, target, the undisplayable rule) and the LOD format.
void read_simplify_settings(const YAML::Node& n, const std::string& path, BatchConfig& c) {
  c.k = get<double>(n, path, "k", c.k);
  require_positive(path, "k", c.k);
  if (n["target"]) {
    long long t = get<long long>(n, path, "target", 0);
    if (t <= 0) throw config_error(path, "'target' must be a positive number of triangles");
    c.target = size_t(t);
    if (c.simplify != "qem") throw config_error(path, "'target' applies only to 'simplify: qem'");
  }
  if (c.simplify == "qem" && c.target == 0)
    throw config_error(path, "'simplify: qem' needs 'target' (the number of triangles to keep)");
  if (const YAML::Node kn = n["keep_undisplayable"]) {
    bool keep = false;
    if (kn.IsScalar() && kn.Scalar() == "auto") c.keep_undisplayable = "auto";
    else if (YAML::convert<bool>::decode(kn, keep)) c.keep_undisplayable = keep ? "true" : "false";
    else throw config_error(path, "'keep_undisplayable' must be true, false or auto");
  }
  if (n["e_undisplayable"]) {
    c.e_undisplayable = get<double>(n, path, "e_undisplayable", c.e_undisplayable);
    check_bound(n, path, c, "e_undisplayable", c.e_undisplayable);
    if (c.keep_undisplayable == "false")
      throw config_error(path, "'e_undisplayable' bounds the collapses of kept undisplayable triangles; "
                               "'keep_undisplayable: false' deletes them");
    c.keep_undisplayable = "true";
  }
  c.format = get<std::string>(n, path, "format", c.format);
  if (c.format != "obj" && c.format != "glb") throw config_error(path, "'format' must be obj or glb");
}

void read_distances(const YAML::Node& n, const std::string& path, BatchConfig& c) {
  if (n["distances"]) {
    if (!n["distances"].IsSequence()) throw config_error(path, "'distances' must be a list of metres");
    for (const auto& d : n["distances"]) {
      double v = 0;
      try {
        v = d.as<double>();
      } catch (const YAML::Exception&) {
        throw config_error(path, "'distances' must be a list of metres, got '" +
                                     (d.IsScalar() ? d.Scalar() : std::string("a list or mapping")) + "'");
      }
      if (const std::string p = distance_problem(v); !p.empty()) throw config_error(path, "'distances': " + p);
      c.distances.push_back(v);
    }
  }
  if (c.distances.empty()) throw config_error(path, "'distances' is required (a list of metres)");
  try {
    check_distinct_tags(c.distances);
  } catch (const std::invalid_argument& e) {
    throw config_error(path, std::string("'distances': ") + e.what());
  }
}

// crs: an EPSG code PROJ can place (as "EPSG:N"), or none; not with crs_origin.
void read_crs(const YAML::Node& n, const std::string& path, BatchConfig& c) {
  const YAML::Node v = n["crs"];
  if (!v) return;
  if (!v.IsScalar()) throw config_error(path, "'crs' must be an EPSG code such as EPSG:7415, or none");
  if (c.crs_origin) throw config_error(path, "give 'crs' (the model's CRS) or 'crs_origin' (a WGS84 point), not both");
  if (v.Scalar() == "none") {
    c.crs = "none";
    return;
  }
  try {
    check_crs(v.Scalar());
  } catch (const std::invalid_argument& e) {
    throw config_error(path, std::string("'crs': ") + e.what());
  }
  c.crs = epsg_code(v.Scalar());
}

// What is written besides the LODs, and how a batch schedules the model.
void read_outputs(const YAML::Node& n, const std::string& path, BatchConfig& c) {
  c.memory_mb = get<double>(n, path, "memory_mb", c.memory_mb);
  if (!(c.memory_mb >= 0) || !std::isfinite(c.memory_mb))
    throw config_error(path, "'memory_mb' must be a non-negative number of MiB (0 = estimate from the file size)");
  c.cityjson_lod = get<std::string>(n, path, "cityjson_lod", c.cityjson_lod);
  c.tileset = get<bool>(n, path, "tileset", c.tileset);
  c.debug_images = get<bool>(n, path, "debug_images", c.debug_images);
  c.marking_near = get<bool>(n, path, "marking_near", c.marking_near);
  if (const YAML::Node o = n["crs_origin"]) {
    if (!o.IsMap()) throw config_error(path, "'crs_origin' must be a mapping {lat, lon, height}");
    static const std::set<std::string> keys = keys_in(config_settings(), "crs_origin");
    check_keys(o, path, keys);
    if (!o["lat"] || !o["lon"]) throw config_error(path, "'crs_origin' needs lat and lon (degrees)");
    c.crs_origin = true;
    c.origin_lat = get<double>(o, path, "lat", 0.0);
    c.origin_lon = get<double>(o, path, "lon", 0.0);
    c.origin_height = get<double>(o, path, "height", 0.0);
    if (!(std::abs(c.origin_lat) <= 90) || !(std::abs(c.origin_lon) <= 180) || !std::isfinite(c.origin_height))
      throw config_error(path, "'crs_origin': lat must be within [-90, 90], lon within [-180, 180] degrees");
  }
  read_crs(n, path, c);
}

BatchConfig parse_model(const YAML::Node& n, const std::string& path, const std::filesystem::path& dir) {
  BatchConfig c;
  read_model_file(n, path, dir, c);
  read_views(n, path, c);
  read_sampling(n, path, c);
  read_label_rule(n, path, c);
  read_simplify_mode(n, path, c);
  read_limits(n, path, c);
  read_fidelity_target(n, path, c);
  read_simplify_settings(n, path, c);
  read_distances(n, path, c);
  read_outputs(n, path, c);
  // The files it names, last: every value above is checked without them.
  std::error_code ec;
  if (!std::filesystem::is_regular_file(c.model, ec)) throw config_error(path, "model '" + c.model + "': no such file");
  if (!c.display.empty()) load_display_profile(c.display);  // throws naming the profile
  return c;
}

}  // namespace

BatchConfig load_batch_config(const std::string& path) {
  ConfigFile f = load_config_file(path);
  if (f.batch)
    throw config_error(path, "names several models ('models:'): run it with perclod run, one folder per model");
  return f.models.front().config;
}

ConfigFile load_config_file(const std::string& path) {
  namespace fs = std::filesystem;
  YAML::Node n = load_yaml(path);
  std::set<std::string> known = model_keys();
  known.insert(batch_keys().begin(), batch_keys().end());
  check_keys(n, path, known);
  const fs::path dir = fs::path(path).parent_path();
  ConfigFile f;
  f.path = path;
  f.out = get<std::string>(n, path, "out", "out");
  if (f.out.empty()) throw config_error(path, "'out' must name an output directory");
  if (!n["models"]) {
    if (n["jobs"] || n["memory_budget_mb"])
      throw config_error(path, "'jobs' and 'memory_budget_mb' apply only to a batch ('models:')");
    BatchConfig c = parse_model(n, path, dir);
    c.out = f.out;
    f.models.push_back({model_stem(c.model), c});
    return f;
  }
  if (n["model"]) throw config_error(path, "give 'model' (one model) or 'models' (a batch), not both");
  f.batch = true;
  const long long jobs = get<long long>(n, path, "jobs", 1);
  if (jobs < 1 || jobs > 64) throw config_error(path, "'jobs' must be 1..64 models at a time");
  f.jobs = int(jobs);
  f.memory_budget_mb = get<double>(n, path, "memory_budget_mb", 0.0);
  if (!(f.memory_budget_mb >= 0) || !std::isfinite(f.memory_budget_mb))
    throw config_error(path, "'memory_budget_mb' must be a non-negative number (0 = no budget)");
  const YAML::Node list = n["models"];
  if (!list.IsSequence() || list.size() == 0)
    throw config_error(path, "'models' must be a non-empty list of model files, globs, folders or mappings");
  // Each entry is parsed from the top-level settings with its own on top.
  YAML::Node base = YAML::Clone(n);
  for (const auto& k : batch_keys()) base.remove(k);
  std::vector<std::string> wheres;  // of each model, for check_model_names
  for (size_t i = 0; i < list.size(); ++i) {
    const std::string where = path + ": models[" + std::to_string(i) + "]";
    const YAML::Node item = list[i];
    YAML::Node merged = YAML::Clone(base);
    std::string pattern;
    if (item.IsScalar()) {
      pattern = item.Scalar();
    } else if (item.IsMap()) {
      check_keys(item, where, model_keys());
      if (!item["model"]) throw config_error(where, "'model' is required in a models entry");
      for (const auto& kv : item) merged[kv.first.as<std::string>()] = YAML::Clone(kv.second);
      pattern = get<std::string>(item, where, "model", "");
    } else {
      throw config_error(where, "must be a model file, glob, folder, or a mapping with 'model'");
    }
    if (pattern.empty()) throw config_error(where, "names no model");
    for (const std::string& file : detail::expand_models(relative_to(dir, pattern), pattern, where)) {
      merged["model"] = fs::absolute(file).lexically_normal().string();  // already joined with `dir`
      BatchConfig c = parse_model(merged, where, dir);
      c.out = f.out;
      f.models.push_back({"", c});
      wheres.push_back(where);
    }
  }
  detail::name_models(f.models);
  detail::check_model_names(f.models, wheres, f.out);
  return f;
}

LodJob lod_job(const BatchConfig& c) {
  LodJob job;
  job.label.up = c.up;
  job.label.display = c.display.empty() ? default_display_profile() : load_display_profile(c.display);
  job.label.perception = perception_settings_for(job.label.display);
  job.label.views = parse_views(c.views, c.up);
  job.label.samples = c.samples;
  job.label.keep_unsampled_surface = c.keep_unsampled_surface;
  job.label.mask_per_sample = c.mask_per_sample;
  job.label.perception.spins = c.spins;
  job.label.per_building = parse_per_building(c.per_building);
  job.label.group_span = c.group_span;
  job.label.own_views_alone = c.own_views_alone;
  job.label.ratio = c.ratio;
  job.label.combine = parse_combine_views(c.combine_views);
  job.label.verify = c.verify;
  job.label.out = output_names_for(c.out, c.model);
  job.label.write_view_images = c.debug_images;
  job.label.write_perception_images = c.debug_images;
  job.label.marking_near = c.marking_near;
  job.distances = c.distances;
  job.tracer = parse_tracer(c.tracer);
  job.simplify.mode = parse_simplify_mode(c.simplify.c_str());
  job.simplify.k = c.k;
  job.simplify.target_triangles = c.target;
  job.simplify.delete_undisplayable = c.keep_undisplayable != "true";
  job.undisplayable_auto = c.keep_undisplayable == "auto";
  job.simplify.bound_perceptible_px = c.e_perceptible;
  job.simplify.bound_imperceptible_px = c.e_imperceptible;
  job.simplify.bound_undisplayable_px = c.e_undisplayable;
  job.simplify.explain_stop = c.explain;
  job.simplify.free_topology = c.free_topology;
  if (!c.judge_views.empty()) job.judge_views = parse_views(c.judge_views, c.up);
  job.limits.max_changed = c.max_changed;
  job.limits.max_silhouette = c.max_silhouette;
  job.limits.min_ssim = c.min_ssim;
  job.limits.max_visible = c.max_visible;
  job.limits.max_visible_local = c.max_visible_local;
  job.fidelity_target = c.fidelity_target;
  job.tighten_to_limits = c.tighten_to_limits;
  job.judge_buildings_alone = c.judge_buildings_alone;
  job.target.max_changed = c.target_max_changed;
  job.target.max_silhouette = c.target_max_silhouette;
  job.target.min_ssim = c.target_min_ssim;
  job.target.max_visible = c.target_max_visible;
  job.target.max_visible_local = c.target_max_visible_local;
  job.lod_format = c.format;
  return job;
}

}  // namespace perclod
