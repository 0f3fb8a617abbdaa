// fitLabelled: one primitive per label, inliers counted at 3 × the surface noise measured from
// each label's points.

#include "slipfit/fitting/labelled_fit.h"
#include "slipfit/sampling/primitive_sampler.h"

#include <gtest/gtest.h>

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

}  // namespace
}  // namespace slipfit
