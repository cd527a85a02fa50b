// The bounds `perclod run` tries for a LOD: the fidelity_target search and
// tighten_to_limits, as rules a caller drives with its own make-and-judge step.
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


#include "perclod/fidelity_search.h"

namespace perclod {

SimplifyOptions fidelity_bounds(SimplifyOptions so, const FidelitySearchStep& step) {
  so.bound_imperceptible_px = step.e;
  // Tighter than the asked e_P: both follow e. Looser: perceptible detail
  // is held to kPerceptibleShare of e, or the asked e_P where that is looser.
  so.bound_perceptible_px = step.e < so.bound_perceptible_px
                                ? step.e
                                : std::max(so.bound_perceptible_px, kPerceptibleShare * step.e);
  if (step.keep_undisplayable) {
    const double e_u = step.e_undisplayable >= 0 ? step.e_undisplayable : step.e;
    so.bound_undisplayable_px = so.delete_undisplayable ? e_u : std::min(so.bound_undisplayable_px, e_u);
    so.delete_undisplayable = false;
  }
  return so;
}

std::vector<FidelitySearchStep> tighten_steps(const SimplifyOptions& so) {
  std::vector<FidelitySearchStep> steps;
  if (so.mode != SimplifyMode::Fidelity) return steps;
  auto same = [](const SimplifyOptions& a, const SimplifyOptions& b) {
    return a.bound_imperceptible_px == b.bound_imperceptible_px && a.bound_perceptible_px == b.bound_perceptible_px &&
           a.delete_undisplayable == b.delete_undisplayable &&
           (a.delete_undisplayable || a.bound_undisplayable_px == b.bound_undisplayable_px);
  };
  // Halvings of the asked e down to kTightenHalvingsTo, then kTightenSteps
  // below it.
  std::vector<FidelitySearchStep> all;
  for (double e = so.bound_imperceptible_px / 2; e > kTightenHalvingsTo; e /= 2) all.push_back({e, false});
  if (so.bound_imperceptible_px > kTightenHalvingsTo) all.push_back({kTightenHalvingsTo, false});
  all.insert(all.end(), std::begin(kTightenSteps), std::end(kTightenSteps));
  SimplifyOptions last = so;
  for (const FidelitySearchStep& step : all) {
    if (step.e > so.bound_imperceptible_px) continue;
    const SimplifyOptions t = tightened_bounds(so, step);
    if (same(t, last)) continue;
    steps.push_back(step);
    last = t;
  }
  return steps;
}

bool worth_tightening(const Judgement& judged, const FidelityLimits& limits) {
  if (judged.met()) return false;
  const WorstFigures& w = judged.worst;
  const bool ssim_within = limits.min_ssim <= 0 || 1 - w.ssim_covered <= kTightenReach * (1 - limits.min_ssim);
  const bool visible_within = (limits.max_visible <= 0 || w.visible_ratio <= kTightenReach * limits.max_visible) &&
                              (limits.max_visible_local <= 0 ||
                               w.visible_local_ratio <= kTightenReach * limits.max_visible_local);
  return w.changed_fraction <= kTightenReach * limits.max_changed &&
         w.silhouette_mismatch <= kTightenReach * limits.max_silhouette && ssim_within && visible_within;
}

bool tighten_step_needs_reach(const FidelitySearchStep& step) { return step.e < kTightenHalvingsTo; }

SimplifyOptions tightened_bounds(const SimplifyOptions& asked, const FidelitySearchStep& step) {
  SimplifyOptions so = fidelity_bounds(asked, step);
  so.bound_perceptible_px = std::min(so.bound_perceptible_px, asked.bound_perceptible_px);
  return so;
}

std::optional<FidelitySearchStep> tighten_midway(const SimplifyOptions& asked, double met_e) {
  const std::vector<FidelitySearchStep> steps = tighten_steps(asked);
  for (size_t i = 0; i < steps.size(); ++i) {
    if (steps[i].keep_undisplayable || steps[i].e != met_e || tighten_step_needs_reach(steps[i])) continue;
    const double before = i == 0 ? asked.bound_imperceptible_px : steps[i - 1].e;
    return midway_step(steps[i], FidelitySearchStep{before, false});
  }
  return std::nullopt;
}

TighteningResult tighten_to_limits(
    const SimplifyOptions& asked, const Judgement& judged, const FidelityLimits& limits,
    const std::function<std::pair<bool, size_t>(const SimplifyOptions&, bool midway)>& try_step) {
  TighteningResult r;
  r.kept = asked;
  if (judged.met()) return r;
  const bool in_reach = worth_tightening(judged, limits);
  for (const FidelitySearchStep& step : tighten_steps(asked)) {
    if (tighten_step_needs_reach(step) && !in_reach) break;
    const SimplifyOptions bounds = tightened_bounds(asked, step);
    const auto [met, triangles] = try_step(bounds, false);
    r.kept = bounds;  // the tightest so far, or the one within
    r.kept_try = r.tries++;
    r.outcome = met ? Tightening::Met : Tightening::NoneWithin;
    if (!met) continue;
    if (const std::optional<FidelitySearchStep> mid = tighten_midway(asked, step.e)) {
      const SimplifyOptions at_mid = tightened_bounds(asked, *mid);
      const auto [mid_met, mid_triangles] = try_step(at_mid, true);
      ++r.tries;
      if (mid_met && mid_triangles <= triangles) {
        r.kept = at_mid;
        r.kept_try = r.tries - 1;
      } else {
        r.remake = true;
      }
    }
    return r;
  }
  return r;
}

std::optional<FidelitySearchStep> midway_step(const FidelitySearchStep& met, const FidelitySearchStep& failed) {
  if (met.keep_undisplayable || failed.keep_undisplayable || !(met.e > 0) || !(failed.e > met.e))
    return std::nullopt;
  return FidelitySearchStep{std::sqrt(met.e * failed.e), false};
}

LooserSearch search_looser(size_t triangles,
                           const std::function<std::pair<bool, size_t>(const FidelitySearchStep&)>& try_step) {
  LooserSearch r{kFidelitySearch[0]};
  for (FidelitySearchStep looser{2 * r.step.e, false}; looser.e <= kFidelitySearchLoosestPx; looser.e *= 2) {
    const auto [met, left] = try_step(looser);
    ++r.tries;
    if (!met || left > triangles) {
      r.remake = true;
      if (met) break;  // within the target, but more triangles: no looser bound helps
      if (const auto mid = midway_step(r.step, looser)) {
        const auto [mid_met, mid_left] = try_step(*mid);
        ++r.tries;
        if (mid_met && mid_left <= triangles) {
          r.step = *mid;
          r.kept = r.tries - 1;
          r.remake = false;
        }
      }
      break;
    }
    r.step = looser;
    r.kept = r.tries - 1;
    if (left == triangles) break;  // looser bounds removed nothing more
    triangles = left;
  }
  return r;
}

TargetSearch search_fidelity_target(
    const std::function<std::pair<bool, size_t>(const FidelitySearchStep&, bool looser)>& try_step) {
  TargetSearch s;
  const size_t n = std::size(kFidelitySearch);
  size_t first = 0, triangles = 0;
  for (; first < n; ++first) {
    const auto [met, left] = try_step(kFidelitySearch[first], false);
    ++s.tries;
    triangles = left;
    if (met) break;
  }
  s.met = first < n;
  s.step = kFidelitySearch[std::min(first, n - 1)];
  s.kept = s.tries - 1;  // the first that met, or the tightest
  if (s.met && first > 0)
    if (const auto mid = midway_step(kFidelitySearch[first], kFidelitySearch[first - 1])) {
      const auto [met, left] = try_step(*mid, false);
      ++s.tries;
      s.remake = true;
      if (met && left <= triangles) {
        s.step = *mid;
        s.kept = s.tries - 1;
        s.remake = false;
      }
    }
  if (first == 0) {  // the loosest step met it: so may looser bounds
    const LooserSearch l =
        search_looser(triangles, [&](const FidelitySearchStep& step) { return try_step(step, true); });
    s.tries += size_t(l.tries);
    s.kept += size_t(l.kept + 1);
    s.step = l.step;
    s.remake = l.remake;
  }
  return s;
}

}  // namespace perclod
