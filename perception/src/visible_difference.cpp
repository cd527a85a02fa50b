// The pooled visible difference of two vision-simulated images.
#include <cmath>
#include <stdexcept>

#include "perclod/perception.h"

namespace perclod {

double visible_difference(const float* a, const float* b, size_t n, const uint8_t* region, double threshold) {
  if (!(threshold > 0)) throw std::invalid_argument("visible_difference: the threshold must be positive");
  double sum = 0;
  size_t counted = 0;
  for (size_t i = 0; i < n; ++i) {
    if (region && !region[i]) continue;
    ++counted;
    const double excess = std::abs(double(a[i]) - double(b[i])) - threshold;
    if (excess > 0) sum += excess * excess;
  }
  return counted ? std::sqrt(sum / double(counted)) / threshold : 0.0;
}

}  // namespace perclod
