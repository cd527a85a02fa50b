// The simplifier on generated facades (perclod/facade.h), labelled with the
// synthetic rule of fixtures.h: the viewer stands in front of wall 0 (which
// faces -y) looking along +y; back faces are undisplayable, front faces of at
// least `min_area` perceptible, smaller front faces imperceptible; and the
// hidden interior (components named interior_*) is undisplayable, as no ray
// from outside reaches it.
#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "fixtures.h"
#include "perclod/facade.h"
#include "perclod/simplify.h"

namespace perclod {
namespace {

Scene small_facade() {
  FacadeParams p;
  p.floors = 2;
  p.bays = 3;
  p.hidden_interior = true;
  p.subpixel_ornaments = true;
  return generate_facade(p);
}

TEST(SimplifyFacade, PerceptibleTrianglesSurviveBitIdentical) {
  Scene in = small_facade();
  auto labels = test::synthetic_labels(in, {0, 1, 0}, 0.02);
  for (size_t t = 0; t < in.triangle_count(); ++t)
    if (in.component_names[in.component[t]].rfind("interior_", 0) == 0) labels[t] = Label::Undisplayable;
  for (SimplifyMode mode : {SimplifyMode::Paper, SimplifyMode::Bounded}) {
    SimplifyOptions opt;
    opt.mode = mode;
    opt.pixel_footprint = 0.03;
    SimplifyStats st;
    std::vector<uint32_t> src;
    Scene out = simplify(in, labels, opt, &st, &src);
    for (float x : out.positions) ASSERT_TRUE(std::isfinite(x));
    std::multiset<test::Tri> want, got;
    for (size_t t = 0; t < in.triangle_count(); ++t)
      if (labels[t] == Label::Perceptible) want.insert(test::canonical(test::tri_of(in, t)));
    for (size_t t = 0; t < out.triangle_count(); ++t)
      if (labels[src[t]] == Label::Perceptible) got.insert(test::canonical(test::tri_of(out, t)));
    ASSERT_GT(want.size(), 100u);
    EXPECT_TRUE(want == got) << simplify_mode_name(mode);
    EXPECT_EQ(st.triangles_after[0], st.triangles_before[0]);
    EXPECT_LT(st.triangles_after[1], st.triangles_before[1]) << simplify_mode_name(mode);
    EXPECT_LT(st.triangles_after[2], st.triangles_before[2]) << simplify_mode_name(mode);
    EXPECT_GT(st.components_removed, 0u);  // the hidden interior
    EXPECT_EQ(out.component_names, in.component_names);
    EXPECT_EQ(out.offset, in.offset);
    if (mode == SimplifyMode::Bounded) {
      EXPECT_LE(st.max_error, 0.03);
    }
  }
}

TEST(SimplifyFacade, QemReachesTarget) {
  Scene in = small_facade();
  std::vector<Label> labels(in.triangle_count(), Label::Imperceptible);
  size_t target = in.triangle_count() / 4;
  SimplifyOptions opt;
  opt.mode = SimplifyMode::Qem;
  opt.target_triangles = target;
  Scene out = simplify(in, labels, opt);
  EXPECT_LE(std::abs(double(out.triangle_count()) - double(target)), 0.01 * double(target))
      << out.triangle_count() << " for " << target << " of " << in.triangle_count();
}

TEST(SimplifyFacade, ClusterShrinksAsTheCellGrows) {
  Scene in = small_facade();
  std::vector<Label> labels(in.triangle_count(), Label::Perceptible);
  size_t prev = in.triangle_count() + 1;
  for (double cell : {0.02, 0.1, 0.5}) {
    SimplifyOptions opt;
    opt.mode = SimplifyMode::Cluster;
    opt.pixel_footprint = cell;
    Scene out = simplify(in, labels, opt);
    EXPECT_LT(out.triangle_count(), prev) << cell;
    prev = out.triangle_count();
  }
}

}  // namespace
}  // namespace perclod
