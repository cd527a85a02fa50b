// perclod/simplify_model.h - `perclod simplify`: one LOD of a model from its
// labels file, and the simplifier's figures as reports give them.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "perclod/display.h"
#include "perclod/labels_io.h"
#include "perclod/outputs.h"
#include "perclod/simplify.h"
#include "perclod/views.h"

namespace perclod {

struct SimplifyJob {
  std::string labels_file;       // from perclod label; "" only for qem and cluster
  std::string model_file;        // named in errors when the labels belong to another model
  const LabelFile* labels = nullptr;  // already read from labels_file (else simplify_model reads it)
  double distance = 0;           // metres: p(d) for bounded and cluster
  DisplayProfile display;
  SimplifyOptions options;       // pixel_footprint is set from distance and display
  OutputNames out;               // the LOD goes to out.lod(distance, format)
  std::string format = "obj";    // "obj" or "glb"
  UpAxis up = UpAxis::Y;         // a Z-up model's GLB is turned to glTF's +Y up
  // keep_undisplayable: auto (fidelity mode, when options.delete_undisplayable):
  // choose_undisplayable decides from the labels' exposure.
  bool undisplayable_auto = true;
};

struct SimplifyRun {
  SimplifyStats stats;
  std::string lod_file;
  double pixel_footprint = 0;
  double write_seconds = 0;
  double undisplayable_exposure = -1;  // measured for keep_undisplayable: auto; -1 = not measured
  SimplifyOptions options;             // what simplified: the job's, with auto resolved
};

// Reads and checks the labels against `scene`, simplifies, exports.
SimplifyRun simplify_model(const Scene& scene, const SimplifyJob& job);


}  // namespace perclod
