#include "slipfit/neighborhoods/grid_search.h"

#include <string>

namespace slipfit {

void PixelGrid::check(std::size_t points) const {
  if (cells.size() != points)
    throw InvalidParameterError("pixel grid: " + std::to_string(cells.size()) +
                                " cells for a cloud of " + std::to_string(points) + " points");
  const std::size_t size = static_cast<std::size_t>(width) * height;
  std::vector<char> taken(size, 0);
  for (std::size_t i = 0; i < cells.size(); ++i) {
    const std::int32_t c = cells[i];
    if (c < 0 || static_cast<std::size_t>(c) >= size)
      throw InvalidParameterError("pixel grid: point " + std::to_string(i) + "'s cell " +
                                  std::to_string(c) + " lies outside the " + std::to_string(width) +
                                  " x " + std::to_string(height) + " image");
    if (taken[static_cast<std::size_t>(c)]++)
      throw InvalidParameterError("pixel grid: cell " + std::to_string(c) +
                                  " holds two points (the second is point " + std::to_string(i) +
                                  ")");
  }
}

}  // namespace slipfit
