// NanoflannSearch against brute force and against PCL's own kd-tree: the same neighbours, in the
// same order (distance, then cloud index), with the squared distances PCL computes; non-finite
// points never returned; and a PCL class (NormalEstimation) run with it as its search method.
#include "slipfit/neighborhoods/nanoflann_search.h"
#include "slipfit/sampling/random_vector.h"

#include <gtest/gtest.h>
#include <pcl/features/normal_3d.h>
#include <pcl/point_types.h>
#include <pcl/search/kdtree.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <utility>
#include <vector>

namespace slipfit {
namespace {

using XyzCloud = pcl::PointCloud<pcl::PointXYZ>;

/// \a n points uniform in a unit cube, every 37th non-finite; on a grid of 1/64 (many equal
/// distances) when \a grid; every tenth a copy of an earlier one (exact ties) when \a copies.
XyzCloud::Ptr testCloud(std::size_t n, unsigned seed, bool grid, bool copies = true) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  auto cloud = pcl::make_shared<XyzCloud>();
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3f w = randomVector<3>(u, rng);
    pcl::PointXYZ p(w.x(), w.y(), w.z());
    if (grid)
      p = pcl::PointXYZ(std::round(p.x * 64) / 64, std::round(p.y * 64) / 64,
                        std::round(p.z * 64) / 64);
    if (copies && i % 10 == 9)
      p = (*cloud)[i / 2];
    if (i % 37 == 36)
      p.x = std::numeric_limits<float>::quiet_NaN();
    cloud->push_back(p);
  }
  cloud->is_dense = false;
  return cloud;
}

/// Every finite point of \a cloud with its squared distance to \a q (computed as PCL's L2 does,
/// in float), nearest first, ties by index.
std::vector<std::pair<float, pcl::index_t>> bruteForce(const XyzCloud& cloud,
                                                       const pcl::PointXYZ& q) {
  std::vector<std::pair<float, pcl::index_t>> all;
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const auto& p = cloud[i];
    if (!pcl::isFinite(p))
      continue;
    const float dx = p.x - q.x, dy = p.y - q.y, dz = p.z - q.z;
    all.emplace_back(dx * dx + dy * dy + dz * dz, static_cast<pcl::index_t>(i));
  }
  std::sort(all.begin(), all.end());
  return all;
}

TEST(NanoflannSearch, KNearestAreBruteForcesInItsOrder) {
  for (const bool grid : {false, true}) {
    const XyzCloud::Ptr cloud = testCloud(3000, 5, grid);
    NanoflannSearch<pcl::PointXYZ> search;
    search.setInputCloud(cloud);
    pcl::Indices ind;
    std::vector<float> d;
    for (std::size_t i = 0; i < cloud->size(); i += 7) {
      if (!pcl::isFinite((*cloud)[i])) {
        EXPECT_EQ(search.nearestKSearch((*cloud)[i], 8, ind, d), 0);
        continue;
      }
      const auto truth = bruteForce(*cloud, (*cloud)[i]);
      ASSERT_EQ(search.nearestKSearch(*cloud, static_cast<pcl::index_t>(i), 16, ind, d), 16);
      for (std::size_t j = 0; j < 16; ++j) {
        EXPECT_EQ(ind[j], truth[j].second) << "grid " << grid << ", point " << i << ", rank " << j;
        EXPECT_FLOAT_EQ(d[j], truth[j].first);
      }
    }
  }
}

// A capped search keeps the nearest max_nn by (distance, index), ties and copies included, whether
// the ball holds fewer points than the cap or a hundred times more.
TEST(NanoflannSearch, RadiusListsAreBruteForcesAndMaxNnKeepsTheNearest) {
  const XyzCloud::Ptr cloud = testCloud(3000, 6, true);
  NanoflannSearch<pcl::PointXYZ> search;
  search.setInputCloud(cloud);
  pcl::Indices ind;
  std::vector<float> d;
  std::size_t beyond_cap = 0;
  for (std::size_t i = 0; i < cloud->size(); i += 11) {
    if (!pcl::isFinite((*cloud)[i]))
      continue;
    const auto truth = bruteForce(*cloud, (*cloud)[i]);
    for (const double r : {0.08, 0.5}) {
      std::size_t within = 0;
      while (within < truth.size() && truth[within].first < static_cast<float>(r * r))
        ++within;
      ASSERT_EQ(static_cast<std::size_t>(search.radiusSearch((*cloud)[i], r, ind, d)), within);
      for (std::size_t j = 0; j < within; ++j)
        EXPECT_EQ(ind[j], truth[j].second) << "point " << i << ", rank " << j;
      for (const unsigned cap : {1u, 5u, 40u, 5000u}) {
        ASSERT_EQ(static_cast<std::size_t>(search.radiusSearch((*cloud)[i], r, ind, d, cap)),
                  std::min<std::size_t>(cap, within));
        beyond_cap += within > 10 * cap ? 1 : 0;
        for (std::size_t j = 0; j < ind.size(); ++j) {
          EXPECT_EQ(ind[j], truth[j].second) << "point " << i << ", r " << r << ", cap " << cap;
          EXPECT_EQ(d[j], truth[j].first);
        }
      }
    }
  }
  EXPECT_GT(beyond_cap, 100u) << "balls far fuller than their cap were not tried";
}

// With indices, only those points are searched and returned, under their cloud indices.
TEST(NanoflannSearch, IndicesRestrictTheSearchedPoints) {
  const XyzCloud::Ptr cloud = testCloud(2000, 7, false);
  auto half = pcl::make_shared<pcl::Indices>();
  for (std::size_t i = 0; i < cloud->size(); i += 2)
    half->push_back(static_cast<pcl::index_t>(i));
  NanoflannSearch<pcl::PointXYZ> search;
  search.setInputCloud(cloud, half);
  EXPECT_EQ(search.getIndices(), half);
  XyzCloud even;
  for (pcl::index_t i : *half)
    even.push_back((*cloud)[static_cast<std::size_t>(i)]);
  pcl::Indices ind;
  std::vector<float> d;
  const pcl::PointXYZ q(0.5f, 0.5f, 0.5f);
  ASSERT_EQ(search.nearestKSearch(q, 10, ind, d), 10);
  const auto truth = bruteForce(even, q);
  for (std::size_t j = 0; j < 10; ++j)
    EXPECT_EQ(ind[j], 2 * truth[j].second);
}

// The proof that it plugs into PCL: NormalEstimation with it as its search method gives the
// normals NormalEstimation gives with PCL's kd-tree (on points without ties at the k-th
// neighbour the lists are the same sets; the covariance does not depend on their order).
TEST(NanoflannSearch, PclsNormalEstimationRunsWithItAsItsSearchMethod) {
  const XyzCloud::Ptr cloud = testCloud(4000, 8, false, false);
  pcl::NormalEstimation<pcl::PointXYZ, pcl::Normal> ne;
  ne.setInputCloud(cloud);
  ne.setKSearch(12);
  pcl::PointCloud<pcl::Normal> ours, theirs;
  ne.setSearchMethod(pcl::make_shared<NanoflannSearch<pcl::PointXYZ>>());
  ne.compute(ours);
  ne.setSearchMethod(pcl::make_shared<pcl::search::KdTree<pcl::PointXYZ>>());
  ne.compute(theirs);
  ASSERT_EQ(ours.size(), theirs.size());
  std::size_t finite = 0;
  for (std::size_t i = 0; i < ours.size(); ++i) {
    EXPECT_EQ(std::isfinite(ours[i].normal_x), std::isfinite(theirs[i].normal_x)) << i;
    if (!std::isfinite(ours[i].normal_x))
      continue;
    ++finite;
    const float dot =
        std::abs(ours[i].getNormalVector3fMap().dot(theirs[i].getNormalVector3fMap()));
    EXPECT_GT(dot, 1.0f - 1e-5f) << "point " << i;
  }
  EXPECT_GT(finite, 3800u);
}

}  // namespace
}  // namespace slipfit
