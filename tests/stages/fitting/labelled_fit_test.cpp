// fitLabelled: one primitive per label, inliers counted at 3 × the surface noise measured from
// each label's points.

#include "slipfit/fitting/labelled_fit.h"
#include "slipfit/fitting/labelled_fitting.h"
#include "slipfit/sampling/primitive_sampler.h"

#include <gtest/gtest.h>

#include <pcl/point_types.h>

#include <memory>
#include <vector>

namespace slipfit {
namespace {

/// \a count points of \a primitive with noise σ, appended to \a x, \a n and \a labels.
void append(const Primitive& primitive, std::size_t count, double sigma, int label,
            std::uint64_t seed, Eigen::Matrix3Xd& x, Eigen::Matrix3Xd& n,
            std::vector<double>& labels) {
  PrimitiveSamplingParameters p;
  p.primitive = primitive;
  p.points = count;
  p.noise = sigma;
  p.seed = seed;
  Eigen::Matrix3Xd px, pn;
  samplePrimitive(p, px, pn);
  const Eigen::Index at = x.cols();
  x.conservativeResize(3, at + px.cols());
  n.conservativeResize(3, at + pn.cols());
  x.rightCols(px.cols()) = px;
  n.rightCols(pn.cols()) = pn;
  labels.insert(labels.end(), static_cast<std::size_t>(px.cols()), label);
}

TEST(LabelledFit, EachLabelGetsItsTypeAndThreeSigmaInliers) {
  constexpr double kSigma = 0.002;
  Eigen::Matrix3Xd x(3, 0), n(3, 0);
  std::vector<double> labels;
  append(Plane{Eigen::Vector3d(0.2, -0.3, 0.93).normalized(), 0.4}, 3000, kSigma, 0, 1, x, n,
         labels);
  append(Sphere{Eigen::Vector3d(3, 0, 0), 0.5}, 3000, kSigma, 1, 2, x, n, labels);
  append(Sphere{Eigen::Vector3d(-3, 0, 0), 0.5}, 5, kSigma, 2, 3, x, n, labels);
  append(Sphere{Eigen::Vector3d(0, 3, 0), 0.5}, 50, kSigma, -1, 4, x, n, labels);
  const std::vector<double> weights(labels.size(), 1.0);

  const LabelledFits fits = fitLabelled(x, n, weights, labels, LabelledFitParameters{}, 1);
  ASSERT_EQ(fits.fits.size(), 3u);
  EXPECT_EQ(fits.fits[0].fit.type, PrimitiveType::plane);
  EXPECT_EQ(fits.fits[1].fit.type, PrimitiveType::sphere);
  EXPECT_EQ(fits.fits[2].fit.status, FitStatus::too_few_points);
  for (int k = 0; k < 2; ++k) {
    const LabelledFit& f = fits.fits[static_cast<std::size_t>(k)];
    EXPECT_EQ(*f.label, k);
    EXPECT_EQ(f.points, 3000);
    // The tolerance is 3 σ̂, σ̂ within 10 % of σ (surface_noise_test); |N(0, σ)| ≤ 2.7 σ holds
    // for 99.3 % of the points.
    ASSERT_TRUE(f.surface_noise.has_value());
    EXPECT_NEAR(*f.surface_noise, kSigma, 0.1 * kSigma);
    EXPECT_NEAR(f.inlier_distance, 3.0 * *f.surface_noise, 1e-15);
    EXPECT_GE(f.inliers, 0.99 * 3000);
  }
  // Points of no label (−1) and of an unfitted label keep distance −1.
  for (std::size_t i = 6000; i < labels.size(); ++i)
    EXPECT_EQ(fits.distance[i], -1.0f) << i;
  EXPECT_GE(fits.distance[0], 0.0f);
}

TEST(LabelledFit, AWholeCloudFitIsRobustByDefault) {
  Eigen::Matrix3Xd x(3, 0), n(3, 0);
  std::vector<double> labels;
  append(Plane{Eigen::Vector3d::UnitZ(), 0.0}, 3000, 0.001, 0, 5, x, n, labels);
  append(Sphere{Eigen::Vector3d(0, 0, 2), 0.3}, 1000, 0.001, 1, 6, x, n, labels);
  const std::vector<double> weights(labels.size(), 1.0);
  LabelledFitParameters p;
  EXPECT_EQ(p.robustMethod(true), RobustMethod::ransac);
  EXPECT_EQ(p.robustMethod(false), RobustMethod::none);
  const LabelledFits fits = fitLabelled(x, n, weights, {}, p, 7);
  ASSERT_EQ(fits.fits.size(), 1u);
  const LabelledFit& f = fits.fits[0];
  EXPECT_FALSE(f.label.has_value());
  EXPECT_EQ(f.fit.type, PrimitiveType::plane);
  EXPECT_EQ(f.tolerance_source, "2.5 x the robust fit's residual scale");
  // The plane's 3000 points are its inliers, the sphere's 1000 are not (they lie 1.7 to 2.3
  // above it).
  EXPECT_GE(f.inliers, 0.98 * 3000);
  EXPECT_LE(f.inliers, 3000);
}

// The PCL front end (LabelledFitting) gives fitLabelled's result on the points it is given, and
// honours setIndices: the plane and sphere of the scene above as a PointNormal cloud, the sphere's
// points as indices: one fit (label 1), the same parameters as fitLabelled on those points alone
// (the same doubles in, the same arithmetic), distances −1 for every point outside the indices.
TEST(LabelledFit, TheFrontEndHonoursIndices) {
  Eigen::Matrix3Xd x(3, 0), n(3, 0);
  std::vector<double> labels;
  append(Plane{Eigen::Vector3d(0.2, -0.3, 0.93).normalized(), 0.4}, 2000, 0.002, 0, 1, x, n,
         labels);
  append(Sphere{Eigen::Vector3d(3, 0, 0), 0.5}, 2000, 0.002, 1, 2, x, n, labels);
  auto cloud = std::make_shared<pcl::PointCloud<pcl::PointNormal>>();
  for (Eigen::Index i = 0; i < x.cols(); ++i) {
    pcl::PointNormal p;
    p.getVector3fMap() = x.col(i).cast<float>();
    p.getNormalVector3fMap() = n.col(i).cast<float>();
    cloud->push_back(p);
  }
  auto sphere = std::make_shared<pcl::Indices>();
  for (pcl::index_t i = 2000; i < 4000; ++i)
    sphere->push_back(i);
  LabelledFitting<pcl::PointNormal> fitting;
  fitting.setInputCloud(cloud);
  fitting.setInputNormals(cloud);
  fitting.setIndices(sphere);
  fitting.setLabels(std::make_shared<const std::vector<double>>(labels));
  fitting.setSeed(3);
  LabelledFits fits;
  fitting.compute(fits);
  ASSERT_EQ(fits.fits.size(), 1u);
  EXPECT_EQ(*fits.fits[0].label, 1);
  ASSERT_EQ(fits.distance.size(), cloud->size());
  for (std::size_t i = 0; i < 2000; ++i)
    ASSERT_EQ(fits.distance[i], -1.0f) << i;

  // The kernel on the same points (the cloud's floats, as the front end reads them).
  Eigen::Matrix3Xd xs(3, 2000), ns(3, 2000);
  for (Eigen::Index j = 0; j < 2000; ++j) {
    xs.col(j) = (*cloud)[static_cast<std::size_t>(2000 + j)].getVector3fMap().cast<double>();
    ns.col(j) = (*cloud)[static_cast<std::size_t>(2000 + j)].getNormalVector3fMap().cast<double>();
  }
  const LabelledFits kernel =
      fitLabelled(xs, ns, std::vector<double>(2000, 1.0),
                  std::vector<double>(labels.begin() + 2000, labels.end()), {}, 3);
  ASSERT_EQ(kernel.fits.size(), 1u);
  const auto& a = std::get<Sphere>(fits.fits[0].fit.refined);
  const auto& b = std::get<Sphere>(kernel.fits[0].fit.refined);
  EXPECT_EQ(a.center, b.center);
  EXPECT_EQ(a.radius, b.radius);
  for (std::size_t j = 0; j < 2000; ++j)
    ASSERT_EQ(fits.distance[2000 + j], kernel.distance[j]) << j;
}

}  // namespace
}  // namespace slipfit
