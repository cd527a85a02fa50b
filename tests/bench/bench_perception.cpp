// Perception timings: perceive() on one thread, default settings, median of
// several runs, for 1280x1024 (target <= 15 ms) and 4096x4096; the DWT alone
// alongside as the in-run peer. Also prints the threshold calibration figure:
// the largest |difference| that 8-bit quantisation of smooth (fully passed)
// content produces.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "perclod/perception.h"

namespace {

using Clock = std::chrono::steady_clock;

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

// A render-like test image: flat facade panels with edges, windows and noise.
std::vector<uint8_t> facade_like(int w, int h) {
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> noise(-6, 6);
  std::vector<uint8_t> rgb(size_t(w) * h * 3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      int base = ((x / 37) % 3 == 0 || (y / 23) % 4 == 0) ? 180 : 90;
      if ((x % 37) < 2 || (y % 23) < 2) base = 30;
      for (int c = 0; c < 3; ++c)
        rgb[(size_t(y) * w + x) * 3 + c] = uint8_t(std::clamp(base + 10 * c + noise(rng), 0, 255));
    }
  return rgb;
}

void time_size(int w, int h, int runs) {
  std::vector<uint8_t> rgb = facade_like(w, h);
  perclod::PerceptionSettings s;
  perclod::PerceptionResult r;
  perclod::perceive_into(rgb.data(), w, h, s, nullptr, r);  // warm up buffers
  std::vector<double> full, dwt;
  std::vector<float> img(size_t(w) * h);
  for (int i = 0; i < runs; ++i) {
    auto t0 = Clock::now();
    perclod::perceive_into(rgb.data(), w, h, s, nullptr, r);
    auto t1 = Clock::now();
    std::copy(r.luminance.begin(), r.luminance.end(), img.begin());
    auto t2 = Clock::now();
    perclod::dwt97_forward(img.data(), w, h, r.levels);
    perclod::dwt97_inverse(img.data(), w, h, r.levels);
    auto t3 = Clock::now();
    full.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
    dwt.push_back(std::chrono::duration<double, std::milli>(t3 - t2).count());
  }
  std::printf("%dx%d: perceive (fir, %d levels) median %.2f ms over %d runs; forward+inverse DWT alone %.2f ms "
              "(%.0f%% of it); imperceptible %.1f%%\n",
              w, h, r.levels, median(full), runs, median(dwt), 100.0 * median(dwt) / median(full),
              100.0 * r.imperceptible_fraction);
  for (auto mode : {perclod::PerceptionSettings::CsfMode::Weights, perclod::PerceptionSettings::CsfMode::Kakadu}) {
    s.csf = mode;
    std::vector<double> t;
    for (int i = 0; i < runs; ++i) {
      auto t0 = Clock::now();
      perclod::perceive_into(rgb.data(), w, h, s, nullptr, r);
      t.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
    }
    std::printf("    %s mode: median %.2f ms\n",
                mode == perclod::PerceptionSettings::CsfMode::Weights ? "weights" : "kakadu", median(t));
  }
}

// Threshold calibration: smooth content the CSF passes in full, quantised to
// 8 bits, should give no imperceptible pixels. Prints the largest |difference|.
void calibration() {
  const int w = 512, h = 512;
  float worst_luma = 0, worst_linear = 0;
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int trial = 0; trial < 12; ++trial) {
    // Random slow gradients and low-frequency gratings (below the CSF peak).
    double gx = u(rng) * 0.5, gy = u(rng) * 0.5, f = 0.002 + 0.02 * u(rng), th = 6.3 * u(rng);
    double amp = 20 + 80 * u(rng), base = 40 + 80 * u(rng);
    std::vector<uint8_t> rgb(size_t(w) * h * 3);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        double v = base + gx * x * 0.2 + gy * y * 0.2 +
                   amp * std::sin(2 * 3.14159265 * f * (x * std::cos(th) + y * std::sin(th)));
        uint8_t q = uint8_t(std::clamp(std::lround(v), 0L, 255L));
        for (int c = 0; c < 3; ++c) rgb[(size_t(y) * w + x) * 3 + c] = q;
      }
    for (auto lum : {perclod::PerceptionSettings::Luminance::Luma, perclod::PerceptionSettings::Luminance::LinearY}) {
      perclod::PerceptionSettings s;
      s.luminance = lum;
      perclod::PerceptionResult r = perclod::perceive(rgb.data(), w, h, s);
      float m = 0;
      for (float d : r.difference) m = std::max(m, std::abs(d));
      (lum == perclod::PerceptionSettings::Luminance::Luma ? worst_luma : worst_linear) =
          std::max(lum == perclod::PerceptionSettings::Luminance::Luma ? worst_luma : worst_linear, m);
    }
  }
  std::printf("calibration: 8-bit quantised smooth content, max |difference| = %.3f grey levels (luma), "
              "%.3f (linear Y); default threshold %.2f\n",
              worst_luma, worst_linear, perclod::PerceptionSettings{}.threshold);
}

}  // namespace

int main() {
  std::printf("bench_perception (single thread, default settings: fir CSF, luma, ppd 29.64)\n");
  time_size(1280, 1024, 21);
  time_size(4096, 4096, 7);
  calibration();
  return 0;
}
