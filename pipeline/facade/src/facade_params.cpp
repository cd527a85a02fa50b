// facade_params.cpp - parameters for a triangle budget.
//
// The count is a cheap closed form, so the search simply walks a grid of
// plausible buildings (sides, floors, bays, column tessellation, ornament
// detail) and keeps the one closest to the target, preferring, among those
// within 2%, the most ordinary building: at most 8 floors x 12 bays, default
// tessellation and detail, one facade, bays about 1.5 times the floors.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <iterator>
#include <limits>
#include <stdexcept>
#include <string>

#include "facade_layout.h"
#include "perclod/facade.h"

namespace perclod {
namespace {

constexpr int kSegmentChoices[] = {12, 8, 16, 24, 32, 48, 64};
constexpr int kDetailChoices[] = {0, 1, 2, 4, 8, 16, 32};
constexpr int kMaxFloors = 80, kMaxBays = 120;

// How unusual a building is (0 = the defaults); small next to the count error.
// Size matters most: a building up to 8 floors x 12 bays still fits a facade
// view at the paper's distances, so big budgets go to four sides and finer
// turned parts before the building grows.
double oddness(const FacadeParams& p, int segment_rank, int detail_rank) {
  double aspect = std::abs(std::log(double(p.bays) / (1.5 * p.floors)));
  double size = std::max(0.0, std::log2(p.floors / 8.0)) + std::max(0.0, std::log2(p.bays / 12.0));
  return 0.004 * aspect + 0.01 * size + 0.002 * (segment_rank + detail_rank + (p.sides == 4));
}

}  // namespace

FacadeParams facade_params_for_triangles(size_t target) {
  FacadeParams smallest;
  smallest.floors = smallest.bays = 1;
  const size_t minimum = facade_detail::building_triangles(smallest);
  if (target < minimum)
    throw std::invalid_argument("facade_params_for_triangles: target " + std::to_string(target) +
                                " is below the smallest building (" + std::to_string(minimum) +
                                " triangles)");
  FacadeParams best;
  double best_score = std::numeric_limits<double>::max(), best_error = 1.0;
  for (int sides : {1, 4})
    for (int si = 0; si < int(std::size(kSegmentChoices)); ++si)
      for (int di = 0; di < int(std::size(kDetailChoices)); ++di)
        for (int floors = 1; floors <= kMaxFloors; ++floors)
          for (int bays = 1; bays <= kMaxBays; ++bays) {
            FacadeParams p;
            p.sides = sides;
            p.floors = floors;
            p.bays = bays;
            p.column_segments = kSegmentChoices[si];
            p.ornament_detail = kDetailChoices[di];
            size_t n = facade_detail::building_triangles(p);
            double error = std::abs(double(n) - double(target)) / double(target);
            // Beyond 2% the error decides; within it, the ordinary building wins.
            double score = std::max(error - 0.02, 0.0) * 100.0 + oddness(p, si, di);
            if (score < best_score) {
              best_score = score;
              best_error = error;
              best = p;
            }
            if (n > target * 2) break;  // more bays only grow the count
          }
  if (best_error > 0.1)
    throw std::invalid_argument("facade_params_for_triangles: no building within 10% of " +
                                std::to_string(target) + " triangles (closest is " +
                                std::to_string(facade_detail::building_triangles(best)) + ")");
  return best;
}

}  // namespace perclod
