// The label-constrained simplifier on the Ingolstadt building that ships in
// data/ (the synthetic cases are simplify/test_constrained.cpp; this one needs
// the pipeline's loader, so it lives here).
#include <gtest/gtest.h>

#include "../simplify/fixtures.h"
#include "perclod/load.h"
#include "perclod/simplify.h"

namespace perclod {
namespace {

using test::expect_perceptible_preserved;
using test::expect_valid;

TEST(SimplifyPaper, RealBuildingKeepsPerceptibleTriangles) {
  // One Ingolstadt LOD3 building (Z up) with the synthetic rule: viewer
  // looking along +y, perceptible from 0.05 m^2.
  Scene in = load_scene(PERCLOD_SOURCE_DIR "/data/ingolstadt/bldg_4018215.obj");
  ASSERT_EQ(in.triangle_count(), 12456u);
  auto labels = test::synthetic_labels(in, {0, 1, 0}, 0.01);
  for (SimplifyMode mode : {SimplifyMode::Paper, SimplifyMode::Bounded}) {
    SimplifyOptions opt;
    opt.mode = mode;
    opt.pixel_footprint = 0.02;
    SimplifyStats st;
    std::vector<uint32_t> src;
    Scene out = simplify(in, labels, opt, &st, &src);
    expect_valid(out);
    expect_perceptible_preserved(in, labels, out, src);
    EXPECT_GT(st.triangles_before[0], 500u);
    EXPECT_GT(st.triangles_before[1], 500u);
    EXPECT_GT(st.triangles_before[2], 500u);
    EXPECT_LT(st.triangles_after[1], st.triangles_before[1]) << simplify_mode_name(mode);
    EXPECT_LT(st.triangles_after[2], st.triangles_before[2]) << simplify_mode_name(mode);
    if (mode == SimplifyMode::Bounded) {
      EXPECT_LE(st.max_error, 0.02);
    }
  }
}

}  // namespace
}  // namespace perclod
