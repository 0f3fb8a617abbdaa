#pragma once
/// \file kNN neighborhoods of a test cloud, and normals estimated on them (the first two steps of
/// every per-point test pipeline).

#include "slipfit/neighborhoods/neighborhood_selection.h"
#include "slipfit/neighborhoods/normal_estimation.h"

#include <memory>

namespace slipfit::testing {

inline std::shared_ptr<Neighborhoods> knnNeighborhoods(
    const pcl::PointCloud<pcl::PointNormal>::ConstPtr& cloud, int k) {
  NeighborhoodSelection<pcl::PointNormal> selection;
  NeighborhoodParameters parameters;
  parameters.k = k;
  selection.setParameters(parameters);
  selection.setInputCloud(cloud);
  auto hoods = std::make_shared<Neighborhoods>();
  selection.compute(*hoods);
  return hoods;
}

/// Replaces the cloud's normals by normals estimated on \a hoods (viewpoint orientation: the
/// sign does not matter to slippage or segmentation).
inline void estimateNormals(pcl::PointCloud<pcl::PointNormal>::Ptr cloud,
                            const std::shared_ptr<const Neighborhoods>& hoods) {
  OrientedNormalEstimation<pcl::PointNormal, pcl::PointNormal> estimation;
  estimation.setInputCloud(cloud);
  estimation.setNeighborhoods(hoods);
  pcl::PointCloud<pcl::PointNormal> estimated;
  estimation.compute(estimated);
  for (std::size_t i = 0; i < cloud->size(); ++i)
    (*cloud)[i].getNormalVector3fMap() = estimated[i].getNormalVector3fMap();
}

}  // namespace slipfit::testing
