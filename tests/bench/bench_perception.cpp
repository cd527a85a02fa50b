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

// Threshold calibration (docs/perception.md). The simulation is linear, so 8-bit
// quantisation adds the simulation of the quantisation error alone: measured
// as difference(quantised) - difference(unquantised) over smooth content the
// CSF passes, next to its worst case 0.5 * L1 norm of the difference operator.
void calibration() {
  const int w = 256, h = 256;
  perclod::PerceptionSettings s;
  perclod::PerceptionResult a, b;
  double l1_worst = 0;
  for (int py = 126; py < 130; ++py)
    for (int px = 126; px < 130; ++px) {
      std::vector<float> impulse(size_t(w) * h, 0.0f);
      impulse[size_t(py) * w + px] = 1.0f;
      perclod::perceive_luminance(impulse.data(), w, h, s, nullptr, a);
      double l1 = 0;
      for (float d : a.difference) l1 += std::abs(d);
      l1_worst = std::max(l1_worst, l1);
    }
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  float quant = 0, raw = 0, roundtrip = 0;
  for (int trial = 0; trial < 50; ++trial) {
    double gx = u(rng) - 0.5, gy = u(rng) - 0.5, f = 0.002 + 0.03 * u(rng), th = 6.3 * u(rng);
    double amp = 10 + 40 * u(rng);
    std::vector<float> smooth(size_t(w) * h), q(smooth.size());
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        double v = 128 + gx * (x - w / 2) + gy * (y - h / 2) +
                   amp * std::sin(2 * 3.14159265358979 * f * (x * std::cos(th) + y * std::sin(th)));
        smooth[size_t(y) * w + x] = float(v);
        q[size_t(y) * w + x] = float(std::round(v));
      }
    perclod::perceive_luminance(smooth.data(), w, h, s, nullptr, a);
    perclod::perceive_luminance(q.data(), w, h, s, nullptr, b);
    for (size_t i = 0; i < q.size(); ++i) {
      quant = std::max(quant, std::abs(b.difference[i] - a.difference[i]));
      raw = std::max(raw, std::abs(b.difference[i]));
    }
    std::vector<float> img = q;
    perclod::dwt97_forward(img.data(), w, h, 2);
    perclod::dwt97_inverse(img.data(), w, h, 2);
    for (size_t i = 0; i < q.size(); ++i) roundtrip = std::max(roundtrip, std::abs(img[i] - q[i]));
  }
  std::printf("calibration (paper display, fir): quantisation contribution max %.3f levels over 50 smooth 8-bit "
              "images (bound 0.5 x L1 = %.3f); float round trip max %.1e; raw |difference| max %.3f "
              "(borders, clipping); default threshold %.2f\n",
              quant, 0.5 * l1_worst, roundtrip, raw, s.threshold);
}

// A cold perceive() allocates and first-touches its result buffers.
void time_cold(int w, int h, int runs) {
  std::vector<uint8_t> rgb = facade_like(w, h);
  std::vector<double> t;
  for (int i = 0; i < runs; ++i) {
    auto t0 = Clock::now();
    perclod::PerceptionResult r = perclod::perceive(rgb.data(), w, h, perclod::PerceptionSettings{});
    t.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
  }
  std::printf("%dx%d: cold perceive() with fresh result buffers median %.2f ms over %d runs\n", w, h, median(t),
              runs);
}

}  // namespace

int main() {
  std::printf("bench_perception (single thread, default settings: fir CSF, luma, ppd 29.64)\n");
  time_size(1280, 1024, 21);
  time_size(4096, 4096, 7);
  time_cold(1280, 1024, 7);
  calibration();
  return 0;
}
