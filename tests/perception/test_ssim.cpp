// ssim_mean: 1 for identical images, lower for a changed region, and only
// the pixels of the region count.
#include <gtest/gtest.h>

#include <cmath>
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
