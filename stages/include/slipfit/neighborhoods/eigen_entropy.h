#pragma once
/// \file Optimal neighborhood size by minimal eigen-entropy of the local covariance
/// (Weinmann, Jutzi, Hinz, Mallet, ISPRS J. 2015; the idea behind PDAL's optimalneighborhood).

#include <Eigen/Core>

namespace slipfit {

/// Eigen-entropy −Σ eᵢ ln eᵢ of the normalised eigenvalues eᵢ = λᵢ/Σλ of a 3×3 covariance.
/// Range [0, ln 3]; 0 for a degenerate (all-zero) covariance.
double eigenEntropy(const Eigen::Matrix3d& covariance);

/// The neighborhood size k in {k_min, k_min + k_step, ..., ≤ k_max} whose first-k neighbors have
/// the covariance of least eigen-entropy.
///
/// \param neighbors 3×M coordinates of the neighbors sorted by increasing distance from the query
///        point (the query itself first). Only the first min(M, k_max) columns are used.
/// \return the chosen k, or min(M, k_min) when M < k_min.
/// Cost O(min(M, k_max)): the covariances of all prefixes come from running sums.
int optimalNeighborhoodSize(const Eigen::Ref<const Eigen::Matrix3Xf>& neighbors, int k_min,
                            int k_max, int k_step = 1);

}  // namespace slipfit
