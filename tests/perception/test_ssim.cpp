// ssim_mean: 1 for identical images, lower for a changed region, and only
// the pixels of the region count.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <utility>
#include <vector>

#include "perclod/perception.h"

using namespace perclod;

namespace {

std::vector<float> pattern(int w, int h) {
  std::vector<float> img(size_t(w) * h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) img[size_t(y) * w + x] = float(128 + 60 * std::sin(0.3 * x) * std::cos(0.2 * y));
  return img;
}

}  // namespace

TEST(Ssim, IdenticalImagesScoreOne) {
  const int w = 37, h = 23;  // odd sizes: the window is renormalised at every border
  std::vector<float> a = pattern(w, h);
  EXPECT_NEAR(ssim_mean(a.data(), a.data(), w, h, nullptr), 1.0, 1e-9);
  std::vector<float> flat(size_t(w) * h, 200.f);
  EXPECT_NEAR(ssim_mean(flat.data(), flat.data(), w, h, nullptr), 1.0, 1e-9);
}

TEST(Ssim, ChangesLowerItWhereTheyAreAndTheRegionSelects) {
  const int w = 64, h = 32;
  std::vector<float> a = pattern(w, h), b = a;
  for (int y = 0; y < h; ++y)
    for (int x = 40; x < 64; ++x) b[size_t(y) * w + x] = 255.f - b[size_t(y) * w + x];  // right part inverted
  const double all = ssim_mean(a.data(), b.data(), w, h, nullptr);
  EXPECT_LT(all, 0.8);
  std::vector<uint8_t> left(size_t(w) * h, 0), right(size_t(w) * h, 0);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) (x < 30 ? left : right)[size_t(y) * w + x] = x < 30 || x >= 45;
  EXPECT_NEAR(ssim_mean(a.data(), b.data(), w, h, left.data()), 1.0, 1e-6);  // 10 px from the change
  EXPECT_LT(ssim_mean(a.data(), b.data(), w, h, right.data()), 0.0);        // inverted structure
  std::vector<uint8_t> none(size_t(w) * h, 0);
  EXPECT_EQ(ssim_mean(a.data(), b.data(), w, h, none.data()), 1.0);
  // A uniform brightness change hurts less than inverting the structure.
  std::vector<float> c = a;
  for (float& v : c) v += 10;
  EXPECT_GT(ssim_mean(a.data(), c.data(), w, h, nullptr), all);
  EXPECT_THROW(ssim_mean(a.data(), b.data(), 0, h, nullptr), std::invalid_argument);
}

// ssim_mean filters only the region's bounding box widened by the window:
// the same region and pixels placed in a larger image (touching its edge on
// one side, far from it on the others) give the same mean to the last bit.
TEST(Ssim, ARegionScoresTheSameInsideALargerImage) {
  const int w = 41, h = 29, W = 200, H = 150, ox = 0, oy = 70;
  const std::vector<float> a = pattern(w, h);
  std::vector<float> b = a;
  for (int y = 8; y < 20; ++y)
    for (int x = 3; x < 30; ++x) b[size_t(y) * w + x] = 255.f - b[size_t(y) * w + x];
  std::vector<uint8_t> region(size_t(w) * h, 0);
  for (int y = 4; y < 25; ++y)
    for (int x = 0; x < 36; ++x) region[size_t(y) * w + x] = 1;  // touches the left edge
  std::vector<float> A(size_t(W) * H, 17.f), B(size_t(W) * H, 230.f);
  std::vector<uint8_t> R(size_t(W) * H, 0);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y) * w + x, j = size_t(y + oy) * W + size_t(x + ox);
      A[j] = a[i], B[j] = b[i], R[j] = region[i];
    }
  // The surroundings differ from the small image's, but lie beyond every
  // region pixel's window only where the small image has pixels: shrink the
  // region by the window's radius (5) on the sides inside the large image.
  std::vector<uint8_t> inner(size_t(w) * h, 0), Inner(size_t(W) * H, 0);
  for (int y = 5; y < h - 5; ++y)
    for (int x = 0; x < w - 5; ++x)
      if (region[size_t(y) * w + x]) inner[size_t(y) * w + x] = 1, Inner[size_t(y + oy) * W + size_t(x + ox)] = 1;
  const double small = ssim_mean(a.data(), b.data(), w, h, inner.data());
  EXPECT_LT(small, 0.9);
  EXPECT_EQ(ssim_mean(A.data(), B.data(), W, H, Inner.data()), small);
  std::vector<uint8_t> none(size_t(W) * H, 0);
  EXPECT_EQ(ssim_mean(A.data(), B.data(), W, H, none.data()), 1.0);
}

// One SsimScratch reused across images of other sizes (larger, then smaller,
// then larger again: its maps shrink and grow) gives each the mean a call
// without scratch gives, to the last bit.
TEST(Ssim, AReusedScratchGivesTheSameMeans) {
  SsimScratch scratch;
  for (auto [w, h] : {std::pair{64, 48}, std::pair{17, 9}, std::pair{90, 70}, std::pair{64, 48}}) {
    const std::vector<float> a = pattern(w, h);
    std::vector<float> b = a;
    for (int y = h / 3; y < h; ++y)
      for (int x = w / 2; x < w; ++x) b[size_t(y) * w + x] = 255.f - b[size_t(y) * w + x];
    std::vector<uint8_t> region(size_t(w) * h, 0);
    for (size_t i = 0; i < region.size(); i += 3) region[i] = 1;
    const double fresh = ssim_mean(a.data(), b.data(), w, h, region.data());
    EXPECT_LT(fresh, 0.95) << w << "x" << h;
    EXPECT_EQ(ssim_mean(a.data(), b.data(), w, h, region.data(), &scratch), fresh) << w << "x" << h;
    EXPECT_EQ(ssim_mean(a.data(), b.data(), w, h, nullptr, &scratch), ssim_mean(a.data(), b.data(), w, h, nullptr))
        << w << "x" << h;
  }
}

// visible_difference: 0 for images within the threshold of each other; the
// RMS of the excess over the threshold, in thresholds, over the region.
TEST(VisibleDifference, RmsOfTheExcessOverTheThresholdInTheRegion) {
  const std::vector<float> a = {10, 10, 10, 10}, b = {10.5f, 13, 10, 40};
  EXPECT_EQ(perclod::visible_difference(a.data(), a.data(), a.size(), nullptr, 1.0), 0.0);
  // Excesses 0, 2, 0, 29 over 4 pixels.
  EXPECT_NEAR(perclod::visible_difference(a.data(), b.data(), 4, nullptr, 1.0), std::sqrt((4.0 + 841.0) / 4), 1e-9);
  const std::vector<uint8_t> region = {1, 1, 1, 0};  // the 40 left out
  EXPECT_NEAR(perclod::visible_difference(a.data(), b.data(), 4, region.data(), 1.0), std::sqrt(4.0 / 3), 1e-9);
  // In thresholds: threshold 2 -> excesses 0, 1, 0, 28, divided by 2.
  EXPECT_NEAR(perclod::visible_difference(a.data(), b.data(), 4, nullptr, 2.0), std::sqrt((1.0 + 784.0) / 4) / 2, 1e-9);
  const std::vector<uint8_t> none = {0, 0, 0, 0};
  EXPECT_EQ(perclod::visible_difference(a.data(), b.data(), 4, none.data(), 1.0), 0.0);
  EXPECT_THROW(perclod::visible_difference(a.data(), b.data(), 4, nullptr, 0.0), std::invalid_argument);
}

// visible_difference_local: the worst square's own RMS. A change of 2
// thresholds beyond the threshold over one 8 x 8 corner of a 64 x 64 image
// is diluted 8x by the whole image's figure and counted in full by a square
// that holds it; a square needs a quarter of its pixels in the region.
TEST(VisibleDifference, LocalFigureIsTheWorstSquaresOwn) {
  const int w = 64, h = 64;
  std::vector<float> a(size_t(w) * h, 10), b = a;
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x) b[size_t(y) * w + x] = 13;  // excess 2 over threshold 1
  const double whole = perclod::visible_difference(a.data(), b.data(), a.size(), nullptr, 1.0);
  EXPECT_NEAR(whole, 2.0 / 8, 1e-9);
  EXPECT_NEAR(perclod::visible_difference_local(a.data(), b.data(), w, h, nullptr, 1.0, 8), 2.0, 1e-9);
  EXPECT_NEAR(perclod::visible_difference_local(a.data(), b.data(), w, h, nullptr, 1.0, 16), 1.0, 1e-9);  // a quarter of 16 x 16
  EXPECT_EQ(perclod::visible_difference_local(a.data(), a.data(), w, h, nullptr, 1.0, 16), 0.0);
  // A uniform change reads the same locally and over the whole image.
  std::vector<float> c(a.size(), 12.5f);
  EXPECT_NEAR(perclod::visible_difference_local(a.data(), c.data(), w, h, nullptr, 1.0, 16),
              perclod::visible_difference(a.data(), c.data(), a.size(), nullptr, 1.0), 1e-9);
  // Squares with under a quarter of their pixels in the region do not count.
  std::vector<uint8_t> region(a.size(), 0);
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 8; ++x) region[size_t(y) * w + x] = 1;  // 32 pixels: a half of 8 x 8, an eighth of 16 x 16
  EXPECT_NEAR(perclod::visible_difference_local(a.data(), b.data(), w, h, region.data(), 1.0, 8), 2.0, 1e-9);
  EXPECT_EQ(perclod::visible_difference_local(a.data(), b.data(), w, h, region.data(), 1.0, 16), 0.0);
  EXPECT_THROW(perclod::visible_difference_local(a.data(), b.data(), w, h, nullptr, 1.0, 1), std::invalid_argument);
}
