// The collapse scales of one case and record (apps/collapse_bracket.h): the
// smallest scale with a collapse, the largest below it that stood, and the
// scales above the smallest collapse that stood, which make the results
// not monotonic (acceptance probe: the two columns read as a threshold).
#include <gtest/gtest.h>

#include <cmath>

#include "collapse_bracket.h"

namespace {

using fq_app::bracket_collapse;
using fq_app::ScaleRun;

TEST(CollapseBracket, AMonotonicSweepHasNoNote) {
  const auto b = bracket_collapse({{1.5, 12.0, "1 2"}, {0.5, 4.0, ""}, {1.0, 8.0, ""}, {2.0, 16.0, "1"}});
  EXPECT_EQ(b.largest_stood, 1.0);
  EXPECT_EQ(b.smallest_collapse, 1.5);
  EXPECT_EQ(b.pga_at_collapse_mps2, 12.0);
  EXPECT_EQ(b.storeys_at_collapse, "1 2");
  EXPECT_EQ(b.largest_completed, 2.0);
  EXPECT_TRUE(b.stood_above_collapse.empty());
  EXPECT_EQ(fq_app::stood_above_collapse_csv(b), "");
  EXPECT_EQ(fq_app::non_monotonic_note("B", "kobe", b), "");
}

// Collapsed at 0.75, stood at 1 and 1.25, collapsed again at 1.5: the
// columns still say 0.5 / 0.75, and the scales that stood above are listed.
TEST(CollapseBracket, ScalesThatStoodAboveTheSmallestCollapseAreListed) {
  const auto b = bracket_collapse(
      {{0.5, 4.0, ""}, {0.75, 6.0, "2"}, {1.0, 8.0, ""}, {1.25, 10.0, ""}, {1.5, 12.0, "1 2"}});
  EXPECT_EQ(b.largest_stood, 0.5);
  EXPECT_EQ(b.smallest_collapse, 0.75);
  EXPECT_EQ(b.storeys_at_collapse, "2");
  EXPECT_EQ(b.stood_above_collapse, (std::vector<double>{1.0, 1.25}));
  EXPECT_EQ(fq_app::stood_above_collapse_csv(b), "1 1.25");
  EXPECT_EQ(fq_app::non_monotonic_note("B", "kobe", b),
            "- B, kobe: not monotonic: collapsed at 0.75 but stood at 1 and 1.25; the two scale columns bracket the "
            "smallest collapse only, not a threshold above which it always collapses");
}

TEST(CollapseBracket, NoCompletedRunAndNoCollapse) {
  const auto none = bracket_collapse({});
  EXPECT_TRUE(std::isnan(none.largest_completed));
  EXPECT_TRUE(std::isnan(none.smallest_collapse));
  const auto stood = bracket_collapse({{1.0, 8.0, ""}, {2.0, 16.0, ""}});
  EXPECT_EQ(stood.largest_stood, 2.0);
  EXPECT_TRUE(std::isnan(stood.smallest_collapse));
  EXPECT_TRUE(stood.stood_above_collapse.empty());
}

}  // namespace
