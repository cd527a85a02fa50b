// perclod/perception.h - vision simulation of a rendered image (docs/method.md section 3).
//
// Images only: an 8-bit sRGB render goes in (raw RGB bytes, row 0 at the top),
// the vision-simulated luminance, the float visual difference and the mask of
// imperceptible pixels come out. No meshes, cameras or file formats here.
//
//   luminance -> CDF 9/7 DWT (L levels) -> CSF on each detail band -> inverse DWT
//   difference = luminance - simulated;  mask = |difference| > threshold
//
// docs/perception.md explains the defaults (luminance, level rule, FIR taps,
// threshold calibration).
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "perclod/display.h"

namespace perclod {

struct PerceptionSettings {
  // Encoded luma (0.299 R' + 0.587 G' + 0.114 B' of the sRGB bytes, the default:
  // 8-bit quantisation is uniform there, so the threshold means grey levels of
  // the image) or linearised CIE Y re-scaled to 0..255.
  enum class Luminance { Luma, LinearY };
  // Fir: a separable zero-phase FIR per detail band following the CSF across the
  // band (the default, Nadenau et al. 2003). Weights: one CSF weight per band at
  // its centre frequency. Kakadu: Nadenau's fixed weight table (30.9 ppd).
  enum class CsfMode { Fir, Weights, Kakadu };

  Luminance luminance = Luminance::Luma;
  CsfMode csf = CsfMode::Fir;
  double k = 0.144;          // CSF constant as the paper prints it (Mannos-Sakrison: 0.114)
  int levels = 0;            // DWT levels; 0 = from f_max and the CSF peak (default_levels)
  double threshold = 1.0;    // grey levels; |difference| > threshold is imperceptible
  double ppd = 29.64;        // pixels per degree of the display (the paper's 19" LCD)
  int fir_half_length = 3;   // FIR taps per axis = 2 * fir_half_length + 1
  // Cycle spinning: 1 = one decimated DWT (the paper); 2 or 4 = the simulated
  // image averaged over the image shifted by (0,0), (1,1) [, (1,0), (0,1)]
  // pixels. A decimated DWT is not shift-invariant: moving the image one pixel
  // changes ~2% of the mask; 4 spins make the finest level shift-invariant.
  int spins = 1;
};

// Settings for a display profile: ppd from the profile, everything else default.
PerceptionSettings perception_settings_for(const DisplayProfile& display);

// ---- luminance -------------------------------------------------------------

// Luminance of an RGB8 image (3 bytes per pixel), 0..255 scale, w*h floats.
std::vector<float> luminance(const uint8_t* rgb, int w, int h, PerceptionSettings::Luminance mode);
// Same into a caller's buffer of w*h floats.
void luminance_into(const uint8_t* rgb, int w, int h, PerceptionSettings::Luminance mode, float* out);

// ---- CDF 9/7 wavelet (JPEG 2000 irreversible lifting) ------------------------
//
// In place, Mallat layout: after one level the image holds [LL HL; LH HH] with
// ceil(n/2) low-pass samples first along each axis. Whole-sample symmetric
// extension; any size including 1x1, odd and prime. The low-pass analysis
// filter has unit DC gain, the high-pass a gain of 2 at Nyquist (the published
// taps). `levels` may exceed what the size allows: axes of length 1 are skipped.
void dwt97_forward(float* img, int w, int h, int levels);
void dwt97_inverse(float* img, int w, int h, int levels);
void dwt97_forward(double* img, int w, int h, int levels);
void dwt97_inverse(double* img, int w, int h, int levels);

// One-dimensional transform of a contiguous signal (used by the tests to derive
// the analysis filters): out = [low (ceil(n/2)) | high (floor(n/2))].
void dwt97_forward_1d(double* x, int n);

// ---- contrast sensitivity ---------------------------------------------------

// A(f) = 2.6 (0.0192 + k f) exp(-(k f)^1.1), f in cycles/degree.
double csf(double f_cpd, double k);
// Frequency of the CSF peak (cycles/degree): 0.8 / k roughly; exact by bisection.
double csf_peak_frequency(double k);
// The CSF held flat at its peak below the peak frequency and normalised to 1 there.
double csf_flat(double f_cpd, double k);

// Default number of levels: the fewest that leave the LL band (0 .. f_max / 2^L)
// entirely at or below the CSF peak, where the flattened CSF is 1; at least 1.
int default_levels(double f_max, double k);

enum class BandOrientation { HL, LH, HH };  // horizontal high-pass, vertical high-pass, diagonal

// Radial frequency (cpd) carried by band-local frequency nu (cycles/sample,
// 0..0.5) along the high-pass axis of a level-l detail band (l = 1 finest).
// Decimating a high-pass band inverts its spectrum: nu = 0 is the band's top
// edge f_max / 2^(l-1), nu = 0.5 its bottom edge f_max / 2^l.
double band_frequency(double nu, int level, double f_max);

// What the CSF does to one detail band.
struct BandResponse {
  int level = 1;                          // 1 = finest
  BandOrientation orientation = BandOrientation::HL;
  double f_low = 0, f_high = 0;           // radial frequency range, cpd (HH: x sqrt(2))
  double target_low = 1, target_high = 1; // flattened CSF at f_low and f_high
  double response_low = 1, response_high = 1;  // response actually applied there
  double weight = 1;                      // Weights/Kakadu: the band's weight; Fir: response at the centre
  std::vector<double> taps;               // Fir: symmetric taps per axis h[0..M] (h[-m] = h[m])
};

// Zero-phase FIR h[0..M] (h[-m] = h[m]) whose response
// H(nu) = h0 + 2 sum h_m cos(2 pi m nu) fits target(nu) on nu in [0, 0.5]
// by least squares over a dense grid. M = half_length.
std::vector<double> design_fir(const std::function<double(double)>& target, int half_length);
double fir_response(const std::vector<double>& taps, double nu);

// Per-axis target of a band's FIR at band-local frequency nu: the flattened CSF
// at band_frequency for HL/LH; for HH the square root of the CSF at sqrt(2)
// times it, so the separable product follows the CSF along the diagonal.
double band_axis_target(double nu, int level, BandOrientation o, double f_max, double k);

// The 3 * levels detail-band responses for these settings (order: level 1 HL, LH,
// HH, level 2 ...).
std::vector<BandResponse> band_responses(const PerceptionSettings& s, int levels);

// ---- the whole simulation ---------------------------------------------------

struct PerceptionResult {
  int width = 0, height = 0;
  std::vector<float> luminance;    // the input as seen (0..255)
  std::vector<float> simulated;    // vision-simulated luminance
  std::vector<float> difference;   // luminance - simulated (float, signed)
  std::vector<uint8_t> mask;       // 1 = imperceptible (|difference| > threshold)
  int levels = 0;
  double ppd = 0, f_max = 0;
  std::vector<BandResponse> bands;
  double imperceptible_fraction = 0;  // among non-background pixels
  long long counted_pixels = 0;       // non-background pixels
  double seconds = 0;                 // time of perceive()
};

// Runs the simulation. background_mask (w*h, nonzero = background, e.g. from the
// renderer's triangle-ID buffer) only excludes pixels from the fraction.
// Throws std::invalid_argument on bad sizes or settings.
PerceptionResult perceive(const uint8_t* rgb, int w, int h, const PerceptionSettings& s,
                          const uint8_t* background_mask = nullptr);
// Same, reusing `out`'s buffers: no allocation once warm. The first call in a
// process pays for first-touching ~13 bytes per pixel of fresh memory; a batch
// should keep one PerceptionResult per thread and call this.
void perceive_into(const uint8_t* rgb, int w, int h, const PerceptionSettings& s,
                   const uint8_t* background_mask, PerceptionResult& out);

// The simulation on a luminance image directly (0..255 scale).
void perceive_luminance(const float* lum, int w, int h, const PerceptionSettings& s,
                        const uint8_t* background_mask, PerceptionResult& out);

// ---- viewing images ---------------------------------------------------------

// The paper's figure 5: black where the pixel is perceptible (|d| <= threshold),
// grey where it carries imperceptible detail: 64 + 4 |d| clamped to 255.
std::vector<uint8_t> difference_view(const PerceptionResult& r);
// Mask as 8-bit: 255 = imperceptible, 0 = perceptible.
std::vector<uint8_t> mask_view(const PerceptionResult& r);
// Simulated luminance rounded and clamped to 8-bit grey.
std::vector<uint8_t> simulated_view(const PerceptionResult& r);

// ---- comparing two images -----------------------------------------------------

// Mean structural similarity (SSIM, Wang, Bovik, Sheikh and Simoncelli 2004)
// of luminance images a and b (w*h, 0..255 scale) over the pixels where
// region[i] != 0 (all pixels when region is null): 1 = identical. Local
// statistics under a Gaussian window (sigma 1.5 px, 11 x 11 taps), weights
// renormalised where the window leaves the image; C1 = (0.01 * 255)^2,
// C2 = (0.03 * 255)^2. Returns 1 for an empty region.
//
// The five filtered maps take 40 bytes a pixel of the region's box; pass the
// same SsimScratch to every call of a series (one per thread) and they are
// allocated once, not page-faulted afresh for each image (the result is the
// same with or without it).
struct SsimScratch {
  std::vector<double> maps[5];
};
double ssim_mean(const float* a, const float* b, int w, int h, const uint8_t* region,
                 SsimScratch* scratch = nullptr);

// How visible the difference between two vision-simulated images is (the
// `simulated` of two PerceptionResults of one size): over the n pixels where
// region[i] != 0 (all when region is null), the root mean square of each
// pixel's difference beyond the detection threshold, in thresholds:
//   sqrt(mean(max(0, |a - b| - threshold)^2)) / threshold.
// 0 when no pixel differs by more than the threshold (or the region is
// empty). The judge sets a LOD's figure beside the same figure for the
// original moved by a quarter pixel (docs/usage.md#judging-a-lod).
double visible_difference(const float* a, const float* b, size_t n, const uint8_t* region, double threshold);

// The same figure, local: the largest over squares of block x block pixels
// (stepped by half a block, each with at least a quarter of its pixels in
// the region) of the square's own root mean square. A change confined to a
// few windows, which the whole-building figure dilutes, shows in full.
double visible_difference_local(const float* a, const float* b, int width, int height, const uint8_t* region,
                                double threshold, int block);

}  // namespace perclod
