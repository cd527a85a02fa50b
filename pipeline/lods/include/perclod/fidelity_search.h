// perclod/fidelity_search.h - the bounds `perclod run` tries for a LOD: the
// fidelity_target search and tighten_to_limits.
#pragma once

#include <cstddef>
#include <functional>
#include <optional>
#include <nlohmann/json.hpp>
#include <utility>
#include <vector>

#include "perclod/judge.h"
#include "perclod/simplify.h"
#include "perclod/undisplayable.h"

namespace perclod {

// One try of a fidelity_target search (or of tighten_to_limits):
// e_imperceptible = e pixels, the perceptible bound tightened to e where e is
// the tighter and loosened to kPerceptibleShare * e where that is the looser
// (perceptible detail held four times tighter than imperceptible detail),
// and undisplayable triangles treated as asked or, with
// keep_undisplayable, collapsed within e_undisplayable (e when not given; the
// asked e_undisplayable where tighter) instead of deleted.
struct FidelitySearchStep {
  double e;
  bool keep_undisplayable;
  double e_undisplayable = -1;  // with keep_undisplayable: their bound, px (< 0: e)
};

// The share of a search step's e the perceptible bound follows when looser
// than the asked e_P. Before 0.4.0 e_P stayed at the asked 0.5 px on looser
// steps, and the search could not reach the perceptual floor: han at 132 m,
// within the floor, kept 10,238 triangles at e_I = 2 px; with e_P = e_I / 4
// it keeps 8,324 at 4 px (e_P 1 px; bench_fidelity, BENCHMARKS.md#the-strongest-peer).
constexpr double kPerceptibleShare = 0.25;

// The tries, in order. Tightening e_I alone cannot help where e_P or the
// deleted undisplayable triangles hold a LOD over the target: on the
// million-triangle facade at 56 m (BENCHMARKS.md#with-a-fidelity-target)
// every e_I from 16 down to 0.5 px at e_P = 0.5 px leaves 2.8-3.0% of the
// worst judged view changed, 0.25 px for both 2.1%; 0.125 px with
// undisplayable triangles kept within it meets 2% (0.98%). The last try moves nothing and deletes nothing:
// only collapses of zero error remain.
constexpr FidelitySearchStep kFidelitySearch[] = {
    {16, false}, {8, false}, {4, false}, {2, false}, {1, false}, {0.5, false},  // undisplayable deleted
    {0.25, false}, {0.25, true}, {0.125, true}, {0, true}};                     // then kept
// When the first try already meets the target, looser bounds may too: e_I
// then doubles, up to this, while the target holds and each try removes
// triangles, and the loosest LOD that met it is kept (han at 56 m: 16 and
// 32 px meet a 2% target, 64 px does not). 1024 px is more than a whole
// display at the paper's profile (1280 x 1024).
constexpr double kFidelitySearchLoosestPx = 1024;

// The looser half of a fidelity_target search, for `run` and its tests: the
// first step (kFidelitySearch[0]) met the target, leaving `triangles`.
// `try_step(step)` makes and judges the LOD at each looser step in turn (e
// doubled, up to kFidelitySearchLoosestPx) and returns whether it met the
// target and its triangle count. A try that meets it with fewer triangles is
// kept and the next tried; one with as many is kept and ends the search;
// one that fails, or keeps more, ends it with the last kept step, whose LOD
// the caller makes again (the simplifier and judge are deterministic). After
// a try that fails the target, the midway step is tried (midway_step).
struct LooserSearch {
  FidelitySearchStep step;  // the bounds of the LOD to write
  int tries = 0;            // looser tries made
  int kept = -1;            // which of them is `step` (from 0); -1: kFidelitySearch[0]
  bool remake = false;      // the last try is not `step`: make its LOD again
};

// The steps double, so the last within the target may be up to half as
// loose as the target allows. When a step met it and the next looser one
// did not, the search tries once more midway between them (the geometric
// mean of their e) and keeps that LOD when it meets the target with no
// more triangles. With the collapses past the half-edge topology (0.8.0)
// the count falls steeply with e: on the demo at 56 m 8 px was within the
// floor (0.86x) and 16 px over it. Only between steps that delete
// undisplayable triangles (those that keep them are under a pixel).
std::optional<FidelitySearchStep> midway_step(const FidelitySearchStep& met, const FidelitySearchStep& failed);
LooserSearch search_looser(size_t triangles,
                           const std::function<std::pair<bool, size_t>(const FidelitySearchStep&)>& try_step);

// The whole fidelity_target search, for `run` and the benchmarks that must
// do as it does: kFidelitySearch's steps in order until one meets the
// target, then the midway step between it and the one before (midway_step),
// or, when the first (loosest) met it, search_looser. `try_step(step,
// looser)` makes and judges the LOD at `step` (looser: a try of
// search_looser) and returns whether it met the target and its triangles.
// The LOD to write is try `kept` (from 0) at `step`; when `remake`, the last
// try is not that one and the caller makes it again. With no step within the
// target (`met` false) it is the last, tightest try.
struct TargetSearch {
  FidelitySearchStep step;
  size_t tries = 0;
  size_t kept = 0;
  bool met = false;
  bool remake = false;
};
TargetSearch search_fidelity_target(
    const std::function<std::pair<bool, size_t>(const FidelitySearchStep&, bool looser)>& try_step);

SimplifyOptions fidelity_bounds(SimplifyOptions so, const FidelitySearchStep& step);

// ---- tightening a LOD that misses its limits (`tighten_to_limits`) ----------

// Fidelity mode without a fidelity_target: when the LOD at the asked bounds
// is over job.limits in a judged view, `run` tries tighten_steps in order
// (the sub-pixel ones only when it is over by no more than kTightenReach
// times each limit: worth_tightening) and keeps the first LOD within the
// limits in every judged view; when none is, the tightest LOD tried stays,
// flagged as over its limits. Tightening from 0.5
// to 0.125 px cut the changed pixels by about 3x where it was tried (the
// million-triangle facade at 56 m: 2.97% -> 0.98%,
// BENCHMARKS.md#tightening-to-the-limits), so a LOD further over than that
// is left alone rather than tried at every step for nothing: the default
// LODs at 427 m are within the limits (the block) or 3.8-19x over 2% (the
// same section), where moving the original by a quarter pixel changes
// 19-65% of a view.
constexpr double kTightenReach = 3;

// The tries, in order: e_imperceptible 0.25 px (undisplayable triangles as
// asked), then undisplayable triangles kept within kAutoUndisplayableBoundPx
// at 0.25 and 0.125 px, then within 0.125 px too. Kept within 4 px they
// cost far fewer triangles than within the step's own bound, for nearly the
// same figures (bench_fidelity, BENCHMARKS.md#tightening-to-the-limits and
// #with-a-fidelity-target: Sponza at 132 m 21,810 triangles and 2.02% of the
// worst held-out view changed, against 34,036 and 1.84%; the
// million-triangle facade at 56 m 186,397 and 1.60% against 194,765 and
// 1.55%).
constexpr FidelitySearchStep kTightenSteps[] = {{0.25, false},
                                                {0.25, true, kAutoUndisplayableBoundPx},
                                                {0.125, true, kAutoUndisplayableBoundPx},
                                                {0.125, true}};

// Above this e_I, tightening halves e (0.9.0): the default asks 8 px
// (kDefaultBoundImperceptiblePx), and a LOD over the floor there is most
// often within it at 4 or 2 px, where jumping to kTightenSteps' 0.25 px
// kept more than 0.8's default did (the demo at 427 m: 3,182 triangles at
// 0.25 px against 1,544 within the floor at 2 px). 0.5 px was the default
// until 0.8: every building of the Delft tile and the Ingolstadt block, and
// the demo, was within the floor there, so the halvings down to it are
// tried whenever a LOD is over its limits, however far (kTightenReach
// gates only the steps below it).
constexpr double kTightenHalvingsTo = 0.5;

// The tightening steps for `so` (fidelity mode), in order: e_I halved while
// at least kTightenHalvingsTo (and kTightenHalvingsTo itself), then
// kTightenSteps; each with e at most so's e_imperceptible and changing some
// bound (a step that would change nothing, or only what the step before
// changed, is left out).
std::vector<FidelitySearchStep> tighten_steps(const SimplifyOptions& so);

// A tightening step's bounds: fidelity_bounds, with e_P never looser than
// the asked one (a step between the asked e_P and 4x it would loosen it).
SimplifyOptions tightened_bounds(const SimplifyOptions& asked, const FidelitySearchStep& step);

// After tightening met the limits at a halving of e_I (`met_e`), the step
// midway between it and the try before it (the asked bounds or the halving
// before; midway_step: the geometric mean), which the caller tries once and
// keeps when it meets the limits with no more triangles. The halvings
// overshoot as the doubling steps of a search do: the demo at 427 m is over
// the floor at 4 px, within at 2 px (1,544 triangles, 0.70x) and at 2.83 px
// (1,438, 0.97x). None after a sub-pixel step or when met_e is no halving.
std::optional<FidelitySearchStep> tighten_midway(const SimplifyOptions& asked, double met_e);

// Whether a step of tighten_steps is tried only for a LOD within
// kTightenReach of its limits (worth_tightening): those below
// kTightenHalvingsTo.
bool tighten_step_needs_reach(const FidelitySearchStep& step);

// Whether `judged` (judge_views' result) is over `limits` and no worst
// figure is beyond kTightenReach times its limit (an SSIM's shortfall from 1
// against min_ssim's).
bool worth_tightening(const Judgement& judged, const FidelityLimits& limits);

// tighten_to_limits itself, for `run` and for the benchmarks that must do as
// it does. `judged` is judge_views' result (against `limits`) for the LOD
// at `asked`. When that LOD is over its limits, `try_step(bounds, midway)`
// makes and judges the LOD at each of tighten_steps' bounds in order and
// returns whether it is within `limits` and its triangles, until one is
// within; the steps below kTightenHalvingsTo only when worth_tightening says
// so. After a halving within the limits comes one try at tighten_midway's
// step (`midway` true), kept when within with no more triangles. When no
// step is within, the tightest tried is kept: over the limits still, but the
// nearest to them the steps came.
enum class Tightening { NotTried, Met, NoneWithin };
struct TighteningResult {
  Tightening outcome = Tightening::NotTried;
  SimplifyOptions kept;   // the bounds of the LOD to write (`asked` when NotTried)
  size_t tries = 0;       // try_step calls
  size_t kept_try = 0;    // the kept LOD's call, from 0 (when tries > 0)
  bool remake = false;    // the last call made another LOD: make `kept`'s again
};
TighteningResult tighten_to_limits(const SimplifyOptions& asked, const Judgement& judged, const FidelityLimits& limits,
                                   const std::function<std::pair<bool, size_t>(const SimplifyOptions&, bool midway)>& try_step);

}  // namespace perclod
