#include "slipfit/neighborhoods/eigen_entropy.h"
#include "slipfit/sampling/random_vector.h"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

namespace slipfit {
namespace {

TEST(EigenEntropy, KnownSpectra) {
  EXPECT_NEAR(eigenEntropy(Eigen::Matrix3d::Identity()), std::log(3.0), 1e-12);
  EXPECT_NEAR(eigenEntropy(Eigen::Vector3d(1, 1, 0).asDiagonal().toDenseMatrix()), std::log(2.0),
              1e-12);
  EXPECT_NEAR(eigenEntropy(Eigen::Vector3d(5, 0, 0).asDiagonal().toDenseMatrix()), 0.0, 1e-12);
  EXPECT_EQ(eigenEntropy(Eigen::Matrix3d::Zero()), 0.0);
}

// The running-sum covariances must choose the same k as covariances recomputed from scratch.
TEST(EigenEntropy, OptimalSizeMatchesBruteForce) {
  std::mt19937_64 rng(7);
  std::normal_distribution<float> g(0.0f, 1.0f);
  for (int trial = 0; trial < 20; ++trial) {
    // An anisotropic blob far from the origin, sorted by distance from its first point.
    std::vector<Eigen::Vector3f> pts(60);
    const Eigen::Vector3f scale(1.0f, 0.3f + 0.03f * trial, 0.05f);
    for (auto& p : pts)
      p = Eigen::Vector3f(1e3f, -2e3f, 5e2f) + randomVector<3>(g, rng).cwiseProduct(scale);
    const Eigen::Vector3f q = pts[0];
    std::sort(pts.begin() + 1, pts.end(), [&](const auto& a, const auto& b) {
      return (a - q).squaredNorm() < (b - q).squaredNorm();
    });
    Eigen::Matrix3Xf m(3, pts.size());
    for (std::size_t i = 0; i < pts.size(); ++i)
      m.col(i) = pts[i];

    const int k_min = 6, k_max = 50, k_step = 4;
    int best = -1;
    double best_e = 1e9;
    for (int k = k_min; k <= k_max; k += k_step) {
      const Eigen::Matrix3Xd block = m.leftCols(k).cast<double>();
      const Eigen::Vector3d mean = block.rowwise().mean();
      const Eigen::Matrix3Xd centred = block.colwise() - mean;
      const double e = eigenEntropy(centred * centred.transpose() / k);
      if (e < best_e - 1e-12) {
        best_e = e;
        best = k;
      }
    }
    EXPECT_EQ(optimalNeighborhoodSize(m, k_min, k_max, k_step), best) << "trial " << trial;
  }
}

TEST(EigenEntropy, FewerNeighborsThanKMin) {
  Eigen::Matrix3Xf m = Eigen::Matrix3Xf::Random(3, 4);
  EXPECT_EQ(optimalNeighborhoodSize(m, 8, 20), 4);
}

// A line followed by scattered points: the collinear prefix has zero entropy and wins.
TEST(EigenEntropy, PrefersTheLinearPrefix) {
  Eigen::Matrix3Xf m(3, 30);
  for (int i = 0; i < 12; ++i)
    m.col(i) = Eigen::Vector3f(0.1f * i, 0, 0);
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<float> u(-3.0f, 3.0f);
  for (int i = 12; i < 30; ++i)
    m.col(i) = randomVector<3>(u, rng);
  const int k = optimalNeighborhoodSize(m, 5, 30, 1);
  EXPECT_GE(k, 5);
  EXPECT_LE(k, 12);
}

}  // namespace
}  // namespace slipfit
