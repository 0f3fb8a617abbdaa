#pragma once
/// \file The square tiles of an out-of-core run: tile (i, j) owns the core
/// [i·size, (i+1)·size) × [j·size, (j+1)·size) of the x-y plane (aligned to multiples of the size,
/// as LAStools and PDAL tile airborne LiDAR, so that the grid does not depend on the data) and
/// also reads the band of width `buffer` around its core, where its segments meet those of its
/// neighbours. Every point has exactly one owner; with buffer < size / 2 it lies in at most four
/// tiles.

#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <tuple>

namespace slipfit {

/// Tile (i, j) of the grid, or with level > 0 a quarter-by-quarter split of one (tile_tree.h):
/// cell (i, j) of the grid whose edge is size / 2^level.
struct TileKey {
  std::int64_t i = 0, j = 0;
  int level = 0;
  bool operator<(const TileKey& o) const {
    return std::tie(level, i, j) < std::tie(o.level, o.i, o.j);
  }
  bool operator==(const TileKey& o) const { return i == o.i && j == o.j && level == o.level; }
  bool operator!=(const TileKey& o) const { return !(*this == o); }
};

class TileGrid {
 public:
  /// Throws std::invalid_argument unless size > 0 and 0 ≤ buffer < size / 2 (both finite).
  TileGrid(double size, double buffer) : size_(size), buffer_(buffer) {
    if (!(std::isfinite(size) && size > 0.0 && std::isfinite(buffer) && buffer >= 0.0 &&
          buffer < 0.5 * size))
      throw std::invalid_argument("tiles need size > 0 and 0 <= buffer < size / 2");
  }
  double size() const { return size_; }
  double buffer() const { return buffer_; }

  /// The tile whose core holds (x, y). Throws std::invalid_argument for a coordinate whose tile
  /// index does not fit in 53 bits (non-finite, or beyond 2^53 tiles from the origin).
  TileKey owner(double x, double y) const { return {index(x), index(y)}; }

  /// Calls \a visit(TileKey) for every tile whose core or buffer holds (x, y), the owner among
  /// them, in ascending order.
  template <typename Visit>
  void forEachCovering(double x, double y, Visit&& visit) const {
    const std::int64_t i0 = index(x - buffer_), i1 = index(x + buffer_);
    const std::int64_t j0 = index(y - buffer_), j1 = index(y + buffer_);
    const TileKey own = owner(x, y);  // always visited, whatever the rounding at its edges
    for (std::int64_t i = i0; i <= i1; ++i)
      for (std::int64_t j = j0; j <= j1; ++j)
        if (TileKey{i, j} == own || covers({i, j}, x, y))
          visit(TileKey{i, j});
  }

  /// Whether (x, y) lies in tile \a t's core expanded by the buffer (half-open, as the core).
  bool covers(TileKey t, double x, double y) const {
    const double lo_x = static_cast<double>(t.i) * size_ - buffer_;
    const double lo_y = static_cast<double>(t.j) * size_ - buffer_;
    const double hi_x = static_cast<double>(t.i + 1) * size_ + buffer_;
    const double hi_y = static_cast<double>(t.j + 1) * size_ + buffer_;
    return x >= lo_x && x < hi_x && y >= lo_y && y < hi_y;
  }

 private:
  std::int64_t index(double v) const {
    const double t = std::floor(v / size_);
    constexpr double kLimit = 9007199254740992.0;  // 2^53
    if (!(std::abs(t) < kLimit))
      throw std::invalid_argument("coordinate outside the tile grid");
    return static_cast<std::int64_t>(t);
  }

  double size_, buffer_;
};

}  // namespace slipfit
