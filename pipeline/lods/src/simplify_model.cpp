// One LOD from a labels file (`perclod simplify`), and the simplifier's
// figures as reports give them.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <future>
#include <iomanip>
#include <iterator>
#include <optional>
#include <sstream>
#include <stdexcept>


#include "perclod/simplify_model.h"

#include "perclod/export.h"
#include "perclod/labels_io.h"
#include "perclod/runtime.h"
#include "perclod/undisplayable.h"

namespace perclod {
using namespace detail;

SimplifyRun simplify_model(const Scene& scene, const SimplifyJob& job) {
  const SimplifyMode mode = job.options.mode;
  if (simplify_mode_uses_labels(mode) && job.labels_file.empty())
    throw std::invalid_argument(std::string(simplify_mode_name(mode)) +
                                " mode needs a labels file (from perclod label)");
  if (!(job.distance > 0) || !std::isfinite(job.distance))
    throw std::invalid_argument("the viewing distance must be positive metres");
  if (job.format != "obj" && job.format != "glb")
    throw std::invalid_argument("LOD format must be obj or glb, not '" + job.format + "'");
  std::vector<Label> labels(scene.triangle_count(), Label::Imperceptible);
  if (!job.labels_file.empty()) {
    LabelFile lf = job.labels ? *job.labels : read_labels(job.labels_file);
    const std::string model = job.model_file.empty() ? std::string("the model") : job.model_file;
    if (lf.labels.size() != scene.triangle_count())
      throw std::invalid_argument(job.labels_file + ": has " + std::to_string(lf.labels.size()) +
                                  " labels but " + model + " has " + std::to_string(scene.triangle_count()) +
                                  " triangles (labels from another model or loader settings?)");
    if (lf.has_model && lf.model_hash != model_fingerprint(scene)) {
      char hash[40];
      std::snprintf(hash, sizeof hash, "%016llx", static_cast<unsigned long long>(model_fingerprint(scene)));
      throw std::invalid_argument(job.labels_file + ": labels of another model: its fingerprint does not match " +
                                  model + " (" + hash + "; another file, or loaded with another --scale?)");
    }
    labels = std::move(lf.labels);
  }
  OutputDirectoryLock lock(job.out.dir);  // a busy directory is refused before the work, not after
  SimplifyRun run;
  SimplifyOptions so = job.options;
  so.pixel_footprint = run.pixel_footprint = display_pixel_footprint(job.display, job.distance);
  if (job.undisplayable_auto && undisplayable_auto_applies(so)) {
    const Framing framing{job.up, job.display, job.distance};
    run.undisplayable_exposure = choose_undisplayable(so, scene, OctreeTracer(scene), labels, framing);
  }
  run.options = so;
  Scene lod = simplify(scene, labels, so, &run.stats);
  run.lod_file = job.out.lod(job.distance, job.format);
  auto t0 = Clock::now();
  export_scene(lod, run.lod_file, ExportOptions{job.up == UpAxis::Z});
  run.write_seconds = since(t0);
  return run;
}

}  // namespace perclod
