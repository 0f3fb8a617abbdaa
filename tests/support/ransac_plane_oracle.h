#pragma once
// PCL's RANSAC plane as the oracle for tables, floors and walls of real scans (issues 12 and 14):
// SACSegmentation with a distance threshold, 1000 iterations, the coefficients refined on the
// inliers. One run is one draw of a random estimator: on the milk-carton scan, 100 runs on the
// same points in 100 orders give planes up to 0.23° from their mean (median 0.05°), so an
// agreement finer than that needs the runs' consensus (their mean normal) as well as the single
// run a user would make.

#include <pcl/ModelCoefficients.h>
#include <pcl/PointIndices.h>
#include <pcl/point_cloud.h>
#include <pcl/segmentation/sac_segmentation.h>
#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

namespace slipfit::testing {

struct RansacPlane {
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();  ///< unit; zero when RANSAC found none
  double d = 0.0;                                    ///< normal · p + d = 0
  pcl::PointIndices inliers;
};

/// One SACSegmentation run on \a cloud in its own order (PCL's default, deterministic generator).
template <typename PointT>
RansacPlane ransacPlane(const typename pcl::PointCloud<PointT>::ConstPtr& cloud, double threshold) {
  pcl::SACSegmentation<PointT> sac;
  sac.setModelType(pcl::SACMODEL_PLANE);
  sac.setMethodType(pcl::SAC_RANSAC);
  sac.setDistanceThreshold(threshold);
  sac.setMaxIterations(1000);
  sac.setOptimizeCoefficients(true);
  sac.setInputCloud(cloud);
  pcl::ModelCoefficients c;
  RansacPlane plane;
  sac.segment(plane.inliers, c);
  if (c.values.size() != 4)
    return plane;
  const Eigen::Vector3d n(c.values[0], c.values[1], c.values[2]);
  plane.normal = n.normalized();
  plane.d = c.values[3] / n.norm();
  return plane;
}

/// The consensus of \a runs SACSegmentation planes: run 0 on the cloud in its own order, run k on
/// it shuffled by std::mt19937(k) (the same points, another sequence of samples). Returns the mean
/// of the unit normals (each turned to agree with run 0's), normalised; \a each receives every
/// run's normal.
template <typename PointT>
Eigen::Vector3d ransacConsensusNormal(const typename pcl::PointCloud<PointT>::ConstPtr& cloud,
                                      double threshold, int runs,
                                      std::vector<Eigen::Vector3d>* each = nullptr) {
  std::vector<Eigen::Vector3d> normals;
  for (int k = 0; k < runs; ++k) {
    auto shuffled = pcl::make_shared<pcl::PointCloud<PointT>>(*cloud);
    if (k > 0) {
      std::mt19937 generator(static_cast<std::mt19937::result_type>(k));
      std::shuffle(shuffled->points.begin(), shuffled->points.end(), generator);
    }
    const Eigen::Vector3d n = ransacPlane<PointT>(shuffled, threshold).normal;
    if (n.isZero())
      continue;
    normals.push_back(normals.empty() || n.dot(normals.front()) >= 0.0 ? n : Eigen::Vector3d(-n));
  }
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (const auto& n : normals)
    sum += n;
  if (each)
    *each = normals;
  return sum.isZero() ? sum : sum.normalized();
}

/// The unsigned angle between two directions, degrees.
inline double unsignedAngleDegrees(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  const double c = std::abs(a.normalized().dot(b.normalized()));
  return std::acos(std::min(1.0, c)) * 180.0 / 3.14159265358979323846;
}

}  // namespace slipfit::testing
