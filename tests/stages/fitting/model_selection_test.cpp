// The simplest adequate primitive: the rule on exact inputs, and fitAuto at the degenerate limits
// (a plane is a cylinder of infinite radius and a cone of 90°; a cylinder is a cone of 0° and a
// torus of infinite R) with the margins derived in docs/THEORY.md §4.4.
#include "slipfit/fitting/model_selection.h"
#include "slipfit/core/angle_units.h"
#include "slipfit/fitting/weighted_fit.h"
#include "slipfit/sampling/primitive_sampler.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace slipfit {
namespace {

TEST(SelectSimplest, FewestParametersAmongTheAdequate) {
  // Torus best; cylinder within 25 %: the cylinder. The plane at 1.4 × is not adequate.
  const std::vector<ModelCandidate> c = {
      {PrimitiveType::plane, 1.4}, {PrimitiveType::cylinder, 1.24}, {PrimitiveType::torus, 1.0}};
  EXPECT_EQ(selectSimplest(c, 0.0), std::optional<std::size_t>(1));
  // A floor of 0.2 admits the plane: 1.4 ≤ 1.25 + 0.2.
  EXPECT_EQ(selectSimplest(c, 0.2), std::optional<std::size_t>(0));
  // Just outside the margin: 1.25 × 1.0 = 1.25 < 1.2500001.
  EXPECT_EQ(selectSimplest({{PrimitiveType::plane, 1.2500001}, {PrimitiveType::sphere, 1.0}}, 0.0),
            std::optional<std::size_t>(1));
}

TEST(SelectSimplest, ExactFitsCompareByComplexityAndNaNIsSkipped) {
  // Noise-free data: every type at rms 0 is adequate and the plane wins.
  EXPECT_EQ(selectSimplest({{PrimitiveType::cone, 0.0}, {PrimitiveType::plane, 0.0}}, 0.0),
            std::optional<std::size_t>(1));
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(selectSimplest({{PrimitiveType::plane, nan}, {PrimitiveType::sphere, 2.0}}, 0.0),
            std::optional<std::size_t>(1));
  EXPECT_FALSE(selectSimplest({{PrimitiveType::plane, nan}}, 0.0));
  EXPECT_FALSE(selectSimplest({}, 0.0));
  EXPECT_EQ(parameterCount(PrimitiveType::torus), 7);
}

struct Cloud {
  Eigen::Matrix3Xd points, normals;
};

Cloud sample(const PrimitiveSamplingParameters& p) {
  Cloud c;
  samplePrimitive(p, c.points, c.normals);
  return c;
}

PrimitiveType autoType(const Cloud& c) {
  const FitResult r = fitAuto(c.points, c.normals, Eigen::VectorXd::Ones(c.points.cols()));
  EXPECT_TRUE(r.ok()) << r.reason;
  return r.type;
}

TEST(FitAutoLimits, CylinderOfHugeRadiusIsAPlane) {
  // A strip 2 wide of a cylinder of radius 1000: sagitta 2²/(8·1000) = 5e-4, a tenth of the
  // noise σ = 5e-3: the data do not demand the curvature.
  PrimitiveSamplingParameters p;
  p.primitive = Cylinder{Eigen::Vector3d(1, 2, 3).normalized(), Eigen::Vector3d(1, 1, 1), 1000.0};
  p.extent = 2.0;
  p.angle_min = 0.0;
  p.angle_max = 2.0 / 1000.0;  // 2 units of arc
  p.points = 3000;
  p.noise = 5e-3;
  p.seed = 11;
  EXPECT_EQ(autoType(sample(p)), PrimitiveType::plane);
  // Radius 2 over the same strip: sagitta 0.25, fifty times the noise: a cylinder.
  p.primitive = Cylinder{Eigen::Vector3d(1, 2, 3).normalized(), Eigen::Vector3d(1, 1, 1), 2.0};
  p.angle_max = 1.0;
  EXPECT_EQ(autoType(sample(p)), PrimitiveType::cylinder);
}

TEST(FitAutoLimits, FlatConeIsAPlaneAndSlimConeACylinder) {
  PrimitiveSamplingParameters p;
  p.points = 3000;
  p.noise = 5e-3;
  p.seed = 12;
  // Half angle 89.95°: a band from 0 to 1 along the axis spans 1146 units of radius at a slope of
  // 1/1146: the band 0.5–1 deviates from its plane by < 5e-4 ≪ σ.
  p.primitive = Cone{Eigen::Vector3d::UnitZ(), Eigen::Vector3d::Zero(), 89.95 * kDegree};
  p.extent_min = 0.5e-3;
  p.extent = 1e-3;
  EXPECT_EQ(autoType(sample(p)), PrimitiveType::plane);
  // Half angle 0.01°, a band of height 2 at 5000 from the apex (radius ≈ 0.87): the radius changes
  // by 3.5e-4 along the band, a fourteenth of σ: a cylinder.
  p.primitive = Cone{Eigen::Vector3d::UnitX(), Eigen::Vector3d::Zero(), 0.01 * kDegree};
  p.extent_min = 5000.0;
  p.extent = 5002.0;
  EXPECT_EQ(autoType(sample(p)), PrimitiveType::cylinder);
}

// The cylinder limit of a cone by its apex: a noise-free band of a cone of 0.5° whose apex lies
// 5000 units away (radius 43.6, changing by 0.017 along the band: 4e-4 of itself) is a cylinder
// however exactly the cone fits; the same cone from 1 to 100 units off its apex (the radius grows
// a hundredfold) is not.
TEST(FitAutoLimits, ConeWithItsApexFarBeyondThePointsIsInItsCylinderLimit) {
  PrimitiveSamplingParameters p;
  p.points = 2000;
  p.noise = 0.0;
  p.seed = 13;
  const Cone cone{Eigen::Vector3d::UnitX(), Eigen::Vector3d::Zero(), 0.5 * kDegree};
  p.primitive = cone;
  p.extent_min = 5000.0;
  p.extent = 5002.0;
  EXPECT_TRUE(isNearlyDegenerate(cone, sample(p).points));
  p.extent_min = 1.0;
  p.extent = 100.0;
  EXPECT_FALSE(isNearlyDegenerate(cone, sample(p).points));
}

TEST(FitAutoLimits, TorusOfHugeMajorRadiusIsACylinder) {
  // R = 1000, r = 1, 2 units of arc around the axis: the tube bends by 2²/(8·1000) = 5e-4 ≪ σ.
  PrimitiveSamplingParameters p;
  p.primitive = Torus{Eigen::Vector3d(0, 1, 1).normalized(), Eigen::Vector3d(3, 0, 0), 1000.0, 1.0};
  p.angle_min = 0.0;
  p.angle_max = 2.0 / 1000.0;
  p.points = 4000;
  p.noise = 5e-3;
  p.seed = 13;
  EXPECT_EQ(autoType(sample(p)), PrimitiveType::cylinder);
  // R = 3, r = 1 all around: a torus.
  p.primitive = Torus{Eigen::Vector3d(0, 1, 1).normalized(), Eigen::Vector3d(3, 0, 0), 3.0, 1.0};
  p.angle_max = 2 * kPi;
  EXPECT_EQ(autoType(sample(p)), PrimitiveType::torus);
}

// The flat limit (isNearlyDegenerate): a Kinect-like table, 1.5 wide, bent into a sphere of
// radius 60 (sagitta 1.5²/(8·60) ≈ 4.7 mm) with 1 mm noise. The sphere fits it far better than the
// plane (its RMS is the noise, the plane's carries the bend), yet its radius is 140 × the points'
// spread: it is the plane's limit, and the plane is the answer.
TEST(FitAutoLimits, SphereFarWiderThanItsPointsIsAPlane) {
  PrimitiveSamplingParameters p;
  p.primitive = Sphere{Eigen::Vector3d(0, 0, -60), 60.0};
  p.cap = std::asin(0.75 / 60.0);
  p.points = 5000;
  p.noise = 1e-3;
  p.seed = 5;
  const Cloud c = sample(p);
  const Eigen::VectorXd w = Eigen::VectorXd::Ones(c.points.cols());
  const FitResult plane = fitPrimitive(PrimitiveType::plane, c.points, c.normals, w);
  const FitResult sphere = fitPrimitive(PrimitiveType::sphere, c.points, c.normals, w);
  ASSERT_TRUE(plane.ok() && sphere.ok());
  // Residuals alone would pick the sphere: the plane is beyond the 25 % margin.
  EXPECT_GT(plane.rms_distance, (1.0 + kAdequacyMargin) * sphere.rms_distance);
  EXPECT_TRUE(isNearlyDegenerate(sphere.refined, c.points));
  EXPECT_EQ(autoType(c), PrimitiveType::plane);
  // Radius 5 over the same width: 20 × the spread, a sphere.
  p.primitive = Sphere{Eigen::Vector3d(0, 0, -5), 5.0};
  p.cap = std::asin(0.75 / 5.0);
  EXPECT_EQ(autoType(sample(p)), PrimitiveType::sphere);
}

// jointModelIsBetter is BIC for one primitive against two: with n = 10,000 and a sphere's 4
// parameters saved, the joint model may raise the residual sum of squares by the factor
// exp(4 ln n / n) = 1.003691 and no more.
TEST(JointModel, BicAllowsTheRiseThatTheSavedParametersPayFor) {
  const std::size_t n = 10000;
  const double bound = std::exp(4.0 * std::log(10000.0) / 10000.0);
  EXPECT_NEAR(bound, 1.003691, 1e-6);
  EXPECT_TRUE(jointModelIsBetter(1.0, 1.0, n, 4));
  EXPECT_TRUE(jointModelIsBetter(0.999 * bound, 1.0, n, 4));
  EXPECT_FALSE(jointModelIsBetter(1.001 * bound, 1.0, n, 4));
  // A speck of 70 outliers 3σ off a plane of 60,000 points with noise σ (σ = 1): RSS 60,000 +
  // 70 · 9 jointly against 60,000 + 70 with the speck's own sphere — 0.93 % more, where the 4
  // parameters saved pay for 4 ln n / n ≈ 0.07 %: refused.
  EXPECT_FALSE(jointModelIsBetter(60000.0 + 630.0, 60000.0 + 70.0, 60070, 4));
  // Two halves of one plane (σ = 1): the joint fit leaves 5 more than the halves' own fits, under
  // the 3 ln n ≈ 30 that the plane's parameters pay for: accepted.
  EXPECT_TRUE(jointModelIsBetter(20000.0 + 5.0, 20000.0, 20000, 3));
  // Noise-free parts: only an exact joint fit is better.
  EXPECT_TRUE(jointModelIsBetter(0.0, 0.0, 100, 3));
  EXPECT_FALSE(jointModelIsBetter(1e-12, 0.0, 100, 3));
}

}  // namespace
}  // namespace slipfit
