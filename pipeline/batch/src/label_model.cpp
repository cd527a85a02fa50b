// `perclod label` for one model and distance (perclod/label_model.h).
#include "perclod/label_model.h"

#include <memory>
#include <optional>

#include "perclod/outputs.h"
#include "perclod/report_json.h"

namespace perclod {

LabelReport label_model(const Scene& scene, const LabelJob& job, TracerKind kind, LabelProgress* progress) {
  std::optional<OutputDirectoryLock> lock;
  if (!job.out.dir.empty()) lock.emplace(job.out.dir);
  check_framing(scene_bounds(scene), job.up, job.display, job.views, {job.distance});  // before any work
  std::unique_ptr<Tracer> tracer = make_tracer(scene, kind);
  if (progress) progress->tracer_built(*tracer);
  Renderer renderer;
  LabelResult r = label_scene(renderer, scene, *tracer, job, progress);
  write_label_outputs(renderer, scene, r, job);
  r.report.tracer_build_seconds = tracer->build_seconds();
  write_text_atomic(job.out.label_report(job.distance), label_report_json(r.report).dump(2) + "\n");
  return r.report;
}

}  // namespace perclod
