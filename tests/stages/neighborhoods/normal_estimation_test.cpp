#include "slipfit/neighborhoods/normal_estimation.h"

#include "normal_estimator.h"
#include "shapes.h"
#include "slipfit/core/cloud_maps.h"
#include "slipfit/core/exceptions.h"
#include "slipfit/neighborhoods/neighborhood_selection.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace slipfit {
namespace {

using testing::Cloud;

/// Normals estimated for \a cloud (the exact ones are in its normal fields).
pcl::PointCloud<pcl::Normal> estimate(const Cloud::Ptr& cloud, const NormalParameters& p,
                                      std::shared_ptr<const Neighborhoods> hoods = nullptr,
                                      NormalStatistics* stats = nullptr) {
  OrientedNormalEstimation<pcl::PointNormal, pcl::Normal> ne;
  ne.setParameters(p);
  ne.setInputCloud(cloud);
  if (hoods)
    ne.setNeighborhoods(hoods);
  pcl::PointCloud<pcl::Normal> out;
  ne.compute(out);
  if (stats)
    *stats = ne.statistics();
  return out;
}

Eigen::Matrix3Xf exact(const Cloud& c) {
  return normals(c);
}
Eigen::Matrix3Xf estimated(const pcl::PointCloud<pcl::Normal>& c) {
  return normals(c);
}

std::size_t outward(const Eigen::Matrix3Xf& n, const Eigen::Matrix3Xf& truth) {
  return static_cast<std::size_t>(((n.array() * truth.array()).colwise().sum() > 0).count());
}

// Accuracy on noise-free analytic shapes, k = 16: every normal within 1 degree. The PCA normal
// tilts by about curvature × (offset of the neighborhood centroid), so the densities are chosen to
// keep curvature × neighborhood radius near 0.025.
TEST(OrientedNormalEstimation, SphereWithinOneDegree) {
  auto cloud =
      std::make_shared<Cloud>(testing::sampleSphere(100000, Eigen::Vector3f(3, -2, 5), 2.0f, 1));
  NormalParameters p;
  p.orientation = NormalOrientation::consistent;
  const auto out = estimate(cloud, p);
  EXPECT_LT(testing::maxAngleDeg(estimated(out), exact(*cloud), false), 1.0);
}

// PCL's convention: NormalOrientation::sensor faces the cloud's sensor_origin_ (what a PCD's
// VIEWPOINT sets). A sphere seen from a sensor inside it, off its centre: every normal points
// inward. The default viewpoint, the origin, lies outside at d = |centre| = √38 from the centre:
// it turns outward the cap it sees, the share (1 − r/d)/2 = 0.338 of the sphere's area.
TEST(OrientedNormalEstimation, SensorOrientationFacesTheCloudsSensorOrigin) {
  const Eigen::Vector3f centre(3, -2, 5);
  auto cloud = std::make_shared<Cloud>(testing::sampleSphere(20000, centre, 2.0f, 4));
  cloud->sensor_origin_ << 3.5f, -1.5f, 4.0f, 0.0f;
  NormalParameters p;
  p.orientation = NormalOrientation::sensor;
  const Eigen::Matrix3Xf inward = -exact(*cloud);
  EXPECT_EQ(outward(estimated(estimate(cloud, p)), inward), cloud->size());
  p.orientation = NormalOrientation::viewpoint;
  const double seen = (1.0 - 2.0 / std::sqrt(38.0)) / 2.0;
  EXPECT_NEAR(static_cast<double>(outward(estimated(estimate(cloud, p)), inward)) /
                  static_cast<double>(cloud->size()),
              1.0 - seen, 0.01);
}

TEST(OrientedNormalEstimation, CylinderWithinOneDegree) {
  auto cloud = std::make_shared<Cloud>(
      testing::sampleCylinder(100000, Eigen::Vector3f(1, 1, -3), 1.0f, 2.0f, 2));
  NormalParameters p;
  p.viewpoint = Eigen::Vector3f(1, 1, -2);  // on the axis: every normal would face inward
  const auto out = estimate(cloud, p);
  const Eigen::Matrix3Xf n = estimated(out);
  EXPECT_LT(testing::maxAngleDeg(n, exact(*cloud), true), 1.0);
  EXPECT_EQ(outward(n, exact(*cloud)), 0u) << "viewpoint orientation must face the axis";
}

TEST(OrientedNormalEstimation, ConsistentOrientationIsOutwardOnClosedSurfaces) {
  for (const bool torus : {false, true}) {
    auto cloud = std::make_shared<Cloud>(
        torus ? testing::sampleTorus(40000, Eigen::Vector3f(0.5f, 0.2f, -1.0f), 1.0f, 0.3f, 3)
              : testing::sampleSphere(20000, Eigen::Vector3f(0, 0, 0), 1.0f, 4));
    NormalParameters p;
    p.orientation = NormalOrientation::consistent;
    NormalStatistics stats;
    const auto out = estimate(cloud, p, nullptr, &stats);
    EXPECT_EQ(outward(estimated(out), exact(*cloud)), cloud->size())
        << (torus ? "torus" : "sphere");
    EXPECT_EQ(stats.components, 1u);
    EXPECT_EQ(stats.failed, 0u);
  }
}

TEST(OrientedNormalEstimation, ConsistentOrientationSurvivesNoise) {
  auto cloud =
      std::make_shared<Cloud>(testing::sampleTorus(40000, Eigen::Vector3f::Zero(), 1.0f, 0.3f, 5));
  testing::addNoise(*cloud, 0.003f, 6);
  NormalParameters p;
  p.orientation = NormalOrientation::consistent;
  const auto out = estimate(cloud, p);
  EXPECT_EQ(outward(estimated(out), exact(*cloud)), cloud->size());
}

TEST(OrientedNormalEstimation, ReferenceOrientationKeepsTheInputSign) {
  auto cloud =
      std::make_shared<Cloud>(testing::sampleSphere(5000, Eigen::Vector3f::Zero(), 1.0f, 7));
  auto reference = std::make_shared<Eigen::Matrix3Xf>(exact(*cloud));
  for (Eigen::Index i = 0; i < reference->cols(); i += 3)
    reference->col(i) *= -1.0f;
  auto ne = testing::normalEstimator(cloud, NormalOrientation::reference);
  ne.setReferenceNormals(reference);
  pcl::PointCloud<pcl::Normal> out;
  ne.compute(out);
  EXPECT_EQ(outward(estimated(out), *reference), cloud->size());
}

TEST(OrientedNormalEstimation, SharedNeighborhoodsGiveIdenticalNormals) {
  auto cloud =
      std::make_shared<Cloud>(testing::sampleSphere(5000, Eigen::Vector3f::Zero(), 1.0f, 8));
  NormalParameters p;
  p.k = 12;
  const auto own = estimate(cloud, p);
  NeighborhoodSelection<pcl::PointNormal> s;
  NeighborhoodParameters np;
  np.k = 12;
  s.setParameters(np);
  s.setInputCloud(cloud);
  auto hoods = std::make_shared<Neighborhoods>();
  s.compute(*hoods);
  NormalStatistics stats;
  const auto shared = estimate(cloud, p, hoods, &stats);
  EXPECT_TRUE(stats.reused_neighborhoods);
  for (std::size_t i = 0; i < cloud->size(); ++i) {
    ASSERT_EQ(own[i].normal_x, shared[i].normal_x) << i;
    ASSERT_EQ(own[i].normal_y, shared[i].normal_y) << i;
    ASSERT_EQ(own[i].normal_z, shared[i].normal_z) << i;
    ASSERT_EQ(own[i].curvature, shared[i].curvature) << i;
  }
}

TEST(OrientedNormalEstimation, OutputIsAlignedWithIndices) {
  auto cloud =
      std::make_shared<Cloud>(testing::sampleSphere(3000, Eigen::Vector3f::Zero(), 1.0f, 9));
  auto ne = testing::normalEstimator<pcl::PointNormal>(cloud, NormalOrientation::consistent);
  auto indices = std::make_shared<pcl::Indices>();
  for (int i = 0; i < 3000; i += 2)
    indices->push_back(i);
  ne.setIndices(indices);
  pcl::PointCloud<pcl::PointNormal> out;
  ne.compute(out);
  ASSERT_EQ(out.size(), indices->size());
  for (std::size_t j = 0; j < out.size(); ++j)
    EXPECT_GT(out[j].getNormalVector3fMap().dot((*cloud)[(*indices)[j]].getNormalVector3fMap()),
              0.99f);
}

TEST(OrientedNormalEstimation, IsolatedPointsFailWithNaN) {
  auto cloud =
      std::make_shared<Cloud>(testing::sampleSphere(2000, Eigen::Vector3f::Zero(), 1.0f, 10));
  pcl::PointNormal far;
  far.getVector3fMap() = Eigen::Vector3f(100, 100, 100);
  cloud->push_back(far);
  NormalParameters p;
  p.radius = 0.2;
  NormalStatistics stats;
  const auto out = estimate(cloud, p, nullptr, &stats);
  EXPECT_EQ(stats.failed, 1u);
  EXPECT_TRUE(std::isnan(out.back().normal_x));
  EXPECT_FALSE(out.is_dense);
}

TEST(OrientedNormalEstimation, RejectsBadInput) {
  NormalParameters p;
  p.k = 1;
  EXPECT_THROW(p.validate(), InvalidParameterError);
  OrientedNormalEstimation<pcl::PointNormal, pcl::Normal> ne;
  ne.setInputCloud(std::make_shared<Cloud>());
  pcl::PointCloud<pcl::Normal> out;
  EXPECT_THROW(ne.compute(out), DegenerateInputError);

  auto cloud =
      std::make_shared<Cloud>(testing::sampleSphere(100, Eigen::Vector3f::Zero(), 1.0f, 11));
  auto ref = testing::normalEstimator(cloud, NormalOrientation::reference);
  EXPECT_THROW(ref.compute(out), DegenerateInputError);  // no reference normals
  ref.setNeighborhoods(std::make_shared<Neighborhoods>(7));
  EXPECT_THROW(ref.compute(out), DegenerateInputError);  // neighborhoods of another cloud
}

}  // namespace
}  // namespace slipfit
