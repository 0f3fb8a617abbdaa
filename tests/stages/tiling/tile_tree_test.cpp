// Tiles split into quarters where they are dense (tile_tree.h): the leaves still partition the
// plane (each point has one owner, which holds it in its core), a point is listed by exactly the
// leaves whose buffered cores hold it, and a tree is rebuilt from its leaves alone.

#include "slipfit/tiling/tile_tree.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <set>
#include <stdexcept>
#include <vector>

namespace slipfit {
namespace {

constexpr double kSize = 8.0, kBuffer = 0.7;

/// Splits grid tile (0, 0) into quarters, its quarter (1, 1) again, and that one's (2, 3) again
/// (edges 4, 2 and 1: 1 > 2 · 0.7 is false, so the last split is refused), and grid tile (-1, 0)
/// once.
TileTree unevenTree() {
  TileTree tree(TileGrid(kSize, kBuffer));
  tree.split({0, 0, 0});
  tree.split({1, 1, 1});
  tree.split({-1, 0, 0});
  return tree;
}

/// Every leaf of \a tree over grid tiles [-2, 1] × [-2, 1].
std::vector<TileKey> leavesOf(const TileTree& tree) {
  std::vector<TileKey> leaves, todo;
  for (std::int64_t i = -2; i <= 1; ++i)
    for (std::int64_t j = -2; j <= 1; ++j)
      todo.push_back({i, j, 0});
  while (!todo.empty()) {
    const TileKey t = todo.back();
    todo.pop_back();
    if (!tree.isSplit(t)) {
      leaves.push_back(t);
      continue;
    }
    for (const TileKey& q : TileTree::quarters(t))
      todo.push_back(q);
  }
  return leaves;
}

TEST(TileTree, EveryPointHasOneOwnerLeafAndIsListedByTheLeavesWithinTheBuffer) {
  const TileTree tree = unevenTree();
  const std::vector<TileKey> leaves = leavesOf(tree);
  // 14 grid tiles unsplit; (0, 0): 3 quarters and the 4 of its quarter (1, 1); (-1, 0): 4.
  EXPECT_EQ(leaves.size(), 14u + 3 + 4 + 4);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-15.0, 15.0);
  std::size_t in_quarters = 0;
  for (int k = 0; k < 40000; ++k) {
    const double x = u(rng), y = u(rng);
    const TileKey own = tree.owner(x, y);
    ASSERT_FALSE(tree.isSplit(own));
    const double e = tree.edge(own.level);
    EXPECT_LE(static_cast<double>(own.i) * e, x);
    EXPECT_GT(static_cast<double>(own.i + 1) * e, x);
    EXPECT_LE(static_cast<double>(own.j) * e, y);
    EXPECT_GT(static_cast<double>(own.j + 1) * e, y);
    in_quarters += own.level > 0 ? 1 : 0;
    std::vector<TileKey> listed;
    tree.forEachCovering(x, y, [&](TileKey t) { listed.push_back(t); });
    EXPECT_EQ(std::count(listed.begin(), listed.end(), own), 1);
    EXPECT_LE(listed.size(), 4u);  // quarters wider than twice the buffer
    // Exactly the leaves whose cores expanded by the buffer hold the point (brute force).
    for (const TileKey& leaf : leaves) {
      const bool is_listed = std::count(listed.begin(), listed.end(), leaf) == 1;
      EXPECT_EQ(is_listed, tree.covers(leaf, x, y))
          << x << " " << y << " leaf " << leaf.i << " " << leaf.j << " " << leaf.level;
    }
  }
  // The split grid tiles [0, 8) × [0, 8) and [-8, 0) × [0, 8) cover 2 · 8 · 8 of the 30 × 30
  // drawn (binomial σ 0.0018).
  EXPECT_NEAR(static_cast<double>(in_quarters) / 40000.0, 128.0 / 900.0, 0.01);
}

TEST(TileTree, QuartersAreSplitOnlyWhileWiderThanTwiceTheBuffer) {
  TileTree tree = unevenTree();
  const TileKey quarter{2, 3, 2};  // edge 2 > 1.4: splittable; its quarters' edge 1 < 1.4
  EXPECT_TRUE(tree.splittable({1, 1, 1}));
  EXPECT_FALSE(tree.splittable(quarter));
  EXPECT_THROW(tree.split(quarter), std::invalid_argument);
  EXPECT_THROW(tree.split({0, 0, 0}), std::invalid_argument);  // already split
  EXPECT_THROW(tree.split({5, 5, 1}), std::invalid_argument);  // its parent (2, 2) is not
  EXPECT_EQ(TileTree::ancestor({-3, 5, 2}, 0), (TileKey{-1, 1, 0}));
  EXPECT_EQ(TileTree::ancestor({-4, 4, 2}, 1), (TileKey{-2, 2, 1}));
}

TEST(TileTree, TwoTilesOverlapWhereTheirBufferedCoresMeet) {
  const TileTree tree = unevenTree();
  EXPECT_TRUE(tree.overlap({0, 0, 1}, {1, 0, 1}));    // side by side
  EXPECT_TRUE(tree.overlap({0, 1, 1}, {-1, 0, 0}));   // a quarter and the grid tile beside
  EXPECT_TRUE(tree.overlap({2, 2, 2}, {1, 0, 1}));    // a quarter's quarter on a quarter
  EXPECT_TRUE(tree.overlap({2, 2, 2}, {0, 0, 1}));    // corner to corner, across the buffers
  EXPECT_FALSE(tree.overlap({1, 1, 1}, {-1, 0, 0}));  // 4 apart
  EXPECT_FALSE(tree.overlap({3, 3, 2}, {0, 0, 1}));   // 4 apart, buffers 0.7 each
  EXPECT_FALSE(tree.overlap({0, 0, 0}, {2, 0, 0}));
}

TEST(TileTree, IsRebuiltFromTheLeavesThatOwnPoints) {
  const TileTree tree = unevenTree();
  // Only some leaves own points: the splits are those of their ancestors.
  const std::vector<TileKey> owning = {{3, 3, 2}, {0, 1, 1}, {-1, -1, 0}, {-2, 0, 1}};
  const TileTree rebuilt = TileTree::fromLeaves(TileGrid(kSize, kBuffer), owning);
  EXPECT_EQ(rebuilt.splits(), (std::set<TileKey>{{0, 0, 0}, {1, 1, 1}, {-1, 0, 0}}));
  EXPECT_EQ(rebuilt.splits(), tree.splits());
  EXPECT_THROW(TileTree::fromLeaves(TileGrid(kSize, kBuffer), {{0, 0, 0}, {1, 1, 1}}),
               std::invalid_argument);  // a tile and its quarter
}

}  // namespace
}  // namespace slipfit
