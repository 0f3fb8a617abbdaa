// The picture's legend: rows of a swatch and text on a white panel, the font's glyphs, the rows
// that do not fit counted, and the segments' entries largest first.
#include "slipfit/render/legend.h"
#include "slipfit/core/exceptions.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

namespace slipfit {
namespace {

constexpr std::uint8_t kBackground = 7;

struct Image {
  int width, height;
  std::vector<std::uint8_t> rgb;
  Image(int w, int h)
      : width(w), height(h), rgb(static_cast<std::size_t>(w * h * 3), kBackground) {}
  const std::uint8_t* at(int x, int y) const { return rgb.data() + 3 * (y * width + x); }
  bool is(int x, int y, const Rgb& c) const {
    return at(x, y)[0] == c[0] && at(x, y)[1] == c[1] && at(x, y)[2] == c[2];
  }
};

TEST(Legend, RowsHoldASwatchAndTheTextOnAWhitePanel) {
  Image image(200, 100);
  const Rgb red{200, 10, 10}, blue{10, 10, 200};
  ASSERT_EQ(drawLegend(image.rgb, image.width, image.height, {{red, "0"}, {blue, "11"}}, 1), 2u);
  // Scale 1: margin 2, rows 10 pixels apart starting at y = 3, swatch 7 × 7 at x = 2, text at
  // x = 11 (swatch + 2).
  for (int y = 3; y < 10; ++y)
    for (int x = 2; x < 9; ++x) {
      ASSERT_TRUE(image.is(x, y, red)) << x << "," << y;
      ASSERT_TRUE(image.is(x, y + 10, blue)) << x << "," << y;
    }
  // The glyph '0' (rows 01110 10001 10011 10101 11001 10001 01110) in ink, the rest panel white.
  const char* zero[7] = {".###.", "#...#", "#..##", "#.#.#", "##..#", "#...#", ".###."};
  for (int row = 0; row < 7; ++row)
    for (int col = 0; col < 5; ++col) {
      const std::uint8_t v = image.at(11 + col, 3 + row)[0];
      EXPECT_EQ(v, zero[row][col] == '#' ? 20 : 255) << row << "," << col;
    }
  // The panel spans the longest text ("11": 2 glyphs of 6) plus the margins, and no further.
  const int panel_width = 11 + 2 * 6 + 2, panel_height = 2 * 2 + 2 * 10;
  EXPECT_EQ(image.at(panel_width - 1, 0)[0], 255);
  EXPECT_EQ(image.at(panel_width, 0)[0], kBackground);
  EXPECT_EQ(image.at(0, panel_height - 1)[0], 255);
  EXPECT_EQ(image.at(0, panel_height)[0], kBackground);
}

TEST(Legend, RowsThatDoNotFitAreCountedOnTheLastRow) {
  Image image(300, 2 * 2 + 5 * 10);  // five rows fit at scale 1
  std::vector<LegendEntry> entries(12, {Rgb{1, 2, 3}, "x"});
  EXPECT_EQ(drawLegend(image.rgb, image.width, image.height, entries, 1), 4u);
  // Four swatches, then the text "+ 8 more" where the fifth swatch would be.
  EXPECT_TRUE(image.is(2, 3 + 3 * 10, Rgb{1, 2, 3}));
  EXPECT_FALSE(image.is(2, 3 + 4 * 10, Rgb{1, 2, 3}));
  bool ink = false;  // the '8' is the third glyph: x = 11 + 2 · 6
  for (int y = 43; y < 50; ++y)
    for (int x = 23; x < 28; ++x)
      ink = ink || image.at(x, y)[0] == 20;
  EXPECT_TRUE(ink);
  // A row limit under what fits does the same.
  Image tall(300, 200);
  EXPECT_EQ(drawLegend(tall.rgb, tall.width, tall.height, entries, 1, 5), 4u);
  EXPECT_FALSE(tall.is(2, 3 + 4 * 10, Rgb{1, 2, 3}));
  EXPECT_EQ(tall.at(0, 2 * 2 + 5 * 10)[0], kBackground);  // the panel ends after five rows
}

TEST(Legend, ScaledGlyphsAreBlocksOfScaleSquaredPixels) {
  Image one(100, 40), three(300, 120);
  drawLegend(one.rgb, one.width, one.height, {{Rgb{0, 0, 0}, "4"}}, 1);
  drawLegend(three.rgb, three.width, three.height, {{Rgb{0, 0, 0}, "4"}}, 3);
  for (int y = 0; y < 7; ++y)
    for (int x = 0; x < 5; ++x)
      for (int dy = 0; dy < 3; ++dy)
        for (int dx = 0; dx < 3; ++dx)
          ASSERT_EQ(three.at(33 + 3 * x + dx, 9 + 3 * y + dy)[0], one.at(11 + x, 3 + y)[0]);
}

TEST(Legend, SegmentsAreListedLargestFirstThenTheUnassigned) {
  const std::vector<LegendEntry> entries = segmentLegend(
      {PrimitiveType::plane, PrimitiveType::sphere, PrimitiveType::cylinder}, {10, 300, 10}, 5);
  ASSERT_EQ(entries.size(), 4u);
  EXPECT_EQ(entries[0].text, "1 sphere 300");
  EXPECT_EQ(entries[0].colour, segmentColour(1));
  EXPECT_EQ(entries[1].text, "0 plane 10");  // ties by id
  EXPECT_EQ(entries[2].text, "2 cylinder 10");
  EXPECT_EQ(entries[3].text, "- none 5");
  EXPECT_EQ(entries[3].colour, kUnassignedColour);
  EXPECT_EQ(segmentLegend({PrimitiveType::plane}, {4}, 0).size(), 1u);
}

TEST(Legend, AWrongImageSizeOrScaleIsRefused) {
  std::vector<std::uint8_t> image(10 * 10 * 3);
  EXPECT_THROW(drawLegend(image, 10, 11, {{Rgb{}, "a"}}, 1), InvalidParameterError);
  EXPECT_THROW(drawLegend(image, 10, 10, {{Rgb{}, "a"}}, 0), InvalidParameterError);
  EXPECT_THROW(segmentLegend({PrimitiveType::plane}, {}, 0), InvalidParameterError);
  EXPECT_EQ(legendScale(480), 1);
  EXPECT_EQ(legendScale(768), 1);
  EXPECT_EQ(legendScale(1200), 2);
}

}  // namespace
}  // namespace slipfit
