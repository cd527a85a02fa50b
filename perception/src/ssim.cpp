// SSIM over a region of two luminance images (perclod/perception.h): five
// separable Gaussian-filtered maps (a, b, a^2, b^2, ab), then the SSIM
// formula at each pixel of the region.
#include <cmath>
#include <stdexcept>
#include <vector>

#include "perclod/perception.h"

namespace perclod {

namespace {

constexpr int kRadius = 5;        // 11 taps
constexpr double kSigma = 1.5;    // pixels

// One axis of the Gaussian filter; `norm` holds per position the sum of the
// taps that fall inside the image, so borders average what they see.
struct Gauss1D {
  double taps[2 * kRadius + 1];
  Gauss1D() {
    for (int i = -kRadius; i <= kRadius; ++i) taps[i + kRadius] = std::exp(-0.5 * i * i / (kSigma * kSigma));
  }
  std::vector<double> norm(int n) const {
    std::vector<double> s(size_t(n), 0.0);
    for (int x = 0; x < n; ++x)
      for (int i = -kRadius; i <= kRadius; ++i)
        if (x + i >= 0 && x + i < n) s[size_t(x)] += taps[i + kRadius];
    return s;
  }
};

// Filters the five maps along x then y, in place. Double precision: the
// variances are differences of large moments (255^2), and identical images
// must give identical variance and covariance, so SSIM 1 exactly.
void blur(std::vector<double>* maps, int nmaps, int w, int h) {
  static const Gauss1D g;
  const std::vector<double> nx = g.norm(w), ny = g.norm(h);
  std::vector<double> line(size_t(std::max(w, h)));
  for (int m = 0; m < nmaps; ++m) {
    double* img = maps[m].data();
    for (int y = 0; y < h; ++y) {
      double* row = img + size_t(y) * w;
      for (int x = 0; x < w; ++x) {
        double s = 0;
        for (int i = -kRadius; i <= kRadius; ++i)
          if (x + i >= 0 && x + i < w) s += g.taps[i + kRadius] * row[x + i];
        line[size_t(x)] = s / nx[size_t(x)];
      }
      std::copy(line.begin(), line.begin() + w, row);
    }
    std::vector<double> out(size_t(w) * h);
    for (int y = 0; y < h; ++y) {
      double* o = out.data() + size_t(y) * w;
      for (int x = 0; x < w; ++x) o[x] = 0;
      for (int i = -kRadius; i <= kRadius; ++i) {
        if (y + i < 0 || y + i >= h) continue;
        const double* r = img + size_t(y + i) * w;
        const double t = g.taps[i + kRadius];
        for (int x = 0; x < w; ++x) o[x] += t * r[x];
      }
      for (int x = 0; x < w; ++x) o[x] /= ny[size_t(y)];
    }
    maps[m].swap(out);
  }
}

}  // namespace

double ssim_mean(const float* a, const float* b, int w, int h, const uint8_t* region) {
  if (w <= 0 || h <= 0 || !a || !b) throw std::invalid_argument("ssim_mean: empty image");
  const size_t n = size_t(w) * h;
  std::vector<double> maps[5];
  for (auto& m : maps) m.resize(n);
  for (size_t i = 0; i < n; ++i) {
    const double x = a[i], y = b[i];
    maps[0][i] = x;
    maps[1][i] = y;
    maps[2][i] = x * x;
    maps[3][i] = y * y;
    maps[4][i] = x * y;
  }
  blur(maps, 5, w, h);
  const double c1 = (0.01 * 255) * (0.01 * 255), c2 = (0.03 * 255) * (0.03 * 255);
  double sum = 0;
  size_t count = 0;
  for (size_t i = 0; i < n; ++i) {
    if (region && !region[i]) continue;
    const double ma = maps[0][i], mb = maps[1][i];
    const double va = maps[2][i] - ma * ma, vb = maps[3][i] - mb * mb;
    const double cov = maps[4][i] - ma * mb;
    sum += ((2 * ma * mb + c1) * (2 * cov + c2)) / ((ma * ma + mb * mb + c1) * (va + vb + c2));
    ++count;
  }
  return count ? sum / double(count) : 1.0;
}

}  // namespace perclod
