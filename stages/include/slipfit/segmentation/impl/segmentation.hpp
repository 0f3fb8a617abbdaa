#pragma once

#include "slipfit/core/exceptions.h"
#include "slipfit/segmentation/segmentation.h"

namespace slipfit {

template <typename PointT>
void SlippageSegmentation<PointT>::segment(std::vector<pcl::PointIndices>& clusters) {
  clusters.clear();
  if (!input_ || input_->empty())
    throw DegenerateInputError("segmentation: the input cloud is empty");
  if (!neighborhoods_ || !slippage_ || slippage_->size() != input_->size())
    throw DegenerateInputError(
        "segmentation: needs neighborhoods and local slippage for every cloud point");
  const auto n = static_cast<Eigen::Index>(input_->size());
  Eigen::Matrix3Xd points(3, n), normals(3, n);
  std::vector<SlippageType> types(input_->size());
  for (Eigen::Index i = 0; i < n; ++i) {
    const auto& p = (*input_)[static_cast<std::size_t>(i)];
    points.col(i) = p.getVector3fMap().template cast<double>();
    normals.col(i) = p.getNormalVector3fMap().template cast<double>();
    types[static_cast<std::size_t>(i)] =
        static_cast<SlippageType>((*slippage_)[static_cast<std::size_t>(i)].slippage_type);
  }
  result_ = segmentBySlippage(points, normals, *neighborhoods_, types, parameters_);
  clusters.resize(result_.segments.size());
  for (std::size_t k = 0; k < clusters.size(); ++k) {
    clusters[k].header = input_->header;
    clusters[k].indices.assign(result_.segments[k].indices.begin(),
                               result_.segments[k].indices.end());
  }
}

}  // namespace slipfit
