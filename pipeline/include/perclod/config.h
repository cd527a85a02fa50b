// perclod/config.h - YAML display profiles and batch configs (configs/).
#pragma once

#include <string>
#include <vector>

#include "perclod/display.h"
#include "perclod/pipeline.h"
#include "perclod/views.h"

namespace perclod {

// configs/displays/*.yaml: name, width, height, dpi, viewer_distance_m,
// optional fov_y_deg. Throws naming the file and the bad key.
DisplayProfile load_display_profile(const std::string& path);
DisplayProfile default_display_profile();  // the paper's 19" LCD

// A batch job (configs/demo.yaml).
struct BatchConfig {
  std::string model;                 // path, relative to the config file's folder
  UpAxis up = UpAxis::Y;
  double scale = 1.0;
  std::string display;               // profile path ("" = default)
  std::vector<double> distances;     // metres
  std::vector<std::string> views = {kDefaultViews};  // view set items (perclod/views.h); "facades:" is the old key
  int samples = kDefaultSamples;     // samples per pixel: 1, 2, 4, 8
  int spins = 1;                     // perception cycle spinning: 1 (the paper), 2, 4
  std::string per_building = "auto"; // true | false | auto (two or more buildings in the file)
  std::string out = "out";
  std::string tracer = "octree";     // octree | embree
  bool verify = false;               // also trace with Embree and report agreement
  double ratio = 0.5;                // label rule: imperceptible / traced >= ratio
  std::string simplify = "fidelity"; // fidelity | paper | bounded | qem | cluster
  double e_perceptible = kDefaultBoundPerceptiblePx;      // fidelity: bound of perceptible triangles, pixels
  double e_imperceptible = kDefaultBoundImperceptiblePx;  // fidelity: bound of imperceptible triangles, pixels
  double k = 1.0;                    // bounded tolerance / cluster cell in pixels
  size_t target = 0;                 // qem: triangles to keep (required by qem, refused otherwise)
  bool keep_undisplayable = false;   // paper: collapse undisplayable triangles instead of deleting them
  std::string format = "obj";        // LOD file format: obj | glb
  std::vector<std::string> judge_views = {kDefaultJudgeViews};  // held-out views; empty = none ('none' in the file)
  double max_changed = 0.02;         // limits every judged view is held to
  double max_silhouette = 0.01;
  bool strict = false;               // a LOD over a limit fails the run (after every output is written)
  // fidelity_target: {max_changed, max_silhouette}: search e_imperceptible per
  // distance for the fewest triangles within these (LodJob::fidelity_target).
  bool fidelity_target = false;
  double target_max_changed = 0.02, target_max_silhouette = 0.01;
};
// Checks the whole config before any work: unknown or repeated keys, every
// value's type and range, each mode's requirements (qem needs target), that
// the model file exists and that the display profile loads. Throws
// "PATH: what is wrong" (or the profile's own error naming the profile).
BatchConfig load_batch_config(const std::string& path);

// The job `perclod run` does for a config: display profile loaded, names
// parsed, outputs named after the model file (OutputNames{out, model stem}).
LodJob lod_job(const BatchConfig& config);

}  // namespace perclod
