#pragma once
/// \file How far a handful of points lie off the smooth surface through them: the spread that
/// noise puts across a surface, measured where the surface's own curvature is taken out.

#include <pcl/point_cloud.h>
#include <pcl/types.h>

#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <Eigen/QR>

#include <algorithm>
#include <cmath>

namespace slipfit {

/// The residuals of points off their local surface.
struct SurfaceThickness {
  double rms = 0.0;       ///< RMS residual, over the residual degrees of freedom
  double kurtosis = 0.0;  ///< m₄ / m₂² of the residuals (Gaussian noise 3; two equal sheets 1)
};

/// The residuals of the points \a indices of \a cloud off the quadric height field
/// h = a u² + b uv + c v² + d u + e v + f over their principal plane (RSS over n − 6), with
/// coordinates normalised before the solve; with fewer than 10 points, off their plane (RSS over
/// n − 3, kurtosis 0). Fewer than 4 points, or all points on one spot: zero.
template <typename PointT>
SurfaceThickness surfaceThickness(const pcl::PointCloud<PointT>& cloud,
                                  const pcl::Indices& indices) {
  const auto n = static_cast<Eigen::Index>(indices.size());
  if (n < 4)
    return {};
  // Centred on the first point, then on the mean: float coordinates far from the origin keep
  // their precision.
  const Eigen::Vector3d origin = cloud[indices[0]].getVector3fMap().template cast<double>();
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  Eigen::Matrix3d outer = Eigen::Matrix3d::Zero();
  for (const auto j : indices) {
    const Eigen::Vector3d p = cloud[j].getVector3fMap().template cast<double>() - origin;
    sum += p;
    outer += p * p.transpose();
  }
  const double count = static_cast<double>(n);
  const Eigen::Vector3d mean = sum / count;
  const Eigen::Matrix3d cov = outer / count - mean * mean.transpose();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen;
  eigen.computeDirect(cov);
  if (n < 10)
    return {std::sqrt(std::max(0.0, eigen.eigenvalues()(0)) * count / (count - 3.0)), 0.0};
  const Eigen::Matrix3d axes = eigen.eigenvectors();  // least variance first: the height
  Eigen::MatrixXd a(n, 6);
  Eigen::VectorXd h(n);
  double extent = 0.0;
  for (Eigen::Index j = 0; j < n; ++j) {
    const Eigen::Vector3d q =
        axes.transpose() *
        (cloud[indices[static_cast<std::size_t>(j)]].getVector3fMap().template cast<double>() -
         origin - mean);
    extent = std::max(extent, std::abs(q(1)) + std::abs(q(2)));
    h(j) = q(0);
    a.row(j) << q(1) * q(1), q(1) * q(2), q(2) * q(2), q(1), q(2), 1.0;
  }
  if (!(extent > 0.0))
    return {};
  a.leftCols(3) /= extent * extent;
  a.middleCols(3, 2) /= extent;
  const Eigen::VectorXd e = a * a.colPivHouseholderQr().solve(h) - h;
  const double m2 = e.squaredNorm() / count;
  const double m4 = e.array().square().square().sum() / count;
  return {std::sqrt(e.squaredNorm() / (count - 6.0)), m2 > 0.0 ? m4 / (m2 * m2) : 0.0};
}

}  // namespace slipfit
