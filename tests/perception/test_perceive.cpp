// The whole simulation on synthetic images: sine gratings against the CSF,
// constant and linear behaviour, the mask, the background, the threshold
// calibration, the viewing images and bad input.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "perclod/perception.h"

namespace {

using perclod::PerceptionResult;
using perclod::PerceptionSettings;

// Gratings on a 257 x 257 image with axis frequency m / 512 cycles/pixel: a
// cosine whose whole-sample mirror at both borders continues it exactly, so
// the borders add nothing. dir: 0 varies along x, 1 along y, 2 along x + y.
constexpr int kSide = 257;

std::vector<float> grating(int m, int dir, double amplitude = 50.0) {
  const double f = m / 512.0;
  std::vector<float> img(size_t(kSide) * kSide);
  for (int y = 0; y < kSide; ++y)
    for (int x = 0; x < kSide; ++x) {
      double phase = dir == 0 ? f * x : dir == 1 ? f * y : f * (x + y);
      img[size_t(y) * kSide + x] = float(128.0 + amplitude * std::cos(2 * std::numbers::pi * phase));
    }
  return img;
}

PerceptionResult simulate(const std::vector<float>& lum, int w, int h, const PerceptionSettings& s = {}) {
  PerceptionResult r;
  perclod::perceive_luminance(lum.data(), w, h, s, nullptr, r);
  return r;
}

// Least-squares gain of the simulated grating against the original, away from
// the borders (16 pixels).
double grating_gain(const std::vector<float>& img, const PerceptionResult& r) {
  double num = 0, den = 0;
  for (int y = 16; y < kSide - 16; ++y)
    for (int x = 16; x < kSide - 16; ++x) {
      double c = img[size_t(y) * kSide + x] - 128.0;
      num += (r.simulated[size_t(y) * kSide + x] - 128.0) * c;
      den += c * c;
    }
  return num / den;
}

float max_abs(const std::vector<float>& v) {
  float m = 0;
  for (float x : v) m = std::max(m, std::abs(x));
  return m;
}

long long count(const std::vector<uint8_t>& mask) {
  long long n = 0;
  for (uint8_t v : mask) n += v;
  return n;
}

// 2 cpd at the paper's 29.64 ppd, well under the CSF peak (6.25 cpd): the eye
// sees it all, so the difference is a small fraction of a grey level.
TEST(Gratings, PassbandGratingIsUntouchedAndTheMaskEmpty) {
  for (int dir : {0, 1}) {
    std::vector<float> img = grating(35, dir);  // 0.068 c/px = 2.03 cpd
    PerceptionResult r = simulate(img, kSide, kSide);
    EXPECT_LT(max_abs(r.difference), 0.25f) << "dir " << dir;
    EXPECT_EQ(count(r.mask), 0) << "dir " << dir;
    EXPECT_EQ(r.imperceptible_fraction, 0.0);
  }
}

// Near f_max the grating's amplitude falls by the flattened CSF at its
// frequency, within 0.02 (measured deviations are under 0.01).
TEST(Gratings, NearFmaxAmplitudeFallsByTheCsfFactor) {
  const PerceptionSettings s;
  for (int m : {205, 230, 250}) {  // 11.9, 13.3, 14.5 cpd
    for (int dir : {0, 1}) {
      std::vector<float> img = grating(m, dir);
      PerceptionResult r = simulate(img, kSide, kSide, s);
      double f_cpd = m / 512.0 * s.ppd;
      double want = perclod::csf_flat(f_cpd, s.k);
      EXPECT_LT(want, 0.8);
      EXPECT_NEAR(grating_gain(img, r), want, 0.02) << "m " << m << " dir " << dir;
      EXPECT_GT(count(r.mask), (long long)(kSide) * kSide / 2);
    }
  }
}

// Borders: a cosine on x = 0..256 with 2 f 256 an integer is whole-sample
// symmetric about both ends, so its symmetric extension is the same cosine on
// x = -256..512. If the DWT and the band FIRs extend every band with the right
// symmetry, the small image's difference equals the big image's middle third.
TEST(Gratings, BordersBehaveAsTheSymmetricExtensionOfTheImage) {
  const int small = 257, big = 769, h = 8;
  for (int m : {150, 205, 250}) {
    const double f = m / 512.0;
    auto image = [&](int w, int x0) {
      std::vector<float> img(size_t(w) * h);
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) img[size_t(y) * w + x] = float(128 + 50 * std::cos(2 * std::numbers::pi * f * (x + x0)));
      return img;
    };
    for (bool transpose : {false, true}) {
      std::vector<float> a = image(small, 0), b = image(big, -256);
      int aw = small, ah = h, bw = big, bh = h;
      if (transpose) {  // same along y: exercises the column filters
        auto t = [&](const std::vector<float>& v, int w, int hh) {
          std::vector<float> o(v.size());
          for (int y = 0; y < hh; ++y)
            for (int x = 0; x < w; ++x) o[size_t(x) * hh + y] = v[size_t(y) * w + x];
          return o;
        };
        a = t(a, small, h);
        b = t(b, big, h);
        std::swap(aw, ah);
        std::swap(bw, bh);
      }
      PerceptionResult ra = simulate(a, aw, ah), rb = simulate(b, bw, bh);
      float worst = 0;
      for (int i = 0; i < small; ++i)
        for (int j = 0; j < h; ++j) {
          size_t ia = transpose ? size_t(i) * h + j : size_t(j) * small + i;
          size_t ib = transpose ? size_t(i + 256) * h + j : size_t(j) * big + i + 256;
          worst = std::max(worst, std::abs(ra.difference[ia] - rb.difference[ib]));
        }
      EXPECT_LT(worst, 2e-3f) << "m " << m << (transpose ? " columns" : " rows");
      EXPECT_GT(max_abs(ra.difference), 2.0f);
    }
  }
}

// Diagonal gratings sit at sqrt(2) times the axis frequency.
TEST(Gratings, DiagonalGratingFollowsTheCsfAtSqrt2TimesTheAxisFrequency) {
  const PerceptionSettings s;
  for (int m : {205, 250}) {
    std::vector<float> img = grating(m, 2);
    PerceptionResult r = simulate(img, kSide, kSide, s);
    double f_cpd = std::sqrt(2.0) * m / 512.0 * s.ppd;
    EXPECT_NEAR(grating_gain(img, r), perclod::csf_flat(f_cpd, s.k), 0.02) << "m " << m;
  }
}

TEST(Gratings, WeightsModeScalesABandCentreGratingByTheBandWeight) {
  PerceptionSettings s;
  s.csf = PerceptionSettings::CsfMode::Weights;
  std::vector<float> img = grating(192, 0);  // 0.375 c/px: centre of level 1
  PerceptionResult r = simulate(img, kSide, kSide, s);
  EXPECT_NEAR(grating_gain(img, r), r.bands[0].weight, 0.02);
  EXPECT_LT(r.bands[0].weight, 0.85);
}

TEST(Simulation, ConstantImageGivesZeroDifferenceAtAnySize) {
  for (auto [w, h] : std::vector<std::pair<int, int>>{{1, 1}, {2, 3}, {7, 7}, {37, 61}, {320, 240}}) {
    std::vector<float> img(size_t(w) * h, 173.0f);
    PerceptionResult r = simulate(img, w, h);
    EXPECT_LT(max_abs(r.difference), 1e-3f) << w << "x" << h;
    EXPECT_EQ(count(r.mask), 0);
  }
}

std::vector<float> noise(int w, int h, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 255.0f);
  std::vector<float> img(size_t(w) * h);
  for (float& v : img) v = u(rng);
  return img;
}

TEST(Simulation, IsLinear) {
  const int w = 61, h = 45;
  std::vector<float> a = noise(w, h, 1), b = noise(w, h, 2), c(a.size());
  for (size_t i = 0; i < c.size(); ++i) c[i] = 0.7f * a[i] + 0.3f * b[i];
  PerceptionResult ra = simulate(a, w, h), rb = simulate(b, w, h), rc = simulate(c, w, h);
  for (size_t i = 0; i < c.size(); ++i)
    ASSERT_NEAR(rc.difference[i], 0.7f * ra.difference[i] + 0.3f * rb.difference[i], 2e-3f) << i;
  EXPECT_GT(max_abs(ra.difference), 10.0f);  // noise really is attenuated
}

TEST(Simulation, MaskIsDifferenceAboveThreshold) {
  const int w = 64, h = 48;
  std::vector<float> img = noise(w, h, 3);
  PerceptionSettings s;
  s.threshold = 7.5;
  PerceptionResult r = simulate(img, w, h, s);
  for (size_t i = 0; i < img.size(); ++i) {
    EXPECT_EQ(r.mask[i], std::abs(r.difference[i]) > 7.5f ? 1 : 0);
    EXPECT_NEAR(r.difference[i], img[i] - r.simulated[i], 1e-4f);
  }
  long long n = count(r.mask);
  EXPECT_GT(n, 0);
  EXPECT_LT(n, (long long)img.size());
  EXPECT_DOUBLE_EQ(r.imperceptible_fraction, double(n) / double(img.size()));
}

TEST(Simulation, BackgroundPixelsAreLeftOutOfTheFraction) {
  // Left half noise (mostly imperceptible detail), right half flat background.
  const int w = 128, h = 64;
  std::vector<float> img(size_t(w) * h, 200.0f);
  std::vector<float> nz = noise(w, h, 4);
  std::vector<uint8_t> background(img.size(), 0);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      if (x < w / 2) img[size_t(y) * w + x] = nz[size_t(y) * w + x];
      else background[size_t(y) * w + x] = 1;
    }
  PerceptionResult all, fg;
  perclod::perceive_luminance(img.data(), w, h, {}, nullptr, all);
  perclod::perceive_luminance(img.data(), w, h, {}, background.data(), fg);
  long long in_fg = 0;
  for (size_t i = 0; i < img.size(); ++i) in_fg += background[i] ? 0 : fg.mask[i];
  EXPECT_EQ(fg.counted_pixels, (long long)img.size() / 2);
  EXPECT_DOUBLE_EQ(fg.imperceptible_fraction, double(in_fg) / double(fg.counted_pixels));
  EXPECT_GT(fg.imperceptible_fraction, all.imperceptible_fraction);
  EXPECT_GT(fg.imperceptible_fraction, 0.5);
}

// A farther (denser in pixels per degree) view of the same picture hides more.
TEST(Simulation, ImperceptibleFractionGrowsWithPixelsPerDegree) {
  const int w = 160, h = 120;
  std::vector<float> img(size_t(w) * h);
  std::mt19937 rng(9);
  std::uniform_int_distribution<int> u(-30, 30);
  for (int y = 0; y < h; ++y)  // facade-like blocks with some texture
    for (int x = 0; x < w; ++x)
      img[size_t(y) * w + x] = float(((x / 6 + y / 9) % 2 ? 170 : 80) + u(rng));
  double prev = -1;
  for (double ppd : {10.0, 20.0, 29.64, 45.0, 70.0}) {
    PerceptionSettings s;
    s.ppd = ppd;
    PerceptionResult r = simulate(img, w, h, s);
    EXPECT_GT(r.imperceptible_fraction, prev) << "ppd " << ppd;
    prev = r.imperceptible_fraction;
  }
}

// Threshold calibration (docs/perception.md). The simulation is linear, so what
// 8-bit quantisation adds to the difference is the simulation of the
// quantisation error alone, |error| <= 0.5. Its worst case is 0.5 times the L1
// norm of the difference operator's impulse response; at the paper's display
// that is about 0.56 grey levels, under the default threshold of 1.
TEST(Threshold, QuantisationAloneStaysUnderTheDefaultThreshold) {
  const PerceptionSettings s;
  const int w = 64, h = 64;
  double worst_l1 = 0;
  for (int py = 30; py < 34; ++py)  // the decimated DWT is shift-variant: all phases of 2 levels
    for (int px = 30; px < 34; ++px) {
      std::vector<float> impulse(size_t(w) * h, 0.0f);
      impulse[size_t(py) * w + px] = 1.0f;
      PerceptionResult r = simulate(impulse, w, h, s);
      double l1 = 0;
      for (float d : r.difference) l1 += std::abs(d);
      worst_l1 = std::max(worst_l1, l1);
    }
  EXPECT_GT(worst_l1, 0.5);  // the operator does something
  EXPECT_LT(0.5 * worst_l1 + 1e-3, s.threshold);

  // And on real quantised content: smooth gradients and low gratings.
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const int n = 128;
  for (int trial = 0; trial < 20; ++trial) {
    double gx = u(rng) - 0.5, gy = u(rng) - 0.5, f = 0.002 + 0.03 * u(rng), th = 6.28 * u(rng);
    std::vector<float> smooth(size_t(n) * n), quantised(smooth.size());
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) {
        double v = 128 + gx * x + gy * y + 40 * std::cos(2 * std::numbers::pi * f * (x * std::cos(th) + y * std::sin(th)));
        smooth[size_t(y) * n + x] = float(v);
        quantised[size_t(y) * n + x] = float(std::round(v));
      }
    PerceptionResult a = simulate(smooth, n, n, s), b = simulate(quantised, n, n, s);
    float worst = 0;
    for (size_t i = 0; i < smooth.size(); ++i)
      worst = std::max(worst, std::abs(b.difference[i] - a.difference[i]));
    EXPECT_LT(worst, 0.5 * worst_l1 + 1e-3) << "trial " << trial;
  }
}

TEST(Luminance, LumaAndLinearY) {
  const uint8_t rgb[] = {255, 0, 0, 128, 128, 128, 255, 255, 255, 0, 0, 0};
  std::vector<float> luma = perclod::luminance(rgb, 4, 1, PerceptionSettings::Luminance::Luma);
  EXPECT_NEAR(luma[0], 76.245f, 1e-3f);
  EXPECT_NEAR(luma[1], 128.0f, 1e-3f);
  EXPECT_NEAR(luma[2], 255.0f, 1e-3f);
  EXPECT_NEAR(luma[3], 0.0f, 1e-6f);
  std::vector<float> lin = perclod::luminance(rgb, 4, 1, PerceptionSettings::Luminance::LinearY);
  EXPECT_NEAR(lin[0], 0.2126f * 255.0f, 1e-3f);
  EXPECT_NEAR(lin[1], 255.0f * 0.21586f, 0.01f);  // sRGB 128 -> 0.2159 linear
  EXPECT_NEAR(lin[2], 255.0f, 1e-3f);
}

TEST(Perceive, RgbEntryPointMatchesTheLuminancePath) {
  const int w = 33, h = 21;
  std::vector<uint8_t> rgb(size_t(w) * h * 3);
  std::mt19937 rng(6);
  for (uint8_t& v : rgb) v = uint8_t(rng() % 256);
  PerceptionSettings s;
  PerceptionResult a = perclod::perceive(rgb.data(), w, h, s);
  std::vector<float> lum = perclod::luminance(rgb.data(), w, h, s.luminance);
  PerceptionResult b = simulate(lum, w, h, s);
  ASSERT_EQ(a.difference.size(), b.difference.size());
  for (size_t i = 0; i < lum.size(); ++i) EXPECT_FLOAT_EQ(a.difference[i], b.difference[i]);
  EXPECT_EQ(a.levels, 2);
  EXPECT_NEAR(a.f_max, 14.82, 1e-9);
  EXPECT_EQ(a.bands.size(), 6u);
  EXPECT_GE(a.seconds, 0.0);
}

TEST(Perceive, SettingsForTheDisplayUseItsPixelsPerDegree) {
  perclod::DisplayProfile d;
  PerceptionSettings s = perclod::perception_settings_for(d);
  EXPECT_NEAR(s.ppd, 29.64, 0.01);
}

TEST(Views, DifferenceIsBlackWherePerceptibleAndGreyWhereNot) {
  const int w = 64, h = 48;
  std::vector<float> img = noise(w, h, 8);
  PerceptionResult r = simulate(img, w, h);
  std::vector<uint8_t> dv = perclod::difference_view(r), mv = perclod::mask_view(r),
                       sv = perclod::simulated_view(r);
  for (size_t i = 0; i < img.size(); ++i) {
    if (r.mask[i]) {
      EXPECT_GE(dv[i], 64);
      EXPECT_EQ(mv[i], 255);
    } else {
      EXPECT_EQ(dv[i], 0);
      EXPECT_EQ(mv[i], 0);
    }
    EXPECT_LE(std::abs(float(sv[i]) - std::clamp(r.simulated[i], 0.0f, 255.0f)), 0.5f);
  }
}

TEST(Perceive, BadInputThrowsWithAMessage) {
  std::vector<float> img(16, 1.0f);
  PerceptionResult r;
  PerceptionSettings s;
  s.ppd = 0;
  EXPECT_THROW(perclod::perceive_luminance(img.data(), 4, 4, s, nullptr, r), std::invalid_argument);
  s = {};
  s.threshold = -1;
  EXPECT_THROW(perclod::perceive_luminance(img.data(), 4, 4, s, nullptr, r), std::invalid_argument);
  s = {};
  s.levels = -2;
  EXPECT_THROW(perclod::perceive_luminance(img.data(), 4, 4, s, nullptr, r), std::invalid_argument);
  s = {};
  EXPECT_THROW(perclod::perceive_luminance(img.data(), 0, 4, s, nullptr, r), std::invalid_argument);
  try {
    s.k = -0.1;
    perclod::perceive_luminance(img.data(), 4, 4, s, nullptr, r);
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("k"), std::string::npos);
  }
}

}  // namespace

namespace {

// Random blocks of detail: the simulated image of the picture moved one
// pixel right, moved back, against the simulated picture. A decimated DWT
// changes with odd shifts; four spins average the finest level's phases.
double shift_change(int spins) {
  const int w = 96, h = 80;
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(0, 255);
  std::vector<float> img(size_t(w + 1) * h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x <= w; ++x) img[size_t(y) * (w + 1) + x] = (x / 3 + y / 2) % 2 ? u(rng) : 100.0f;
  std::vector<float> a(size_t(w) * h), b(size_t(w) * h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      a[size_t(y) * w + x] = img[size_t(y) * (w + 1) + x + 1];
      b[size_t(y) * w + x] = img[size_t(y) * (w + 1) + x];
    }
  PerceptionSettings s;
  s.spins = spins;
  PerceptionResult ra, rb;
  perclod::perceive_luminance(a.data(), w, h, s, nullptr, ra);
  perclod::perceive_luminance(b.data(), w, h, s, nullptr, rb);
  double sum = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 8; x < w - 8; ++x) sum += std::abs(ra.simulated[size_t(y) * w + x] - rb.simulated[size_t(y) * w + x + 1]);
  return sum / double(h * (w - 16));
}

}  // namespace

TEST(Simulation, CycleSpinningMakesTheSimulationNearlyShiftInvariant) {
  const double one = shift_change(1), two = shift_change(2), four = shift_change(4);
  EXPECT_GT(one, 0.5);  // grey levels: one decimated DWT moves with the image's phase
  EXPECT_LT(two, one);
  EXPECT_LT(four, 0.25 * one);
  // A constant image stays constant, and bad spin counts are refused.
  std::vector<float> c(50 * 30, 77.0f);
  PerceptionSettings s;
  s.spins = 4;
  PerceptionResult r;
  perclod::perceive_luminance(c.data(), 50, 30, s, nullptr, r);
  for (float v : r.simulated) ASSERT_NEAR(v, 77.0f, 1e-3f);
  s.spins = 3;
  EXPECT_THROW(perclod::perceive_luminance(c.data(), 50, 30, s, nullptr, r), std::invalid_argument);
}
