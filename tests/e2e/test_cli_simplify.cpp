// `perclod simplify` on the real building that ships in data/, through the
// CLI. Labels by a fixed rule on the triangle index: t % 5 == 0 perceptible,
// 1 or 2 imperceptible, 3 or 4 undisplayable.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace {

namespace fs = std::filesystem;

const char* kModel = PERCLOD_SOURCE_DIR "/data/ingolstadt/bldg_4018215.obj";

std::string run(const std::string& args, int* status) {
  std::string cmd = std::string(PERCLOD_CLI) + " " + args + " 2>/dev/null";
  FILE* p = popen(cmd.c_str(), "r");
  std::string out;
  char buf[4096];
  size_t n;
  while (p && (n = fread(buf, 1, sizeof buf, p)) > 0) out.append(buf, n);
  int st = p ? pclose(p) : -1;
  *status = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  return out;
}

void write_labels(const fs::path& path, size_t n) {
  std::ofstream f(path);
  f << "perclod-labels 1\ntriangles " << n << "\nviews 0\n";
  for (size_t t = 0; t < n; ++t) f << (t % 5 == 0 ? "P" : t % 5 < 3 ? "I" : "U") << " 0 0\n";
}

// The value after "key": in the JSON report (flat numbers only).
double field(const std::string& json, const std::string& object, const std::string& key) {
  size_t at = object.empty() ? 0 : json.find("\"" + object + "\"");
  at = json.find("\"" + key + "\"", at);
  if (at == std::string::npos) return -1;
  return std::strtod(json.c_str() + json.find(':', at) + 1, nullptr);
}

TEST(SimplifyCli, PaperKeepsEveryPerceptibleTriangleOfARealBuilding) {
  fs::path dir = fs::temp_directory_path() / "perclod_simplify_cli";
  fs::create_directories(dir);
  write_labels(dir / "labels.txt", 12456);
  int st = 0;
  std::string json = run("simplify " + std::string(kModel) + " --up z --distance 56 --labels " +
                             (dir / "labels.txt").string() + " --out " + (dir / "lod.obj").string() + " --json",
                         &st);
  ASSERT_EQ(st, 0) << json;
  EXPECT_EQ(field(json, "triangles_before", "perceptible"), 2492);
  EXPECT_EQ(field(json, "triangles_after", "perceptible"), 2492);
  EXPECT_LT(field(json, "triangles_after", "imperceptible"), field(json, "triangles_before", "imperceptible"));
  EXPECT_LT(field(json, "triangles_after", "undisplayable"), field(json, "triangles_before", "undisplayable"));
  EXPECT_GE(field(json, "", "max_displacement_rel"), 0.0);
  EXPECT_TRUE(fs::exists(dir / "lod.obj"));
  EXPECT_FALSE(fs::exists(dir / "lod.obj.tmp"));
  fs::remove_all(dir);
}

TEST(SimplifyCli, RefusesLabelsOfAnotherModel) {
  fs::path dir = fs::temp_directory_path() / "perclod_simplify_cli_bad";
  fs::create_directories(dir);
  write_labels(dir / "labels.txt", 100);
  int st = 0;
  run("simplify " + std::string(kModel) + " --up z --distance 56 --labels " + (dir / "labels.txt").string() +
          " --out " + (dir / "lod.obj").string(),
      &st);
  EXPECT_EQ(st, 1);
  EXPECT_FALSE(fs::exists(dir / "lod.obj"));
  run("simplify " + std::string(kModel) + " --distance 56 --mode bounded --out " + (dir / "lod.obj").string(), &st);
  EXPECT_EQ(st, 1);  // bounded without labels
  fs::remove_all(dir);
}

}  // namespace
