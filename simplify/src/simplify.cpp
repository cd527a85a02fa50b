// simplify(): checks the input, drops components nobody can see, welds the
// vertices, hands the work to the collapse simplifier or to vertex clustering,
// and assembles the output Scene and its statistics.
#include "perclod/simplify.h"

#include <chrono>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>

#include "simplify_internal.h"

namespace perclod {

const char* simplify_mode_name(SimplifyMode m) {
  switch (m) {
    case SimplifyMode::Paper: return "paper";
    case SimplifyMode::Bounded: return "bounded";
    case SimplifyMode::Qem: return "qem";
    case SimplifyMode::Cluster: return "cluster";
    case SimplifyMode::Fidelity: return "fidelity";
  }
  return "?";
}

SimplifyMode parse_simplify_mode(const char* name) {
  for (SimplifyMode m : {SimplifyMode::Paper, SimplifyMode::Bounded, SimplifyMode::Qem,
                         SimplifyMode::Cluster, SimplifyMode::Fidelity})
    if (std::strcmp(name, simplify_mode_name(m)) == 0) return m;
  throw std::invalid_argument(std::string("simplify: unknown mode '") + name +
                              "' (expected fidelity, paper, bounded, qem or cluster)");
}

bool simplify_mode_uses_labels(SimplifyMode m) {
  return m == SimplifyMode::Paper || m == SimplifyMode::Bounded || m == SimplifyMode::Fidelity;
}

bool simplify_mode_keeps_perceptible(SimplifyMode m) {
  return m == SimplifyMode::Paper || m == SimplifyMode::Bounded;
}

std::vector<uint32_t> weld_exact(const Scene& scene) {
  detail::Work work;
  work.scene = &scene;
  work.faces.resize(scene.triangle_count());
  for (size_t t = 0; t < work.faces.size(); ++t) work.faces[t] = uint32_t(t);
  detail::weld_corners(work, false, 0.0);
  return std::move(work.weld.corner);
}

uint32_t connected_parts(const Scene& scene, std::vector<uint32_t>& part) {
  const std::vector<uint32_t> corner = weld_exact(scene);
  const size_t nt = scene.triangle_count();
  uint32_t welded = 0;
  for (uint32_t c : corner) welded = std::max(welded, c + 1);
  detail::DisjointSets sets(welded);
  for (size_t t = 0; t < nt; ++t)
    for (int k = 1; k < 3; ++k) sets.unite(corner[3 * t], corner[3 * t + k]);
  std::vector<uint32_t> id(welded, UINT32_MAX);
  uint32_t count = 0;
  part.resize(nt);
  for (size_t t = 0; t < nt; ++t) {
    uint32_t& r = id[sets.find(corner[3 * t])];
    if (r == UINT32_MAX) r = count++;
    part[t] = r;
  }
  return count;
}

namespace {

void fail(const std::string& what) { throw std::invalid_argument("simplify: " + what); }

void check_input(const Scene& s, const std::vector<Label>& labels, const SimplifyOptions& opt) {
  validate(s);
  const size_t nt = s.triangle_count();
  if (labels.size() != nt)
    fail(std::to_string(labels.size()) + " labels for " + std::to_string(nt) + " triangles");
  for (size_t t = 0; t < nt; ++t)
    if (uint8_t(labels[t]) > 2) fail("triangle " + std::to_string(t) + " has an invalid label");
  const bool needs_footprint =
      opt.mode == SimplifyMode::Bounded || opt.mode == SimplifyMode::Cluster || opt.mode == SimplifyMode::Fidelity;
  if (needs_footprint && !(opt.pixel_footprint > 0 && opt.k > 0 && std::isfinite(opt.pixel_footprint * opt.k)))
    fail(std::string(simplify_mode_name(opt.mode)) + " mode needs a positive pixel footprint and k");
  if (opt.mode == SimplifyMode::Fidelity) {
    auto bound_ok = [](double b) { return b >= 0 && !std::isnan(b); };
    if (!bound_ok(opt.bound_perceptible_px) || !bound_ok(opt.bound_imperceptible_px) ||
        !bound_ok(opt.bound_undisplayable_px) || !bound_ok(opt.bound_area_px2))
      fail("fidelity mode needs error bounds >= 0 pixels");
    if (!std::isfinite(opt.bound_perceptible_px) || !std::isfinite(opt.bound_imperceptible_px))
      fail("fidelity mode needs finite bounds for perceptible and imperceptible triangles");
    if (!opt.bound_scale.empty() && opt.bound_scale.size() != nt)
      fail("bound_scale holds " + std::to_string(opt.bound_scale.size()) + " factors for " + std::to_string(nt) +
           " triangles");
    if (!opt.keep_undisplayable_of.empty() && opt.keep_undisplayable_of.size() != nt)
      fail("keep_undisplayable_of holds " + std::to_string(opt.keep_undisplayable_of.size()) + " flags for " +
           std::to_string(nt) + " triangles");
    for (size_t t = 0; t < opt.bound_scale.size(); ++t)
      if (!(opt.bound_scale[t] >= 0 && std::isfinite(opt.bound_scale[t])))
        fail("triangle " + std::to_string(t) + " has a bound scale that is not a finite number >= 0");
  }
  if (opt.mode == SimplifyMode::Qem && opt.target_triangles == 0)
    fail("qem mode needs a positive target triangle count");
  if (!(opt.weld_tolerance_rel >= 0)) fail("weld tolerance must be >= 0");
}

// Triangles in play: in the labelled modes, components whose triangles are
// all undisplayable are dropped outright; Paper and Fidelity (with
// delete_undisplayable) also drop every undisplayable triangle. No pixel
// centre of any labelling view reaches those, so the labelling views render
// the same without them; collapsing them instead would move the vertices they
// share with imperceptible triangles, which the views do show, and would
// still leave every one whose corners all sit on perceptible triangles. In
// Fidelity the held-out views judge whether deleting them was safe. Dropped
// before welding, they cost no welding either.
std::vector<uint32_t> faces_in_play(const Scene& s, const std::vector<Label>& labels, const SimplifyOptions& opt,
                                    SimplifyStats& stats) {
  const bool labelled = simplify_mode_uses_labels(opt.mode);
  const size_t nt = s.triangle_count();
  std::vector<uint32_t> faces;
  faces.reserve(nt);
  if (!labelled) {
    for (size_t t = 0; t < nt; ++t) faces.push_back(uint32_t(t));
    return faces;
  }
  size_t nc = 1;
  for (size_t t = 0; t < nt; ++t) nc = std::max<size_t>(nc, s.component_of(t) + 1);
  std::vector<uint8_t> seen(nc, 0), displayable(nc, 0);
  for (size_t t = 0; t < nt; ++t) {
    seen[s.component_of(t)] = 1;
    if (labels[t] != Label::Undisplayable) displayable[s.component_of(t)] = 1;
  }
  for (size_t c = 0; c < nc; ++c) stats.components_removed += seen[c] && !displayable[c];
  const bool drop_undisplayable =
      (opt.mode == SimplifyMode::Paper || opt.mode == SimplifyMode::Fidelity) && opt.delete_undisplayable;
  for (size_t t = 0; t < nt; ++t) {
    if (!displayable[s.component_of(t)]) continue;
    const bool kept = opt.mode == SimplifyMode::Fidelity && !opt.keep_undisplayable_of.empty() &&
                      opt.keep_undisplayable_of[t];
    if (drop_undisplayable && labels[t] == Label::Undisplayable && !kept)
      stats.undisplayable_faces_deleted++;
    else
      faces.push_back(uint32_t(t));
  }
  return faces;
}

}  // namespace

namespace detail {

Work prepare_work(const Scene& scene, const std::vector<Label>& labels, const SimplifyOptions& opt,
                  SimplifyStats& stats) {
  Work work;
  work.scene = &scene;
  work.labels = &labels;
  work.diagonal = scene_bounds(scene).diagonal();
  work.faces = faces_in_play(scene, labels, opt, stats);
  weld_corners(work, opt.weld_per_component, opt.weld_tolerance_rel * work.diagonal);
  return work;
}

}  // namespace detail

Scene simplify(const Scene& scene, const std::vector<Label>& labels, const SimplifyOptions& opt,
               SimplifyStats* stats_out, std::vector<uint32_t>* out_source) {
  auto t0 = std::chrono::steady_clock::now();
  check_input(scene, labels, opt);
  SimplifyStats stats;
  for (Label l : labels) stats.triangles_before[size_t(l)]++;
  const detail::Work work = detail::prepare_work(scene, labels, opt, stats);
  stats.bbox_diagonal = work.diagonal;

  detail::Result r;
  if (opt.mode == SimplifyMode::Cluster)
    detail::cluster_simplify(work, opt, stats, r);
  else
    detail::collapse_simplify(work, opt, stats, r);

  Scene out;
  out.positions = std::move(r.positions);
  out.indices = std::move(r.indices);
  out.component_names = scene.component_names;
  out.materials = scene.materials;
  out.offset = scene.offset;
  for (uint32_t src : r.source) {
    if (!scene.component.empty()) out.component.push_back(scene.component[src]);
    if (!scene.material.empty()) out.material.push_back(scene.material[src]);
    stats.triangles_after[size_t(labels[src])]++;
  }
  if (out_source) *out_source = std::move(r.source);
  stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (stats_out) *stats_out = stats;
  return out;
}

std::string refused_text(const SimplifyStats::Refused& why) {
  std::string s = std::to_string(why.total()) + " half-edges left: " + std::to_string(why.bound_or_locked) +
                  " locked or over their bound, " + std::to_string(why.shape) +
                  " refused by shape (normal change, sliver, area), " + std::to_string(why.topology) +
                  " by topology, " + std::to_string(why.valence) + " by the valence cap";
  if (why.legal) s += ", " + std::to_string(why.legal) + " legal only after the last pass";
  return s;
}

}  // namespace perclod
