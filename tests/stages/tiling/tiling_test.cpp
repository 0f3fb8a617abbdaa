// The tile grid, the joining of tile segments and the voxel counts that tiles add up: the
// properties a tiled run rests on (each point owned once, counts additive, joins symmetric).

#include "slipfit/filters/subsampling.h"
#include "slipfit/tiling/segment_joining.h"
#include "slipfit/tiling/tile_grid.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <random>
#include <set>
#include <stdexcept>

namespace slipfit {
namespace {

TEST(TileGrid, EveryPointHasOneOwnerAmongTheTilesThatCoverIt) {
  const TileGrid grid(10.0, 1.5);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-55.0, 55.0);
  for (int k = 0; k < 20000; ++k) {
    const double x = u(rng), y = u(rng);
    const TileKey own = grid.owner(x, y);
    // The owner's core holds the point: [i·size, (i+1)·size).
    EXPECT_LE(static_cast<double>(own.i) * 10.0, x);
    EXPECT_GT(static_cast<double>(own.i + 1) * 10.0, x);
    std::vector<TileKey> covering;
    grid.forEachCovering(x, y, [&](TileKey t) { covering.push_back(t); });
    ASSERT_FALSE(covering.empty());
    EXPECT_LE(covering.size(), 4u);  // buffer < size / 2: at most two tiles along each axis
    EXPECT_EQ(std::count(covering.begin(), covering.end(), own), 1);
    // Exactly the tiles within the buffer of the point's position.
    for (std::int64_t i = own.i - 1; i <= own.i + 1; ++i)
      for (std::int64_t j = own.j - 1; j <= own.j + 1; ++j) {
        const double dx = std::max(
            {static_cast<double>(i) * 10.0 - x, 0.0, x - static_cast<double>(i + 1) * 10.0});
        const double dy = std::max(
            {static_cast<double>(j) * 10.0 - y, 0.0, y - static_cast<double>(j + 1) * 10.0});
        const bool inside = std::max(dx, dy) < 1.5 - 1e-9;
        const bool outside = std::max(dx, dy) > 1.5 + 1e-9;
        const bool listed =
            std::find(covering.begin(), covering.end(), TileKey{i, j}) != covering.end();
        if (inside)
          EXPECT_TRUE(listed) << x << " " << y << " tile " << i << " " << j;
        if (outside)
          EXPECT_FALSE(listed) << x << " " << y << " tile " << i << " " << j;
      }
  }
  EXPECT_THROW(TileGrid(10.0, 5.0), std::invalid_argument);
  EXPECT_THROW(TileGrid(0.0, 0.0), std::invalid_argument);
  EXPECT_THROW(grid.owner(std::nan(""), 0.0), std::invalid_argument);
}

TEST(SegmentJoining, CountsTheSharedRowsOfTwoTiles) {
  // Rows 5..9 are shared; A labels them 0 0 0 1 −1, B labels them 4 4 4 4 4.
  const std::vector<std::uint64_t> rows_a = {1, 2, 5, 6, 7, 8, 9};
  const std::vector<std::int32_t> labels_a = {0, 0, 0, 0, 0, 1, -1};
  const std::vector<std::uint64_t> rows_b = {5, 6, 7, 8, 9, 12};
  const std::vector<std::int32_t> labels_b = {4, 4, 4, 4, 4, 4};
  const OverlapCounts c = countOverlap(rows_a, labels_a, rows_b, labels_b);
  EXPECT_EQ(c.shared, 5u);
  EXPECT_EQ(c.in_a.at(0), 3u);
  EXPECT_EQ(c.in_a.at(1), 1u);
  EXPECT_EQ(c.in_b.at(4), 5u);
  EXPECT_EQ(c.both.at({0, 4}), 3u);
  EXPECT_EQ(c.both.at({1, 4}), 1u);
  EXPECT_THROW(countOverlap({3, 2}, {0, 0}, rows_b, labels_b), std::invalid_argument);
  EXPECT_THROW(countOverlap({1}, {0, 0}, rows_b, labels_b), std::invalid_argument);
}

TEST(SegmentJoining, JoinsOnAMajorityOfBothSidesAndOneType) {
  OverlapCounts c;
  // A's 0 and B's 0: the same shape (40 of 42 and 40 of 41 shared points agree).
  // B's 1 holds A's 1 and A's 2 (two shapes wrongly one segment in B): 30 + 12 of 42.
  c.both = {{{0, 0}, 40}, {{1, 1}, 30}, {{2, 1}, 12}, {{3, 2}, 5}};
  c.in_a = {{0, 42}, {1, 31}, {2, 12}, {3, 5}};
  c.in_b = {{0, 41}, {1, 42}, {2, 5}};
  const std::vector<int> planes = {0, 0, 0, 0};
  const auto joins = segmentsToJoin(c, planes, {0, 0, 0});
  // 0–0 joins; 1–1 joins (30 ≥ half of 31 and of 42); 2–1 does not (12 < 21): B's wrong union
  // takes only the larger shape; 3–2 has too few points (5 < 10).
  EXPECT_EQ(joins, (std::vector<std::pair<std::int32_t, std::int32_t>>{{0, 0}, {1, 1}}));
  // Another type never joins.
  const auto typed = segmentsToJoin(c, {0, 2, 0, 0}, {0, 0, 0});
  EXPECT_EQ(typed, (std::vector<std::pair<std::int32_t, std::int32_t>>{{0, 0}}));
}

TEST(SegmentJoining, DisjointSetsAreRepresentedByTheirSmallestMember) {
  DisjointSets s(6);
  s.join(5, 3);
  s.join(3, 4);
  s.join(1, 2);
  EXPECT_EQ(s.find(5), 3u);
  EXPECT_EQ(s.find(4), 3u);
  EXPECT_EQ(s.find(2), 1u);
  s.join(4, 2);
  for (std::size_t k = 1; k < 6; ++k)
    EXPECT_EQ(s.find(k), 1u);
  EXPECT_EQ(s.find(0), 0u);
}

/// A cloud on three planes over 40 × 30 units: points of the xy-plane, a wall and a ramp.
Eigen::Matrix3Xd plantedCloud(int n) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Eigen::Matrix3Xd p(3, n);
  for (int k = 0; k < n; ++k) {
    const double a = 40.0 * u(rng) - 7.0, b = 30.0 * u(rng) - 3.0;
    switch (k % 3) {
      case 0:
        p.col(k) << a, b, 0.0;
        break;
      case 1:
        p.col(k) << a, 12.5, 0.1 * b;
        break;
      default:
        p.col(k) << a, b, 0.2 * a + 1.0;
        break;
    }
  }
  return p;
}

TEST(TiledVoxelCounts, TilesCountingTheVoxelsOfTheirCoresAddUpToTheWholeCloud) {
  const Eigen::Matrix3Xd cloud = plantedCloud(60000);
  const Eigen::Matrix3Xf whole = cloud.cast<float>();
  const Eigen::Matrix3Xd exact = whole.cast<double>();  // the values a float file holds
  const TileGrid grid(10.0, 1.0);
  const Eigen::Vector3d origin = exact.rowwise().minCoeff();  // the untiled run's grid corner
  // Each tile holds its core and buffer, as the tiler writes it.
  std::map<TileKey, std::vector<Eigen::Index>> members;
  for (Eigen::Index k = 0; k < exact.cols(); ++k)
    grid.forEachCovering(exact(0, k), exact(1, k), [&](TileKey t) { members[t].push_back(k); });
  const auto tileSum = [&](double leaf) {
    std::size_t n = 0;
    for (const auto& [key, rows] : members) {
      Eigen::Matrix3Xd part(3, static_cast<Eigen::Index>(rows.size()));
      for (std::size_t r = 0; r < rows.size(); ++r)
        part.col(static_cast<Eigen::Index>(r)) = exact.col(rows[r]);
      const TileKey tile = key;
      n += occupiedVoxels(part, leaf, origin, [&](const Eigen::Vector3d& corner) {
        return grid.owner(corner.x(), corner.y()) == tile;
      });
    }
    return n;
  };
  for (const double leaf : {0.05, 0.2, 0.7})
    EXPECT_EQ(tileSum(leaf), voxelSample(whole, leaf).kept.size()) << leaf;
  // The leaf the tiles choose together is the untiled run's.
  const Subsample untiled = voxelSampleTo(whole, 20000);
  const Eigen::Vector3f sizes = whole.rowwise().maxCoeff() - whole.rowwise().minCoeff();
  EXPECT_EQ(voxelLeafForTarget(sizes.cast<double>(), 20000, tileSum), untiled.leaf);
  // A tile sampled on the whole cloud's grid has, in its core, the untiled run's voxels: each
  // core point is represented by the point that represents it untiled.
  const auto& [key, rows] = *std::max_element(
      members.begin(), members.end(),
      [](const auto& a, const auto& b) { return a.second.size() < b.second.size(); });
  Eigen::Matrix3Xf part(3, static_cast<Eigen::Index>(rows.size()));
  for (std::size_t r = 0; r < rows.size(); ++r)
    part.col(static_cast<Eigen::Index>(r)) = whole.col(rows[r]);
  const Subsample tile = voxelSample(part, untiled.leaf, origin);
  std::size_t core = 0;
  for (std::size_t r = 0; r < rows.size(); ++r) {
    const Eigen::Index u = rows[r];
    if (grid.owner(exact(0, u), exact(1, u)) != key)
      continue;  // a buffer point's voxel may reach beyond the tile
    ++core;
    const std::int32_t rep = tile.representative[r];
    const std::int32_t untiled_rep =
        untiled.kept[static_cast<std::size_t>(untiled.representative[static_cast<std::size_t>(u)])];
    // Same voxel: both representatives are the first of its points, in the same order.
    EXPECT_EQ(rows[static_cast<std::size_t>(tile.kept[static_cast<std::size_t>(rep)])],
              untiled_rep);
  }
  EXPECT_GT(core, 1000u);
}

}  // namespace
}  // namespace slipfit
