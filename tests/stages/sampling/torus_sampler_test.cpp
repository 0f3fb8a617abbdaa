#include "slipfit/sampling/torus_sampler.h"
#include "slipfit/core/angle_units.h"

#include "slipfit/core/exceptions.h"

#include <gtest/gtest.h>

#include <cmath>

namespace slipfit {
namespace {

TorusSamplingParameters posed() {
  TorusSamplingParameters p;
  p.shape = {1.5, 0.4};
  p.center = Eigen::Vector3d(1e3, -2e2, 50);
  p.axis = Eigen::Vector3d(1, -2, 0.5);
  p.spin = 0.3;
  p.points = 20000;
  p.seed = 42;
  return p;
}

/// α of a point in the torus frame.
double alphaOf(const TorusShape& t, const Eigen::Vector3d& x) {
  const double a = std::atan2(x.z(), std::hypot(x.x(), x.y()) - t.R);
  return a < 0 ? a + 2 * kPi : a;
}

TEST(TorusSampler, SamplesLieOnTheTorusWithOutwardNormals) {
  for (const auto mode : {TorusSampling::area, TorusSampling::angle, TorusSampling::parameter}) {
    TorusSamplingParameters p = posed();
    p.sampling = mode;
    TorusSampler s;
    s.setParameters(p);
    Eigen::Matrix3Xd x, n;
    s.sample(x, n);
    ASSERT_EQ(x.cols(), 20000);
    const Eigen::Isometry3d to_local = p.pose().inverse();
    for (Eigen::Index i = 0; i < x.cols(); ++i) {
      const Eigen::Vector3d local = to_local * x.col(i);
      // Undoing a pose with a 1e3 offset costs about 1e3 × machine epsilon in the coordinates:
      // the residual is bounded by 1e-12 relative to R² times the offset-to-size ratio.
      const double offset_ratio = p.center.norm() / p.shape.R;
      ASSERT_LE(std::abs(torusImplicit(p.shape, local)),
                1e-12 * p.shape.R * p.shape.R * offset_ratio)
          << i;
      const Eigen::Vector3d nl = to_local.linear() * n.col(i);
      const Eigen::Vector3d circle =
          p.shape.R * Eigen::Vector3d(local.x(), local.y(), 0).normalized();
      ASSERT_NEAR(nl.dot((local - circle).normalized()), 1.0, 1e-9);
    }
  }
}

TEST(TorusSampler, PoseMapsTheAxisAndSpinsBetaZero) {
  TorusSamplingParameters p = posed();
  const Eigen::Isometry3d pose = p.pose();
  EXPECT_LE((pose.linear() * Eigen::Vector3d::UnitZ() - p.axis.normalized()).norm(), 1e-15);
  p.spin = 0.0;
  const Eigen::Vector3d x0 = p.pose().linear() * Eigen::Vector3d::UnitX();
  const Eigen::Vector3d x1 = pose.linear() * Eigen::Vector3d::UnitX();
  EXPECT_NEAR(std::acos(x0.dot(x1)), 0.3, 1e-12);
}

TEST(TorusSampler, UnposedSamplesMeetTheImplicitEquationTo1e12) {
  TorusSamplingParameters p;
  p.shape = {3.0, 1.0};
  p.points = 50000;
  TorusSampler s;
  s.setParameters(p);
  Eigen::Matrix3Xd x, n;
  s.sample(x, n);
  for (Eigen::Index i = 0; i < x.cols(); ++i)
    ASSERT_LE(std::abs(torusImplicit(p.shape, x.col(i))) / (p.shape.r * p.shape.r), 1e-12);
}

/// Chi-square statistic of the α histogram (36 bands) against the area element R + r cos α.
double chiSquareAgainstArea(TorusSampling mode) {
  TorusSamplingParameters p;
  p.shape = {1.0, 0.6};
  p.points = 200000;
  p.sampling = mode;
  TorusSampler s;
  s.setParameters(p);
  Eigen::Matrix3Xd x, n;
  s.sample(x, n);
  constexpr int kBands = 36;
  std::vector<double> count(kBands, 0.0);
  for (Eigen::Index i = 0; i < x.cols(); ++i)
    count[std::min(kBands - 1,
                   static_cast<int>(alphaOf(p.shape, x.col(i)) / (2 * kPi) * kBands))] += 1;
  double chi2 = 0.0;
  for (int k = 0; k < kBands; ++k) {
    const double a0 = 2 * kPi * k / kBands, a1 = 2 * kPi * (k + 1) / kBands;
    // ∫ (R + r cos α) dα over the band, over the whole 2πR.
    const double share =
        (p.shape.R * (a1 - a0) + p.shape.r * (std::sin(a1) - std::sin(a0))) / (2 * kPi * p.shape.R);
    const double expected = share * p.points;
    chi2 += (count[k] - expected) * (count[k] - expected) / expected;
  }
  return chi2;
}

TEST(TorusSampler, AreaSamplingFollowsTheAreaElement) {
  // 35 degrees of freedom: P(χ² > 66.6) = 0.001.
  EXPECT_LT(chiSquareAgainstArea(TorusSampling::area), 66.6);
  // The test has teeth: angle-uniform sampling is far from area-uniform on a fat torus.
  EXPECT_GT(chiSquareAgainstArea(TorusSampling::angle), 1000.0);
}

TEST(TorusSampler, ParameterSamplingIsTwiceAsDenseInAlphaAtTheSeams) {
  // dα/du = 2 / ((1 − u)² + u²): 2 at the seams (u = 0, 1), 4 at u = 1/2, so the density in α is
  // twice as high near α = 0 as near α = π/2.
  TorusSamplingParameters p;
  p.shape = {1.0, 0.3};
  p.points = 400000;
  p.sampling = TorusSampling::parameter;
  TorusSampler s;
  s.setParameters(p);
  Eigen::Matrix3Xd x, n;
  s.sample(x, n);
  double near_seam = 0, near_top = 0;
  for (Eigen::Index i = 0; i < x.cols(); ++i) {
    const double a = alphaOf(p.shape, x.col(i));
    if (a < 0.05 || a > 2 * kPi - 0.05)
      near_seam += 1;
    if (std::abs(a - kPi / 2) < 0.05)
      near_top += 1;
  }
  EXPECT_NEAR(near_seam / near_top, 2.0, 0.1);
}

TEST(TorusSampler, NoiseOutliersCoverageAndSeeds) {
  TorusSamplingParameters p;
  p.shape = {1.0, 0.3};
  p.points = 20000;
  p.noise = 0.01;
  p.outlier_fraction = 0.1;
  p.alpha_min = 0.0;
  p.alpha_max = kPi / 2;
  p.beta_min = kPi;
  p.beta_max = 1.5 * kPi;
  TorusSampler s;
  s.setParameters(p);
  pcl::PointCloud<pcl::PointNormal> cloud;
  std::vector<std::int32_t> outlier;
  s.sample(cloud, &outlier);
  ASSERT_EQ(cloud.size(), 22000u);
  ASSERT_EQ(std::count(outlier.begin(), outlier.end(), 1), 2000);
  double sq = 0.0;
  for (std::size_t i = 0; i < 20000; ++i) {
    const Eigen::Vector3d x = cloud[i].getVector3fMap().cast<double>();
    const double d =
        std::hypot(std::hypot(x.x(), x.y()) - 1.0, x.z()) - 0.3;  // distance to the torus
    sq += d * d;
    double b = std::atan2(x.y(), x.x());
    if (b < 0)
      b += 2 * kPi;
    ASSERT_GT(b, kPi - 0.1);
    ASSERT_LT(b, 1.5 * kPi + 0.1);
  }
  // Isotropic noise σ per coordinate: the normal component has RMS σ.
  EXPECT_NEAR(std::sqrt(sq / 20000), 0.01, 0.0005);

  pcl::PointCloud<pcl::PointNormal> again;
  s.sample(again);
  EXPECT_EQ(std::memcmp(again.data(), cloud.data(), cloud.size() * sizeof(pcl::PointNormal)), 0);
  p.seed = 2;
  s.setParameters(p);
  s.sample(again);
  EXPECT_NE(again[0].x, cloud[0].x);
}

TEST(TorusSampler, BadParametersThrow) {
  TorusSamplingParameters p;
  p.shape = {1.0, 1.0};
  EXPECT_THROW(p.validate(), InvalidParameterError);
  p.shape = {1.0, 0.0};
  EXPECT_THROW(p.validate(), InvalidParameterError);
  p.shape = {1.0, 0.2};
  p.noise = -1.0;
  EXPECT_THROW(p.validate(), InvalidParameterError);
  p.noise = 0.0;
  p.alpha_min = 2.0;
  p.alpha_max = 1.0;
  EXPECT_THROW(p.validate(), InvalidParameterError);
}

}  // namespace
}  // namespace slipfit
