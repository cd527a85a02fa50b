// The CLI's foundation commands, as a user runs them.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <nlohmann/json.hpp>

#include "cli_util.h"
#include "perclod/image_io.h"

using perclod::test::run_cli;
namespace fs = std::filesystem;

using perclod::test::fresh_dir;
using perclod::test::kBuilding;

TEST(Cli, HelpExplainsEveryCommand) {
  auto r = run_cli("--help");
  EXPECT_EQ(r.exit_code, 0);
  for (const char* c : {"info", "render", "generate", "run"}) EXPECT_NE(r.out.find(c), std::string::npos) << c;
  auto none = run_cli("");
  EXPECT_NE(none.exit_code, 0);  // a subcommand is required
}

TEST(Cli, InfoJsonDescribesTheBuilding) {
  auto r = run_cli("info " + kBuilding + " --up z --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["triangles"], 12456);
  EXPECT_EQ(j["components"], 50);
  EXPECT_EQ(j["degenerate_triangles"], 0);
  EXPECT_GT(j["non_manifold_edges"].get<int>(), 0);
  EXPECT_NEAR(j["bounds_min"][0].get<double>(), 108.077, 1e-3);
  EXPECT_NEAR(j["bounds_max"][2].get<double>(), 29.18, 1e-3);
}

// OpenImageIO (some 260 shared libraries, 0.42 s to load) is dlopen()ed by
// the first image read or write (pipeline/io/src/image_codec.h): a command that
// touches no image never loads it, one that writes images does. The dynamic
// loader lists every file it loads under LD_DEBUG=files.
TEST(Cli, OpenImageIoIsLoadedOnlyByCommandsThatTouchImages) {
  auto info = run_cli("info " + kBuilding + " --up z", "export LD_DEBUG=files;");
  ASSERT_EQ(info.exit_code, 0) << info.err;
  EXPECT_NE(info.err.find("file=libOSMesa"), std::string::npos) << "LD_DEBUG listed nothing";
  EXPECT_EQ(info.err.find("libOpenImageIO"), std::string::npos);
  EXPECT_EQ(info.err.find("libperclod_oiio"), std::string::npos);

  const fs::path out = fresh_dir("lazy-oiio");
  auto render = run_cli("render " + kBuilding + " --up z -d 427 -f +x -o " + out.string(), "export LD_DEBUG=files;");
  ASSERT_EQ(render.exit_code, 0) << render.err;
  EXPECT_NE(render.err.find("libperclod_oiio.so"), std::string::npos);
  EXPECT_NE(render.err.find("file=libOpenImageIO"), std::string::npos);
  EXPECT_EQ(perclod::read_rgb8((out / "bldg_4018215_+x_427m.png").string()).width, 1280);
  fs::remove_all(out);
}

// A perclod copied elsewhere with its module loads the module beside it,
// not the build's.
TEST(Cli, ACopiedPerclodLoadsTheImageModuleBesideIt) {
  const fs::path dir = fresh_dir("copied", true);
  const fs::path build = fs::path(PERCLOD_CLI).parent_path();
  fs::copy_file(PERCLOD_CLI, dir / "perclod");
  fs::copy_file(build / "libperclod_oiio.so", dir / "libperclod_oiio.so");
  auto r = perclod::test::run_program((dir / "perclod").string(),
                                      "render " + kBuilding + " --up z -d 427 -f +x -o " + (dir / "out").string(),
                                      "export LD_DEBUG=files;");
  ASSERT_EQ(r.exit_code, 0) << r.err.substr(0, 2000);
  EXPECT_NE(r.err.find("file=" + (dir / "libperclod_oiio.so").string()), std::string::npos) << r.err.substr(0, 2000);
  EXPECT_EQ(r.err.find("file=" + (build / "libperclod_oiio.so").string()), std::string::npos);
  EXPECT_TRUE(fs::exists(dir / "out" / "bldg_4018215_+x_427m.png"));
  fs::remove_all(dir);
}

TEST(Cli, BadInputFailsWithAMessageOnStderr) {
  auto missing = run_cli("info /nonexistent/model.obj");
  EXPECT_EQ(missing.exit_code, 1);
  EXPECT_NE(missing.err.find("/nonexistent/model.obj: no such file"), std::string::npos) << missing.err;
  EXPECT_TRUE(missing.out.empty());
  auto facade = run_cli("render " + kBuilding + " --up z -d 56 -f +z -o /tmp/perclod-never");
  EXPECT_EQ(facade.exit_code, 1);
  EXPECT_NE(facade.err.find("view '+z'"), std::string::npos) << facade.err;
  EXPECT_FALSE(fs::exists("/tmp/perclod-never"));
  auto distance = run_cli("render " + kBuilding + " -d -5");
  EXPECT_NE(distance.exit_code, 0);
}

TEST(Cli, RenderWritesOneFilePerFacadeAndDistance) {
  fs::path out = fs::temp_directory_path() / ("perclod-render-" + std::to_string(getpid()));
  fs::remove_all(out);
  auto r = run_cli("render " + kBuilding + " --up z -d 56,132 -f +x,-y --ids --json -o " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto j = nlohmann::json::parse(r.out);
  ASSERT_EQ(j["views"].size(), 4u);
  for (const char* f : {"+x", "-y"})
    for (const char* d : {"56", "132"}) {
      std::string base = (out / (std::string("bldg_4018215_") + f + "_" + d + "m")).string();
      ASSERT_TRUE(fs::exists(base + ".png")) << base;
      ASSERT_TRUE(fs::exists(base + "_ids.tif")) << base;
      auto img = perclod::read_rgb8(base + ".png");
      EXPECT_EQ(img.width, 1280);
      EXPECT_EQ(img.height, 1024);
      int w, h;
      auto ids = perclod::read_tiff_uint32(base + "_ids.tif", &w, &h);
      size_t covered = 0;
      for (uint32_t id : ids) {
        covered += id != 0;
        ASSERT_LE(id, 12456u);
      }
      EXPECT_GT(covered, 1000u);
    }
  // No temporary files left behind.
  for (const auto& e : fs::directory_iterator(out)) EXPECT_EQ(e.path().filename().string().rfind(".tmp-", 0), std::string::npos);
  fs::remove_all(out);
}
