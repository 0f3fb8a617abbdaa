#pragma once
/// \file 3 × N points as a PCL cloud without normals, the input of the segmentation tests.

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <Eigen/Core>

namespace slipfit::testing {

/// The columns of \a points as a cloud (normals zero, to be estimated).
inline pcl::PointCloud<pcl::PointNormal>::Ptr pointsCloud(const Eigen::Matrix3Xd& points) {
  auto cloud = pcl::make_shared<pcl::PointCloud<pcl::PointNormal>>();
  cloud->reserve(static_cast<std::size_t>(points.cols()));
  for (Eigen::Index i = 0; i < points.cols(); ++i) {
    pcl::PointNormal q;
    q.getVector3fMap() = points.col(i).cast<float>();
    cloud->push_back(q);
  }
  return cloud;
}

}  // namespace slipfit::testing
