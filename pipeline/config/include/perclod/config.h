// perclod/config.h - YAML display profiles and batch configs (configs/).
#pragma once

#include <cmath>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "perclod/display.h"
#include "perclod/lods.h"
#include "perclod/views.h"

namespace perclod {

// configs/displays/*.yaml: name, width, height, dpi, viewer_distance_m,
// optional fov_y_deg. Throws naming the file and the bad key.
DisplayProfile load_display_profile(const std::string& path);
DisplayProfile default_display_profile();  // the paper's 19" LCD

// A batch job (configs/demo.yaml). Its keys, with their types, defaults,
// allowed values and help, are config_settings() (perclod/settings.h,
// docs/usage.md#config-keys); tests/pipeline/test_settings.cpp checks the
// defaults below against that table's.
struct BatchConfig {
  std::string model;                 // path, relative to the config file's folder
  UpAxis up = UpAxis::Y;
  double scale = 1.0;
  std::string display;               // profile path ("" = default)
  std::vector<double> distances;     // metres
  std::vector<std::string> views = {kDefaultViews};  // view set items (perclod/views.h); "facades:" is the old key
  int samples = kDefaultSamples;     // samples per pixel: kAutoSamples ("auto"), 1, 2, 4, 8, 9, 16
  int spins = 1;                     // perception cycle spinning: 1 (the paper), 2, 4
  bool keep_unsampled_surface = false;  // label rule: sub-pixel triangles between the samples of a drawn surface are seen (LabelJob)
  bool mask_per_sample = false;      // one render and perception mask per sample offset (LabelJob)
  std::string per_building = "auto"; // true | false | auto (two or more buildings named "<building>/<part>")
  bool own_views_alone = kDefaultOwnViewsAlone;  // per building: own views of the building alone (LabelJob)
  double group_span = kDefaultGroupSpan;  // per building: neighbours within this many distances share views (LabelJob)
  std::string out = "out";
  std::string tracer = "octree";     // octree | embree
  bool verify = false;               // also trace with Embree and report agreement
  double ratio = 0.5;                // label rule: imperceptible / traced >= ratio
  std::string combine_views = kDefaultCombineViews;  // label rule over views: pooled | any (the paper; LabelJob::combine)
  std::string simplify = "fidelity"; // fidelity | paper | bounded | qem | cluster
  double e_perceptible = kDefaultBoundPerceptiblePx;      // fidelity: bound of perceptible triangles, pixels
  double e_imperceptible = kDefaultBoundImperceptiblePx;  // fidelity: bound of imperceptible triangles, pixels
  double e_undisplayable = INFINITY;  // fidelity: bound of kept undisplayable triangles, pixels (sets keep_undisplayable)
  double k = 1.0;                    // bounded tolerance / cluster cell in pixels
  size_t target = 0;                 // qem: triangles to keep (required by qem, refused otherwise)
  // paper, fidelity: "true" collapses undisplayable triangles instead of
  // deleting them, "false" deletes them, "auto" (fidelity: keeps them when
  // deleting would open what views between the labelling ones see,
  // choose_undisplayable; paper: deletes them).
  std::string keep_undisplayable = "auto";
  std::string format = "obj";        // LOD file format: obj | glb
  std::vector<std::string> judge_views = {kDefaultJudgeViews};  // held-out views; empty = none ('none' in the file)
  bool judge_buildings_alone = true;  // buildings labelled alone are judged alone (LodJob)
  // Limits every judged view is held to: by default the perceptual one
  // alone (the visible difference within its quarter-pixel floor); changed
  // pixels, silhouette and SSIM are reported, and limited only when set.
  double max_changed = 1;            // fraction of changed pixels (1: no limit)
  double max_silhouette = 1;         // silhouette mismatch (1: no limit)
  double min_ssim = 0;               // lowest covered-region SSIM of a judged view (0: no limit)
  double max_visible = 1;            // visible difference over the perceptual floor (0: no limit)
  double max_visible_local = 0;      // the same, the worst 16 px square's (0: no limit)
  bool strict = false;               // a LOD over a limit fails the run (after every output is written)
  // fidelity_target: {max_changed, max_silhouette, min_ssim}: search
  // e_imperceptible per distance for the fewest triangles within these
  // (LodJob::fidelity_target).
  bool fidelity_target = false;
  // fidelity, no fidelity_target: a LOD over the limits (within
  // kTightenReach) is tried again at tighter bounds (LodJob::tighten_to_limits).
  bool tighten_to_limits = true;
  // fidelity: go on collapsing past the half-edge mesh's topological rules
  // (SimplifyOptions::free_topology).
  bool free_topology = true;
  // Collapse modes: also count why each half-edge left was not collapsed
  // (SimplifyOptions::explain_stop; the report's simplify.refused).
  bool explain = false;
  double target_max_changed = 1, target_max_silhouette = 1, target_min_ssim = 0, target_max_visible = 1;
  double target_max_visible_local = 0;
  std::string cityjson_lod;          // CityJSON input: the LOD geometry to read ("" = each object's highest)
  double memory_mb = 0;              // batch: this model's peak memory for memory_budget_mb (0 = estimate_memory_mb)
  bool tileset = true;               // also write the all-LOD GLB, a GLB per LOD and a 3D Tiles tileset.json
  bool debug_images = true;          // per-view PNGs: renders, perception images, markings, LOD-vs-original pictures
  bool marking_near = false;         // also the marking from d/4 (one more full render per view and distance)
  // crs: the model's CRS as an EPSG code ("EPSG:7415", checked with PROJ;
  // perclod/crs.h), "none" (source coordinates, a CityJSON file's
  // referenceSystem ignored), or "" (unset: a CityJSON file's referenceSystem,
  // else source coordinates). Not with crs_origin.
  std::string crs;
  // crs_origin: {lat, lon, height}: the model's coordinates are metres east,
  // north, up of this point (WGS84 degrees, ellipsoidal metres); the tileset
  // is placed there by a local ENU transform.
  bool crs_origin = false;
  double origin_lat = 0, origin_lon = 0, origin_height = 0;
};

// One model of a config file and the name of its output folder.
struct ModelEntry {
  std::string name;    // file stem, made unique (parent folder's name, then a number)
  BatchConfig config;  // the top-level settings with the entry's own on top; config.out = the batch's out
};

// A config file: one model ('model:'), or a batch ('models:'): a list whose
// items are a model file, a glob ("tiles/*.obj"), a folder (every model file
// under it, sorted) or a mapping {model: FILE_GLOB_OR_FOLDER, KEY: VALUE...}
// overriding the top-level settings for those models.
struct ConfigFile {
  std::string path;
  bool batch = false;             // 'models:': one output folder per model, out/<name>/
  std::vector<ModelEntry> models; // in list order (globs and folders sorted)
  std::string out = "out";
  int jobs = 1;                   // models processed at once
  double memory_budget_mb = 0;    // 0 = no budget; else models start only while their estimates fit
};
// Checks the whole config before any work: unknown or repeated keys, every
// value's type and range, each mode's requirements (qem needs target), that
// the model file exists and that the display profile loads. Throws
// "PATH: what is wrong" (or the profile's own error naming the profile).
// A config naming several models is refused here (use load_config_file).
BatchConfig load_batch_config(const std::string& path);
// Any config, checked whole before any work (every entry of a batch too).
ConfigFile load_config_file(const std::string& path);

// The settings that decide a model's outputs, as JSON (the display profile's
// values, not its path): hashed to tell whether an output is up to date.
nlohmann::json settings_json(const BatchConfig& config);

// The job `perclod run` does for a config: display profile loaded, names
// parsed, outputs named after the model file (OutputNames{out, model stem}).
LodJob lod_job(const BatchConfig& config);

}  // namespace perclod
