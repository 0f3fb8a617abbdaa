#pragma once
/// \file A pcl::search::Search that answers from neighborhoods computed earlier, so that PCL
/// algorithms (pcl::NormalEstimationOMP, ...) reuse them instead of searching again.

#include "slipfit/core/exceptions.h"
#include "slipfit/neighborhoods/neighborhoods.h"

#include <pcl/search/search.h>

#include <algorithm>
#include <memory>
#include <string>
#include <vector>

namespace slipfit {

/// Answers nearest-neighbor queries *by index* of the cloud the neighborhoods were computed on.
///
/// nearestKSearch(cloud, i, k) returns the first min(k, |N(i)|) neighbors of point i;
/// radiusSearch(cloud, i, r) returns those of N(i) within r. Queries by coordinates, or for a
/// different cloud, have no stored answer and throw: this class never searches. Thread-safe for
/// concurrent queries.
template <typename PointT>
class PrecomputedSearch : public pcl::search::Search<PointT> {
 public:
  using Ptr = std::shared_ptr<PrecomputedSearch<PointT>>;
  using typename pcl::search::Search<PointT>::PointCloud;
  using typename pcl::search::Search<PointT>::PointCloudConstPtr;
  using IndicesConstPtr = pcl::IndicesConstPtr;
  using pcl::search::Search<PointT>::nearestKSearch;
  using pcl::search::Search<PointT>::radiusSearch;

  explicit PrecomputedSearch(std::shared_ptr<const Neighborhoods> neighborhoods)
      : pcl::search::Search<PointT>("PrecomputedSearch", true),
        neighborhoods_(std::move(neighborhoods)) {}

  /// Binds the cloud the neighborhoods belong to; builds nothing.
  void setInputCloud(const PointCloudConstPtr& cloud,
                     const IndicesConstPtr& indices = IndicesConstPtr()) override {
    if (cloud && cloud->size() != neighborhoods_->size())
      throw InvalidParameterError("PrecomputedSearch: the cloud has " +
                                  std::to_string(cloud->size()) +
                                  " points but the neighborhoods were computed for " +
                                  std::to_string(neighborhoods_->size()));
    this->input_ = cloud;
    this->indices_ = indices;
  }

  int nearestKSearch(const PointCloud& cloud, pcl::index_t index, int k, pcl::Indices& k_indices,
                     std::vector<float>& k_sqr_distances) const override {
    checkCloud(cloud);
    const NeighborView v = (*neighborhoods_)[static_cast<std::size_t>(index)];
    const std::size_t count =
        std::min<std::size_t>(v.size(), k > 0 ? static_cast<std::size_t>(k) : 0);
    k_indices.assign(v.indices, v.indices + count);
    k_sqr_distances.assign(v.sqr_distances, v.sqr_distances + count);
    return static_cast<int>(count);
  }

  int nearestKSearch(pcl::index_t index, int k, pcl::Indices& k_indices,
                     std::vector<float>& k_sqr_distances) const override {
    return nearestKSearch(*this->input_, index, k, k_indices, k_sqr_distances);
  }

  int nearestKSearch(const PointT&, int, pcl::Indices&, std::vector<float>&) const override {
    throw InvalidParameterError("PrecomputedSearch answers queries by point index only");
  }

  int radiusSearch(const PointCloud& cloud, pcl::index_t index, double radius,
                   pcl::Indices& k_indices, std::vector<float>& k_sqr_distances,
                   unsigned int max_nn = 0) const override {
    checkCloud(cloud);
    const NeighborView v = (*neighborhoods_)[static_cast<std::size_t>(index)];
    const auto r2 = static_cast<float>(radius * radius);
    k_indices.clear();
    k_sqr_distances.clear();
    for (std::size_t j = 0; j < v.size(); ++j) {
      if (v.sqr_distances[j] > r2)
        continue;
      if (max_nn != 0 && k_indices.size() >= max_nn)
        break;
      k_indices.push_back(v.indices[j]);
      k_sqr_distances.push_back(v.sqr_distances[j]);
    }
    return static_cast<int>(k_indices.size());
  }

  int radiusSearch(pcl::index_t index, double radius, pcl::Indices& k_indices,
                   std::vector<float>& k_sqr_distances, unsigned int max_nn = 0) const override {
    return radiusSearch(*this->input_, index, radius, k_indices, k_sqr_distances, max_nn);
  }

  int radiusSearch(const PointT&, double, pcl::Indices&, std::vector<float>&,
                   unsigned int = 0) const override {
    throw InvalidParameterError("PrecomputedSearch answers queries by point index only");
  }

  const Neighborhoods& neighborhoods() const { return *neighborhoods_; }

 private:
  void checkCloud(const PointCloud& cloud) const {
    if (!this->input_ || &cloud != this->input_.get())
      throw InvalidParameterError("PrecomputedSearch: query for a cloud other than its input");
  }

  std::shared_ptr<const Neighborhoods> neighborhoods_;
};

}  // namespace slipfit
