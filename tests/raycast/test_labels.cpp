// The label rule, view combination, counting and marking colours.
#include <gtest/gtest.h>

#include "perclod/raycast.h"

namespace perclod {
namespace {

TEST(RaycastLabels, RatioExactlyHalfIsImperceptible) {
  TriangleCounts c;
  c.traced = {4, 4, 0, 1, 1, 3, 1000001};
  c.imperceptible = {2, 1, 0, 1, 0, 2, 500000};
  const auto l = label_triangles(c, 0.5);
  EXPECT_EQ(l[0], Label::Imperceptible);   // 2/4 == 0.5
  EXPECT_EQ(l[1], Label::Perceptible);     // 1/4 < 0.5
  EXPECT_EQ(l[2], Label::Undisplayable);   // traced == 0
  EXPECT_EQ(l[3], Label::Imperceptible);   // 1/1
  EXPECT_EQ(l[4], Label::Perceptible);     // 0/1
  EXPECT_EQ(l[5], Label::Imperceptible);   // 2/3
  EXPECT_EQ(l[6], Label::Perceptible);     // just below one half
}

TEST(RaycastLabels, ZeroTracedIsUndisplayableAtAnyRatio) {
  TriangleCounts c;
  c.traced = {0};
  c.imperceptible = {0};
  for (double r : {0.0, 0.5, 1.0}) EXPECT_EQ(label_triangles(c, r)[0], Label::Undisplayable);
  c.traced = {5};
  EXPECT_EQ(label_triangles(c, 0.0)[0], Label::Imperceptible);  // 0/5 >= 0
  EXPECT_EQ(label_triangles(c, 1.0)[0], Label::Perceptible);
}

TEST(RaycastLabels, BadCountsThrow) {
  TriangleCounts c;
  c.traced = {1, 2};
  c.imperceptible = {1};
  EXPECT_THROW(label_triangles(c), std::invalid_argument);
  c.imperceptible = {2, 0};
  EXPECT_THROW(label_triangles(c), std::invalid_argument);  // more imperceptible than traced
  c.imperceptible = {0, 0};
  EXPECT_THROW(label_triangles(c, 1.5), std::invalid_argument);
  EXPECT_THROW(label_triangles(c, std::nan("")), std::invalid_argument);
}

TEST(RaycastLabels, CountTrianglesFromBufferAndMask) {
  const std::vector<uint32_t> ids = {0, 1, 1, 3, 3, 3, 1, 0};
  const std::vector<uint8_t> mask = {1, 1, 0, 1, 1, 0, 0, 1};
  const TriangleCounts c = count_triangles(ids.data(), mask.data(), ids.size(), 4);
  EXPECT_EQ(c.traced, (std::vector<uint32_t>{3, 0, 3, 0}));
  EXPECT_EQ(c.imperceptible, (std::vector<uint32_t>{1, 0, 2, 0}));
  const TriangleCounts n = count_triangles(ids.data(), nullptr, ids.size(), 4);
  EXPECT_EQ(n.imperceptible, (std::vector<uint32_t>{0, 0, 0, 0}));
  EXPECT_THROW(count_triangles(ids.data(), mask.data(), ids.size(), 2), std::invalid_argument);
}

TEST(RaycastLabels, CombineViews) {
  using L = Label;
  const std::vector<std::vector<Label>> views = {
      {L::Perceptible, L::Imperceptible, L::Undisplayable, L::Undisplayable, L::Imperceptible},
      {L::Undisplayable, L::Undisplayable, L::Undisplayable, L::Imperceptible, L::Perceptible},
      {L::Imperceptible, L::Undisplayable, L::Undisplayable, L::Undisplayable, L::Imperceptible}};
  const auto c = combine_views(views);
  EXPECT_EQ(c, (std::vector<Label>{L::Perceptible, L::Imperceptible, L::Undisplayable, L::Imperceptible,
                                   L::Perceptible}));
  EXPECT_THROW(combine_views({}), std::invalid_argument);
  EXPECT_THROW(combine_views({{L::Perceptible}, {}}), std::invalid_argument);
  const LabelCounts lc = count_labels(c);
  EXPECT_EQ(lc.perceptible, 2u);
  EXPECT_EQ(lc.imperceptible, 2u);
  EXPECT_EQ(lc.undisplayable, 1u);
}

TEST(RaycastLabels, MarkingColours) {
  const auto rgb = marking_colors({Label::Perceptible, Label::Imperceptible, Label::Undisplayable});
  ASSERT_EQ(rgb.size(), 9u);
  EXPECT_GT(rgb[1], rgb[0] + 0.5f);  // green dominates
  EXPECT_GT(rgb[1], rgb[2] + 0.5f);
  EXPECT_GT(rgb[3], rgb[4] + 0.5f);  // red
  EXPECT_GT(rgb[3], rgb[5] + 0.5f);
  EXPECT_GT(rgb[8], rgb[6] + 0.5f);  // blue
  EXPECT_GT(rgb[8], rgb[7] + 0.5f);
}

}  // namespace
}  // namespace perclod
