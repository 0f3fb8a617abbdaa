#include "slipfit/render/legend.h"

#include "slipfit/core/exceptions.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cstddef>
#include <numeric>

namespace slipfit {

namespace {

/// A glyph: seven rows of five pixels, the most significant of the five bits on the left.
using Glyph = std::array<std::uint8_t, 7>;

struct GlyphOf {
  char c;
  Glyph rows;
};

// The classic 5 × 7 dot-matrix shapes.
constexpr GlyphOf kFont[] = {
    {'0', {0x0E, 0x11, 0x13, 0x15, 0x19, 0x11, 0x0E}},
    {'1', {0x04, 0x0C, 0x04, 0x04, 0x04, 0x04, 0x0E}},
    {'2', {0x0E, 0x11, 0x01, 0x02, 0x04, 0x08, 0x1F}},
    {'3', {0x1F, 0x02, 0x04, 0x02, 0x01, 0x11, 0x0E}},
    {'4', {0x02, 0x06, 0x0A, 0x12, 0x1F, 0x02, 0x02}},
    {'5', {0x1F, 0x10, 0x1E, 0x01, 0x01, 0x11, 0x0E}},
    {'6', {0x06, 0x08, 0x10, 0x1E, 0x11, 0x11, 0x0E}},
    {'7', {0x1F, 0x01, 0x02, 0x04, 0x08, 0x08, 0x08}},
    {'8', {0x0E, 0x11, 0x11, 0x0E, 0x11, 0x11, 0x0E}},
    {'9', {0x0E, 0x11, 0x11, 0x0F, 0x01, 0x02, 0x0C}},
    {'A', {0x0E, 0x11, 0x11, 0x1F, 0x11, 0x11, 0x11}},
    {'B', {0x1E, 0x11, 0x11, 0x1E, 0x11, 0x11, 0x1E}},
    {'C', {0x0E, 0x11, 0x10, 0x10, 0x10, 0x11, 0x0E}},
    {'D', {0x1C, 0x12, 0x11, 0x11, 0x11, 0x12, 0x1C}},
    {'E', {0x1F, 0x10, 0x10, 0x1E, 0x10, 0x10, 0x1F}},
    {'F', {0x1F, 0x10, 0x10, 0x1E, 0x10, 0x10, 0x10}},
    {'G', {0x0E, 0x11, 0x10, 0x17, 0x11, 0x11, 0x0F}},
    {'H', {0x11, 0x11, 0x11, 0x1F, 0x11, 0x11, 0x11}},
    {'I', {0x0E, 0x04, 0x04, 0x04, 0x04, 0x04, 0x0E}},
    {'J', {0x07, 0x02, 0x02, 0x02, 0x02, 0x12, 0x0C}},
    {'K', {0x11, 0x12, 0x14, 0x18, 0x14, 0x12, 0x11}},
    {'L', {0x10, 0x10, 0x10, 0x10, 0x10, 0x10, 0x1F}},
    {'M', {0x11, 0x1B, 0x15, 0x15, 0x11, 0x11, 0x11}},
    {'N', {0x11, 0x11, 0x19, 0x15, 0x13, 0x11, 0x11}},
    {'O', {0x0E, 0x11, 0x11, 0x11, 0x11, 0x11, 0x0E}},
    {'P', {0x1E, 0x11, 0x11, 0x1E, 0x10, 0x10, 0x10}},
    {'Q', {0x0E, 0x11, 0x11, 0x11, 0x15, 0x12, 0x0D}},
    {'R', {0x1E, 0x11, 0x11, 0x1E, 0x14, 0x12, 0x11}},
    {'S', {0x0F, 0x10, 0x10, 0x0E, 0x01, 0x01, 0x1E}},
    {'T', {0x1F, 0x04, 0x04, 0x04, 0x04, 0x04, 0x04}},
    {'U', {0x11, 0x11, 0x11, 0x11, 0x11, 0x11, 0x0E}},
    {'V', {0x11, 0x11, 0x11, 0x11, 0x11, 0x0A, 0x04}},
    {'W', {0x11, 0x11, 0x11, 0x15, 0x15, 0x15, 0x0A}},
    {'X', {0x11, 0x11, 0x0A, 0x04, 0x0A, 0x11, 0x11}},
    {'Y', {0x11, 0x11, 0x11, 0x0A, 0x04, 0x04, 0x04}},
    {'Z', {0x1F, 0x01, 0x02, 0x04, 0x08, 0x10, 0x1F}},
    {'.', {0x00, 0x00, 0x00, 0x00, 0x00, 0x0C, 0x0C}},
    {',', {0x00, 0x00, 0x00, 0x00, 0x0C, 0x04, 0x08}},
    {':', {0x00, 0x0C, 0x0C, 0x00, 0x0C, 0x0C, 0x00}},
    {'-', {0x00, 0x00, 0x00, 0x1F, 0x00, 0x00, 0x00}},
    {'+', {0x00, 0x04, 0x04, 0x1F, 0x04, 0x04, 0x00}},
    {'#', {0x0A, 0x0A, 0x1F, 0x0A, 0x1F, 0x0A, 0x0A}},
    {'(', {0x02, 0x04, 0x08, 0x08, 0x08, 0x04, 0x02}},
    {')', {0x08, 0x04, 0x02, 0x02, 0x02, 0x04, 0x08}},
    {'/', {0x00, 0x01, 0x02, 0x04, 0x08, 0x10, 0x00}},
    {'%', {0x18, 0x19, 0x02, 0x04, 0x08, 0x13, 0x03}},
};

const Glyph* glyphOf(char c) {
  const char upper = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  for (const GlyphOf& g : kFont)
    if (g.c == upper)
      return &g.rows;
  return nullptr;  // a blank
}

constexpr int kGlyphWidth = 5, kGlyphHeight = 7, kAdvance = 6;  // font pixels
constexpr std::uint8_t kPanel[3] = {255, 255, 255}, kInk[3] = {20, 20, 20};

class Canvas {
 public:
  Canvas(std::vector<std::uint8_t>& image, int width, int height)
      : image_(image), width_(width), height_(height) {}
  void fill(int x0, int y0, int w, int h, const std::uint8_t* rgb) {
    for (int y = std::max(0, y0); y < std::min(height_, y0 + h); ++y)
      for (int x = std::max(0, x0); x < std::min(width_, x0 + w); ++x)
        std::copy(rgb, rgb + 3, image_.begin() + 3 * (static_cast<std::ptrdiff_t>(y) * width_ + x));
  }
  /// Text at (x0, y0), its top-left corner; returns its width in pixels.
  int text(int x0, int y0, const std::string& s, int scale) {
    for (std::size_t k = 0; k < s.size(); ++k) {
      const Glyph* g = glyphOf(s[k]);
      if (!g)
        continue;
      const int left = x0 + static_cast<int>(k) * kAdvance * scale;
      for (int row = 0; row < kGlyphHeight; ++row)
        for (int col = 0; col < kGlyphWidth; ++col)
          if ((*g)[static_cast<std::size_t>(row)] >> (kGlyphWidth - 1 - col) & 1)
            fill(left + col * scale, y0 + row * scale, scale, scale, kInk);
    }
    return static_cast<int>(s.size()) * kAdvance * scale;
  }

 private:
  std::vector<std::uint8_t>& image_;
  int width_, height_;
};

}  // namespace

std::size_t drawLegend(std::vector<std::uint8_t>& image, int width, int height,
                       const std::vector<LegendEntry>& entries, int scale, std::size_t max_rows) {
  if (width < 1 || height < 1 ||
      image.size() != static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 3)
    throw InvalidParameterError("legend: the image is not width × height × 3 bytes");
  if (scale < 1)
    throw InvalidParameterError("legend: scale must be at least 1");
  if (entries.empty())
    return 0;
  const int margin = 2 * scale, row = (kGlyphHeight + 3) * scale, swatch = kGlyphHeight * scale;
  const int fit = std::max(0, (height - 2 * margin) / row);
  std::size_t shown =
      std::min({entries.size(), static_cast<std::size_t>(fit), std::max<std::size_t>(max_rows, 1)});
  const bool more = shown < entries.size();
  if (more && shown > 0)
    --shown;  // the last row that fits says how many were left out
  const std::string more_text = "+ " + std::to_string(entries.size() - shown) + " more";
  std::size_t longest = more ? more_text.size() : 0;
  for (std::size_t k = 0; k < shown; ++k)
    longest = std::max(longest, entries[k].text.size());
  const int text_x = margin + swatch + 2 * scale;
  const int panel_w = text_x + static_cast<int>(longest) * kAdvance * scale + margin;
  const int rows = static_cast<int>(shown) + (more ? 1 : 0);
  Canvas canvas(image, width, height);
  canvas.fill(0, 0, panel_w, 2 * margin + rows * row, kPanel);
  for (std::size_t k = 0; k < shown; ++k) {
    const int y = margin + static_cast<int>(k) * row + scale;
    canvas.fill(margin, y, swatch, swatch, entries[k].colour.data());
    canvas.text(text_x, y, entries[k].text, scale);
  }
  if (more)
    canvas.text(text_x, margin + static_cast<int>(shown) * row + scale, more_text, scale);
  return shown;
}

std::vector<LegendEntry> segmentLegend(const std::vector<PrimitiveType>& types,
                                       const std::vector<std::size_t>& points,
                                       std::size_t unassigned) {
  std::vector<std::string> names;
  names.reserve(types.size());
  for (const PrimitiveType t : types)
    names.emplace_back(primitiveTypeName(t));
  return segmentLegend(names, points, unassigned);
}

std::vector<LegendEntry> segmentLegend(const std::vector<std::string>& type_names,
                                       const std::vector<std::size_t>& points,
                                       std::size_t unassigned) {
  if (type_names.size() != points.size())
    throw InvalidParameterError("legend: one type and one point count per segment");
  std::vector<std::size_t> order(type_names.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return points[a] > points[b]; });
  std::vector<LegendEntry> entries;
  entries.reserve(order.size() + 1);
  for (const std::size_t k : order)
    entries.push_back({segmentColour(k),
                       std::to_string(k) + " " + type_names[k] + " " + std::to_string(points[k])});
  if (unassigned > 0)
    entries.push_back({kUnassignedColour, "- none " + std::to_string(unassigned)});
  return entries;
}

int legendScale(int height) {
  return std::max(1, height / 600);
}

}  // namespace slipfit
