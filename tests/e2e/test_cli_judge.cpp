// `perclod judge`: a LOD from any tool against the original, through the CLI,
// on the real building that ships in data/.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <string>

#include "cli_util.h"

namespace {

using perclod::test::kBuilding;
using perclod::test::run_cli;
namespace fs = std::filesystem;

// The worst figures of the first distance of `judge --json`'s output.
nlohmann::json worst(const std::string& out) { return nlohmann::json::parse(out)["distances"][0]["fidelity"]["worst"]; }

// A copy of the building with one more triangle 1 km away: its box, and so
// the centre it would be recentred on, moves by ~500 m. Read onto the
// original's centre its positions are the original's, float for float, so
// nothing differs; a LOD left 500 m off would cover none of the original.
TEST(JudgeCli, ALodInTheOriginalsSourceCoordinatesLinesUp) {
  const fs::path dir = perclod::test::fresh_dir("perclod_judge_cli_frame", true);
  const fs::path copy = dir / "copy.obj";
  {
    std::ifstream in(kBuilding);
    std::ofstream out(copy);
    out << in.rdbuf() << "\nv 1000 1000 0\nv 1000.1 1000 0\nv 1000 1000.1 0\nf -3 -2 -1\n";
  }
  const auto r = run_cli("judge " + std::string(kBuilding) + " " + copy.string() + " --up z -d 56 --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json w = worst(r.out);
  EXPECT_EQ(w["visible_ratio"].get<double>(), 0.0) << r.err;
  EXPECT_EQ(w["silhouette_mismatch"].get<double>(), 0.0) << r.err;
  EXPECT_EQ(r.err.find("degenerate"), std::string::npos) << r.err;  // rounded once, as the original
  EXPECT_EQ(nlohmann::json::parse(r.out)["distances"][0]["views"].size(), 9u);  // held_out
  EXPECT_NE(r.err.find("56 m: worst of 9 views: visible"), std::string::npos) << r.err;
  fs::remove_all(dir);
}

// A LOD with every other triangle deleted (paper mode, the others labelled
// undisplayable) is far over the quarter-pixel floor at 56 m: judge says
// so, and --strict fails after printing it.
TEST(JudgeCli, StrictFailsOnALodOverItsFloor) {
  const fs::path dir = perclod::test::fresh_dir("perclod_judge_cli_strict", true);
  {
    std::ofstream f(dir / "labels.txt");
    f << "perclod-labels 1\ntriangles 12456\nviews 0\n";
    for (int t = 0; t < 12456; ++t) f << (t % 2 ? "U 0 0\n" : "P 0 0\n");
  }
  auto s = run_cli("simplify " + std::string(kBuilding) + " --up z -d 56 --mode paper --labels " +
                   (dir / "labels.txt").string() + " -o " + dir.string());
  ASSERT_EQ(s.exit_code, 0) << s.err;
  const std::string lod = (dir / "bldg_4018215_lod_56m.obj").string();
  auto r = run_cli("judge " + std::string(kBuilding) + " " + lod + " --up z -d 56 -f az22.5el15,+x --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_GT(worst(r.out)["visible_ratio"].get<double>(), 1.0);
  EXPECT_LT(nlohmann::json::parse(r.out)["lod_triangles"].get<int>(), 12456);
  auto strict = run_cli("judge " + std::string(kBuilding) + " " + lod + " --up z -d 56 -f az22.5el15 --strict");
  EXPECT_EQ(strict.exit_code, 1);
  EXPECT_NE(strict.err.find("(over the limit)"), std::string::npos) << strict.err;
  EXPECT_NE(strict.err.find("strict mode"), std::string::npos) << strict.err;
  // A missing LOD is named.
  auto missing = run_cli("judge " + std::string(kBuilding) + " " + (dir / "none.obj").string() + " -d 56");
  EXPECT_NE(missing.exit_code, 0);
  EXPECT_NE(missing.err.find("none.obj"), std::string::npos) << missing.err;
  fs::remove_all(dir);
}

}  // namespace
