// keep_undisplayable: auto: how much of what a viewer sees between the
// labelling views the undisplayable triangles are, and what that decides.
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


#include "perclod/undisplayable.h"

namespace perclod {

std::vector<std::string> exposure_views() {
  std::vector<std::string> v;
  for (int i = 0; i < 8; ++i) {
    std::ostringstream ss;
    ss << "az" << 22.5 + 45.0 * i << "el30";
    v.push_back(ss.str());
  }
  return v;
}

double undisplayable_exposure(const Scene& scene, const Tracer& tracer, const std::vector<Label>& labels,
                              const Framing& job) {
  if (labels.size() != scene.triangle_count())
    throw std::invalid_argument("undisplayable_exposure: labels and scene differ in size");
  const Bounds b = scene_bounds(scene);
  size_t hits = 0, undisplayable = 0;
  std::vector<uint32_t> ids;
  for (const std::string& v : exposure_views())
    for (const ViewTile& t : frame_view(b, job.up, v, job.distance, job.display)) {
      ids.resize(size_t(t.camera.width) * size_t(t.camera.height));
      tracer.trace(t.camera, ids.data());
      for (uint32_t id : ids)
        if (id) {
          ++hits;
          undisplayable += labels[id - 1] == Label::Undisplayable;
        }
    }
  return hits ? double(undisplayable) / double(hits) : 0.0;
}

SimplifyOptions choose_undisplayable(SimplifyOptions so, double exposure) {
  if (undisplayable_auto_applies(so) && exposure > kKeepUndisplayableExposure) {
    so.delete_undisplayable = false;
    so.bound_undisplayable_px = kAutoUndisplayableBoundPx;
  }
  return so;
}

double choose_undisplayable(SimplifyOptions& so, const Scene& scene, const Tracer& tracer,
                            const std::vector<Label>& labels, const Framing& framing) {
  const double exposure = undisplayable_exposure(scene, tracer, labels, framing);
  so = choose_undisplayable(so, exposure);
  return exposure;
}

UndisplayableRule undisplayable_rule_of(const SimplifyOptions& so, double exposure) {
  return {so.delete_undisplayable, so.bound_undisplayable_px, exposure};
}


// The same in words, for progress lines and warnings.
std::string undisplayable_rule_text(const UndisplayableRule& rule) {
  if (rule.deleted) return "deleted";
  if (!std::isfinite(rule.bound_px)) return "collapsed, unbounded";
  std::ostringstream ss;
  ss << "collapsed within " << rule.bound_px << " px";
  return ss.str();
}

}  // namespace perclod
