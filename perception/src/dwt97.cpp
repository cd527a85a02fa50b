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
// Columns lift whole rows against whole rows, the four steps fused into one
// sweep down the image (see columns_forward). Each level reads and writes the
// image about twice, through one image-sized scratch kept per thread.
#include <algorithm>
#include <cstddef>
#include <stdexcept>
#include <vector>

#include "perclod/perception.h"
#include "simd.h"

namespace perclod {
namespace {

constexpr double kAlpha = -1.586134342059924;
constexpr double kBeta = -0.052980118572961;
constexpr double kGamma = 0.882911075530934;
constexpr double kDelta = 0.443506852043971;
constexpr double kK = 1.230174104914001;

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

// ---- rows: de-interleave into a contiguous scratch, lift, write back ----

// Rows 0..h of the w-wide (w >= 2) region: src (row stride src_stride) to img
// (row stride `stride`), result [s / K | d * K]. src may equal img.
template <class T>
void rows_forward(const T* src, size_t src_stride, T* img, size_t stride, int w, int h) {
  int ns = (w + 1) / 2, nd = w / 2;
  T* s = scratch_of<T>(0, size_t(w));
  T* d = s + ns;
  const T lo = T(1 / kK), hi = T(kK);
  for (int y = 0; y < h; ++y) {
    const T* in = src + size_t(y) * src_stride;
    T* row = img + size_t(y) * stride;
    for (int i = 0; i < nd; ++i) { s[i] = in[2 * i]; d[i] = in[2 * i + 1]; }
    if (ns > nd) s[ns - 1] = in[w - 1];
    lift_forward1(s, d, ns, nd);
    for (int i = 0; i < ns; ++i) row[i] = s[i] * lo;
    for (int i = 0; i < nd; ++i) row[ns + i] = d[i] * hi;
  }
}

template <class T>
void rows_inverse(const T* src, size_t src_stride, T* img, size_t stride, int w, int h) {
  int ns = (w + 1) / 2, nd = w / 2;
  T* s = scratch_of<T>(0, size_t(w));
  T* d = s + ns;
  const T lo = T(kK), hi = T(1 / kK);
  for (int y = 0; y < h; ++y) {
    const T* in = src + size_t(y) * src_stride;
    T* row = img + size_t(y) * stride;
    for (int i = 0; i < ns; ++i) s[i] = in[i] * lo;
    for (int i = 0; i < nd; ++i) d[i] = in[ns + i] * hi;
    lift_inverse1(s, d, ns, nd);
    for (int i = 0; i < nd; ++i) { row[2 * i] = s[i]; row[2 * i + 1] = d[i]; }
    if (ns > nd) row[w - 1] = s[ns - 1];
  }
}

// ---- columns: line-based lifting over whole rows ----
//
// A column transform lifts rows against rows: row 2i is s[i], row 2i+1 is d[i],
// and every lifting step is "row += c (row above + row below)", a unit-stride
// loop over the region's width. The four steps are fused into one sweep down
// the image (each step lags the previous one by one row pair), so only a
// window of about six rows is live and the image is read and written once.

template <class T>
inline void lift_rows(T* __restrict y, const T* a, const T* b, T c, int w) {
  for (int x = 0; x < w; ++x) y[x] += c * (a[x] + b[x]);
}

template <class T>
inline void scale_row(T* __restrict dst, const T* __restrict src, T c, int w) {
  for (int x = 0; x < w; ++x) dst[x] = src[x] * c;
}

// Forward column transform of the w x h (h >= 2) region at img, lifting in
// place in img's rows and writing the scaled result in Mallat order (s rows,
// then d rows) to dst (row stride dst_stride).
template <class T>
void columns_forward(T* img, size_t stride, T* dst, size_t dst_stride, int w, int h) {
  const int ns = (h + 1) / 2, nd = h / 2;
  auto S = [&](int i) { return img + size_t(2 * i) * stride; };
  auto D = [&](int i) { return img + size_t(2 * i + 1) * stride; };
  auto Sc = [&](int i) { return S(std::min(i, ns - 1)); };               // s[ns] -> s[ns-1] (even h)
  auto Dc = [&](int i) { return D(std::clamp(i, 0, nd - 1)); };         // d[-1] -> d[0], d[nd] -> d[nd-1]
  const T lo = T(1 / kK), hi = T(kK);
  for (int t = 0; t <= ns; ++t) {
    if (t < nd) lift_rows(D(t), S(t), Sc(t + 1), T(kAlpha), w);
    if (t < ns) lift_rows(S(t), Dc(t - 1), Dc(t), T(kBeta), w);
    int u = t - 1;
    if (u >= 0 && u < nd) {
      lift_rows(D(u), S(u), Sc(u + 1), T(kGamma), w);
      if (u >= 1) scale_row(dst + size_t(ns + u - 1) * dst_stride, D(u - 1), hi, w);  // d[u-1] no longer read
    }
    if (u >= 0 && u < ns) {
      lift_rows(S(u), Dc(u - 1), Dc(u), T(kDelta), w);
      scale_row(dst + size_t(u) * dst_stride, S(u), lo, w);
    }
  }
  scale_row(dst + size_t(ns + nd - 1) * dst_stride, D(nd - 1), hi, w);
}

// Inverse column transform: src holds the Mallat-order region (row stride
// src_stride); the result is built in place in img's rows.
template <class T>
void columns_inverse(const T* src, size_t src_stride, T* img, size_t stride, int w, int h) {
  const int ns = (h + 1) / 2, nd = h / 2;
  auto S = [&](int i) { return img + size_t(2 * i) * stride; };
  auto D = [&](int i) { return img + size_t(2 * i + 1) * stride; };
  auto Sc = [&](int i) { return S(std::min(i, ns - 1)); };
  auto Dc = [&](int i) { return D(std::clamp(i, 0, nd - 1)); };
  const T lo = T(kK), hi = T(1 / kK);
  for (int t = 0; t <= ns + 1; ++t) {
    if (t < nd) scale_row(D(t), src + size_t(ns + t) * src_stride, hi, w);
    if (t < ns) {
      scale_row(S(t), src + size_t(t) * src_stride, lo, w);
      lift_rows(S(t), Dc(t - 1), Dc(t), T(-kDelta), w);
    }
    int u = t - 1;
    if (u >= 0 && u < nd) lift_rows(D(u), S(u), Sc(u + 1), T(-kGamma), w);
    if (u >= 0 && u < ns) lift_rows(S(u), Dc(u - 1), Dc(u), T(-kBeta), w);
    int v = t - 2;
    if (v >= 0 && v < nd) lift_rows(D(v), S(v), Sc(v + 1), T(-kAlpha), w);
  }
}

void check_size(int w, int h, int levels) {
  if (w < 1 || h < 1) throw std::invalid_argument("dwt97: image size must be at least 1x1");
  if (levels < 0) throw std::invalid_argument("dwt97: levels must be >= 0");
}

// Copies a w x h region between buffers of different strides.
template <class T>
void copy_region(const T* src, size_t src_stride, T* dst, size_t dst_stride, int w, int h) {
  for (int y = 0; y < h; ++y) std::copy(src + size_t(y) * src_stride, src + size_t(y) * src_stride + w,
                                        dst + size_t(y) * dst_stride);
}

// One level, in place on the lw x lh region of img (row stride `stride`):
// columns (img -> scratch, Mallat order) then rows (scratch -> img). The two
// axes commute, and this order lets the row pass bring the data back.
template <class T>
void level_forward(T* img, size_t stride, int lw, int lh) {
  if (lh > 1) {
    T* tmp = scratch_of<T>(1, size_t(lw) * size_t(lh));
    columns_forward(img, stride, tmp, size_t(lw), lw, lh);
    if (lw > 1) rows_forward(tmp, size_t(lw), img, stride, lw, lh);
    else copy_region(tmp, size_t(lw), img, stride, lw, lh);
  } else if (lw > 1) {
    rows_forward(img, stride, img, stride, lw, lh);
  }
}

template <class T>
void level_inverse(T* img, size_t stride, int lw, int lh) {
  if (lh > 1) {
    T* tmp = scratch_of<T>(1, size_t(lw) * size_t(lh));
    if (lw > 1) rows_inverse(img, stride, tmp, size_t(lw), lw, lh);
    else copy_region(img, stride, tmp, size_t(lw), lw, lh);
    columns_inverse(tmp, size_t(lw), img, stride, lw, lh);
  } else if (lw > 1) {
    rows_inverse(img, stride, img, stride, lw, lh);
  }
}

template <class T>
void forward2d(T* img, int w, int h, int levels) {
  check_size(w, h, levels);
  int lw = w, lh = h;
  for (int l = 0; l < levels && (lw > 1 || lh > 1); ++l) {
    level_forward(img, size_t(w), lw, lh);
    lw = (lw + 1) / 2;
    lh = (lh + 1) / 2;
  }
}

template <class T>
void inverse2d(T* img, int w, int h, int levels) {
  check_size(w, h, levels);
  int n = 0, lw = w, lh = h;
  while (n < levels && (lw > 1 || lh > 1)) {
    ++n;
    lw = (lw + 1) / 2;
    lh = (lh + 1) / 2;
  }
  for (int l = n - 1; l >= 0; --l) {
    int rw = w, rh = h;  // region of level l
    for (int i = 0; i < l; ++i) {
      rw = (rw + 1) / 2;
      rh = (rh + 1) / 2;
    }
    level_inverse(img, size_t(w), rw, rh);
  }
}

}  // namespace

PERCLOD_SIMD_CLONES void dwt97_forward(float* img, int w, int h, int levels) { forward2d(img, w, h, levels); }
PERCLOD_SIMD_CLONES void dwt97_inverse(float* img, int w, int h, int levels) { inverse2d(img, w, h, levels); }
PERCLOD_SIMD_CLONES void dwt97_forward(double* img, int w, int h, int levels) { forward2d(img, w, h, levels); }
PERCLOD_SIMD_CLONES void dwt97_inverse(double* img, int w, int h, int levels) { inverse2d(img, w, h, levels); }

void dwt97_forward_1d(double* x, int n) {
  if (n < 1) throw std::invalid_argument("dwt97: signal length must be at least 1");
  if (n > 1) rows_forward(x, size_t(n), x, size_t(n), n, 1);
}

}  // namespace perclod
