#include "slipfit/neighborhoods/neighborhood_selection.h"

#include "counting_search.h"
#include "normal_estimator.h"
#include "shapes.h"
#include "slipfit/core/exceptions.h"
#include "slipfit/neighborhoods/normal_estimation.h"
#include "slipfit/sampling/random_vector.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

namespace slipfit {
namespace {

using XyzCloud = pcl::PointCloud<pcl::PointXYZ>;

XyzCloud::Ptr randomCloud(std::size_t n, std::uint64_t seed) {
  auto c = std::make_shared<XyzCloud>();
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3f w = randomVector<3>(u, rng);
    c->push_back(pcl::PointXYZ(w.x(), w.y(), w.z()));
  }
  return c;
}

/// Squared distances from point i to every point, sorted ascending (with the index).
std::vector<std::pair<float, int>> bruteForce(const XyzCloud& c, std::size_t i) {
  std::vector<std::pair<float, int>> all;
  for (std::size_t j = 0; j < c.size(); ++j)
    all.emplace_back((c[j].getVector3fMap() - c[i].getVector3fMap()).squaredNorm(),
                     static_cast<int>(j));
  std::sort(all.begin(), all.end());
  return all;
}

/// How many of the sorted (squared distance, index) pairs lie within \a radius.
std::size_t countWithin(const std::vector<std::pair<float, int>>& truth, float radius) {
  return static_cast<std::size_t>(std::count_if(
      truth.begin(), truth.end(), [&](const auto& t) { return t.first <= radius * radius; }));
}

NeighborhoodParameters withRadius(NeighborhoodMode mode, double radius) {
  NeighborhoodParameters p;
  p.mode = mode;
  p.radius = radius;
  return p;
}

Neighborhoods select(const XyzCloud::Ptr& cloud, const NeighborhoodParameters& p) {
  NeighborhoodSelection<pcl::PointXYZ> s;
  s.setParameters(p);
  s.setInputCloud(cloud);
  Neighborhoods out;
  s.compute(out);
  return out;
}

TEST(NeighborhoodSelection, KnnMatchesBruteForce) {
  const auto cloud = randomCloud(500, 1);
  NeighborhoodParameters p;
  p.k = 12;
  const Neighborhoods h = select(cloud, p);
  ASSERT_EQ(h.size(), cloud->size());
  for (std::size_t i = 0; i < cloud->size(); ++i) {
    const auto truth = bruteForce(*cloud, i);
    const NeighborView v = h[i];
    ASSERT_EQ(v.size(), 12u);
    EXPECT_EQ(v[0], static_cast<int>(i));  // the point itself first
    for (std::size_t j = 0; j < v.size(); ++j) {
      EXPECT_EQ(v[j], truth[j].second) << "point " << i << " rank " << j;
      EXPECT_NEAR(v.sqr_distances[j], truth[j].first, 1e-6f);
    }
  }
}

TEST(NeighborhoodSelection, RadiusIsExactlyTheBall) {
  const auto cloud = randomCloud(400, 2);
  const Neighborhoods h = select(cloud, withRadius(NeighborhoodMode::radius, 0.3));
  for (std::size_t i = 0; i < cloud->size(); ++i) {
    EXPECT_EQ(h[i].size(), countWithin(bruteForce(*cloud, i), 0.3f)) << "point " << i;
    EXPECT_LE(h.radius(i), 0.3f + 1e-6f);
  }
}

TEST(NeighborhoodSelection, RadiusWithCapKeepsTheNearest) {
  const auto cloud = randomCloud(400, 3);
  NeighborhoodParameters p = withRadius(NeighborhoodMode::radius, 0.5);
  p.max_neighbors = 5;
  const Neighborhoods h = select(cloud, p);
  for (std::size_t i = 0; i < cloud->size(); ++i) {
    const auto truth = bruteForce(*cloud, i);
    ASSERT_EQ(h[i].size(), std::min<std::size_t>(5, countWithin(truth, 0.5f)));
    const std::size_t last = h[i].size() - 1;
    EXPECT_NEAR(h[i].sqr_distances[last], truth[last].first, 1e-6f);
  }
}

TEST(NeighborhoodSelection, HybridIsKnnCappedByRadius) {
  const auto cloud = randomCloud(300, 4);
  NeighborhoodParameters p = withRadius(NeighborhoodMode::hybrid, 0.25);
  p.k = 10;
  const Neighborhoods h = select(cloud, p);
  std::size_t capped = 0;
  for (std::size_t i = 0; i < cloud->size(); ++i) {
    EXPECT_EQ(h[i].size(), std::min<std::size_t>(10, countWithin(bruteForce(*cloud, i), 0.25f)));
    capped += h[i].size() < 10 ? 1 : 0;
  }
  EXPECT_GT(capped, 0u) << "the radius never bound: the test does not exercise it";
}

TEST(NeighborhoodSelection, AdaptiveSizesInRangeAndPrefixesOfKmax) {
  auto cloud = std::make_shared<XyzCloud>();
  // A plane next to a volume: planar points prefer their coplanar neighbors.
  for (const auto& p : testing::samplePlane(1500, 0, 1, 0, 1, 0, 5))
    cloud->push_back(pcl::PointXYZ(p.x, p.y, p.z));
  NeighborhoodParameters p;
  p.mode = NeighborhoodMode::adaptive;
  p.k_min = 6;
  p.k_max = 30;
  p.k_step = 3;
  const Neighborhoods h = select(cloud, p);
  NeighborhoodParameters q;
  q.k = 30;
  const Neighborhoods full = select(cloud, q);
  for (std::size_t i = 0; i < cloud->size(); ++i) {
    const std::size_t s = h[i].size();
    EXPECT_GE(s, 6u);
    EXPECT_LE(s, 30u);
    EXPECT_EQ((s - 6) % 3, 0u);
    for (std::size_t j = 0; j < s; ++j)
      EXPECT_EQ(h[i][j], full[i][j]);
  }
}

TEST(NeighborhoodSelection, NonFinitePointsGetEmptyLists) {
  auto cloud = randomCloud(100, 6);
  (*cloud)[7].x = std::numeric_limits<float>::quiet_NaN();
  cloud->is_dense = false;
  NeighborhoodSelection<pcl::PointXYZ> s;
  s.setInputCloud(cloud);
  Neighborhoods h;
  s.compute(h);
  EXPECT_TRUE(h[7].empty());
  EXPECT_EQ(s.statistics().skipped_nonfinite, 1u);
  for (std::size_t i = 0; i < h.size(); ++i)
    for (const auto j : h[i])
      EXPECT_NE(j, 7);
}

TEST(NeighborhoodSelection, IndicesLimitTheQueries) {
  const auto cloud = randomCloud(100, 7);
  NeighborhoodSelection<pcl::PointXYZ> s;
  s.setInputCloud(cloud);
  s.setIndices(std::make_shared<pcl::Indices>(pcl::Indices{3, 50}));
  Neighborhoods h;
  s.compute(h);
  EXPECT_EQ(s.statistics().queries, 2u);
  for (std::size_t i = 0; i < h.size(); ++i)
    EXPECT_EQ(h[i].empty(), i != 3 && i != 50);
}

TEST(NeighborhoodSelection, SameResultWithOneAndTwoThreads) {
  const auto cloud = randomCloud(3000, 8);
  NeighborhoodParameters p;
  p.mode = NeighborhoodMode::adaptive;
  p.threads = 1;
  const Neighborhoods a = select(cloud, p);
  p.threads = 2;
  const Neighborhoods b = select(cloud, p);
  ASSERT_EQ(a.entries(), b.entries());
  for (std::size_t i = 0; i < a.size(); ++i)
    ASSERT_TRUE(std::equal(a[i].begin(), a[i].end(), b[i].begin(), b[i].end()));
}

TEST(NeighborhoodSelection, RejectsBadParametersAndInput) {
  NeighborhoodParameters p;
  p.mode = NeighborhoodMode::radius;
  EXPECT_THROW(p.validate(), InvalidParameterError);  // no radius
  p.radius = -1.0;
  EXPECT_THROW(p.validate(), InvalidParameterError);
  NeighborhoodParameters q;
  q.k = 2;
  EXPECT_THROW(q.validate(), InvalidParameterError);
  q.k = 16;
  q.k_min = 20;
  q.k_max = 10;
  EXPECT_THROW(q.validate(), InvalidParameterError);

  NeighborhoodSelection<pcl::PointXYZ> s;
  s.setInputCloud(std::make_shared<XyzCloud>());
  Neighborhoods h;
  EXPECT_THROW(s.compute(h), DegenerateInputError);
}

// The pipeline's promise: one kd-tree build and one search per point for neighborhoods + normals.
TEST(NeighborhoodSelection, SharedNeighborhoodsMeanOneSearchPerPoint) {
  auto cloud = std::make_shared<pcl::PointCloud<pcl::PointNormal>>(
      testing::sampleSphere(5000, Eigen::Vector3f::Zero(), 1.0f, 9));
  auto tree = std::make_shared<testing::CountingKdTree<pcl::PointNormal>>();
  NeighborhoodSelection<pcl::PointNormal> s;
  s.setInputCloud(cloud);
  s.setSearchMethod(tree);
  auto hoods = std::make_shared<Neighborhoods>();
  s.compute(*hoods);
  EXPECT_EQ(tree->builds.load(), 1u);
  EXPECT_EQ(tree->queries.load(), cloud->size());

  auto ne = testing::normalEstimator(cloud, NormalOrientation::consistent);
  ne.setNeighborhoods(hoods);
  ne.setSearchMethod(tree);  // must stay unused
  pcl::PointCloud<pcl::Normal> normals;
  ne.compute(normals);
  EXPECT_TRUE(ne.statistics().reused_neighborhoods);
  EXPECT_EQ(tree->builds.load(), 1u);
  EXPECT_EQ(tree->queries.load(), cloud->size());
}

}  // namespace
}  // namespace slipfit
