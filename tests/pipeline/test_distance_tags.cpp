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
