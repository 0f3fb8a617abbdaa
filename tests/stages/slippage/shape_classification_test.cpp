// classifyShape's inliers: counted at 3 × the surface noise measured from the points.

#include "slipfit/slippage/shape_classification.h"
#include "slipfit/sampling/motion_surface_sampler.h"
#include "slipfit/sampling/primitive_sampler.h"
#include "varied_shapes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

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

// Issue 37: the sampler's one-motion surfaces at σ = 0.03 (1.5 % of their length 2, 3 % of their
// radius 1) with PCA normals of 16 neighbours, 4 seeds each. Their motion's eigenvalue is 0.06–0.19
// of the largest, over the fixed threshold 0.05: with it all 20 read "none" or torus. It is the
// energy the measured noise predicts for an exact motion (ShapeClassification::noise_energy; λ₁
// measured at 1.09–1.79 × it, asserted within [0.5, 3]), and read below 3 × that, the vases,
// extrusions, open extrusions and twisted columns get their class and their axis (within 2°;
// measured at most 1.6°). The helicoids, which a torus explains within 2 σ̂, read helix once the
// helical surface with its fitted profile competes by BIC (kinematic_fit.h): 20 of 20.
TEST(ShapeClassification, OneMotionSurfacesUnderNoiseAreReadBelowTheirPredictedEnergy) {
  int right = 0;
  for (const auto& [surface, name] : kMotionSurfaceNames)
    for (std::uint64_t seed = 1; seed <= 4; ++seed) {
      MotionSurfaceParameters m;
      m.surface = surface;
      m.noise = 0.03;
      m.seed = seed;
      m.axis = Eigen::Vector3d(1.0, 0.5, 2.0);
      Eigen::Matrix3Xd x, exact;
      sampleMotionSurface(m, x, exact);
      Eigen::Matrix3Xd n(3, x.cols());
      testing::estimatePcaNormals(x, 16, n);
      const ShapeClassification c = classifyShape(x, n, Eigen::VectorXd::Ones(x.cols()));
      const double ratio = c.spectral.spectrum(0) / c.noise_energy;
      EXPECT_GE(ratio, 0.5) << name << " seed " << seed;
      EXPECT_LE(ratio, 3.0) << name << " seed " << seed;
      const SlippageType truth =
          surface == MotionSurface::revolution ? SlippageType::revolution
          : surface == MotionSurface::twisted_column || surface == MotionSurface::helix
              ? SlippageType::helix
              : SlippageType::extrusion;
      EXPECT_EQ(c.verdict.type, truth) << name << " seed " << seed;
      ASSERT_TRUE(c.verdict.axis.has_value()) << name << " seed " << seed;
      const double cosine = std::abs(c.verdict.axis->dot(m.axis.normalized()));
      EXPECT_GE(cosine, std::cos(2.0 * M_PI / 180.0)) << name << " seed " << seed;
      right += c.verdict.type == truth ? 1 : 0;
    }
  EXPECT_EQ(right, 20);
}

}  // namespace
}  // namespace slipfit
