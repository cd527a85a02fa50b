// perclod/undisplayable.h - `keep_undisplayable: auto`: whether the triangles
// no labelling view sees are deleted or kept (collapsed within a bound).
#pragma once

#include <cmath>
#include <string>
#include <vector>

#include "perclod/label.h"
#include "perclod/raycast.h"
#include "perclod/simplify.h"

namespace perclod {

// The views undisplayable_exposure looks from: az22.5el30, az67.5el30, ...,
// az337.5el30, between the default labelling azimuths at the labelling
// ring's elevation. None is a view of the default labelling set, of the
// `held_out` preset or of the benchmarks' 17 held-out views.
std::vector<std::string> exposure_views();

// How much of what a viewer sees from between the labelling views the
// triangles labelled undisplayable are: over exposure_views() framed at
// job.distance (tiles included), the nearest hits on undisplayable triangles
// over all hits, each pixel traced once at its centre. What deleting them
// would open from those views.
double undisplayable_exposure(const Scene& scene, const Tracer& tracer, const std::vector<Label>& labels,
                              const Framing& framing);

// keep_undisplayable: auto (fidelity mode) deletes undisplayable triangles
// when their exposure is at most kKeepUndisplayableExposure, and otherwise
// keeps them, collapsed within kAutoUndisplayableBoundPx (an asked
// e_undisplayable keeps them anyway: auto has nothing to decide).
// BENCHMARKS.md#keeping-undisplayable-triangles has the measurements that
// chose both.
constexpr double kKeepUndisplayableExposure = 0.004;
constexpr double kAutoUndisplayableBoundPx = 4;

// Whether keep_undisplayable: auto has anything to decide for `so`: the
// fidelity mode, undisplayable triangles not already kept.
inline bool undisplayable_auto_applies(const SimplifyOptions& so) {
  return so.mode == SimplifyMode::Fidelity && so.delete_undisplayable;
}
// What keep_undisplayable: auto makes of `so` for an exposure (above): `so`
// unchanged unless the rule applies and the exposure is over
// kKeepUndisplayableExposure; then undisplayable triangles are kept and
// collapsed within kAutoUndisplayableBoundPx.
SimplifyOptions choose_undisplayable(SimplifyOptions so, double exposure);
// The same from the labels: measures undisplayable_exposure (framed by
// `framing`'s up, display and distance), applies it to `so`, returns it.
double choose_undisplayable(SimplifyOptions& so, const Scene& scene, const Tracer& tracer,
                            const std::vector<Label>& labels, const Framing& framing);

// How a LOD treats undisplayable triangles: deleted, or kept and collapsed
// within bound_px (infinite: unbounded); exposure is what
// keep_undisplayable: auto measured (< 0: not measured).
struct UndisplayableRule {
  bool deleted = true;
  double bound_px = INFINITY;
  double exposure = -1;
};
UndisplayableRule undisplayable_rule_of(const SimplifyOptions& so, double exposure = -1);

// A rule in words, for progress lines and warnings: "deleted",
// "collapsed, unbounded" or "collapsed within E px".
std::string undisplayable_rule_text(const UndisplayableRule& rule);

}  // namespace perclod
