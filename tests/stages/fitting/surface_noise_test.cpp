// The surface noise estimate (surface_noise.h) against the σ of the Gaussian noise put on a plane,
// on uniform samples and on scan lines, with and without the points' normals.
#include "slipfit/fitting/surface_noise.h"

#include "slipfit/core/exceptions.h"
#include "slipfit/sampling/random_vector.h"

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <random>

namespace slipfit {
namespace {

/// 20000 points of the plane z = 0 in [−1, 1]², σ = 0.01 Gaussian noise in 3-D; on \a lines the
/// points keep only stripes a fifth of the 0.1 line spacing wide (a line scanner).
void noisyPlane(bool lines, Eigen::Matrix3Xd& x, Eigen::Matrix3Xd& n) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::normal_distribution<double> g(0.0, 0.01);
  x.resize(3, 20000);
  n.resize(3, 20000);
  for (Eigen::Index i = 0; i < x.cols();) {
    const double a = u(rng), b = u(rng);
    if (lines && std::fmod(a + 1.0, 0.1) > 0.02)
      continue;
    x.col(i) = Eigen::Vector3d(a, b, 0.0) + randomVector<3>(g, rng);
    n.col(i++) = Eigen::Vector3d::UnitZ();
  }
}

TEST(SurfaceNoise, ReadsTheSigmaOfAUniformlySampledPlane) {
  Eigen::Matrix3Xd x, n;
  noisyPlane(false, x, n);
  // The median over 2000 queries of a 26-degree-of-freedom estimate (32 points, a 6-parameter
  // quadric): its own median is 1 % low and it scatters by about 2 %: 5 % either way.
  EXPECT_NEAR(estimateSurfaceNoise(x, 32), 0.01, 0.0005);
  EXPECT_NEAR(estimateSurfaceNoise(x, n, 32), 0.01, 0.0005);
}

TEST(SurfaceNoise, ReadsTheSigmaOnScanLines) {
  Eigen::Matrix3Xd x, n;
  noisyPlane(true, x, n);
  // On stripes 0.02 wide (2 σ) the 32 nearest points in space lie on one stripe, at the query's
  // height: their least-squares plane tilts with the noise and reads it low (0.0087). Chosen
  // along the surface from 64, with the height measured across the plane of those 64 or the
  // given normal, σ holds.
  const double free = estimateSurfaceNoise(x, 32), across = estimateSurfaceNoise(x, n, 32);
  std::cout << "scan lines: sigma-hat " << free << " without normals, " << across << " with\n";
  EXPECT_NEAR(free, 0.01, 0.0005);
  EXPECT_NEAR(across, 0.01, 0.0005);
}

TEST(SurfaceNoise, RejectsBadArguments) {
  Eigen::Matrix3Xd x = Eigen::Matrix3Xd::Random(3, 100), n = Eigen::Matrix3Xd::Random(3, 99);
  EXPECT_THROW(estimateSurfaceNoise(x, 3), InvalidParameterError);
  EXPECT_THROW(estimateSurfaceNoise(x, n, 16), InvalidParameterError);
  EXPECT_EQ(estimateSurfaceNoise(x.leftCols(10), 16), 0.0);  // fewer than k + 1 points
}

}  // namespace
}  // namespace slipfit
