#pragma once
/// \file The per-point segmentation flow every segmentation test runs: kNN neighborhoods, normals
/// estimated on them, local slippage, then SlippageSegmentation (the PCL front end).

#include "shared_neighborhoods.h"

#include "slipfit/segmentation/segmentation.h"
#include "slipfit/slippage/local_slippage.h"

#include <memory>
#include <vector>

namespace slipfit::testing {

struct SegmentedCloud {
  std::shared_ptr<Neighborhoods> neighborhoods;
  SegmentationResult result;
  std::size_t clusters = 0;  ///< pcl::PointIndices returned by segment()
};

/// Replaces \a cloud's normals by estimated ones and segments it with neighborhoods of \a k (over
/// the whole cloud); only the points \a indices when given (setIndices).
inline SegmentedCloud segmentCloud(const pcl::PointCloud<pcl::PointNormal>::Ptr& cloud, int k,
                                   const pcl::IndicesConstPtr& indices = nullptr,
                                   const SegmentationParameters& parameters = {}) {
  SegmentedCloud out;
  out.neighborhoods = knnNeighborhoods(cloud, k);
  estimateNormals(cloud, out.neighborhoods);
  auto slippage = std::make_shared<pcl::PointCloud<PointSlippage>>();
  LocalSlippage<pcl::PointNormal> local;
  local.setInputCloud(cloud);
  local.setNeighborhoods(out.neighborhoods);
  local.compute(*slippage);
  SlippageSegmentation<pcl::PointNormal> seg;
  seg.setInputCloud(cloud);
  seg.setNeighborhoods(out.neighborhoods);
  seg.setLocalSlippage(slippage);
  if (indices)
    seg.setIndices(indices);
  seg.setParameters(parameters);
  std::vector<pcl::PointIndices> clusters;
  seg.segment(clusters);
  out.result = seg.result();
  out.clusters = clusters.size();
  return out;
}

}  // namespace slipfit::testing
