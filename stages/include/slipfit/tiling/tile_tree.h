#pragma once
/// \file Tiles bounded by points: the grid's square tiles (tile_grid.h), each split into four
/// quarters, and those again, where a core holds more points than a tile may hold
/// (`tiling.max_points`). The leaves partition the plane as the grid's tiles do: every point has
/// exactly one owner leaf, and each leaf also reads the band of width `buffer` around its core.
/// A tile is split only while its quarters stay wider than twice the buffer, so that a point
/// still lies in at most four leaves.

#include "slipfit/tiling/tile_grid.h"

#include <array>
#include <cmath>
#include <cstdint>
#include <set>
#include <stdexcept>
#include <vector>

namespace slipfit {

class TileTree {
 public:
  /// The deepest level a split may reach (the edge is then size / 2^20).
  static constexpr int kDeepestLevel = 20;

  /// The grid's tiles, none split.
  explicit TileTree(const TileGrid& grid) : grid_(grid) {}

  const TileGrid& grid() const { return grid_; }
  /// The edge of a tile of \a level: size / 2^level.
  double edge(int level) const { return std::ldexp(grid_.size(), -level); }

  /// Whether \a t's quarters would still be wider than twice the buffer.
  bool splittable(const TileKey& t) const {
    return t.level < kDeepestLevel && grid_.buffer() < 0.5 * edge(t.level + 1);
  }
  /// Splits the leaf \a t into its quarters. Throws std::invalid_argument unless \a t is
  /// splittable and a leaf (its ancestors split, itself not).
  void split(const TileKey& t);
  bool isSplit(const TileKey& t) const { return split_.count(t) != 0; }
  /// Every tile that is split (the leaves' ancestors).
  const std::set<TileKey>& splits() const { return split_; }

  /// The four quarters of \a t, ascending.
  static std::array<TileKey, 4> quarters(const TileKey& t);
  /// \a t's ancestor of \a level (\a t itself at its level); level ≤ t.level.
  static TileKey ancestor(const TileKey& t, int level);
  /// The quarter of \a t whose core holds (x, y), for a point of \a t's core.
  TileKey quarterOf(const TileKey& t, double x, double y) const;

  /// The leaf whose core holds (x, y). Throws std::invalid_argument as TileGrid::owner does.
  TileKey owner(double x, double y) const {
    TileKey t = grid_.owner(x, y);
    while (isSplit(t))
      t = quarterOf(t, x, y);
    return t;
  }

  /// Calls \a visit(TileKey) for every leaf whose core or buffer holds (x, y), the owner among
  /// them (whatever the rounding at its edges).
  template <typename Visit>
  void forEachCovering(double x, double y, Visit&& visit) const {
    const TileKey own = owner(x, y);
    grid_.forEachCovering(x, y, [&](TileKey base) { visitLeaves(base, own, x, y, visit); });
  }

  /// Whether (x, y) lies in \a t's core expanded by the buffer (half-open, as the core).
  bool covers(const TileKey& t, double x, double y) const {
    const double e = edge(t.level), b = grid_.buffer();
    return x >= static_cast<double>(t.i) * e - b && x < static_cast<double>(t.i + 1) * e + b &&
           y >= static_cast<double>(t.j) * e - b && y < static_cast<double>(t.j + 1) * e + b;
  }
  /// Whether the cores of \a a and \a b expanded by the buffer overlap: the tiles may share
  /// points.
  bool overlap(const TileKey& a, const TileKey& b) const;

  /// The tree whose leaves include \a leaves: every ancestor of each split. Throws
  /// std::invalid_argument when one of them is another's ancestor or a split it needs is not
  /// splittable.
  static TileTree fromLeaves(const TileGrid& grid, const std::vector<TileKey>& leaves);

 private:
  template <typename Visit>
  void visitLeaves(const TileKey& t, const TileKey& own, double x, double y, Visit& visit) const {
    if (!isSplit(t)) {
      visit(t);
      return;
    }
    for (const TileKey& q : quarters(t))
      if ((own.level >= q.level && ancestor(own, q.level) == q) || covers(q, x, y))
        visitLeaves(q, own, x, y, visit);
  }

  TileGrid grid_;
  std::set<TileKey> split_;
};

}  // namespace slipfit
