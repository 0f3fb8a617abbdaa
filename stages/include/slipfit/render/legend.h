#pragma once
/// \file A legend drawn into an RGB image: one row per entry, a swatch of its colour and a line of
/// text in a 5 × 7 pixel font (upper-case letters, digits and . , : - # ( ) / %), on a white panel
/// in the top-left corner. No I/O: the image is a w × h × 3 byte array, rows top to bottom.

#include "slipfit/fitting/primitives.h"
#include "slipfit/render/segment_palette.h"

#include <cstdint>
#include <string>
#include <vector>

namespace slipfit {

struct LegendEntry {
  Rgb colour;
  std::string text;  ///< lower-case letters are drawn upper-case; other characters as blanks
};

/// Draws \a entries into \a image (\a width × \a height × 3 bytes) at \a scale pixels per font
/// pixel (≥ 1), in at most \a max_rows rows. Rows past that or past the image's height are left
/// out, the last row then saying how many were ("+ 12 MORE"). Throws InvalidParameterError when
/// the image's size does not match or \a scale < 1. Returns the number of entries drawn.
std::size_t drawLegend(std::vector<std::uint8_t>& image, int width, int height,
                       const std::vector<LegendEntry>& entries, int scale,
                       std::size_t max_rows = static_cast<std::size_t>(-1));

/// The legend of segments 0 … n − 1 of \a types with their \a points: "ID TYPE POINTS" in the
/// segment's colour (segmentColour), largest first (ties by id), then the points in no segment in
/// their grey when \a unassigned > 0.
std::vector<LegendEntry> segmentLegend(const std::vector<PrimitiveType>& types,
                                       const std::vector<std::size_t>& points,
                                       std::size_t unassigned);
/// The same with each segment's type by name (a kinematic segment's "revolution", ...).
std::vector<LegendEntry> segmentLegend(const std::vector<std::string>& type_names,
                                       const std::vector<std::size_t>& points,
                                       std::size_t unassigned);

/// The rows of the pictures' legends: the 19 largest segments, then "+ N more" (a legend of every
/// segment of a scan would cover its picture).
constexpr std::size_t kLegendRows = 20;

/// The font scale for an image \a height pixels high: 1 (7-pixel glyphs) under 1200 pixels, 2
/// under 1800, and so on.
int legendScale(int height);

}  // namespace slipfit
