// Two distances whose file names would be the same are refused (issue 12):
// 56 and 56.0000001 both print "56m" and would overwrite each other's files.
#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

#include "perclod/outputs.h"
#include "test_util.h"

using namespace perclod;

using test::has;

TEST(DistanceTags, DistancesWithTheSameFileNameAreRefused) {
  EXPECT_NO_THROW(check_distinct_tags({56, 132, 12.5}));
  try {
    check_distinct_tags({56, 56.0000001});
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_TRUE(has(e.what(), "56 and 56.0000001 both name their files '56m'")) << e.what();
  }
  EXPECT_THROW(check_distinct_tags({56, 132, 56}), std::invalid_argument);
}

// Outputs are named after the model file's stem; CityJSON's "name.city.json"
// gives "name" (not "name.city"), and only a JSON file loses ".city".
TEST(OutputNames, ACityJsonModelIsNamedWithoutDotCity) {
  EXPECT_EQ(model_stem("data/bldg.obj"), "bldg");
  EXPECT_EQ(model_stem("tiles/3dbag_5910_delft.city.json"), "3dbag_5910_delft");
  EXPECT_EQ(model_stem("tiles/B.CITY.JSON"), "B");
  EXPECT_EQ(model_stem("a.cityjson"), "a");
  EXPECT_EQ(model_stem("old.city.obj"), "old.city");  // not CityJSON: the stem as it is
  EXPECT_EQ(model_stem(".city.json"), ".city");       // nothing would be left
  EXPECT_EQ(output_names_for("out", "d/x.city.json").lod(56, "glb"), "out/x_lod_56m.glb");
}
