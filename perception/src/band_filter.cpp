// CSF filtering of wavelet detail bands: a weight, or a short zero-phase FIR.
//
// The FIR runs along the band's high-pass axis. The band is extended beyond its
// borders the way the high-pass coefficients of a whole-sample symmetric signal
// are symmetric: half-sample at the start (d[-1] = d[0]); at the end
// whole-sample (d[n] = d[n-2]) if the parent signal had even length, else
// half-sample (d[n] = d[n-1]). Filtering then commutes with the extension, so
// borders get the same treatment as the interior.
#include "band_filter.h"

#include <algorithm>

#include "simd.h"

namespace perclod::detail {
namespace {

// Index into a high band of length n >= 1 for any i, following the symmetry.
int extend(int i, int n, bool parent_even) {
  if (n == 1) return 0;
  for (int guard = 0; guard < 64 && (i < 0 || i >= n); ++guard) {
    if (i < 0) i = -1 - i;
    else i = parent_even ? 2 * (n - 1) - i : 2 * n - 1 - i;
  }
  return std::clamp(i, 0, n - 1);
}

std::vector<float>& scratch() {
  thread_local std::vector<float> buffer;
  return buffer;
}

float* scratch_of(size_t n) {
  std::vector<float>& v = scratch();
  if (v.size() < n) v.resize(n);
  return v.data();
}

// Taps in float on the stack (half length <= 16, checked by the settings).
struct FloatTaps {
  float h[17] = {};
  explicit FloatTaps(const std::vector<double>& taps) {
    for (size_t m = 0; m < taps.size() && m < 17; ++m) h[m] = float(taps[m]);
  }
  float operator[](int m) const { return h[m]; }
};

}  // namespace

PERCLOD_SIMD_CLONES void scale_band(const Band& b, float weight) {
  for (int y = 0; y < b.h; ++y) {
    float* row = b.data + size_t(y) * b.stride;
    for (int x = 0; x < b.w; ++x) row[x] *= weight;
  }
}

PERCLOD_SIMD_CLONES void fir_rows(const Band& b, const std::vector<double>& taps) {
  if (b.w < 1 || b.h < 1 || taps.empty()) return;
  const int m_len = std::min(int(taps.size()) - 1, 16);
  const FloatTaps h(taps);
  const bool even = b.parent_w % 2 == 0;
  float* pad = scratch_of(size_t(b.w + 2 * m_len));
  float* p = pad + m_len;  // p[-m_len .. w + m_len)
  for (int y = 0; y < b.h; ++y) {
    float* row = b.data + size_t(y) * b.stride;
    std::copy(row, row + b.w, p);
    for (int m = 1; m <= m_len; ++m) {
      p[-m] = row[extend(-m, b.w, even)];
      p[b.w - 1 + m] = row[extend(b.w - 1 + m, b.w, even)];
    }
    for (int x = 0; x < b.w; ++x) row[x] = h[0] * p[x];
    for (int m = 1; m <= m_len; ++m) {
      const float hm = h[m];
      const float* __restrict lo = p - m;
      const float* __restrict hi = p + m;
      for (int x = 0; x < b.w; ++x) row[x] += hm * (lo[x] + hi[x]);
    }
  }
}

PERCLOD_SIMD_CLONES void fir_columns(const Band& b, const std::vector<double>& taps) {
  if (b.w < 1 || b.h < 1 || taps.empty()) return;
  const int m_len = std::min(int(taps.size()) - 1, 16);
  const FloatTaps h(taps);
  const bool even = b.parent_h % 2 == 0;
  const size_t w = size_t(b.w);
  // Copy the band with m_len extended rows above and below.
  float* copy = scratch_of(w * size_t(b.h + 2 * m_len));
  auto src_row = [&](int y) { return b.data + size_t(extend(y, b.h, even)) * b.stride; };
  for (int y = -m_len; y < b.h + m_len; ++y) {
    const float* src = src_row(y);
    std::copy(src, src + w, copy + size_t(y + m_len) * w);
  }
  for (int y = 0; y < b.h; ++y) {
    float* __restrict out = b.data + size_t(y) * b.stride;
    const float* c = copy + size_t(y + m_len) * w;
    for (size_t x = 0; x < w; ++x) out[x] = h[0] * c[x];
    for (int m = 1; m <= m_len; ++m) {
      const float hm = h[m];
      const float* __restrict up = c - size_t(m) * w;
      const float* __restrict down = c + size_t(m) * w;
      for (size_t x = 0; x < w; ++x) out[x] += hm * (up[x] + down[x]);
    }
  }
}

}  // namespace perclod::detail
