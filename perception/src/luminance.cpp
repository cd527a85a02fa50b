// Luminance of an 8-bit sRGB render, 0..255 scale.
//
// Luma (default): Y' = 0.299 R' + 0.587 G' + 0.114 B' on the encoded bytes
// (Rec. 601 weights). Encoded values are roughly perceptually uniform and the
// 8-bit quantisation step is one grey level everywhere, so a threshold in grey
// levels means the same at every brightness.
// LinearY: sRGB decoded to linear light, CIE Y = 0.2126 R + 0.7152 G + 0.0722 B,
// times 255. Physically the luminance, but one 8-bit step near white becomes
// about 2.3 linear levels, so quantisation alone can exceed a 1-level threshold.
#include <array>
#include <cmath>
#include <stdexcept>

#include "perclod/perception.h"
#include "simd.h"

namespace perclod {
namespace {

std::array<float, 256> srgb_to_linear_255() {
  std::array<float, 256> t{};
  for (int i = 0; i < 256; ++i) {
    double c = i / 255.0;
    double lin = c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
    t[i] = float(255.0 * lin);
  }
  return t;
}

}  // namespace

PERCLOD_SIMD_CLONES void luminance_into(const uint8_t* rgb, int w, int h, PerceptionSettings::Luminance mode, float* out) {
  if (w < 1 || h < 1) throw std::invalid_argument("luminance: image size must be at least 1x1");
  if (!rgb || !out) throw std::invalid_argument("luminance: null pixel buffer");
  const size_t n = size_t(w) * size_t(h);
  if (mode == PerceptionSettings::Luminance::Luma) {
    for (size_t i = 0; i < n; ++i)
      out[i] = 0.299f * rgb[3 * i] + 0.587f * rgb[3 * i + 1] + 0.114f * rgb[3 * i + 2];
  } else {
    static const std::array<float, 256> lut = srgb_to_linear_255();
    for (size_t i = 0; i < n; ++i)
      out[i] = 0.2126f * lut[rgb[3 * i]] + 0.7152f * lut[rgb[3 * i + 1]] + 0.0722f * lut[rgb[3 * i + 2]];
  }
}

std::vector<float> luminance(const uint8_t* rgb, int w, int h, PerceptionSettings::Luminance mode) {
  if (w < 1 || h < 1) throw std::invalid_argument("luminance: image size must be at least 1x1");
  std::vector<float> out(size_t(w) * size_t(h));
  luminance_into(rgb, w, h, mode, out.data());
  return out;
}

}  // namespace perclod
