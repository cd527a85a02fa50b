// The collapser skips an edge that cannot become a candidate until one of its
// ends moves (Collapser::dead_ in simplify/src/collapse.cpp). That is only
// an economy: this file builds the collapser a second time with
// PERCLOD_EVALUATE_EVERY_EDGE, which evaluates every edge around each
// collapse again, and checks that both make the same LOD, collapse for
// collapse, on creased and noisy height fields where bounds refuse many
// edges and collapses move the ends of refused ones.
#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "simplify_internal.h"

// The second collapser, under another name (collapse_simplify is its only
// symbol with external linkage; everything else in the file is internal).
#define PERCLOD_EVALUATE_EVERY_EDGE
#define collapse_simplify collapse_simplify_every_edge
#include "collapse.cpp"
#undef collapse_simplify
#undef PERCLOD_EVALUATE_EVERY_EDGE

namespace {

using perclod::Label;
using perclod::Scene;
using perclod::SimplifyMode;
using perclod::SimplifyOptions;
using perclod::SimplifyStats;

struct Field {
  Scene scene;
  std::vector<Label> labels;
};

// An n x n grid of unit cells: flat on one side of a crease, sloping on the
// other, with height noise, a few raised vertices, random diagonals and
// random labels (one in five perceptible, one in ten undisplayable).
Field height_field(uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  const int n = 6 + int(seed % 10);
  const double crease = u(rng) * n, slope = 0.2 + u(rng), noise = 0.05 * u(rng);
  Field f;
  for (int y = 0; y <= n; ++y)
    for (int x = 0; x <= n; ++x) {
      double h = (x > crease ? (x - crease) * slope : 0.0) + noise * (u(rng) - 0.5);
      if ((7 * y + 3 * x) % 5 == 0) h += 0.3 * u(rng);
      f.scene.positions.insert(f.scene.positions.end(), {float(x), float(y), float(h)});
    }
  auto id = [n](int x, int y) { return uint32_t(y * (n + 1) + x); };
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const uint32_t a = id(x, y), b = id(x + 1, y), c = id(x + 1, y + 1), d = id(x, y + 1);
      if (u(rng) < 0.5)
        f.scene.indices.insert(f.scene.indices.end(), {a, b, c, a, c, d});
      else
        f.scene.indices.insert(f.scene.indices.end(), {a, b, d, b, c, d});
      for (int k = 0; k < 2; ++k) {
        const double r = u(rng);
        f.labels.push_back(r < 0.2 ? Label::Perceptible : r < 0.9 ? Label::Imperceptible : Label::Undisplayable);
      }
    }
  return f;
}

struct Lod {
  perclod::detail::Result result;
  SimplifyStats stats;
};

// The work simplify() prepares, then one of the two collapsers.
template <class Collapse>
Lod simplify_with(const Field& f, const SimplifyOptions& opt, Collapse collapse) {
  Lod lod;
  const perclod::detail::Work work = perclod::detail::prepare_work(f.scene, f.labels, opt, lod.stats);
  EXPECT_EQ(work.faces.size(), f.scene.triangle_count());  // none deleted: every label's bound in play
  collapse(work, opt, lod.stats, lod.result);
  return lod;
}

TEST(DeadEdges, SkippingThemChangesNoLod) {
  size_t cases = 0, collapses = 0;
  for (uint32_t seed = 0; seed < 300; ++seed) {
    const Field f = height_field(seed);
    for (SimplifyMode mode : {SimplifyMode::Fidelity, SimplifyMode::Bounded})
      for (double footprint : {0.05, 0.1, 0.2, 0.4}) {
        SimplifyOptions opt;
        opt.mode = mode;
        opt.pixel_footprint = footprint;
        opt.delete_undisplayable = false;  // all three labels' bounds in play
        const Lod skip = simplify_with(f, opt, perclod::detail::collapse_simplify);
        const Lod every = simplify_with(f, opt, perclod::detail::collapse_simplify_every_edge);
        const std::string what = "seed " + std::to_string(seed) + ", " + perclod::simplify_mode_name(mode) +
                                 ", footprint " + std::to_string(footprint);
        ASSERT_EQ(skip.stats.collapses, every.stats.collapses) << what;
        ASSERT_EQ(skip.result.indices, every.result.indices) << what;
        ASSERT_EQ(skip.result.positions, every.result.positions) << what;
        ASSERT_EQ(skip.result.source, every.result.source) << what;
        ++cases;
        collapses += skip.stats.collapses;
      }
  }
  // The fields simplify: the comparison is not between two untouched meshes.
  EXPECT_EQ(cases, 2400u);
  EXPECT_GT(collapses, 10 * cases);
}

}  // namespace
