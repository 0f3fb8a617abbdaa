// Segment colours: the first 256 are all different and none is the unassigned grey.
#include "slipfit/render/segment_palette.h"

#include <gtest/gtest.h>

#include <set>

namespace slipfit {
namespace {

TEST(SegmentPalette, TheFirst256SegmentsHaveTheirOwnColours) {
  std::set<Rgb> seen;
  for (std::size_t k = 0; k < 256; ++k) {
    const Rgb c = segmentColour(k);
    EXPECT_NE(c, kUnassignedColour) << k;
    EXPECT_TRUE(seen.insert(c).second) << "segment " << k << " repeats a colour";
  }
  EXPECT_EQ(segmentColour(0), (Rgb{31, 119, 180}));   // the familiar first colours stay
  EXPECT_EQ(segmentColour(300), segmentColour(300));  // deterministic
}

}  // namespace
}  // namespace slipfit
