// `perclod generate facade` through the CLI and back through the loader (the
// generator's own tests are pipeline/facade/test_facade.cpp).
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>

#include "../pipeline/facade/facade_fixtures.h"
#include "cli_util.h"
#include "perclod/facade.h"
#include "perclod/load.h"

namespace perclod {
namespace {

using test::facade_fixtures::all_on;
using test::facade_fixtures::corner;

// `perclod generate facade` writes what the library builds, and the
// project's loader reads it back with every triangle, group and the offset.
TEST(Facade, CliWritesTheFacadeAndItLoadsBack) {
  namespace fs = std::filesystem;
  fs::path dir = test::fresh_dir("facade", true);
  const std::string obj = (dir / "f.obj").string();
  auto r = test::run_cli("generate facade --floors 2 --bays 3 --coplanar-panels --hidden-interior " +
                         obj + " --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  FacadeParams p = all_on(2, 3);
  p.subpixel_ornaments = false;
  Scene expected = generate_facade(p);
  auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["triangles"].get<size_t>(), expected.triangle_count());
  EXPECT_EQ(j["components"].get<size_t>(), expected.component_count());

  Scene loaded = load_scene(obj);
  ASSERT_EQ(loaded.triangle_count(), expected.triangle_count());
  EXPECT_EQ(loaded.component_names, expected.component_names);
  EXPECT_EQ(loaded.component, expected.component);
  for (int a = 0; a < 3; ++a) EXPECT_NEAR(loaded.offset[a], expected.offset[a], 1e-6);
  for (size_t t = 0; t < expected.triangle_count(); t += 97)
    for (int k = 0; k < 3; ++k)
      for (int a = 0; a < 3; ++a)
        EXPECT_NEAR(corner(loaded, t, k)[a], corner(expected, t, k)[a], 1e-4);
  EXPECT_EQ(analyse_scene(loaded).degenerate_triangles, 0u);

  // A budget picks the building; bad parameters fail with the field's name.
  r = test::run_cli("generate facade --triangles 20000 " + obj + " --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NEAR(nlohmann::json::parse(r.out)["triangles"].get<double>() / 20000.0, 1.0, 0.1);
  r = test::run_cli("generate facade --floors 0 " + obj);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("floors"), std::string::npos) << r.err;
  r = test::run_cli("generate facade --triangles 5 " + obj);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("smallest building"), std::string::npos) << r.err;
  fs::remove_all(dir);
}

}  // namespace
}  // namespace perclod
