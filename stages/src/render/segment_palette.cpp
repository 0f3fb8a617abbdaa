#include "slipfit/render/segment_palette.h"

#include <cmath>

namespace slipfit {

namespace {

constexpr std::array<Rgb, 12> kFirst{{{31, 119, 180},
                                      {255, 127, 14},
                                      {44, 160, 44},
                                      {214, 39, 40},
                                      {148, 103, 189},
                                      {140, 86, 75},
                                      {227, 119, 194},
                                      {188, 189, 34},
                                      {23, 190, 207},
                                      {255, 187, 120},
                                      {152, 223, 138},
                                      {197, 176, 213}}};

Rgb fromHsv(double h, double s, double v) {
  const double c = v * s, hp = h * 6.0;
  const double x = c * (1.0 - std::abs(std::fmod(hp, 2.0) - 1.0));
  double r = 0, g = 0, b = 0;
  switch (static_cast<int>(hp) % 6) {
    case 0:
      r = c, g = x;
      break;
    case 1:
      r = x, g = c;
      break;
    case 2:
      g = c, b = x;
      break;
    case 3:
      g = x, b = c;
      break;
    case 4:
      r = x, b = c;
      break;
    default:
      r = c, b = x;
      break;
  }
  const double m = v - c;
  auto byte = [&](double t) { return static_cast<std::uint8_t>(std::lround(255.0 * (t + m))); };
  return {byte(r), byte(g), byte(b)};
}

}  // namespace

Rgb segmentColour(std::size_t k) {
  if (k < kFirst.size())
    return kFirst[k];
  // Golden-angle hue steps never repeat and stay spread; the three levels alternate so that
  // neighbouring indices differ in brightness too.
  constexpr double kGolden = 0.6180339887498949;
  constexpr double kSaturation[] = {0.75, 0.55, 0.95};
  constexpr double kValue[] = {0.90, 0.70, 0.55};
  const std::size_t j = k - kFirst.size();
  const double hue = std::fmod(0.07 + static_cast<double>(j) * kGolden, 1.0);
  return fromHsv(hue, kSaturation[j % 3], kValue[j % 3]);
}

}  // namespace slipfit
