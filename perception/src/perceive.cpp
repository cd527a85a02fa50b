// The vision simulation: luminance -> DWT -> CSF per band -> inverse DWT ->
// difference and mask (docs/method.md section 3).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>

#include "band_filter.h"
#include "perclod/perception.h"
#include "simd.h"

namespace perclod {
namespace {

void check_settings(const PerceptionSettings& s) {
  if (!(s.ppd > 0) || !std::isfinite(s.ppd))
    throw std::invalid_argument("perception: ppd must be a positive number, got " + std::to_string(s.ppd));
  if (!(s.k > 0) || !std::isfinite(s.k))
    throw std::invalid_argument("perception: CSF constant k must be positive, got " + std::to_string(s.k));
  if (s.levels < 0 || s.levels > 30)
    throw std::invalid_argument("perception: levels must be 0 (automatic) .. 30, got " + std::to_string(s.levels));
  if (!(s.threshold >= 0) || !std::isfinite(s.threshold))
    throw std::invalid_argument("perception: threshold must be >= 0 grey levels, got " +
                                std::to_string(s.threshold));
  if (s.spins != 1 && s.spins != 2 && s.spins != 4)
    throw std::invalid_argument("perception: spins must be 1, 2 or 4, got " + std::to_string(s.spins));
  if (s.fir_half_length < 0 || s.fir_half_length > 16)
    throw std::invalid_argument("perception: FIR half length must be 0..16, got " +
                                std::to_string(s.fir_half_length));
}

bool is_identity(const BandResponse& b, PerceptionSettings::CsfMode mode) {
  if (mode != PerceptionSettings::CsfMode::Fir) return b.weight == 1.0;
  if (std::abs(b.taps[0] - 1.0) > 1e-9) return false;
  for (size_t m = 1; m < b.taps.size(); ++m)
    if (std::abs(b.taps[m]) > 1e-9) return false;
  return true;
}

// Where the three detail bands of one level sit in the Mallat layout.
struct LevelGeometry {
  int w = 0, h = 0;  // size of the region this level transformed
  int ws() const { return (w + 1) / 2; }
  int hs() const { return (h + 1) / 2; }
};

detail::Band band_at(float* img, int stride, const LevelGeometry& g, BandOrientation o) {
  detail::Band b;
  b.stride = size_t(stride);
  b.parent_w = g.w;
  b.parent_h = g.h;
  int x0 = o == BandOrientation::LH ? 0 : g.ws();
  int y0 = o == BandOrientation::HL ? 0 : g.hs();
  b.w = o == BandOrientation::LH ? g.ws() : g.w - g.ws();
  b.h = o == BandOrientation::HL ? g.hs() : g.h - g.hs();
  b.data = img + size_t(y0) * size_t(stride) + size_t(x0);
  return b;
}

void apply_band(float* img, int stride, const LevelGeometry& g, const BandResponse& r,
                PerceptionSettings::CsfMode mode) {
  detail::Band b = band_at(img, stride, g, r.orientation);
  if (b.w < 1 || b.h < 1 || is_identity(r, mode)) return;
  if (mode != PerceptionSettings::CsfMode::Fir) {
    detail::scale_band(b, float(r.weight));
    return;
  }
  if (r.orientation != BandOrientation::LH) detail::fir_rows(b, r.taps);
  if (r.orientation != BandOrientation::HL) detail::fir_columns(b, r.taps);
}

void apply_csf(float* img, int w, int h, int levels, const std::vector<BandResponse>& bands,
               PerceptionSettings::CsfMode mode) {
  LevelGeometry g{w, h};
  for (int l = 1; l <= levels && (g.w > 1 || g.h > 1); ++l) {
    for (const BandResponse& r : bands)
      if (r.level == l) apply_band(img, w, g, r, mode);
    g = LevelGeometry{g.ws(), g.hs()};
  }
}

// Designing the FIRs costs about as much as filtering a small image: keep the
// last design per thread and reuse it while the settings that shape it agree.
const std::vector<BandResponse>& cached_band_responses(const PerceptionSettings& s, int levels) {
  struct Key {
    PerceptionSettings::CsfMode csf;
    double k, ppd;
    int levels, half_length;
    bool operator==(const Key&) const = default;
  };
  thread_local Key last{};
  thread_local std::vector<BandResponse> bands;
  Key key{s.csf, s.k, s.ppd, levels, s.fir_half_length};
  if (bands.empty() || !(key == last)) {
    bands = band_responses(s, levels);
    last = key;
  }
  return bands;
}

// diff = lum - sim, mask = |diff| > t; returns the masked count among
// non-background pixels and stores how many those are.
PERCLOD_SIMD_CLONES long long difference_and_mask(const float* lum, const float* sim, size_t n, float t,
                                                  const uint8_t* background, float* diff, uint8_t* mask,
                                                  long long* counted) {
  long long imperceptible = 0;
  for (size_t i = 0; i < n; ++i) {
    diff[i] = lum[i] - sim[i];
    mask[i] = std::abs(diff[i]) > t ? 1 : 0;
  }
  if (!background) {
    for (size_t i = 0; i < n; ++i) imperceptible += mask[i];
    *counted = (long long)n;
    return imperceptible;
  }
  long long c = 0;
  for (size_t i = 0; i < n; ++i) {
    c += background[i] ? 0 : 1;
    imperceptible += background[i] ? 0 : mask[i];
  }
  *counted = c;
  return imperceptible;
}

}  // namespace

PerceptionSettings perception_settings_for(const DisplayProfile& display) {
  PerceptionSettings s;
  s.ppd = display.pixels_per_degree();
  return s;
}

void perceive_luminance(const float* lum, int w, int h, const PerceptionSettings& s,
                        const uint8_t* background_mask, PerceptionResult& out) {
  auto t0 = std::chrono::steady_clock::now();
  check_settings(s);
  if (w < 1 || h < 1)
    throw std::invalid_argument("perception: image size must be at least 1x1, got " + std::to_string(w) +
                                "x" + std::to_string(h));
  if (!lum) throw std::invalid_argument("perception: null luminance buffer");
  const size_t n = size_t(w) * size_t(h);
  out.width = w;
  out.height = h;
  out.ppd = s.ppd;
  out.f_max = 0.5 * s.ppd;
  out.levels = s.levels > 0 ? s.levels : default_levels(out.f_max, s.k);
  out.bands = cached_band_responses(s, out.levels);
  if (out.luminance.data() != lum) out.luminance.assign(lum, lum + n);

  if (s.spins == 1) {
    out.simulated.assign(lum, lum + n);
    dwt97_forward(out.simulated.data(), w, h, out.levels);
    apply_csf(out.simulated.data(), w, h, out.levels, out.bands, s.csf);
    dwt97_inverse(out.simulated.data(), w, h, out.levels);
  } else {
    // Cycle spinning: the image shifted by (dx, dy) pixels (first row/column
    // repeated), filtered, shifted back; the simulated images averaged.
    out.simulated.assign(n, 0.0f);
    std::vector<float> buf;
    const int shifts[4][2] = {{0, 0}, {1, 1}, {1, 0}, {0, 1}};
    for (int k = 0; k < s.spins; ++k) {
      const int dx = shifts[k][0], dy = shifts[k][1], W = w + dx, H = h + dy;
      buf.resize(size_t(W) * size_t(H));
      for (int y = 0; y < H; ++y) {
        const float* src = lum + size_t(std::max(y - dy, 0)) * size_t(w);
        float* dst = buf.data() + size_t(y) * size_t(W);
        if (dx) dst[0] = src[0];
        std::copy(src, src + w, dst + dx);
      }
      dwt97_forward(buf.data(), W, H, out.levels);
      apply_csf(buf.data(), W, H, out.levels, out.bands, s.csf);
      dwt97_inverse(buf.data(), W, H, out.levels);
      for (int y = 0; y < h; ++y) {
        const float* src = buf.data() + size_t(y + dy) * size_t(W) + dx;
        float* dst = out.simulated.data() + size_t(y) * size_t(w);
        for (int x = 0; x < w; ++x) dst[x] += src[x];
      }
    }
    const float inv = 1.0f / float(s.spins);
    for (float& v : out.simulated) v *= inv;
  }

  out.difference.resize(n);
  out.mask.resize(n);
  const float t = float(s.threshold);
  const float* sim = out.simulated.data();
  float* diff = out.difference.data();
  uint8_t* mask = out.mask.data();
  long long counted = 0;
  long long imperceptible = difference_and_mask(lum, sim, n, t, background_mask, diff, mask, &counted);
  out.counted_pixels = counted;
  out.imperceptible_fraction = counted ? double(imperceptible) / double(counted) : 0.0;
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

void perceive_into(const uint8_t* rgb, int w, int h, const PerceptionSettings& s,
                   const uint8_t* background_mask, PerceptionResult& out) {
  auto t0 = std::chrono::steady_clock::now();
  if (w < 1 || h < 1)
    throw std::invalid_argument("perception: image size must be at least 1x1, got " + std::to_string(w) +
                                "x" + std::to_string(h));
  out.luminance.resize(size_t(w) * size_t(h));
  luminance_into(rgb, w, h, s.luminance, out.luminance.data());
  perceive_luminance(out.luminance.data(), w, h, s, background_mask, out);
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

PerceptionResult perceive(const uint8_t* rgb, int w, int h, const PerceptionSettings& s,
                          const uint8_t* background_mask) {
  PerceptionResult r;
  perceive_into(rgb, w, h, s, background_mask, r);
  return r;
}

std::vector<uint8_t> difference_view(const PerceptionResult& r) {
  std::vector<uint8_t> v(r.difference.size());
  for (size_t i = 0; i < v.size(); ++i) {
    float g = 64.0f + 4.0f * std::abs(r.difference[i]);
    v[i] = r.mask[i] ? uint8_t(std::min(255.0f, g)) : 0;
  }
  return v;
}

std::vector<uint8_t> mask_view(const PerceptionResult& r) {
  std::vector<uint8_t> v(r.mask.size());
  for (size_t i = 0; i < v.size(); ++i) v[i] = r.mask[i] ? 255 : 0;
  return v;
}

std::vector<uint8_t> simulated_view(const PerceptionResult& r) {
  std::vector<uint8_t> v(r.simulated.size());
  for (size_t i = 0; i < v.size(); ++i)
    v[i] = uint8_t(std::clamp(std::lround(r.simulated[i]), 0L, 255L));
  return v;
}

}  // namespace perclod
