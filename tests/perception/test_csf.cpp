// Contrast sensitivity, the level rule, and the per-band FIR design.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "perclod/perception.h"

namespace {

using perclod::BandOrientation;
using perclod::PerceptionSettings;

TEST(Csf, MatchesTheFormulaAtHandComputedPoints) {
  // 2.6 (0.0192 + 0.912) exp(-0.912^1.1) = 0.9807 (Mannos-Sakrison near its 8 cpd peak)
  EXPECT_NEAR(perclod::csf(8.0, 0.114), 0.9807, 1e-3);
  // k = 0.144, f = 14.82: x = 2.134, 2.6 * 2.153 * exp(-2.302) = 0.5604
  EXPECT_NEAR(perclod::csf(14.82, 0.144), 0.5604, 2e-3);
}

TEST(Csf, PeakIsAMaximumAndScalesWithOneOverK) {
  for (double k : {0.114, 0.144}) {
    double p = perclod::csf_peak_frequency(k);
    EXPECT_GT(perclod::csf(p, k), perclod::csf(p * 0.98, k));
    EXPECT_GT(perclod::csf(p, k), perclod::csf(p * 1.02, k));
  }
  EXPECT_NEAR(perclod::csf_peak_frequency(0.114) / perclod::csf_peak_frequency(0.144), 0.144 / 0.114, 1e-9);
  // 1.1 x^0.1 (0.0192 + x) = 1 at x* = 0.8997 (by hand): 6.25 cpd for k = 0.144
  EXPECT_NEAR(perclod::csf_peak_frequency(0.144), 0.8997 / 0.144, 0.01);
}

TEST(Csf, FlattenedIsOneBelowThePeakAndFallsAbove) {
  const double k = 0.144, p = perclod::csf_peak_frequency(k);
  EXPECT_DOUBLE_EQ(perclod::csf_flat(0.0, k), 1.0);
  EXPECT_DOUBLE_EQ(perclod::csf_flat(0.5 * p, k), 1.0);
  EXPECT_NEAR(perclod::csf_flat(p, k), 1.0, 1e-12);
  double prev = 1.0;
  for (double f = p + 0.5; f < 40; f += 0.5) {
    double v = perclod::csf_flat(f, k);
    EXPECT_LT(v, prev);
    EXPECT_NEAR(v, perclod::csf(f, k) / perclod::csf(p, k), 1e-12);
    prev = v;
  }
}

TEST(Csf, RejectsNonPositiveK) {
  EXPECT_THROW(perclod::csf_peak_frequency(0.0), std::invalid_argument);
  EXPECT_THROW(perclod::csf_peak_frequency(-1.0), std::invalid_argument);
}

// The LL band (0 .. f_max / 2^L) lies at or below the peak, and with one level
// fewer it would not.
TEST(Levels, DefaultLeavesTheLowPassBandBelowThePeak) {
  for (double ppd : {10.0, 29.64, 45.0, 60.0, 120.0}) {
    const double k = 0.144, f_max = 0.5 * ppd, peak = perclod::csf_peak_frequency(k);
    int L = perclod::default_levels(f_max, k);
    EXPECT_GE(L, 1);
    EXPECT_LE(f_max / std::ldexp(1.0, L), peak) << "ppd " << ppd;
    if (L > 1) {
      EXPECT_GT(f_max / std::ldexp(1.0, L - 1), peak) << "ppd " << ppd;
    }
  }
  EXPECT_EQ(perclod::default_levels(14.82, 0.144), 2);  // the paper's display
}

TEST(Bands, HighPassBandsAreSpectrallyInverted) {
  const double f_max = 14.82;
  EXPECT_DOUBLE_EQ(perclod::band_frequency(0.0, 1, f_max), f_max);
  EXPECT_DOUBLE_EQ(perclod::band_frequency(0.5, 1, f_max), f_max / 2);
  EXPECT_DOUBLE_EQ(perclod::band_frequency(0.0, 2, f_max), f_max / 2);
  EXPECT_DOUBLE_EQ(perclod::band_frequency(0.5, 2, f_max), f_max / 4);
}

// Measured response of a tap set: filter a long cosine of band-local
// frequency nu with the symmetric taps and read its amplitude in the middle.
double measured_response(const std::vector<double>& taps, double nu) {
  const int n = 256, M = int(taps.size()) - 1;
  std::vector<double> x(n), y(n, 0.0);
  for (int i = 0; i < n; ++i) x[i] = std::cos(2 * std::numbers::pi * nu * i);
  for (int i = M; i < n - M; ++i) {
    y[i] = taps[0] * x[i];
    for (int m = 1; m <= M; ++m) y[i] += taps[m] * (x[i - m] + x[i + m]);
  }
  // Least-squares amplitude of cos at the interior samples (phase is zero).
  double num = 0, den = 0;
  for (int i = 2 * M; i < n - 2 * M; ++i) {
    num += y[i] * x[i];
    den += x[i] * x[i];
  }
  return num / den;
}

// Every FIR follows its target at the band's sample frequencies nu = j/16
// (7 taps per axis): within 0.02 inside the band, within 0.05 at its two edges
// (a zero-phase response has zero slope at nu = 0 and 0.5, the target does
// not; there the neighbouring band carries the signal too). On the diagonal
// the separable product follows the CSF at sqrt(2) times the axis frequency.
TEST(Fir, MeasuredResponseFollowsTheCsfAcrossEachBand) {
  for (double ppd : {29.64, 60.0}) {
    PerceptionSettings s;
    s.ppd = ppd;
    const double f_max = 0.5 * ppd;
    int levels = perclod::default_levels(f_max, s.k);
    std::vector<perclod::BandResponse> bands = perclod::band_responses(s, levels);
    ASSERT_EQ(bands.size(), size_t(3 * levels));
    for (const perclod::BandResponse& b : bands) {
      ASSERT_EQ(b.taps.size(), size_t(s.fir_half_length + 1));
      for (int j = 0; j <= 8; ++j) {
        double nu = j / 16.0;
        double f = perclod::band_frequency(nu, b.level, f_max);
        double got = measured_response(b.taps, nu);
        const double tol = (j == 0 || j == 8) ? 0.05 : 0.02;
        if (b.orientation == BandOrientation::HH) {
          EXPECT_NEAR(got * got, perclod::csf_flat(std::sqrt(2.0) * f, s.k), tol)
              << "ppd " << ppd << " level " << b.level << " HH nu " << nu;
        } else {
          EXPECT_NEAR(got, perclod::csf_flat(f, s.k), tol)
              << "ppd " << ppd << " level " << b.level << " nu " << nu;
        }
        EXPECT_NEAR(got, perclod::fir_response(b.taps, nu), 1e-9);
      }
    }
  }
}

TEST(Fir, DesignReproducesACosineSeriesExactly) {
  // A target that is itself a 3-term cosine series is fitted exactly.
  auto target = [](double nu) { return 0.5 + 2 * 0.2 * std::cos(2 * std::numbers::pi * nu) - 2 * 0.05 * std::cos(4 * std::numbers::pi * nu); };
  std::vector<double> taps = perclod::design_fir(target, 3);
  EXPECT_NEAR(taps[0], 0.5, 1e-9);
  EXPECT_NEAR(taps[1], 0.2, 1e-9);
  EXPECT_NEAR(taps[2], -0.05, 1e-9);
  EXPECT_NEAR(taps[3], 0.0, 1e-9);
}

TEST(Bands, WeightsModeUsesTheCsfAtTheBandCentre) {
  PerceptionSettings s;
  s.csf = PerceptionSettings::CsfMode::Weights;
  std::vector<perclod::BandResponse> bands = perclod::band_responses(s, 2);
  const double f_max = 0.5 * s.ppd;
  for (const perclod::BandResponse& b : bands) {
    double centre = 0.75 * f_max / std::ldexp(1.0, b.level - 1);
    if (b.orientation == BandOrientation::HH) centre *= std::sqrt(2.0);
    EXPECT_NEAR(b.weight, perclod::csf_flat(centre, s.k), 1e-12);
    EXPECT_TRUE(b.taps.empty());
  }
  EXPECT_LT(bands[2].weight, bands[0].weight);  // the diagonal sits higher, so lower
}

TEST(Bands, KakaduModeUsesNadenausTable) {
  PerceptionSettings s;
  s.csf = PerceptionSettings::CsfMode::Kakadu;
  std::vector<perclod::BandResponse> b = perclod::band_responses(s, 3);
  EXPECT_DOUBLE_EQ(b[0].weight, 0.2758);
  EXPECT_DOUBLE_EQ(b[1].weight, 0.2758);
  EXPECT_DOUBLE_EQ(b[2].weight, 0.0901);
  EXPECT_DOUBLE_EQ(b[3].weight, 0.8378);
  EXPECT_DOUBLE_EQ(b[5].weight, 0.7018);
  EXPECT_DOUBLE_EQ(b[8].weight, 1.0);
}

}  // namespace
