// `perclod perceive`: files, JSON summary, background, option errors.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>

#include "cli_util.h"

namespace fs = std::filesystem;

namespace {

// A 96 x 64 binary PPM: left half fine noise on grey, right half white.
fs::path write_test_image(const fs::path& dir) {
  fs::create_directories(dir);
  fs::path p = dir / "grid.ppm";
  std::ofstream f(p, std::ios::binary);
  f << "P6\n96 64\n255\n";
  std::mt19937 rng(2);
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 96; ++x) {
      unsigned char v = x < 48 ? (unsigned char)(100 + rng() % 80) : 255;
      f.put(char(v)).put(char(v)).put(char(v));
    }
  return p;
}

struct CliPerceive : ::testing::Test {
  fs::path dir = perclod::test::fresh_dir("perceive");
  void TearDown() override { fs::remove_all(dir); }
};

TEST_F(CliPerceive, WritesImagesAndAJsonSummary) {
  fs::path img = write_test_image(dir);
  auto r = perclod::test::run_cli("perceive " + img.string() + " --ppd 29.64 --raw --json --out " +
                                  (dir / "out").string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* suffix : {"_simulated.png", "_difference.png", "_mask.png", "_difference.tif", "_perception.json"})
    EXPECT_TRUE(fs::exists(dir / "out" / (std::string("grid") + suffix))) << suffix;
  nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_NEAR(j["ppd"].get<double>(), 29.64, 1e-9);
  EXPECT_NEAR(j["f_max_cpd"].get<double>(), 14.82, 1e-9);
  EXPECT_EQ(j["levels"].get<int>(), 2);
  EXPECT_EQ(j["bands"].size(), 6u);
  EXPECT_EQ(j["bands"][0]["taps"].size(), 4u);
  EXPECT_EQ(j["counted_pixels"].get<long long>(), 96 * 64);
  double all = j["imperceptible_fraction"].get<double>();
  EXPECT_GT(all, 0.05);
  EXPECT_GE(j["seconds"].get<double>(), 0.0);

  // Leaving the white half out as background raises the fraction.
  auto bg = perclod::test::run_cli("perceive " + img.string() + " --ppd 29.64 --background 255,255,255 --json --out " +
                                   (dir / "out").string());
  ASSERT_EQ(bg.exit_code, 0) << bg.err;
  nlohmann::json jb = nlohmann::json::parse(bg.out);
  EXPECT_LT(jb["counted_pixels"].get<long long>(), 96 * 64);
  EXPECT_GT(jb["imperceptible_fraction"].get<double>(), all);
}

TEST_F(CliPerceive, BadOptionsFailWithAMessage) {
  fs::path img = write_test_image(dir);
  auto r = perclod::test::run_cli("perceive " + img.string() + " --csf gauss --out " + (dir / "out").string());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("--csf"), std::string::npos) << r.err;
  r = perclod::test::run_cli("perceive " + img.string() + " --ppd -3 --out " + (dir / "out").string());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("--ppd"), std::string::npos) << r.err;
  r = perclod::test::run_cli("perceive " + img.string() + " --background 1,2 --out " + (dir / "out").string());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("--background"), std::string::npos) << r.err;
  r = perclod::test::run_cli("perceive " + img.string() + " --threshold -1 --out " + (dir / "out").string());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("threshold"), std::string::npos) << r.err;
}

}  // namespace
