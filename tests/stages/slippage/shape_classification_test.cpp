// classifyShape's inliers: counted at 3 × the surface noise measured from the points.

#include "slipfit/slippage/shape_classification.h"
#include "slipfit/sampling/primitive_sampler.h"

#include <gtest/gtest.h>

namespace slipfit {
namespace {

TEST(ShapeClassification, InliersAreThePointsWithinThreeMeasuredSigmas) {
  constexpr double kSigma = 0.003;
  PrimitiveSamplingParameters p;
  p.primitive = Sphere{Eigen::Vector3d(0.5, -0.2, 1.0), 0.8};
  p.points = 8000;
  p.noise = kSigma;
  p.seed = 12;
  Eigen::Matrix3Xd x, n;
  samplePrimitive(p, x, n);
  const ShapeClassification c = classifyShape(x, n, Eigen::VectorXd::Ones(x.cols()));
  ASSERT_TRUE(c.fit.has_value());
  EXPECT_EQ(c.fit->type, PrimitiveType::sphere);
  // σ̂ within 10 % of σ (surface_noise_test), so the tolerance lies in [2.7 σ, 3.3 σ]: at least
  // 99.3 % of the 8000 Gaussian samples (at the fit's own RMS, about σ, it would be 68 %).
  EXPECT_NEAR(c.inlier_distance, 3.0 * c.noise, 1e-15);
  EXPECT_NEAR(c.noise, kSigma, 0.1 * kSigma);
  EXPECT_GE(c.inliers, static_cast<std::size_t>(0.993 * 8000));
  EXPECT_LE(c.inliers, 8000u);
}

}  // namespace
}  // namespace slipfit
