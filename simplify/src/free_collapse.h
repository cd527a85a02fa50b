// Collapses past the half-edge mesh's topology (Fidelity, opt-in).
//
// The half-edge collapse loop (collapse.cpp) must keep OpenMesh's mesh
// manifold: it refuses a collapse that breaks the link condition, one that
// would leave a dangling edge (a boundary ear), and one that pinches a strip
// (an interior edge between two boundary vertices), and it cannot hold a
// face on a non-manifold edge at all (that face gets vertices of its own and
// never collapses). A building's visible surface, once its undisplayable
// triangles are deleted, is mostly such strips, ears and loose faces: on the
// demo at 56 m, with bounds of 1000 px, 2,814 of 5,009 visible triangles
// stayed, 11,824 half-edges refused by topology alone.
//
// This pass goes on from where that loop stopped, on a plain triangle list
// over the welded vertices (so the loose faces rejoin their neighbours):
// the same quadrics, bounds, area budgets, normal-change and sliver rules,
// and no topological rule. A face holding both ends of a collapse goes; the
// LOD may be non-manifold, as any triangle-list simplifier's may (a renderer
// does not care). Vertices never move (v1 stays where it is), so everything
// the bound says about the half-edge collapses holds here too.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "collapse_rules.h"
#include "perclod/simplify.h"
#include "quadric.h"

namespace perclod::detail {

struct FreeMesh {
  std::vector<float> points;        // x,y,z per vertex
  std::vector<uint32_t> tri;        // 3 vertices per face, in the input's winding
  std::vector<uint32_t> source;     // per face: its input triangle
  std::vector<uint8_t> alive;       // per face
  // Per vertex, as the half-edge model keeps them (empty tol: no bound).
  std::vector<Quadric> qa, qd;      // area-weighted (the cost), unit-weight (the bound)
  std::vector<double> tol, area_budget, area_used;
  std::vector<uint8_t> locked;      // may not be v0
  std::vector<uint32_t> merged_into;
  size_t faces_alive = 0;
};

// Collapses v0 -> v1 in order of cost while any is within both ends'
// bounds and the half-edge loop's shape and area rules (`lim`; its valence
// cap does not apply here), in up to `max_passes` passes (a refused collapse
// is tried again in the next pass when something collapsed). Returns the
// collapses made; `max_error` grows to the largest error bound taken.
// `refused`, when not null, receives every edge left by the first rule that
// refuses each of its two directions (topology never does here).
size_t free_collapse(FreeMesh& m, const Limits& lim, double& max_error, SimplifyStats::Refused* refused,
                     int max_passes = 8);

}  // namespace perclod::detail
