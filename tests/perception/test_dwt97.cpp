// CDF 9/7 lifting: perfect reconstruction at any size, the published analysis
// filters, linearity.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "perclod/perception.h"

namespace {

std::vector<float> random_image(int w, int h, unsigned seed, float top = 255.0f) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, top);
  std::vector<float> img(size_t(w) * h);
  for (float& v : img) v = u(rng);
  return img;
}

float max_abs_diff(const std::vector<float>& a, const std::vector<float>& b) {
  float m = 0;
  for (size_t i = 0; i < a.size(); ++i) m = std::max(m, std::abs(a[i] - b[i]));
  return m;
}

struct Size {
  int w, h;
};

class Reconstruction : public ::testing::TestWithParam<Size> {};

// The criterion: max error < 1e-4 on random images, here in [0, 1] with
// float lifting (the error is relative: a few float ulps of the values).
TEST_P(Reconstruction, FloatRoundTripOnUnitRangeIsBelow1e4) {
  const Size s = GetParam();
  const std::vector<float> orig = random_image(s.w, s.h, 17u + s.w * 31u + s.h, 1.0f);
  for (int levels : {1, 2, 3, 6}) {
    std::vector<float> img = orig;
    perclod::dwt97_forward(img.data(), s.w, s.h, levels);
    if (s.w * s.h > 1) {
      EXPECT_GT(max_abs_diff(img, orig), 0.01f) << "transform did nothing";
    }
    perclod::dwt97_inverse(img.data(), s.w, s.h, levels);
    EXPECT_LT(max_abs_diff(img, orig), 1e-4f) << s.w << "x" << s.h << " levels " << levels;
  }
}

// On 0..255 grey levels in float the same relative error is < 1e-3 levels,
// three orders of magnitude under the 1-level mask threshold.
TEST_P(Reconstruction, FloatRoundTripOnGreyLevelsIsBelow1e3) {
  const Size s = GetParam();
  const std::vector<float> orig = random_image(s.w, s.h, 3u + s.h);
  std::vector<float> img = orig;
  perclod::dwt97_forward(img.data(), s.w, s.h, 6);
  perclod::dwt97_inverse(img.data(), s.w, s.h, 6);
  EXPECT_LT(max_abs_diff(img, orig), 1e-3f);
}

// In double the round trip on 0..255 is exact to 1e-9.
TEST_P(Reconstruction, ForwardThenInverseIsIdentityInDouble) {
  const Size s = GetParam();
  const std::vector<float> f = random_image(s.w, s.h, 5u + s.w);
  std::vector<double> orig(f.begin(), f.end()), img = orig;
  perclod::dwt97_forward(img.data(), s.w, s.h, 4);
  perclod::dwt97_inverse(img.data(), s.w, s.h, 4);
  double m = 0;
  for (size_t i = 0; i < img.size(); ++i) m = std::max(m, std::abs(img[i] - orig[i]));
  EXPECT_LT(m, 1e-9);
}

INSTANTIATE_TEST_SUITE_P(Sizes, Reconstruction,
                         ::testing::Values(Size{1, 1}, Size{2, 3}, Size{7, 7}, Size{37, 61}, Size{1, 13},
                                           Size{13, 1}, Size{2, 2}, Size{1280, 1024}),
                         [](const ::testing::TestParamInfo<Size>& i) {
                           return std::to_string(i.param.w) + "x" + std::to_string(i.param.h);
                         });

// Analysis impulse responses read off the lifting implementation: push a unit
// impulse through the 1-D transform and see what one interior coefficient gets.
constexpr int kN = 64;

std::vector<double> forward_of_impulse(int p) {
  std::vector<double> x(kN, 0.0);
  x[p] = 1.0;
  perclod::dwt97_forward_1d(x.data(), kN);
  return x;
}

TEST(Dwt97Filters, LowPassAnalysisEqualsPublishedTaps) {
  // s[16] is centred on x[32]: its tap for offset k is the response to x[32 + k].
  const double published[5] = {0.602949, 0.266864, -0.078223, -0.016864, 0.026749};  // centre, +-1..4
  for (int k = -6; k <= 6; ++k) {
    double tap = forward_of_impulse(32 + k)[16];
    double want = std::abs(k) <= 4 ? published[std::abs(k)] : 0.0;
    EXPECT_NEAR(tap, want, 1e-6) << "offset " << k;
  }
}

TEST(Dwt97Filters, HighPassAnalysisEqualsPublishedTaps) {
  // d[16] sits at index kN/2 + 16 of the output and is centred on x[33].
  const double published[4] = {1.115087, -0.591272, -0.057544, 0.091272};  // centre, +-1..3
  for (int k = -6; k <= 6; ++k) {
    double tap = forward_of_impulse(33 + k)[kN / 2 + 16];
    double want = std::abs(k) <= 3 ? published[std::abs(k)] : 0.0;
    EXPECT_NEAR(tap, want, 1e-6) << "offset " << k;
  }
}

TEST(Dwt97Filters, LowPassHasUnitDcGainAndHighPassKillsConstants) {
  std::vector<double> x(kN, 7.5);
  perclod::dwt97_forward_1d(x.data(), kN);
  for (int i = 0; i < kN / 2; ++i) EXPECT_NEAR(x[i], 7.5, 1e-12);
  for (int i = kN / 2; i < kN; ++i) EXPECT_NEAR(x[i], 0.0, 1e-12);
}

TEST(Dwt97Filters, OddLengthSplitsCeilLowFloorHigh) {
  // Length 5 constant: 3 low coefficients equal the constant, 2 high are zero.
  std::vector<double> x(5, 3.0);
  perclod::dwt97_forward_1d(x.data(), 5);
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(x[i], 3.0, 1e-12);
  for (int i = 3; i < 5; ++i) EXPECT_NEAR(x[i], 0.0, 1e-12);
}

TEST(Dwt97, TransformIsLinear) {
  const int w = 37, h = 29;
  std::vector<float> a = random_image(w, h, 1), b = random_image(w, h, 2), c(a.size());
  for (size_t i = 0; i < c.size(); ++i) c[i] = 2.0f * a[i] - 0.5f * b[i];
  perclod::dwt97_forward(a.data(), w, h, 3);
  perclod::dwt97_forward(b.data(), w, h, 3);
  perclod::dwt97_forward(c.data(), w, h, 3);
  for (size_t i = 0; i < c.size(); ++i) EXPECT_NEAR(c[i], 2.0f * a[i] - 0.5f * b[i], 2e-3f);
}

TEST(Dwt97, RejectsBadSizes) {
  std::vector<float> img(4);
  EXPECT_THROW(perclod::dwt97_forward(img.data(), 0, 4, 1), std::invalid_argument);
  EXPECT_THROW(perclod::dwt97_inverse(img.data(), 2, 2, -1), std::invalid_argument);
}

}  // namespace
