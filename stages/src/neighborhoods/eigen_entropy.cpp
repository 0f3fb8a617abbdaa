#include "slipfit/neighborhoods/eigen_entropy.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <limits>

namespace slipfit {

double eigenEntropy(const Eigen::Matrix3d& covariance) {
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver;
  solver.computeDirect(covariance, Eigen::EigenvaluesOnly);
  const Eigen::Vector3d lambda = solver.eigenvalues().cwiseMax(0.0);
  const double sum = lambda.sum();
  if (!(sum > 0.0))
    return 0.0;
  double entropy = 0.0;
  for (int i = 0; i < 3; ++i) {
    const double e = lambda[i] / sum;
    if (e > 0.0)
      entropy -= e * std::log(e);
  }
  return entropy;
}

int optimalNeighborhoodSize(const Eigen::Ref<const Eigen::Matrix3Xf>& neighbors, int k_min,
                            int k_max, int k_step) {
  const int m = static_cast<int>(std::min<Eigen::Index>(neighbors.cols(), k_max));
  if (m <= k_min)
    return m;
  // Sums relative to the query point keep the running covariance free of cancellation far from
  // the origin.
  const Eigen::Vector3d origin = neighbors.col(0).cast<double>();
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  Eigen::Matrix3d sum_sq = Eigen::Matrix3d::Zero();
  int best_k = k_min;
  double best_entropy = std::numeric_limits<double>::infinity();
  for (int k = 1; k <= m; ++k) {
    const Eigen::Vector3d d = neighbors.col(k - 1).cast<double>() - origin;
    sum += d;
    sum_sq.noalias() += d * d.transpose();
    if (k < k_min || (k - k_min) % k_step != 0)
      continue;
    const Eigen::Vector3d mean = sum / k;
    const Eigen::Matrix3d cov = sum_sq / k - mean * mean.transpose();
    const double entropy = eigenEntropy(cov);
    // Strictly smaller: on ties the smaller, more local neighborhood wins.
    if (entropy < best_entropy) {
      best_entropy = entropy;
      best_k = k;
    }
  }
  return best_k;
}

}  // namespace slipfit
