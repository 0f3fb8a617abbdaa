#pragma once
/// \file A pcl::search::KdTree that counts tree builds and queries, to prove that neighborhoods
/// are searched once and then shared.

#include <pcl/search/kdtree.h>

#include <atomic>

namespace slipfit::testing {

template <typename PointT>
class CountingKdTree : public pcl::search::KdTree<PointT> {
 public:
  using Base = pcl::search::KdTree<PointT>;
  using Base::nearestKSearch;
  using Base::radiusSearch;
  CountingKdTree() : Base(true) {}

  void setInputCloud(const typename Base::PointCloudConstPtr& cloud,
                     const pcl::IndicesConstPtr& indices = pcl::IndicesConstPtr()) override {
    ++builds;
    Base::setInputCloud(cloud, indices);
  }
  int nearestKSearch(const PointT& point, int k, pcl::Indices& ind,
                     std::vector<float>& d) const override {
    ++queries;
    return Base::nearestKSearch(point, k, ind, d);
  }
  int radiusSearch(const PointT& point, double r, pcl::Indices& ind, std::vector<float>& d,
                   unsigned int max_nn = 0) const override {
    ++queries;
    return Base::radiusSearch(point, r, ind, d, max_nn);
  }

  mutable std::atomic<std::size_t> builds{0};
  mutable std::atomic<std::size_t> queries{0};
};

}  // namespace slipfit::testing
