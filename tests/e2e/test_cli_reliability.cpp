// Issue 12 (reliability) through the CLI: a full disk, clashing distances and
// coordinates beyond float fail with exit 1, a message naming the file, and
// nothing half-written under a final name.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "cli_util.h"
#include "perclod/outputs.h"

namespace {

using perclod::test::run_cli;
namespace fs = std::filesystem;

using perclod::test::fresh_dir;
using perclod::test::kBuilding;

// Files this shell's children write may not grow beyond 8 KB: write() fails
// with EFBIG as on a full disk (SIGXFSZ ignored so the process sees the error).
const std::string kFullDisk = "trap '' XFSZ; ulimit -f 16; ";

// Names of the files in `dir`, each with its size.
std::string listing(const fs::path& dir) {
  std::string s;
  for (const auto& e : fs::directory_iterator(dir))
    s += e.path().filename().string() + " (" + std::to_string(fs::file_size(e.path())) + ")\n";
  return s;
}

TEST(ReliabilityCli, AFullDiskFailsRenderSimplifyAndGenerateWithNothingHalfWritten) {
  fs::path out = fresh_dir("rel-full", true);
  auto r = run_cli("render " + kBuilding + " --up z -d 56 -f +x -o " + out.string(), kFullDisk);
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("bldg_4018215_+x_56m.png: cannot write"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out / "bldg_4018215_+x_56m.png")) << listing(out);

  r = run_cli("simplify " + kBuilding + " --up z -d 56 --mode qem --target 2000 --format glb -o " + out.string(), kFullDisk);
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("bldg_4018215_lod_56m.glb: cannot write"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out / "bldg_4018215_lod_56m.glb")) << listing(out);

  const std::string glb = (out / "g.glb").string();
  r = run_cli("generate facade " + glb, kFullDisk);
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find(glb + ": cannot write"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(glb)) << listing(out);
  for (const auto& e : fs::directory_iterator(out))
    EXPECT_NE(e.path().filename().string().rfind(".tmp-", 0), 0u) << e.path();

  // The same commands succeed with room to write.
  r = run_cli("generate facade " + glb);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::exists(glb));
  fs::remove_all(out);
}

TEST(ReliabilityCli, DistancesThatNameTheSameFilesAreRefused) {
  fs::path out = fresh_dir("rel-dist", true);
  auto r = run_cli("render " + kBuilding + " --up z -d 56,56.0000001 -f +x -o " + out.string());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("56 and 56.0000001 both name their files '56m'"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("loaded"), std::string::npos) << "refused only after loading the model:\n" << r.err;
  EXPECT_TRUE(fs::is_empty(out)) << listing(out);
  std::ofstream(out / "job.yaml") << "model: " << kBuilding << "\nup: z\nout: " << (out / "o").string()
                                  << "\ndistances: [56, 56.0000001]\n";
  r = run_cli("run " + (out / "job.yaml").string());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find((out / "job.yaml").string() + ": 'distances': distances 56 and 56.0000001"),
            std::string::npos)
      << r.err;
  EXPECT_FALSE(fs::exists(out / "o"));
  fs::remove_all(out);
}

TEST(ReliabilityCli, CoordinatesBeyondFloatAreRefusedNamingTheFile) {
  fs::path out = fresh_dir("rel-float", true);
  const std::string big = (out / "big.obj").string();
  std::ofstream(big) << "v 1e39 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\n";
  auto r = run_cli("info " + big);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("perclod: error: " + big + ": vertex 1 coordinate 1e+39"), std::string::npos) << r.err;
  r = run_cli("info " + kBuilding + " --scale 1e300");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("perclod: error: " + kBuilding + ": "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("unit scale 1e+300"), std::string::npos) << r.err;
  fs::remove_all(out);
}

// A crash would show as a signal (exit code -1 from run_cli), a hang as a timeout.
TEST(ReliabilityCli, TruncatedAndOverDeclaredPlyFilesAreErrors) {
  fs::path out = fresh_dir("rel-ply", true);
  std::string ply =
      "ply\nformat binary_little_endian 1.0\nelement vertex 8\nproperty float x\nproperty float y\n"
      "property float z\nelement face 6\nproperty list uchar int vertex_indices\nend_header\n";
  for (int v = 0; v < 8; ++v)
    for (int a = 0; a < 3; ++a) {
      float f = float(v >> a & 1);
      ply.append(reinterpret_cast<const char*>(&f), 4);
    }
  const int32_t quads[6][4] = {{0, 2, 6, 4}, {1, 5, 7, 3}, {0, 4, 5, 1}, {2, 3, 7, 6}, {0, 1, 3, 2}, {4, 6, 7, 5}};
  for (auto& q : quads) ply.append(1, char(4)).append(reinterpret_cast<const char*>(q), 16);
  ASSERT_EQ(ply.size(), 367u);
  const std::string cut = (out / "cut.ply").string(), huge = (out / "huge.ply").string();
  std::ofstream(cut, std::ios::binary) << ply.substr(0, 337);
  std::ofstream(huge) << "ply\nformat ascii 1.0\nelement vertex 100000000\nproperty float x\nproperty float y\n"
                         "property float z\nend_header\n";
  auto r = run_cli("info " + cut);
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("perclod: error: " + cut + ": "), std::string::npos) << r.err;
  r = run_cli("info " + huge);
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("perclod: error: " + huge + ": PLY header declares 100000000 vertex"), std::string::npos)
      << r.err;
  fs::remove_all(out);
}

// Two commands writing to one directory: the second is refused while the
// first holds it, and writes nothing there.
TEST(ReliabilityCli, ASecondCommandOnABusyOutputDirectoryIsRefused) {
  fs::path out = fresh_dir("rel-busy", true);
  {
    perclod::OutputDirectoryLock busy(out.string());  // as a running `perclod run` holds it
    auto r = run_cli("render " + kBuilding + " --up z -d 56 -f +x -o " + out.string());
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_NE(r.err.find("another perclod command is writing to this directory"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(out / "bldg_4018215_+x_56m.png"));
  }
  auto r = run_cli("render " + kBuilding + " --up z -d 56 -f +x -o " + out.string());
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::exists(out / "bldg_4018215_+x_56m.png"));
  // The lock file stays (deleted while held, two commands could hold a lock
  // at once: OutputDirectoryLock.TheLockFileIsNotDeletedWhileHeld), empty.
  EXPECT_TRUE(fs::exists(out / ".perclod.lock"));
  EXPECT_EQ(fs::file_size(out / ".perclod.lock"), 0u);
  fs::remove_all(out);
}

}  // namespace
