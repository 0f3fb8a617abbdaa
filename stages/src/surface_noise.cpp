#include "slipfit/surface_noise.h"

#include "slipfit/exceptions.h"

#include <pcl/kdtree/kdtree_flann.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace slipfit {

double estimateSurfaceNoise(const Eigen::Ref<const Eigen::Matrix3Xd>& points, int k) {
  if (k < 4 || k > 64)
    throw InvalidParameterError("surface noise: k must be in [4, 64], got " + std::to_string(k));
  std::vector<Eigen::Index> finite;
  finite.reserve(static_cast<std::size_t>(points.cols()));
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (Eigen::Index i = 0; i < points.cols(); ++i)
    if (points.col(i).allFinite()) {
      finite.push_back(i);
      centroid += points.col(i);
    }
  if (finite.size() <= static_cast<std::size_t>(k))
    return 0.0;
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
  std::vector<int> found;
  std::vector<float> squared;
  std::vector<double> sigma;
  for (std::size_t q = 0; q < finite.size(); q += stride) {
    if (tree.nearestKSearch((*cloud)[q], k, found, squared) < k)
      continue;
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (const int j : found)
      mean += points.col(finite[static_cast<std::size_t>(j)]);
    mean /= k;
    Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
    for (const int j : found) {
      const Eigen::Vector3d d = points.col(finite[static_cast<std::size_t>(j)]) - mean;
      covariance += d * d.transpose();
    }
    covariance /= k;
    const double lambda0 = std::max(
        0.0, Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(covariance, Eigen::EigenvaluesOnly)
                 .eigenvalues()(0));
    sigma.push_back(std::sqrt(lambda0 * k / (k - 3.0)));
  }
  if (sigma.empty())
    return 0.0;
  auto middle = sigma.begin() + static_cast<std::ptrdiff_t>(sigma.size() / 2);
  std::nth_element(sigma.begin(), middle, sigma.end());
  return *middle;
}

}  // namespace slipfit
