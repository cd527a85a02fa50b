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
  float taps[2 * kRadius + 1];
  Gauss1D() {
    for (int i = -kRadius; i <= kRadius; ++i) taps[i + kRadius] = float(std::exp(-0.5 * i * i / (kSigma * kSigma)));
  }
  std::vector<float> norm(int n) const {
    std::vector<float> s(size_t(n), 0.f);
    for (int x = 0; x < n; ++x)
      for (int i = -kRadius; i <= kRadius; ++i)
        if (x + i >= 0 && x + i < n) s[size_t(x)] += taps[i + kRadius];
    return s;
  }
};

// Filters the five maps along x then y, in place.
void blur(std::vector<float>* maps, int nmaps, int w, int h) {
  static const Gauss1D g;
  const std::vector<float> nx = g.norm(w), ny = g.norm(h);
  std::vector<float> line(size_t(std::max(w, h)));
  for (int m = 0; m < nmaps; ++m) {
    float* img = maps[m].data();
    for (int y = 0; y < h; ++y) {
      float* row = img + size_t(y) * w;
      for (int x = 0; x < w; ++x) {
        float s = 0;
        for (int i = -kRadius; i <= kRadius; ++i)
          if (x + i >= 0 && x + i < w) s += g.taps[i + kRadius] * row[x + i];
        line[size_t(x)] = s / nx[size_t(x)];
      }
      std::copy(line.begin(), line.begin() + w, row);
    }
    std::vector<float> out(size_t(w) * h);
    for (int y = 0; y < h; ++y) {
      float* o = out.data() + size_t(y) * w;
      for (int x = 0; x < w; ++x) o[x] = 0;
      for (int i = -kRadius; i <= kRadius; ++i) {
        if (y + i < 0 || y + i >= h) continue;
        const float* r = img + size_t(y + i) * w;
        const float t = g.taps[i + kRadius];
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
  std::vector<float> maps[5];
  for (auto& m : maps) m.resize(n);
  for (size_t i = 0; i < n; ++i) {
    maps[0][i] = a[i];
    maps[1][i] = b[i];
    maps[2][i] = a[i] * a[i];
    maps[3][i] = b[i] * b[i];
    maps[4][i] = a[i] * b[i];
  }
  blur(maps, 5, w, h);
  const double c1 = (0.01 * 255) * (0.01 * 255), c2 = (0.03 * 255) * (0.03 * 255);
  double sum = 0;
  size_t count = 0;
  for (size_t i = 0; i < n; ++i) {
    if (region && !region[i]) continue;
    const double ma = maps[0][i], mb = maps[1][i];
    // Variances from filtered moments can dip below zero by rounding.
    const double va = std::max(0.0, maps[2][i] - ma * ma), vb = std::max(0.0, maps[3][i] - mb * mb);
    const double cov = maps[4][i] - ma * mb;
    sum += ((2 * ma * mb + c1) * (2 * cov + c2)) / ((ma * ma + mb * mb + c1) * (va + vb + c2));
    ++count;
  }
  return count ? sum / double(count) : 1.0;
}

}  // namespace perclod
