#pragma once

#include "slipfit/core/exceptions.h"
#include "slipfit/segmentation/segmentation.h"

#include <algorithm>

namespace slipfit {

template <typename PointT>
void SlippageSegmentation<PointT>::segment(std::vector<pcl::PointIndices>& clusters) {
  clusters.clear();
  if (!input_ || input_->empty())
    throw DegenerateInputError("segmentation: the input cloud is empty");
  const bool has_types =
      types_ ? types_->size() == input_->size() : slippage_ && slippage_->size() == input_->size();
  if (!neighborhoods_ || !has_types || neighborhoods_->size() != input_->size())
    throw DegenerateInputError(
        "segmentation: needs neighborhoods and local slippage for every cloud point");
  if (!this->initCompute())
    throw DegenerateInputError("segmentation: the input cloud or its indices are unusable");
  // The points segmented: the indices given (setIndices), or all of them. A point's neighbors
  // outside the indices are not its neighbors here.
  const std::size_t n = input_->size();
  const std::size_t m = indices_->size();
  std::vector<pcl::index_t> position(n, -1);  // cloud index → position among the indices
  for (std::size_t k = 0; k < m; ++k) {
    const pcl::index_t i = (*indices_)[k];
    if (i < 0 || static_cast<std::size_t>(i) >= n || position[static_cast<std::size_t>(i)] >= 0)
      throw DegenerateInputError("segmentation: index " + std::to_string(i) +
                                 (i < 0 || static_cast<std::size_t>(i) >= n
                                      ? " is outside the cloud"
                                      : " is given twice"));
    position[static_cast<std::size_t>(i)] = static_cast<pcl::index_t>(k);
  }
  const bool whole = this->fake_indices_;
  Eigen::Matrix3Xd points(3, static_cast<Eigen::Index>(m)), normals(3, points.cols());
  std::vector<SlippageType> types(m);
  Neighborhoods subset;
  if (!whole)
    subset.reserve(m, neighborhoods_->entries());
  std::vector<pcl::index_t> ids;
  std::vector<float> sqr;
  for (std::size_t k = 0; k < m; ++k) {
    const auto i = static_cast<std::size_t>((*indices_)[k]);
    const auto& p = (*input_)[i];
    const auto col = static_cast<Eigen::Index>(k);
    points.col(col) = p.getVector3fMap().template cast<double>();
    normals.col(col) = p.getNormalVector3fMap().template cast<double>();
    types[k] = types_ ? (*types_)[i] : static_cast<SlippageType>((*slippage_)[i].slippage_type);
    if (whole)
      continue;
    const NeighborView v = (*neighborhoods_)[i];
    ids.clear();
    sqr.clear();
    for (std::size_t j = 0; j < v.size(); ++j)
      if (position[static_cast<std::size_t>(v[j])] >= 0) {
        ids.push_back(position[static_cast<std::size_t>(v[j])]);
        sqr.push_back(v.sqr_distances[j]);
      }
    subset.append(ids.data(), sqr.data(), ids.size());
  }
  // A sensor's view, as PCL records one: an organized cloud, or a sensor pose set.
  SegmentationParameters parameters = parameters_;
  parameters.sensor_view =
      parameters.sensor_view || input_->isOrganized() ||
      input_->sensor_origin_.template head<3>() != Eigen::Vector3f::Zero() ||
      input_->sensor_orientation_.coeffs() != Eigen::Quaternionf::Identity().coeffs();
  result_ = segmentBySlippage(points, normals, whole ? *neighborhoods_ : subset, types, parameters,
                              on_phase_);
  if (!whole) {
    // Back to cloud indices: labels for every cloud point (−1 outside the indices).
    std::vector<std::int32_t> labels(n, -1);
    for (std::size_t k = 0; k < m; ++k)
      labels[static_cast<std::size_t>((*indices_)[k])] = result_.labels[k];
    result_.labels = std::move(labels);
    for (Segment& segment : result_.segments) {
      for (int& i : segment.indices)
        i = (*indices_)[static_cast<std::size_t>(i)];
      std::sort(segment.indices.begin(), segment.indices.end());
    }
  }
  this->deinitCompute();
  clusters.resize(result_.segments.size());
  for (std::size_t k = 0; k < clusters.size(); ++k) {
    clusters[k].header = input_->header;
    clusters[k].indices.assign(result_.segments[k].indices.begin(),
                               result_.segments[k].indices.end());
  }
}

}  // namespace slipfit
