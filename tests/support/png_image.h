#pragma once
/// \file Reads a PNG into 8-bit RGB with libpng's simplified API (tests only), and what a test
/// asks of a picture: how much of it the scene covers and in how many colours.

#include <png.h>

#include <algorithm>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace slipfit::testing {

struct RgbImage {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgb;  ///< rows top to bottom, 3 bytes per pixel
};

/// The image of \a path; an empty image (width 0) when libpng cannot read it.
inline RgbImage readPng(const std::string& path) {
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  RgbImage out;
  if (!png_image_begin_read_from_file(&image, path.c_str()))
    return out;
  image.format = PNG_FORMAT_RGB;
  std::vector<std::uint8_t> buffer(PNG_IMAGE_SIZE(image));
  if (!png_image_finish_read(&image, nullptr, buffer.data(), 0, nullptr)) {
    png_image_free(&image);
    return out;
  }
  out.width = static_cast<int>(image.width);
  out.height = static_cast<int>(image.height);
  out.rgb = std::move(buffer);
  return out;
}

/// What a picture of segments shows: the share of its pixels that are not the white background,
/// and the share of those pixels the most common hue holds (1: one colour, whatever its shading:
/// a pixel's colour is taken relative to its brightest channel, in steps of 1/8).
struct PictureCoverage {
  double covered = 0.0;
  double largest_colour = 0.0;
  /// The shares of the image's width and height within the 2nd to 98th percentiles of the
  /// covered pixels' columns and rows (a legend's few pixels in a corner do not count).
  double span_x = 0.0, span_y = 0.0;
};

inline PictureCoverage pictureCoverage(const RgbImage& image) {
  std::map<std::uint32_t, std::size_t> count;
  std::size_t covered = 0;
  std::vector<int> columns, rows;
  for (std::size_t i = 0; i + 2 < image.rgb.size(); i += 3) {
    const std::uint8_t r = image.rgb[i], g = image.rgb[i + 1], b = image.rgb[i + 2];
    if (r == 255 && g == 255 && b == 255)
      continue;
    const unsigned top = std::max({1u, unsigned{r}, unsigned{g}, unsigned{b}});
    const auto step = [&](std::uint8_t v) { return (8u * v + top / 2) / top; };
    const std::uint32_t c = step(r) << 8 | step(g) << 4 | step(b);
    ++covered;
    ++count[c];
    columns.push_back(static_cast<int>(i / 3 % static_cast<std::size_t>(image.width)));
    rows.push_back(static_cast<int>(i / 3 / static_cast<std::size_t>(image.width)));
  }
  PictureCoverage p;
  const std::size_t pixels = static_cast<std::size_t>(image.width) * image.height;
  if (pixels == 0 || covered == 0)
    return p;
  std::size_t largest = 0;
  for (const auto& [c, k] : count)
    largest = std::max(largest, k);
  p.covered = static_cast<double>(covered) / static_cast<double>(pixels);
  p.largest_colour = static_cast<double>(largest) / static_cast<double>(covered);
  const auto extent = [](std::vector<int>& v) {
    const auto at = [&](double q) {
      auto it = v.begin() + static_cast<std::ptrdiff_t>(q * static_cast<double>(v.size() - 1));
      std::nth_element(v.begin(), it, v.end());
      return *it;
    };
    return at(0.98) - at(0.02) + 1;
  };
  p.span_x = static_cast<double>(extent(columns)) / image.width;
  p.span_y = static_cast<double>(extent(rows)) / image.height;
  return p;
}

}  // namespace slipfit::testing
