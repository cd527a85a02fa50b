// The pooled visible difference of two vision-simulated images.
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "perclod/perception.h"

namespace perclod {
namespace {

// One pixel's squared difference beyond the threshold (0 within it).
double excess_squared(float a, float b, double threshold) {
  const double excess = std::abs(double(a) - double(b)) - threshold;
  return excess > 0 ? excess * excess : 0.0;
}

}  // namespace

double visible_difference(const float* a, const float* b, size_t n, const uint8_t* region, double threshold) {
  if (!(threshold > 0)) throw std::invalid_argument("visible_difference: the threshold must be positive");
  double sum = 0;
  size_t counted = 0;
  for (size_t i = 0; i < n; ++i) {
    if (region && !region[i]) continue;
    ++counted;
    sum += excess_squared(a[i], b[i], threshold);
  }
  return counted ? std::sqrt(sum / double(counted)) / threshold : 0.0;
}

double visible_difference_local(const float* a, const float* b, int width, int height, const uint8_t* region,
                                double threshold, int block) {
  if (!(threshold > 0)) throw std::invalid_argument("visible_difference_local: the threshold must be positive");
  if (block < 2) throw std::invalid_argument("visible_difference_local: the block must be 2 pixels or more");
  const int step = block / 2;
  double worst = 0;
  for (int y0 = 0; y0 < height; y0 += step)
    for (int x0 = 0; x0 < width; x0 += step) {
      double sum = 0;
      int counted = 0;
      for (int y = y0; y < std::min(height, y0 + block); ++y)
        for (int x = x0; x < std::min(width, x0 + block); ++x) {
          const size_t i = size_t(y) * size_t(width) + size_t(x);
          if (region && !region[i]) continue;
          ++counted;
          sum += excess_squared(a[i], b[i], threshold);
        }
      if (4 * counted >= block * block) worst = std::max(worst, std::sqrt(sum / counted) / threshold);
    }
  return worst;
}

}  // namespace perclod
