// CDF 9/7 wavelet by lifting (JPEG 2000 irreversible transform, ISO 15444-1 F.4).
//
// A signal x[0..n) splits into s = even samples (ceil(n/2)) and d = odd samples
// (floor(n/2)). Four lifting steps, each with whole-sample symmetric extension
// (x[-1] = x[1], x[n] = x[n-2]), then scaling:
//   d += alpha (s left + s right);  s += beta (d left + d right)
//   d += gamma (s left + s right);  s += delta (d left + d right)
//   s /= K;  d *= K
// The inverse runs the same steps backwards with the signs flipped.
//
// Layout and speed: rows are de-interleaved into a contiguous scratch (s then d)
// and lifted there, so every step is a unit-stride loop the compiler vectorises.
// Columns are done in strips of kStrip adjacent columns: the strip is copied
// row by row into a scratch (even rows first, then odd rows), and each lifting
// step runs over whole strip rows. One pass over memory per axis and level.
#include <algorithm>
#include <cstddef>
#include <stdexcept>
#include <vector>

#include "perclod/perception.h"

namespace perclod {
namespace {

constexpr double kAlpha = -1.586134342059924;
constexpr double kBeta = -0.052980118572961;
constexpr double kGamma = 0.882911075530934;
constexpr double kDelta = 0.443506852043971;
constexpr double kK = 1.230174104914001;

constexpr int kStrip = 16;  // columns per strip (one or two cache lines)

// Scratch that grows and is kept per thread: no allocation once warm.
template <class T>
std::vector<T>& scratch(int which) {
  thread_local std::vector<T> buffers[2];
  return buffers[which];
}

template <class T>
T* scratch_of(int which, size_t n) {
  std::vector<T>& v = scratch<T>(which);
  if (v.size() < n) v.resize(n);
  return v.data();
}

// ---- lifting on split arrays, one value per sample (rows) ----

// d[i] += c (s[i] + s[i+1]); s[ns] mirrors to s[ns-1] when ns == nd.
template <class T>
void predict1(T* __restrict d, const T* __restrict s, int nd, int ns, T c) {
  int last = nd - 1;
  for (int i = 0; i < last; ++i) d[i] += c * (s[i] + s[i + 1]);
  d[last] += c * (s[last] + s[last + 1 < ns ? last + 1 : last]);
}

// s[i] += c (d[i-1] + d[i]); d[-1] mirrors to d[0], d[nd] to d[nd-1].
template <class T>
void update1(T* __restrict s, const T* __restrict d, int ns, int nd, T c) {
  s[0] += c * (d[0] + d[0]);
  for (int i = 1; i < nd; ++i) s[i] += c * (d[i - 1] + d[i]);
  if (ns > nd) s[ns - 1] += c * (d[nd - 1] + d[nd - 1]);
}

template <class T>
void lift_forward1(T* s, T* d, int ns, int nd) {
  predict1(d, s, nd, ns, T(kAlpha));
  update1(s, d, ns, nd, T(kBeta));
  predict1(d, s, nd, ns, T(kGamma));
  update1(s, d, ns, nd, T(kDelta));
}

template <class T>
void lift_inverse1(T* s, T* d, int ns, int nd) {
  update1(s, d, ns, nd, T(-kDelta));
  predict1(d, s, nd, ns, T(-kGamma));
  update1(s, d, ns, nd, T(-kBeta));
  predict1(d, s, nd, ns, T(-kAlpha));
}

// ---- lifting on split arrays of strip rows (sw values per sample, stride kStrip) ----

template <class T>
inline void axpy2(T* __restrict y, const T* __restrict a, const T* __restrict b, T c) {
  for (int j = 0; j < kStrip; ++j) y[j] += c * (a[j] + b[j]);
}

template <class T>
void predictN(T* d, const T* s, int nd, int ns, T c) {
  for (int i = 0; i < nd; ++i) {
    const T* right = s + (i + 1 < ns ? i + 1 : i) * kStrip;
    axpy2(d + i * kStrip, s + i * kStrip, right, c);
  }
}

template <class T>
void updateN(T* s, const T* d, int ns, int nd, T c) {
  for (int i = 0; i < ns; ++i) {
    const T* left = d + (i > 0 ? i - 1 : 0) * kStrip;
    const T* right = d + (i < nd ? i : nd - 1) * kStrip;
    axpy2(s + i * kStrip, left, right, c);
  }
}

template <class T>
void lift_forwardN(T* s, T* d, int ns, int nd) {
  predictN(d, s, nd, ns, T(kAlpha));
  updateN(s, d, ns, nd, T(kBeta));
  predictN(d, s, nd, ns, T(kGamma));
  updateN(s, d, ns, nd, T(kDelta));
}

template <class T>
void lift_inverseN(T* s, T* d, int ns, int nd) {
  updateN(s, d, ns, nd, T(-kDelta));
  predictN(d, s, nd, ns, T(-kGamma));
  updateN(s, d, ns, nd, T(-kBeta));
  predictN(d, s, nd, ns, T(-kAlpha));
}

// ---- one axis of one level ----

// Rows 0..h of the w-wide region at img (row stride `stride`), each n = w >= 2 long.
template <class T>
void rows_forward(T* img, int w, int h, size_t stride) {
  int ns = (w + 1) / 2, nd = w / 2;
  T* s = scratch_of<T>(0, size_t(w));
  T* d = s + ns;
  const T lo = T(1 / kK), hi = T(kK);
  for (int y = 0; y < h; ++y) {
    T* row = img + size_t(y) * stride;
    for (int i = 0; i < nd; ++i) { s[i] = row[2 * i]; d[i] = row[2 * i + 1]; }
    if (ns > nd) s[ns - 1] = row[w - 1];
    lift_forward1(s, d, ns, nd);
    for (int i = 0; i < ns; ++i) row[i] = s[i] * lo;
    for (int i = 0; i < nd; ++i) row[ns + i] = d[i] * hi;
  }
}

template <class T>
void rows_inverse(T* img, int w, int h, size_t stride) {
  int ns = (w + 1) / 2, nd = w / 2;
  T* s = scratch_of<T>(0, size_t(w));
  T* d = s + ns;
  const T lo = T(kK), hi = T(1 / kK);
  for (int y = 0; y < h; ++y) {
    T* row = img + size_t(y) * stride;
    for (int i = 0; i < ns; ++i) s[i] = row[i] * lo;
    for (int i = 0; i < nd; ++i) d[i] = row[ns + i] * hi;
    lift_inverse1(s, d, ns, nd);
    for (int i = 0; i < nd; ++i) { row[2 * i] = s[i]; row[2 * i + 1] = d[i]; }
    if (ns > nd) row[w - 1] = s[ns - 1];
  }
}

// Columns of the w-wide, h >= 2 tall region, kStrip columns at a time.
template <class T>
void columns_forward(T* img, int w, int h, size_t stride) {
  int ns = (h + 1) / 2, nd = h / 2;
  T* s = scratch_of<T>(1, size_t(h) * kStrip);
  T* d = s + size_t(ns) * kStrip;
  const T lo = T(1 / kK), hi = T(kK);
  for (int x0 = 0; x0 < w; x0 += kStrip) {
    int sw = std::min(kStrip, w - x0);
    for (int y = 0; y < h; ++y) {
      const T* src = img + size_t(y) * stride + x0;
      T* dst = (y & 1 ? d : s) + size_t(y / 2) * kStrip;
      std::copy(src, src + sw, dst);
    }
    lift_forwardN(s, d, ns, nd);
    for (int i = 0; i < ns; ++i) {
      T* dst = img + size_t(i) * stride + x0;
      const T* src = s + size_t(i) * kStrip;
      for (int j = 0; j < sw; ++j) dst[j] = src[j] * lo;
    }
    for (int i = 0; i < nd; ++i) {
      T* dst = img + size_t(ns + i) * stride + x0;
      const T* src = d + size_t(i) * kStrip;
      for (int j = 0; j < sw; ++j) dst[j] = src[j] * hi;
    }
  }
}

template <class T>
void columns_inverse(T* img, int w, int h, size_t stride) {
  int ns = (h + 1) / 2, nd = h / 2;
  T* s = scratch_of<T>(1, size_t(h) * kStrip);
  T* d = s + size_t(ns) * kStrip;
  const T lo = T(kK), hi = T(1 / kK);
  for (int x0 = 0; x0 < w; x0 += kStrip) {
    int sw = std::min(kStrip, w - x0);
    for (int i = 0; i < ns; ++i) {
      const T* src = img + size_t(i) * stride + x0;
      T* dst = s + size_t(i) * kStrip;
      for (int j = 0; j < sw; ++j) dst[j] = src[j] * lo;
    }
    for (int i = 0; i < nd; ++i) {
      const T* src = img + size_t(ns + i) * stride + x0;
      T* dst = d + size_t(i) * kStrip;
      for (int j = 0; j < sw; ++j) dst[j] = src[j] * hi;
    }
    lift_inverseN(s, d, ns, nd);
    for (int y = 0; y < h; ++y) {
      const T* src = (y & 1 ? d : s) + size_t(y / 2) * kStrip;
      std::copy(src, src + sw, img + size_t(y) * stride + x0);
    }
  }
}

void check_size(int w, int h, int levels) {
  if (w < 1 || h < 1) throw std::invalid_argument("dwt97: image size must be at least 1x1");
  if (levels < 0) throw std::invalid_argument("dwt97: levels must be >= 0");
}

template <class T>
void forward2d(T* img, int w, int h, int levels) {
  check_size(w, h, levels);
  int lw = w, lh = h;
  for (int l = 0; l < levels && (lw > 1 || lh > 1); ++l) {
    if (lw > 1) rows_forward(img, lw, lh, size_t(w));
    if (lh > 1) columns_forward(img, lw, lh, size_t(w));
    lw = (lw + 1) / 2;
    lh = (lh + 1) / 2;
  }
}

template <class T>
void inverse2d(T* img, int w, int h, int levels) {
  check_size(w, h, levels);
  std::vector<int> ws, hs;  // region size at each level actually transformed
  int lw = w, lh = h;
  for (int l = 0; l < levels && (lw > 1 || lh > 1); ++l) {
    ws.push_back(lw);
    hs.push_back(lh);
    lw = (lw + 1) / 2;
    lh = (lh + 1) / 2;
  }
  for (int l = int(ws.size()) - 1; l >= 0; --l) {
    if (hs[l] > 1) columns_inverse(img, ws[l], hs[l], size_t(w));
    if (ws[l] > 1) rows_inverse(img, ws[l], hs[l], size_t(w));
  }
}

}  // namespace

void dwt97_forward(float* img, int w, int h, int levels) { forward2d(img, w, h, levels); }
void dwt97_inverse(float* img, int w, int h, int levels) { inverse2d(img, w, h, levels); }
void dwt97_forward(double* img, int w, int h, int levels) { forward2d(img, w, h, levels); }
void dwt97_inverse(double* img, int w, int h, int levels) { inverse2d(img, w, h, levels); }

void dwt97_forward_1d(double* x, int n) {
  if (n < 1) throw std::invalid_argument("dwt97: signal length must be at least 1");
  if (n > 1) rows_forward(x, n, 1, size_t(n));
}

void dwt97_inverse_1d(double* x, int n) {
  if (n < 1) throw std::invalid_argument("dwt97: signal length must be at least 1");
  if (n > 1) rows_inverse(x, n, 1, size_t(n));
}

}  // namespace perclod
