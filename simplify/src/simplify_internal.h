// Internal interfaces of perclod_simplify: welding, the collapse simplifier and
// vertex clustering share one flat description of the work to do.
#pragma once

#include <cstdint>
#include <vector>

#include "perclod/simplify.h"

namespace perclod::detail {

// Welded vertices: corner k of input triangle t is welded vertex
// corner[3t+k] (UINT32_MAX for triangles not in play); a welded vertex keeps
// the position of the first input vertex that went into it.
struct Welded {
  std::vector<uint32_t> corner;
  std::vector<float> positions;  // x,y,z per welded vertex
};

// What a simplifier works on: the input triangles still in play (after
// all-undisplayable components are dropped) and the welded vertices.
struct Work {
  const Scene* scene = nullptr;
  const std::vector<Label>* labels = nullptr;
  std::vector<uint32_t> faces;  // input triangle indices in play
  Welded weld;
  double diagonal = 0.0;        // bounding-box diagonal of the input
};

// The work simplify() hands to a simplifier: the triangles in play (all,
// less those of components no view displays and, where the mode deletes
// them, undisplayable ones; counted in stats) with their corners welded as
// opt says.
Work prepare_work(const Scene& scene, const std::vector<Label>& labels, const SimplifyOptions& opt,
                  SimplifyStats& stats);

// Fills work.weld for work.faces: corners whose positions round to the same
// cell of size `tolerance` weld (two points closer than the tolerance but on
// either side of a cell border stay apart; equal positions always weld;
// tolerance 0 welds equal positions only). With per_component, only corners
// of the same component weld.
void weld_corners(Work& work, bool per_component, double tolerance);

// Union-find over n elements (path halving; unite keeps the first root).
class DisjointSets {
 public:
  explicit DisjointSets(size_t n) : parent_(n) {
    for (size_t i = 0; i < n; ++i) parent_[i] = uint32_t(i);
  }
  uint32_t find(uint32_t x) {
    while (parent_[x] != x) x = parent_[x] = parent_[parent_[x]];
    return x;
  }
  void unite(uint32_t a, uint32_t b) {
    a = find(a), b = find(b);
    if (a != b) parent_[b] = a;
  }

 private:
  std::vector<uint32_t> parent_;
};

// A simplified triangle list; source[t] = input triangle of output triangle t.
struct Result {
  std::vector<float> positions;
  std::vector<uint32_t> indices;
  std::vector<uint32_t> source;
};

// Paper, Bounded and Qem: quadric half-edge collapses on an OpenMesh TriMesh.
void collapse_simplify(const Work& work, const SimplifyOptions& opt, SimplifyStats& stats,
                       Result& out);

// Cluster: Rossignac-Borrel vertex clustering (with Belblidia's bbox option).
void cluster_simplify(const Work& work, const SimplifyOptions& opt, SimplifyStats& stats,
                      Result& out);

}  // namespace perclod::detail
