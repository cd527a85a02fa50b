// The tables of config and display profile keys (perclod/settings.h).
// docs/usage.md#config-keys and docs/usage.md#display-profiles show them;
// tests/e2e/test_settings_docs.cpp holds those tables to these.
#include "perclod/settings.h"

#include <stdexcept>
#include <string>

namespace perclod {

namespace {
constexpr bool kHashed = true, kNotHashed = false;
constexpr bool kTopOnly = true, kAnyLevel = false;
}  // namespace

// The defaults written here are BatchConfig's (perclod/config.h) and the
// constants it takes (kDefaultViews, kDefaultSamples, ...); tests/pipeline/
// test_settings.cpp checks that writing a default into a config changes nothing.
namespace {
const std::vector<SettingSpec> kConfigSettings = {
    // key, type, default, allowed, help, hashed, top_only, alias_of
    {"model", "path", "(required in a one-model config and in each mapping of models)",
     "an existing model file, relative to the config; not beside models", "The model to simplify", kNotHashed,
     kAnyLevel, nullptr},
    {"models", "list", "(none: a one-model config)",
     "model files, globs, folders, or mappings {model: ..., KEY: VALUE}; non-empty",
     "Makes the config a batch, one output folder per model (docs/usage.md#batches)", kNotHashed, kTopOnly, nullptr},
    {"out", "path", "out", "a non-empty directory name", "Output directory, relative to where perclod runs",
     kNotHashed, kTopOnly, nullptr},
    {"jobs", "integer", "1", "1..64", "Batch: models processed at once", kNotHashed, kTopOnly, nullptr},
    {"memory_budget_mb", "number (MiB)", "0", ">= 0; 0 = no budget",
     "Batch: start a model only while the running ones' memory estimates and its own fit (MiB; 0 = no budget)",
     kNotHashed, kTopOnly, nullptr},
    {"memory_mb", "number (MiB)", "0 (estimate: 500 MiB + 10 x the file's MiB)", ">= 0",
     "This model's peak memory, for memory_budget_mb", kNotHashed, kAnyLevel, nullptr},
    {"up", "string", "y", "y, z", "Up axis of the model: y or z (CityGML-derived data)", kHashed, kAnyLevel,
     nullptr},
    {"scale", "number", "1", "> 0", "Unit scale to metres (e.g. 0.001 for a model in mm)", kHashed, kAnyLevel,
     nullptr},
    {"display", "path", "(the paper's 19\" LCD)", "a display profile file (Display profiles)",
     "Display profile YAML: how the images are looked at (docs/usage.md#display-profiles)", kHashed, kAnyLevel,
     nullptr},
    {"distances", "list of numbers", "(required)", "> 0 m, at most 1e8 m; no two with the same file tag",
     "Viewing distances in metres; one LOD per distance", kHashed, kAnyLevel, nullptr},
    {"views", "view set: string or list", "facades,ring8el30,ring8el60,top", "view names and presets (View sets)",
     "View set: presets facades obliques top ring<N>[el<E>/...] and views +x -x ... az<A>el<E>, comma separated "
     "(docs/usage.md#view-sets)",
     kHashed, kAnyLevel, nullptr},
    {"facades", "view set: string or list", "(none)", "as views; not together with views", "The old name of views",
     kHashed, kAnyLevel, "views"},
    {"samples", "auto or integer", "auto", "auto, 1, 2, 4, 8, 9, 16",
     "Samples per pixel: auto (per view, docs/usage.md#choosing-the-samples-per-view), 1, 2, 4, 8, or 9 / 16 "
     "(an ordered grid from one render at 3x / 4x the resolution, a mask per sample; "
     "docs/usage.md#grids-of-samples)",
     kHashed, kAnyLevel, nullptr},
    {"spins", "integer", "1", "1, 2, 4",
     "Perception cycle spinning: 1 (the paper), 2 or 4 DWT phases averaged (shift-invariant mask)", kHashed,
     kAnyLevel, nullptr},
    {"keep_unsampled_surface", "boolean", "false",
     "not with mask_per_sample (unless samples: 1) or samples: 9/16",
     "With samples > 1: a sub-pixel triangle no sample hit but lying on the drawn surface, where such triangles "
     "fill half a pixel or more, is labelled from that pixel, not undisplayable (docs/usage.md#unsampled-surface)",
     kHashed, kAnyLevel, nullptr},
    {"mask_per_sample", "boolean", "false", "not with keep_unsampled_surface (unless samples: 1)",
     "Render and perceive each sample offset on its own (a render per sample, one ray per pixel each), so every "
     "sample reads the mask of its own picture: labels that a sub-pixel move hardly changes "
     "(docs/usage.md#mask-per-sample)",
     kHashed, kAnyLevel, nullptr},
    {"per_building", "string or boolean", "auto", "auto, true, false (on, off)",
     "Also label each building from views framed on it: true, false or auto (when the component names give two "
     "or more buildings; docs/usage.md#per-building)",
     kHashed, kAnyLevel, nullptr},
    {"group_span", "number", "0", "0..100; 0 = each building alone",
     "Per building: neighbours whose boxes together span at most this many times the distance across share one "
     "set of views framed on the group (docs/usage.md#building-groups)",
     kHashed, kAnyLevel, nullptr},
    {"own_views_alone", "boolean", "true", "",
     "Per building: each building's own views show the building alone, so the walls only its neighbours hide "
     "are labelled as seen and kept; false: in place, neighbours drawn (docs/usage.md#own-views-of-the-building-alone)",
     kHashed, kAnyLevel, nullptr},
    {"combine_views", "string", "pooled", "pooled, any",
     "How views combine perceptible and imperceptible: pooled (imperceptible/traced >= ratio over every view's "
     "samples together) or any (perceptible in any view wins: the paper; docs/usage.md#combining-views)",
     kHashed, kAnyLevel, nullptr},
    {"tracer", "string", "octree", "octree, embree", "Pixel-to-triangle tracer: octree or embree", kHashed,
     kAnyLevel, nullptr},
    {"verify", "boolean", "false", "", "Also trace with Embree (tie-rule reference) and report per-pixel agreement",
     kHashed, kAnyLevel, nullptr},
    {"ratio", "number", "0.5", "0..1", "Imperceptible when imperceptible/traced samples >= ratio", kHashed,
     kAnyLevel, nullptr},
    {"simplify", "string", "fidelity", "fidelity, paper, bounded, qem, cluster",
     "Simplification mode: fidelity, paper, bounded, qem or cluster (docs/usage.md#simplification-modes)", kHashed,
     kAnyLevel, nullptr},
    {"e_perceptible", "number (px)", "0.5", "0..1000; fidelity only",
     "fidelity: how far a collapse may move a perceptible triangle, pixels at the distance", kHashed, kAnyLevel,
     nullptr},
    {"e_imperceptible", "number (px)", "8", "0..1000; fidelity only",
     "fidelity: the same for imperceptible triangles (and pieces without a perceptible face)", kHashed, kAnyLevel,
     nullptr},
    {"e_undisplayable", "number (px)", "(none)", "0..1000; fidelity only; not with keep_undisplayable: false",
     "fidelity: keep undisplayable triangles and collapse them within this many pixels "
     "(docs/usage.md#undisplayable-triangles)",
     kHashed, kAnyLevel, nullptr},
    {"keep_undisplayable", "auto or boolean", "auto", "auto, true, false",
     "paper, fidelity: collapse undisplayable triangles and keep those collapses cannot reach (true), delete them "
     "(false), or auto: fidelity decides per distance, paper deletes them",
     kHashed, kAnyLevel, nullptr},
    {"k", "number (px)", "1", "> 0", "bounded: tolerance, cluster: cell size, in pixels at the distance", kHashed,
     kAnyLevel, nullptr},
    {"target", "integer", "(required by qem)", "> 0; qem only", "qem: triangles to keep", kHashed, kAnyLevel,
     nullptr},
    {"format", "string", "obj", "obj, glb", "LOD file format: obj (+ .mtl) or glb", kHashed, kAnyLevel, nullptr},
    {"judge_views", "view set, or none", "held_out", "view names and presets, or none",
     "Views besides the labelling ones that judge each LOD (docs/usage.md#judging-a-lod)", kHashed, kAnyLevel,
     nullptr},
    {"judge_buildings_alone", "boolean", "true", "",
     "When each building is labelled from its own views alone: judge each building's LOD alone from judge_views "
     "framed on it; false: from judge_views framed on the whole model (docs/usage.md#judging-buildings-alone)",
     kHashed, kAnyLevel, nullptr},
    {"max_changed", "fraction", "1 (no limit)", "0..1", "Limit on a judged view's fraction of changed pixels", kHashed,
     kAnyLevel, nullptr},
    {"max_silhouette", "fraction", "1 (no limit)", "0..1", "Limit on a judged view's silhouette mismatch", kHashed,
     kAnyLevel, nullptr},
    {"min_ssim", "number", "0 (no limit)", "0..1", "Lowest covered-region SSIM of a judged view", kHashed,
     kAnyLevel, nullptr},
    {"max_visible", "number (x floor)", "1", ">= 0 (0: no limit)",
     "Limit on a judged view's visible difference over its perceptual floor, the quarter-pixel shift "
     "(docs/usage.md#judging-a-lod)",
     kHashed, kAnyLevel, nullptr},
    {"max_visible_local", "number (x floor)", "0 (no limit)", ">= 0",
     "Limit on a judged view's local visible difference (its worst 16 px square) over its local floor "
     "(docs/usage.md#judging-a-lod)",
     kHashed, kAnyLevel, nullptr},
    {"strict", "boolean", "false", "",
     "Fail (exit 1, after every output is written) when a LOD exceeds max_visible, max_changed or "
     "max_silhouette, or falls below min_ssim, in any judged view",
     kNotHashed, kAnyLevel, nullptr},
    {"tighten_to_limits", "boolean", "true", "fidelity only",
     "Remake a LOD just over the limits at tighter bounds (docs/usage.md#tightening-to-the-limits)", kHashed,
     kAnyLevel, nullptr},
    {"free_topology", "boolean", "true", "fidelity only",
     "Once the half-edge collapses stop, go on collapsing on the plain triangle list, which no topological rule "
     "limits (the LOD may be non-manifold; docs/usage.md#free-topology)",
     kHashed, kAnyLevel, nullptr},
    {"explain", "boolean", "false", "not with cluster",
     "Say why each LOD stopped: count its half-edges left by the first rule that refuses their collapse (locked "
     "or over its bound, shape, topology, valence; collapse modes; docs/usage.md#explaining-a-lod)",
     kHashed, kAnyLevel, nullptr},
    {"fidelity_target", "mapping", "(none: no search)", "the three keys below; fidelity only",
     "Search the bounds per distance for the fewest triangles within these limits "
     "(docs/usage.md#fidelity-target)",
     kHashed, kAnyLevel, nullptr},
    {"fidelity_target.max_changed", "fraction", "max_changed", "0..1", "The search's limit on changed pixels",
     kHashed, kAnyLevel, nullptr},
    {"fidelity_target.max_silhouette", "fraction", "max_silhouette", "0..1",
     "The search's limit on silhouette mismatch", kHashed, kAnyLevel, nullptr},
    {"fidelity_target.min_ssim", "number", "min_ssim", "0..1", "The search's lowest SSIM", kHashed, kAnyLevel,
     nullptr},
    {"fidelity_target.max_visible", "number (x floor)", "max_visible", ">= 0",
     "The search's limit on visible difference over the floor", kHashed, kAnyLevel, nullptr},
    {"fidelity_target.max_visible_local", "number (x floor)", "max_visible_local", ">= 0",
     "The search's limit on local visible difference over the local floor", kHashed, kAnyLevel, nullptr},
    {"cityjson_lod", "string", "\"\" (each object's highest)", "a LOD such as 2, 2.2, 3",
     "CityJSON: the LOD geometry to read, e.g. 2 or 2.2", kHashed, kAnyLevel, nullptr},
    {"crs", "string", "(none: a CityJSON file's referenceSystem, else source coordinates)",
     "an EPSG code: EPSG:7415, 7415, urn:ogc:def:crs:EPSG::7415, https://www.opengis.net/def/crs/EPSG/0/7415; "
     "none; not with crs_origin",
     "The model's coordinate reference system: PROJ places the tileset by it (none: source coordinates; "
     "docs/usage.md#export-for-viewers)",
     kHashed, kAnyLevel, nullptr},
    {"crs_origin", "mapping", "(none: source coordinates)", "lat and lon required; not with crs",
     "Place the tileset at this WGS84 point (docs/usage.md#export-for-viewers)", kHashed, kAnyLevel, nullptr},
    {"crs_origin.lat", "number (degrees)", "(required)", "-90..90", "Latitude of the model's origin", kHashed,
     kAnyLevel, nullptr},
    {"crs_origin.lon", "number (degrees)", "(required)", "-180..180", "Longitude of the model's origin", kHashed,
     kAnyLevel, nullptr},
    {"crs_origin.height", "number (m)", "0", "finite", "Ellipsoidal height of the model's origin", kHashed,
     kAnyLevel, nullptr},
    {"tileset", "boolean", "true", "", "Also write a GLB per LOD, the all-LOD GLB and a 3D Tiles tileset", kHashed,
     kAnyLevel, nullptr},
    {"debug_images", "boolean", "true", "",
     "Write the per-view PNGs: renders, perception images, markings, LOD-vs-original pictures", kHashed, kAnyLevel,
     nullptr},
    {"marking_near", "boolean", "false", "",
     "Also write each marking image from d/4 (one more full render per view and distance)", kHashed, kAnyLevel,
     nullptr},
};
}  // namespace

const std::vector<SettingSpec>& config_settings() { return kConfigSettings; }

// DisplayProfile's fields (perclod/display.h); load_display_profile reads them.
namespace {
const std::vector<SettingSpec> kDisplaySettings = {
    {"name", "string", "the file's stem", "", "The profile's name in reports and manifests", kHashed, kAnyLevel,
     nullptr},
    {"width", "integer (px)", "(required)", "16..16384", "Image width", kHashed, kAnyLevel, nullptr},
    {"height", "integer (px)", "(required)", "16..16384", "Image height", kHashed, kAnyLevel, nullptr},
    {"dpi", "number", "(required)", "> 0", "Pixel density of the screen", kHashed, kAnyLevel, nullptr},
    {"viewer_distance_m", "number (m)", "(required)", "> 0", "Distance from the eye to the screen", kHashed,
     kAnyLevel, nullptr},
    {"fov_y_deg", "number (degrees)", "the natural field of view", "1..179",
     "Vertical field of view, instead of the angle the screen subtends", kHashed, kAnyLevel, nullptr},
};
}  // namespace

const std::vector<SettingSpec>& display_settings() { return kDisplaySettings; }

const SettingSpec* find_setting(const std::vector<SettingSpec>& table, std::string_view key) {
  for (const SettingSpec& s : table)
    if (key == s.key) return &s;
  return nullptr;
}

const SettingSpec& config_setting(std::string_view key) {
  if (const SettingSpec* s = find_setting(config_settings(), key)) return *s;
  throw std::logic_error("no config key '" + std::string(key) + "' in config_settings()");
}

}  // namespace perclod
