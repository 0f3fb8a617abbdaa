#pragma once
/// \file A kd-tree neighbour search built with nanoflann behind PCL's pcl::search::Search
/// interface: any PCL class that takes a search method (setSearchMethod) can use it. Built once
/// per cloud over its finite points (non-finite ones are never returned); each query is const and
/// may run in parallel. Results of either search are sorted by distance, ties by the lower cloud
/// index (by the earlier of the indices given, when they are not ascending): the k nearest are
/// the k least by (distance, index), a list that does not depend on the tree's layout. Squared
/// distances are in the cloud's float precision, as pcl::search::KdTree returns them; a radius
/// search returns the points strictly within the radius.

#if defined(NANOFLANN_HPP_) && !defined(NANOFLANN_FIRST_MATCH)
#error "nanoflann.hpp was included without NANOFLANN_FIRST_MATCH: include this header first"
#endif
#ifndef NANOFLANN_FIRST_MATCH
#define NANOFLANN_FIRST_MATCH  // equal distances: the lower index first (a stable order)
#endif
#include <nanoflann.hpp>

#include <pcl/common/point_tests.h>
#include <pcl/search/search.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace slipfit {

template <typename PointT>
class NanoflannSearch : public pcl::search::Search<PointT> {
 public:
  using Ptr = std::shared_ptr<NanoflannSearch<PointT>>;
  using PointCloudConstPtr = typename pcl::search::Search<PointT>::PointCloudConstPtr;
  using IndicesConstPtr = pcl::IndicesConstPtr;
  // The base's other overloads (by cloud and index, many queries at once) call these.
  using pcl::search::Search<PointT>::nearestKSearch;
  using pcl::search::Search<PointT>::radiusSearch;

  /// \a sorted: results by ascending distance (they always are; the flag is PCL's).
  explicit NanoflannSearch(bool sorted = true)
      : pcl::search::Search<PointT>("NanoflannSearch", sorted) {}
  NanoflannSearch(const NanoflannSearch&) = delete;  // the tree holds a view of xyz_
  NanoflannSearch& operator=(const NanoflannSearch&) = delete;

  /// Builds the tree over the finite points of \a cloud (of \a indices when given).
  void setInputCloud(const PointCloudConstPtr& cloud,
                     const IndicesConstPtr& indices = IndicesConstPtr()) override {
    this->input_ = cloud;
    this->indices_ = indices;
    xyz_.clear();
    rows_.clear();
    tree_.reset();
    if (!cloud)
      return;
    const auto take = [&](pcl::index_t i) {
      const PointT& p = (*cloud)[static_cast<std::size_t>(i)];
      if (!pcl::isFinite(p))
        return;
      xyz_.insert(xyz_.end(), {p.x, p.y, p.z});
      rows_.push_back(i);
    };
    if (indices)
      for (pcl::index_t i : *indices)
        take(i);
    else
      for (std::size_t i = 0; i < cloud->size(); ++i)
        take(static_cast<pcl::index_t>(i));
    tree_ = std::make_unique<Tree>(3, points_, nanoflann::KDTreeSingleIndexAdaptorParams(10));
  }

  /// The \a k nearest finite points to \a point (fewer when the cloud has fewer).
  int nearestKSearch(const PointT& point, int k, pcl::Indices& k_indices,
                     std::vector<float>& k_sqr_distances) const override {
    k_indices.clear();
    k_sqr_distances.clear();
    if (!tree_ || k <= 0 || rows_.empty() || !pcl::isFinite(point))
      return 0;
    const auto want = std::min<std::size_t>(static_cast<std::size_t>(k), rows_.size());
    thread_local std::vector<std::uint32_t> rows;  // one buffer per thread, not one per query
    rows.resize(want);
    k_sqr_distances.resize(want);
    const float query[3] = {point.x, point.y, point.z};
    StableKnn result(want);
    result.init(rows.data(), k_sqr_distances.data());
    tree_->findNeighbors(result, query, nanoflann::SearchParams());
    const std::size_t found = result.size();
    k_sqr_distances.resize(found);
    k_indices.resize(found);
    for (std::size_t j = 0; j < found; ++j)
      k_indices[j] = rows_[rows[j]];
    return static_cast<int>(found);
  }

  /// The finite points within \a radius of \a point; with \a max_nn > 0 the nearest \a max_nn of
  /// them.
  int radiusSearch(const PointT& point, double radius, pcl::Indices& k_indices,
                   std::vector<float>& k_sqr_distances, unsigned int max_nn = 0) const override {
    k_indices.clear();
    k_sqr_distances.clear();
    if (!tree_ || rows_.empty() || !pcl::isFinite(point) || !(radius >= 0.0))
      return 0;
    const float query[3] = {point.x, point.y, point.z};
    const auto r2 = static_cast<float>(radius * radius);
    // By distance, ties by row; the tree's rows follow the cloud's order, so ordering rows orders
    // cloud indices. One integer per result: a distance is a non-negative float, whose bits order
    // as its values do, above the row (a sort of 64-bit keys, not of pairs by a comparison).
    thread_local std::vector<std::uint64_t> keys;
    keys.clear();
    if (max_nn > 0) {
      // The nearest max_nn within the radius, kept in a heap while the tree is searched: a ball
      // holding far more points than max_nn (a wide radius in a dense or volumetric cloud) costs
      // max_nn, not every point in it.
      CappedBall ball(r2, max_nn, keys);
      tree_->findNeighbors(ball, query, nanoflann::SearchParams());
      std::sort(keys.begin(), keys.end());  // faster than sort_heap
    } else {
      thread_local std::vector<std::pair<std::uint32_t, float>> found;
      found.clear();
      nanoflann::SearchParams params;
      params.sorted = false;
      tree_->radiusSearch(query, r2, found, params);
      keys.resize(found.size());
      for (std::size_t j = 0; j < found.size(); ++j)
        keys[j] = key(found[j].second, found[j].first);
      std::sort(keys.begin(), keys.end());
    }
    k_indices.resize(keys.size());
    k_sqr_distances.resize(keys.size());
    for (std::size_t j = 0; j < keys.size(); ++j) {
      k_sqr_distances[j] = distance(keys[j]);
      k_indices[j] = rows_[static_cast<std::uint32_t>(keys[j])];
    }
    return static_cast<int>(keys.size());
  }

 private:
  /// nanoflann's k-nearest result set, which takes a point only when it is strictly nearer than
  /// the k-th so far: at the k-th distance the point found first would stay, whichever the tree
  /// visits first. Reporting the k-th distance one float step further lets an equally distant
  /// point in, and NANOFLANN_FIRST_MATCH orders equal distances by index: the k kept are the k
  /// least by (distance, index), whatever the tree's layout.
  class StableKnn : public nanoflann::KNNResultSet<float, std::uint32_t> {
   public:
    using nanoflann::KNNResultSet<float, std::uint32_t>::KNNResultSet;
    float worstDist() const {
      return std::nextafter(nanoflann::KNNResultSet<float, std::uint32_t>::worstDist(),
                            std::numeric_limits<float>::infinity());
    }
  };

  /// A result's sort key: its squared distance's bits above its tree row.
  static std::uint64_t key(float sqr_distance, std::uint32_t row) {
    std::uint32_t bits;
    std::memcpy(&bits, &sqr_distance, sizeof bits);
    return std::uint64_t{bits} << 32 | row;
  }
  static float distance(std::uint64_t key) {
    const auto bits = static_cast<std::uint32_t>(key >> 32);
    float d;
    std::memcpy(&d, &bits, sizeof d);
    return d;
  }

  /// A nanoflann result set holding the \a cap least keys strictly within a squared radius, as a
  /// max-heap. Once full, the tree prunes at the largest kept distance (one float step further,
  /// so that an equally distant point of a lower row can still replace it).
  class CappedBall {
   public:
    CappedBall(float sqr_radius, std::size_t cap, std::vector<std::uint64_t>& heap)
        : sqr_radius_(sqr_radius), cap_(cap), heap_(heap) {}
    std::size_t size() const { return heap_.size(); }
    bool full() const { return heap_.size() == cap_; }
    bool addPoint(float dist, std::uint32_t row) {
      if (!(dist < sqr_radius_))
        return true;
      const std::uint64_t k = key(dist, row);
      if (heap_.size() < cap_) {
        heap_.push_back(k);
        std::push_heap(heap_.begin(), heap_.end());
      } else if (k < heap_.front()) {
        std::pop_heap(heap_.begin(), heap_.end());
        heap_.back() = k;
        std::push_heap(heap_.begin(), heap_.end());
      }
      return true;
    }
    float worstDist() const {
      if (!full())
        return sqr_radius_;
      return std::min(sqr_radius_, std::nextafter(distance(heap_.front()),
                                                  std::numeric_limits<float>::infinity()));
    }

   private:
    float sqr_radius_;
    std::size_t cap_;
    std::vector<std::uint64_t>& heap_;
  };

  /// nanoflann's view of the packed coordinates.
  struct Points {
    const std::vector<float>* xyz;
    std::size_t kdtree_get_point_count() const { return xyz->size() / 3; }
    float kdtree_get_pt(std::size_t i, std::size_t dim) const { return (*xyz)[3 * i + dim]; }
    template <class Box>
    bool kdtree_get_bbox(Box&) const {
      return false;
    }
  };
  using Tree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<float, Points>,
                                                   Points, 3, std::uint32_t>;

  std::vector<float> xyz_;          ///< the finite points, x y z after one another
  std::vector<pcl::index_t> rows_;  ///< each tree row's cloud index
  Points points_{&xyz_};
  std::unique_ptr<Tree> tree_;
};

}  // namespace slipfit
