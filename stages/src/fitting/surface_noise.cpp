#include "slipfit/fitting/surface_noise.h"

#include "slipfit/core/exceptions.h"
#include "slipfit/core/median.h"

#include <pcl/kdtree/kdtree_flann.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <Eigen/QR>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace slipfit {

namespace {

/// Candidates in space per neighbour kept along the surface: enough to choose from without the
/// height bias, few enough that the ball stays on one layer of a tightly curved surface (at 4 a
/// twisted column's 128-point ball reaches the opposite face, which projects onto the same
/// tangent-plane spot, and σ̂ reads 50 × the noise).
constexpr int kCandidates = 2;

SurfaceNoise estimate(const Eigen::Ref<const Eigen::Matrix3Xd>& points,
                      const Eigen::Matrix3Xd* normals, int k) {
  if (k < 8 || k > 64)
    throw InvalidParameterError("surface noise: k must be in [8, 64], got " + std::to_string(k));
  std::vector<Eigen::Index> finite;
  finite.reserve(static_cast<std::size_t>(points.cols()));
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (Eigen::Index i = 0; i < points.cols(); ++i)
    if (points.col(i).allFinite()) {
      finite.push_back(i);
      centroid += points.col(i);
    }
  if (finite.size() <= static_cast<std::size_t>(k))
    return {};
  centroid /= static_cast<double>(finite.size());
  // The search runs in float on the centred points (their spread, not their distance from the
  // origin, sets the rounding); the covariances use the double coordinates.
  auto cloud = std::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
  cloud->reserve(finite.size());
  for (const Eigen::Index i : finite) {
    pcl::PointXYZ q;
    q.getVector3fMap() = (points.col(i) - centroid).cast<float>();
    cloud->push_back(q);
  }
  pcl::KdTreeFLANN<pcl::PointXYZ> tree;
  tree.setInputCloud(cloud);
  constexpr std::size_t kQueries = 2000;
  const std::size_t stride = (finite.size() + kQueries - 1) / kQueries;
  const int m = std::min<int>(kCandidates * k, static_cast<int>(finite.size()));
  std::vector<int> found;
  std::vector<float> squared;
  std::vector<std::pair<double, int>> tangential;
  std::vector<double> sigma, tilt;
  for (std::size_t q = 0; q < finite.size(); q += stride) {
    if (tree.nearestKSearch((*cloud)[q], m, found, squared) < k)
      continue;
    const Eigen::Vector3d origin = points.col(finite[q]);
    // The direction across the surface: the point's own normal, else the least-squares plane's
    // normal of the m nearest points.
    Eigen::Vector3d u = Eigen::Vector3d::Zero();
    const bool own =
        normals && normals->col(finite[q]).allFinite() && normals->col(finite[q]).norm() > 0.0;
    if (own) {
      u = normals->col(finite[q]).normalized();
    } else {
      Eigen::Vector3d mean = Eigen::Vector3d::Zero();
      for (const int j : found)
        mean += points.col(finite[static_cast<std::size_t>(j)]);
      mean /= static_cast<double>(found.size());
      Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
      for (const int j : found) {
        const Eigen::Vector3d d = points.col(finite[static_cast<std::size_t>(j)]) - mean;
        covariance += d * d.transpose();
      }
      u = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(covariance).eigenvectors().col(0);
    }
    // The k nearest along the surface: a search in 3-D prefers the points whose noise put them
    // at the query's own height, and would read the noise low where it is near the spacing.
    tangential.clear();
    for (const int j : found) {
      const Eigen::Vector3d d = points.col(finite[static_cast<std::size_t>(j)]) - origin;
      tangential.emplace_back((d - d.dot(u) * u).squaredNorm(), j);
    }
    std::partial_sort(tangential.begin(), tangential.begin() + k, tangential.end());
    // The residual of the local quadric h = a s² + b st + c t² + d s + e t + f over the tangent
    // coordinates (s, t) (scaled to unit RMS): the surface's curvature, the plane's tilt and its
    // offset are the model, what is left is noise, with k − 6 degrees of freedom.
    const Eigen::Vector3d e1 = u.unitOrthogonal(), e2 = u.cross(e1);
    double spread = 0.0;
    for (int j = 0; j < k; ++j)
      spread += tangential[static_cast<std::size_t>(j)].first;
    const double scale = std::sqrt(std::max(spread / k, std::numeric_limits<double>::min()));
    Eigen::MatrixXd design(k, 6);
    Eigen::VectorXd height(k);
    for (int j = 0; j < k; ++j) {
      const auto index = static_cast<std::size_t>(tangential[static_cast<std::size_t>(j)].second);
      const Eigen::Vector3d d = points.col(finite[index]) - origin;
      const double a = e1.dot(d) / scale, b = e2.dot(d) / scale;
      design.row(j) << a * a, a * b, b * b, a, b, 1.0;
      height[j] = u.dot(d);
    }
    const Eigen::VectorXd coefficients = design.colPivHouseholderQr().solve(height);
    const double rss = (height - design * coefficients).squaredNorm();
    if (std::isfinite(rss))
      sigma.push_back(std::sqrt(rss / (k - 6.0)));
    // The quadric's slope at the query, (d, e) / scale: how far the given normal is tilted from
    // the surface's (its estimate carries σ / (scale √k) of its own).
    if (own && coefficients.allFinite())
      tilt.push_back((coefficients[3] * coefficients[3] + coefficients[4] * coefficients[4]) /
                     (scale * scale));
  }
  SurfaceNoise out;
  if (!sigma.empty())
    out.position = medianInPlace(sigma);
  // θ² of a tilt whose two components are N(0, σ_t²) is σ_t² χ²₂, whose median is 2 ln 2.
  if (!tilt.empty())
    out.normal_tilt = std::sqrt(medianInPlace(tilt) / (2.0 * std::log(2.0)));
  return out;
}

}  // namespace

double estimateSurfaceNoise(const Eigen::Ref<const Eigen::Matrix3Xd>& points, int k) {
  return estimate(points, nullptr, k).position;
}

double estimateSurfaceNoise(const Eigen::Ref<const Eigen::Matrix3Xd>& points,
                            const Eigen::Ref<const Eigen::Matrix3Xd>& normals, int k) {
  if (normals.cols() != points.cols())
    throw InvalidParameterError("surface noise: " + std::to_string(normals.cols()) +
                                " normals for " + std::to_string(points.cols()) + " points");
  const Eigen::Matrix3Xd n = normals;
  return estimate(points, &n, k).position;
}

SurfaceNoise estimateSurfaceAndNormalNoise(const Eigen::Ref<const Eigen::Matrix3Xd>& points,
                                           const Eigen::Ref<const Eigen::Matrix3Xd>& normals,
                                           int k) {
  if (normals.cols() != points.cols())
    throw InvalidParameterError("surface noise: " + std::to_string(normals.cols()) +
                                " normals for " + std::to_string(points.cols()) + " points");
  const Eigen::Matrix3Xd n = normals;
  return estimate(points, &n, k);
}

}  // namespace slipfit
