#include "slipfit/neighborhoods/spatial_order.h"

#include "slipfit/neighborhoods/neighborhood_selection.h"
#include "slipfit/sampling/random_vector.h"

#include <gtest/gtest.h>

#include <iostream>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <random>

namespace slipfit {
namespace {

using XyzCloud = pcl::PointCloud<pcl::PointXYZ>;

/// \a n points on a 1 cm lattice in a cube of \a cells cells a side, in random order: many equal
/// distances, so that the lists' ties are tested too.
XyzCloud::Ptr shuffledLattice(std::size_t n, std::uint64_t seed, int cells = 100) {
  auto c = std::make_shared<XyzCloud>();
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<int> cell(0, cells - 1);
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3i v = randomVector<3>(cell, rng);
    c->push_back(pcl::PointXYZ(0.01f * v.x(), 0.01f * v.y(), 0.01f * v.z()));
  }
  return c;
}

double meanStep(const XyzCloud& c, const pcl::Indices& order) {
  double sum = 0.0;
  for (std::size_t k = 1; k < order.size(); ++k)
    sum += (c[order[k]].getVector3fMap() - c[order[k - 1]].getVector3fMap()).norm();
  return sum / static_cast<double>(order.size() - 1);
}

TEST(SpatialOrder, IsAPermutationWithNearPointsNextToEachOtherAndNonFiniteLast) {
  auto cloud = shuffledLattice(20000, 1);
  (*cloud)[5].y = std::numeric_limits<float>::quiet_NaN();
  (*cloud)[11].z = std::numeric_limits<float>::infinity();
  cloud->is_dense = false;
  pcl::Indices all(cloud->size());
  std::iota(all.begin(), all.end(), 0);
  const pcl::Indices order = spatialOrder(*cloud, all);
  pcl::Indices sorted = order;
  std::sort(sorted.begin(), sorted.end());
  EXPECT_EQ(sorted, all);
  ASSERT_EQ(order.size(), all.size());
  EXPECT_EQ(order[order.size() - 2], 5);  // non-finite last, in the given order
  EXPECT_EQ(order.back(), 11);
  EXPECT_EQ(spatialOrder(*cloud, all), order);  // the same input, the same order

  // Uniform points in a unit cube: consecutive ones in file order are 0.66 apart on average (the
  // mean distance of two random points); along a Morton curve a step is the spacing N^(-1/3) =
  // 0.037 times a small factor for the curve's jumps between octants (measured 1.30: 0.048).
  // Sorting by one coordinate only would give steps of about 0.3.
  const pcl::Indices finite(order.begin(), order.end() - 2);
  const pcl::Indices file_order(all.begin() + 12, all.end());
  EXPECT_GT(meanStep(*cloud, file_order), 0.5);
  EXPECT_LT(meanStep(*cloud, finite), 2.0 * std::cbrt(1.0 / 20000.0));
}

TEST(SpatialOrder, KeepsTheGivenIndicesOnly) {
  const auto cloud = shuffledLattice(1000, 2);
  const pcl::Indices some = {900, 3, 3, 500, 42};
  pcl::Indices order = spatialOrder(*cloud, some);
  std::sort(order.begin(), order.end());
  EXPECT_EQ(order, (pcl::Indices{3, 3, 42, 500, 900}));
}

// knn lists are searched in spatial order and written in place; hybrid lists with an unbounded
// radius are the same k nearest, searched in cloud order and appended. The two agree entry for
// entry (ties by index included), with non-finite points and a subset of queries. 8,000 points
// on 25³ lattice nodes: most lists hold two neighbours at the same distance, the ties whose order
// is compared.
TEST(SpatialOrder, KnnListsSearchedInSpatialOrderEqualThoseSearchedInCloudOrder) {
  constexpr int kPoints = 8000;
  auto cloud = shuffledLattice(kPoints, 3, 25);
  for (const int i : {17, 2048, kPoints - 1})
    (*cloud)[static_cast<std::size_t>(i)].x = std::numeric_limits<float>::quiet_NaN();
  cloud->is_dense = false;
  auto subset = std::make_shared<pcl::Indices>();
  for (int i = 0; i < kPoints; i += 3)
    subset->push_back(i);
  for (const bool all : {true, false}) {
    Neighborhoods lists[2];
    std::size_t queries[2];
    for (int path = 0; path < 2; ++path) {
      NeighborhoodParameters p;
      p.k = 16;
      p.threads = 2;
      p.span_noise = false;
      if (path == 1) {
        p.mode = NeighborhoodMode::hybrid;
        p.radius = 1e30;
      }
      NeighborhoodSelection<pcl::PointXYZ> s;
      s.setParameters(p);
      s.setInputCloud(cloud);
      if (!all)
        s.setIndices(subset);
      s.compute(lists[path]);
      queries[path] = s.statistics().queries;
    }
    EXPECT_EQ(queries[0], queries[1]);
    ASSERT_EQ(lists[0].size(), lists[1].size());
    ASSERT_EQ(lists[0].entries(), lists[1].entries());
    std::size_t tied = 0, listed = 0;
    for (std::size_t i = 0; i < lists[0].size(); ++i) {
      const NeighborView a = lists[0][i], b = lists[1][i];
      ASSERT_EQ(a.size(), b.size()) << "point " << i;
      bool tie = false;
      for (std::size_t j = 0; j < a.size(); ++j) {
        ASSERT_EQ(a[j], b[j]) << "point " << i << " rank " << j;
        ASSERT_EQ(a.sqr_distances[j], b.sqr_distances[j]);
        tie = tie || (j > 0 && a.sqr_distances[j] == a.sqr_distances[j - 1]);
      }
      tied += tie ? 1 : 0;
      listed += a.size() > 0 ? 1 : 0;
    }
    std::cout << tied << " of " << listed << " lists hold a tie\n";
    EXPECT_GT(2 * tied, listed) << "too few ties to test their order";
  }
}

}  // namespace
}  // namespace slipfit
