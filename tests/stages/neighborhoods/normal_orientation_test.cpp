#include "slipfit/neighborhoods/normal_orientation.h"

#include "shapes.h"
#include "slipfit/neighborhoods/neighborhood_selection.h"

#include <gtest/gtest.h>

#include <limits>
#include <random>

namespace slipfit {
namespace {

using testing::Cloud;

Neighborhoods knn(const Cloud::Ptr& cloud, int k) {
  NeighborhoodSelection<pcl::PointNormal> s;
  NeighborhoodParameters p;
  p.k = k;
  s.setParameters(p);
  s.setInputCloud(cloud);
  Neighborhoods h;
  s.compute(h);
  return h;
}

TEST(NormalOrientation, ViewpointFlipsTowardsTheViewer) {
  Eigen::Matrix3Xf pts(3, 2), nrm(3, 2);
  pts << 0, 1, 0, 0, 0, 0;
  nrm << 0, 0, 0, 0, 1, -1;
  const auto flipped = orientTowardsViewpoint(
      ConstCoords3Map(pts.data(), 3, 2, Eigen::OuterStride<>(3)),
      Coords3Map(nrm.data(), 3, 2, Eigen::OuterStride<>(3)), Eigen::Vector3f(0, 0, -5));
  EXPECT_EQ(flipped, 1u);
  EXPECT_EQ(nrm(2, 0), -1.0f);
  EXPECT_EQ(nrm(2, 1), -1.0f);
}

// Random sign flips on two separate closed surfaces are undone: two components, all outward.
TEST(NormalOrientation, ConsistentRestoresRandomFlipsPerComponent) {
  auto cloud =
      std::make_shared<Cloud>(testing::sampleSphere(4000, Eigen::Vector3f(-3, 0, 0), 1.0f, 1));
  testing::append(*cloud, testing::sampleTorus(8000, Eigen::Vector3f(3, 0, 0), 1.0f, 0.35f, 2));
  const Eigen::Matrix3Xf truth = normals(std::as_const(*cloud));
  std::mt19937_64 rng(3);
  for (auto& p : cloud->points)
    if (rng() % 2)
      p.getNormalVector3fMap() *= -1.0f;
  (*cloud)[5].normal_x = std::numeric_limits<float>::quiet_NaN();  // an unestimated normal
  const Neighborhoods h = knn(cloud, 12);
  const auto report = orientConsistently(coordinates(*cloud), normals(*cloud), h);
  EXPECT_EQ(report.components, 2u);
  EXPECT_EQ(report.oriented, cloud->size() - 1);
  const Eigen::Matrix3Xf n = normals(std::as_const(*cloud));
  for (Eigen::Index i = 0; i < n.cols(); ++i)
    if (i != 5)
      ASSERT_GT(n.col(i).dot(truth.col(i)), 0.0f) << "point " << i;
}

TEST(NormalOrientation, ConsistentSeedFacesTheViewpointWhenGiven) {
  auto cloud = std::make_shared<Cloud>(testing::samplePlane(3000, -1, 1, -1, 1, 0, 4));
  for (auto& p : cloud->points)
    p.normal_z = -1.0f;  // all facing down
  const Neighborhoods h = knn(cloud, 10);
  orientConsistently(coordinates(*cloud), normals(*cloud), h, Eigen::Vector3f(0, 0, 5));
  for (const auto& p : cloud->points)
    ASSERT_EQ(p.normal_z, 1.0f);
}

}  // namespace
}  // namespace slipfit
