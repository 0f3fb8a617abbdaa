#pragma once
/// \file A OrientedNormalEstimation on a cloud with the given orientation and otherwise default
/// parameters: the set-up most normal tests share.

#include "slipfit/neighborhoods/normal_estimation.h"

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

namespace slipfit::testing {

template <typename PointOut = pcl::Normal>
OrientedNormalEstimation<pcl::PointNormal, PointOut> normalEstimator(
    const pcl::PointCloud<pcl::PointNormal>::ConstPtr& cloud, NormalOrientation orientation) {
  OrientedNormalEstimation<pcl::PointNormal, PointOut> estimation;
  NormalParameters p;
  p.orientation = orientation;
  estimation.setParameters(p);
  estimation.setInputCloud(cloud);
  return estimation;
}

}  // namespace slipfit::testing
