// Contrast sensitivity and the CSF response of each wavelet band.
//
// Frequencies: the display carries up to f_max = ppd / 2 cycles/degree. DWT
// level l (1 = finest) holds f_max / 2^l .. f_max / 2^(l-1) along its high-pass
// axis. A decimated high-pass band is spectrally inverted: band-local frequency
// nu (cycles per band sample, 0..0.5) maps to (1 - nu) f_max / 2^(l-1).
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "perclod/perception.h"

namespace perclod {
namespace {

constexpr double kPi = 3.14159265358979323846;

void check_k(double k) {
  if (!(k > 0) || !std::isfinite(k))
    throw std::invalid_argument("CSF constant k must be a positive number, got " + std::to_string(k));
}

// Solves the small symmetric system a x = b (n x n, row major) in place.
std::vector<double> solve(std::vector<double> a, std::vector<double> b) {
  const int n = int(b.size());
  for (int c = 0; c < n; ++c) {
    int p = c;
    for (int r = c + 1; r < n; ++r)
      if (std::abs(a[r * n + c]) > std::abs(a[p * n + c])) p = r;
    if (std::abs(a[p * n + c]) < 1e-300) throw std::runtime_error("design_fir: singular system");
    for (int j = 0; j < n; ++j) std::swap(a[c * n + j], a[p * n + j]);
    std::swap(b[c], b[p]);
    for (int r = c + 1; r < n; ++r) {
      double f = a[r * n + c] / a[c * n + c];
      for (int j = c; j < n; ++j) a[r * n + j] -= f * a[c * n + j];
      b[r] -= f * b[c];
    }
  }
  std::vector<double> x(n);
  for (int r = n - 1; r >= 0; --r) {
    double v = b[r];
    for (int j = r + 1; j < n; ++j) v -= a[r * n + j] * x[j];
    x[r] = v / a[r * n + r];
  }
  return x;
}

// Nadenau's weights as Kakadu ships them (luminance, 15 cm at 300 dpi = 30.9 ppd).
double kakadu_weight(int level, BandOrientation o) {
  if (level == 1) return o == BandOrientation::HH ? 0.0901 : 0.2758;
  if (level == 2) return o == BandOrientation::HH ? 0.7018 : 0.8378;
  return 1.0;
}

double diagonal_factor(BandOrientation o) { return o == BandOrientation::HH ? std::sqrt(2.0) : 1.0; }

}  // namespace

double csf(double f, double k) {
  double x = k * f;
  return 2.6 * (0.0192 + x) * std::exp(-std::pow(x, 1.1));
}

// dA/dx = 0  <=>  1 = 1.1 x^0.1 (0.0192 + x) with x = k f: the peak's x* does not
// depend on k, so it is found once (bisection) and f_peak = x* / k.
static double csf_peak_x() {
  static const double x_star = [] {
    double lo = 1e-6, hi = 10.0;
    for (int i = 0; i < 200; ++i) {
      double x = 0.5 * (lo + hi);
      if (1.1 * std::pow(x, 0.1) * (0.0192 + x) < 1.0) lo = x; else hi = x;
    }
    return 0.5 * (lo + hi);
  }();
  return x_star;
}

double csf_peak_frequency(double k) {
  check_k(k);
  return csf_peak_x() / k;
}

double csf_flat(double f, double k) {
  double x = k * f, x_star = csf_peak_x();
  if (x <= x_star) return 1.0;
  return csf(f, k) / csf(x_star / k, k);
}

int default_levels(double f_max, double k) {
  if (!(f_max > 0)) throw std::invalid_argument("f_max must be positive");
  double ratio = f_max / csf_peak_frequency(k);
  if (ratio <= 2.0) return 1;
  return int(std::ceil(std::log2(ratio) - 1e-12));
}

double band_frequency(double nu, int level, double f_max) {
  return (1.0 - nu) * f_max / std::ldexp(1.0, level - 1);
}

double band_axis_target(double nu, int level, BandOrientation o, double f_max, double k) {
  double f = band_frequency(nu, level, f_max);
  if (o == BandOrientation::HH) return std::sqrt(csf_flat(std::sqrt(2.0) * f, k));
  return csf_flat(f, k);
}

double fir_response(const std::vector<double>& taps, double nu) {
  double r = taps.empty() ? 0.0 : taps[0];
  for (size_t m = 1; m < taps.size(); ++m) r += 2.0 * taps[m] * std::cos(2.0 * kPi * double(m) * nu);
  return r;
}

// Least squares over a dense grid of nu in [0, 0.5]: basis 1, 2 cos(2 pi m nu).
std::vector<double> design_fir(const std::function<double(double)>& target, int half_length) {
  if (half_length < 0 || half_length > 16)
    throw std::invalid_argument("FIR half length must be 0..16, got " + std::to_string(half_length));
  const int n = half_length + 1, grid = 257;
  std::vector<double> a(size_t(n) * n, 0.0), b(n, 0.0), phi(n);
  for (int g = 0; g < grid; ++g) {
    double nu = 0.5 * g / (grid - 1);
    phi[0] = 1.0;
    for (int m = 1; m < n; ++m) phi[m] = 2.0 * std::cos(2.0 * kPi * m * nu);
    double t = target(nu);
    for (int r = 0; r < n; ++r) {
      b[r] += phi[r] * t;
      for (int c = 0; c < n; ++c) a[r * n + c] += phi[r] * phi[c];
    }
  }
  return solve(a, b);
}

std::vector<BandResponse> band_responses(const PerceptionSettings& s, int levels) {
  check_k(s.k);
  if (!(s.ppd > 0)) throw std::invalid_argument("ppd must be positive");
  const double f_max = 0.5 * s.ppd;
  std::vector<BandResponse> out;
  for (int l = 1; l <= levels; ++l) {
    for (BandOrientation o : {BandOrientation::HL, BandOrientation::LH, BandOrientation::HH}) {
      BandResponse b;
      b.level = l;
      b.orientation = o;
      double g = diagonal_factor(o);
      b.f_low = g * band_frequency(0.5, l, f_max);
      b.f_high = g * band_frequency(0.0, l, f_max);
      b.target_low = csf_flat(b.f_low, s.k);
      b.target_high = csf_flat(b.f_high, s.k);
      switch (s.csf) {
        case PerceptionSettings::CsfMode::Fir: {
          b.taps = design_fir([&](double nu) { return band_axis_target(nu, l, o, f_max, s.k); },
                              s.fir_half_length);
          double p = o == BandOrientation::HH ? 2.0 : 1.0;  // separable product on the diagonal
          b.response_low = std::pow(fir_response(b.taps, 0.5), p);
          b.response_high = std::pow(fir_response(b.taps, 0.0), p);
          b.weight = std::pow(fir_response(b.taps, 0.25), p);
          break;
        }
        case PerceptionSettings::CsfMode::Weights:
          b.weight = csf_flat(g * band_frequency(0.5, l, f_max) * 1.5, s.k);  // band centre
          b.response_low = b.response_high = b.weight;
          break;
        case PerceptionSettings::CsfMode::Kakadu:
          b.weight = kakadu_weight(l, o);
          b.response_low = b.response_high = b.weight;
          break;
      }
      out.push_back(std::move(b));
    }
  }
  return out;
}

}  // namespace perclod
