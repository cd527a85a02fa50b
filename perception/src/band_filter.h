// Applying a CSF response to one detail band of a Mallat-layout DWT image.
#pragma once

#include <cstddef>
#include <vector>

namespace perclod::detail {

// A rectangular band inside an image of row stride `stride`.
struct Band {
  float* data = nullptr;  // top-left coefficient
  int w = 0, h = 0;
  size_t stride = 0;
  // Length of the signal the band was decimated from, along x and y: decides
  // the symmetry at the far border (high band of an even-length signal is
  // whole-sample symmetric there, of an odd-length one half-sample).
  int parent_w = 0, parent_h = 0;
};

// Multiplies every coefficient by `weight`.
void scale_band(const Band& b, float weight);
// Zero-phase FIR (taps h[0..M], h[-m] = h[m]) along x (rows) or y (columns) of a
// high-pass axis, with the high band's symmetric extension at the borders.
void fir_rows(const Band& b, const std::vector<double>& taps);
void fir_columns(const Band& b, const std::vector<double>& taps);

}  // namespace perclod::detail
