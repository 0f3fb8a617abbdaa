#include "slipfit/tiling/tile_tree.h"

#include <algorithm>

namespace slipfit {

namespace {

/// ⌊v / 2^shift⌋ for any sign of v.
std::int64_t floorShift(std::int64_t v, int shift) {
  const std::int64_t d = std::int64_t{1} << shift;
  return v >= 0 ? v / d : -((-v + d - 1) / d);
}

/// The index of v's cell of edge \a e within [first, first + 1]: the two quarters of the cell
/// that holds v one level up (clamped, so that rounding cannot leave the parent).
std::int64_t halfIndex(double v, double e, std::int64_t first) {
  const double t = std::floor(v / e);
  if (!(t >= static_cast<double>(first)))
    return first;
  return t >= static_cast<double>(first + 1) ? first + 1 : first;
}

}  // namespace

void TileTree::split(const TileKey& t) {
  if (!splittable(t))
    throw std::invalid_argument("a tile split into quarters as narrow as twice the buffer");
  if (isSplit(t))
    throw std::invalid_argument("a tile split twice");
  for (int l = 0; l < t.level; ++l)
    if (!isSplit(ancestor(t, l)))
      throw std::invalid_argument("a tile split whose parent is not");
  split_.insert(t);
}

std::array<TileKey, 4> TileTree::quarters(const TileKey& t) {
  const int l = t.level + 1;
  return {TileKey{2 * t.i, 2 * t.j, l}, TileKey{2 * t.i, 2 * t.j + 1, l},
          TileKey{2 * t.i + 1, 2 * t.j, l}, TileKey{2 * t.i + 1, 2 * t.j + 1, l}};
}

TileKey TileTree::ancestor(const TileKey& t, int level) {
  if (level < 0 || level > t.level)
    throw std::invalid_argument("an ancestor below the tile");
  const int shift = t.level - level;
  return {floorShift(t.i, shift), floorShift(t.j, shift), level};
}

TileKey TileTree::quarterOf(const TileKey& t, double x, double y) const {
  const double e = edge(t.level + 1);
  return {halfIndex(x, e, 2 * t.i), halfIndex(y, e, 2 * t.j), t.level + 1};
}

bool TileTree::overlap(const TileKey& a, const TileKey& b) const {
  const double ea = edge(a.level), eb = edge(b.level), r = grid_.buffer();
  const auto meets = [&](std::int64_t ia, std::int64_t ib) {
    const double a_lo = static_cast<double>(ia) * ea - r,
                 a_hi = static_cast<double>(ia + 1) * ea + r;
    const double b_lo = static_cast<double>(ib) * eb - r,
                 b_hi = static_cast<double>(ib + 1) * eb + r;
    return a_lo < b_hi && b_lo < a_hi;
  };
  return meets(a.i, b.i) && meets(a.j, b.j);
}

TileTree TileTree::fromLeaves(const TileGrid& grid, const std::vector<TileKey>& leaves) {
  TileTree tree(grid);
  std::vector<TileKey> sorted = leaves;
  std::sort(sorted.begin(), sorted.end());  // by level: parents are split before their quarters
  for (const TileKey& leaf : sorted)
    for (int l = 0; l < leaf.level; ++l) {
      const TileKey a = ancestor(leaf, l);
      if (!tree.isSplit(a))
        tree.split(a);
    }
  for (const TileKey& leaf : leaves)
    if (tree.isSplit(leaf))
      throw std::invalid_argument("a tile listed with one of its quarters");
  return tree;
}

}  // namespace slipfit
