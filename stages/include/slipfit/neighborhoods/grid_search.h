#pragma once
/// \file A pcl::search::Search over the pixel grid of a range image: the neighbors of a point are
/// found among the points of the pixels around its own (as PCL's OrganizedNeighbor), with no tree.

#include "slipfit/core/exceptions.h"

#include <pcl/search/search.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace slipfit {

/// The pixels of a sensor's image: width × height cells, and the cell of each point of a cloud
/// that holds only the finite returns (row × width + column; each cell at most once).
struct PixelGrid {
  std::uint32_t width = 0;
  std::uint32_t height = 0;
  std::vector<std::int32_t> cells;  ///< per cloud point

  bool empty() const { return cells.empty(); }
  /// Throws InvalidParameterError when a cell lies outside the image or holds two points, or when
  /// \a points (the cloud's size) differs from the number of cells.
  void check(std::size_t points) const;
};

/// Answers nearest-neighbor queries *by index* from the image window around the query's pixel:
/// the candidates are the points whose pixels lie within a square window, and the answer is
/// theirs, nearest first by the Euclidean distance in space (so a depth discontinuity inside the
/// window separates: the far side is far).
///
/// - nearestKSearch(cloud, i, k): the window grows from radius 2 (doubling, at most kMaxWindow)
///   until its k-th nearest lies within (radius + 1) pixel pitches, nearer than any point of a
///   smooth surface outside the window can; its k nearest. Within a smooth surface this is the
///   kd-tree's answer, and at a depth discontinuity the window grows rather than take the far
///   side.
/// - radiusSearch(cloud, i, r, max_nn): the window spans r in pixels at the query's own pixel
///   pitch (the smallest distance to a 4-neighbor pixel: the pitch across the ray, which a tilted
///   surface does not stretch), at most kMaxWindow; the points within r, nearest first, at most
///   max_nn.
/// Queries by coordinates, or for a cloud other than the input, throw (this class knows pixels,
/// not a projection). Thread-safe for concurrent queries.
template <typename PointT>
class GridSearch : public pcl::search::Search<PointT> {
 public:
  using Ptr = std::shared_ptr<GridSearch<PointT>>;
  using typename pcl::search::Search<PointT>::PointCloud;
  using typename pcl::search::Search<PointT>::PointCloudConstPtr;
  using IndicesConstPtr = pcl::IndicesConstPtr;
  using pcl::search::Search<PointT>::nearestKSearch;
  using pcl::search::Search<PointT>::radiusSearch;

  /// The largest window radius, pixels: a query never reads more than (2·64 + 1)² pixels.
  static constexpr int kMaxWindow = 64;
  /// The window every query reads whole, radius in pixels (5 × 5).
  static constexpr int kInner = 2;

  explicit GridSearch(PixelGrid grid)
      : pcl::search::Search<PointT>("GridSearch", true), grid_(std::move(grid)) {}

  /// Binds the cloud whose points sit on the grid's cells and fills the pixel → point map.
  void setInputCloud(const PointCloudConstPtr& cloud,
                     const IndicesConstPtr& indices = IndicesConstPtr()) override {
    this->input_ = cloud;
    this->indices_ = indices;
    if (!cloud)
      return;
    grid_.check(cloud->size());
    point_of_.assign(static_cast<std::size_t>(grid_.width) * grid_.height, -1);
    for (std::size_t i = 0; i < grid_.cells.size(); ++i)
      point_of_[static_cast<std::size_t>(grid_.cells[i])] = static_cast<std::int32_t>(i);
  }

  int nearestKSearch(const PointCloud& cloud, pcl::index_t index, int k, pcl::Indices& k_indices,
                     std::vector<float>& k_sqr_distances) const override {
    checkCloud(cloud);
    k_indices.clear();
    k_sqr_distances.clear();
    if (k <= 0)
      return 0;
    const auto want = static_cast<std::size_t>(k);
    const double pitch = pixelPitch(index);
    auto& found = buffer();  // one per thread: no allocation per query
    for (int radius = kInner;; radius = std::min(2 * radius, kMaxWindow)) {
      found.clear();
      collect(index, radius, std::numeric_limits<float>::infinity(), found);
      if (radius == kMaxWindow)
        break;
      if (found.size() < want)
        continue;
      // Done when the k-th nearest lies nearer than any pixel outside the window can: those lie
      // at least radius + 1 pixel pitches away on a smooth surface.
      std::nth_element(found.begin(), found.begin() + static_cast<std::ptrdiff_t>(want - 1),
                       found.end());
      const double reach = (radius + 1) * pitch;
      if (static_cast<double>(found[want - 1].first) <= reach * reach)
        break;
    }
    return answer(found, want, k_indices, k_sqr_distances);
  }

  int nearestKSearch(pcl::index_t index, int k, pcl::Indices& k_indices,
                     std::vector<float>& k_sqr_distances) const override {
    return nearestKSearch(*this->input_, index, k, k_indices, k_sqr_distances);
  }

  int nearestKSearch(const PointT&, int, pcl::Indices&, std::vector<float>&) const override {
    throw InvalidParameterError("GridSearch answers queries by point index only");
  }

  int radiusSearch(const PointCloud& cloud, pcl::index_t index, double radius,
                   pcl::Indices& k_indices, std::vector<float>& k_sqr_distances,
                   unsigned int max_nn = 0) const override {
    checkCloud(cloud);
    k_indices.clear();
    k_sqr_distances.clear();
    const double pitch = pixelPitch(index);
    int window = kInner;
    if (pitch > 0.0 && std::isfinite(radius))
      window =
          static_cast<int>(std::clamp<double>(std::ceil(radius / pitch) + 1.0, kInner, kMaxWindow));
    // Beyond the inner window, every stride-th row and column: about max_nn pixels in all.
    int stride = 1;
    if (max_nn != 0) {
      const double side = 2.0 * window + 1.0;
      stride = std::max(1, static_cast<int>(std::floor(side / std::sqrt(double(max_nn)))));
    }
    auto& found = buffer();  // one per thread: no allocation per query
    collect(index, window, static_cast<float>(radius * radius), found, stride);
    const std::size_t want =
        max_nn == 0 ? found.size() : std::min<std::size_t>(max_nn, found.size());
    return answer(found, want, k_indices, k_sqr_distances);
  }

  int radiusSearch(pcl::index_t index, double radius, pcl::Indices& k_indices,
                   std::vector<float>& k_sqr_distances, unsigned int max_nn = 0) const override {
    return radiusSearch(*this->input_, index, radius, k_indices, k_sqr_distances, max_nn);
  }

  int radiusSearch(const PointT&, double, pcl::Indices&, std::vector<float>&,
                   unsigned int = 0) const override {
    throw InvalidParameterError("GridSearch answers queries by point index only");
  }

  const PixelGrid& grid() const { return grid_; }

 private:
  void checkCloud(const PointCloud& cloud) const {
    if (!this->input_ || &cloud != this->input_.get())
      throw InvalidParameterError("GridSearch: query for a cloud other than its input");
  }

  float squaredDistance(std::int32_t a, std::int32_t b) const {
    const PointT& p = (*this->input_)[static_cast<std::size_t>(a)];
    const PointT& q = (*this->input_)[static_cast<std::size_t>(b)];
    const float dx = p.x - q.x, dy = p.y - q.y, dz = p.z - q.z;
    return dx * dx + dy * dy + dz * dz;
  }

  /// The points of the pixels within \a radius (Chebyshev) of point \a index's pixel that lie
  /// within sqrt(\a limit) of it, as (squared distance, point).
  void collect(pcl::index_t index, int radius, float limit,
               std::vector<std::pair<float, std::int32_t>>& found, int stride = 1) const {
    const auto cell = grid_.cells[static_cast<std::size_t>(index)];
    const int w = static_cast<int>(grid_.width), h = static_cast<int>(grid_.height);
    const int row = cell / w, col = cell % w;
    for (int r = std::max(0, row - radius); r <= std::min(h - 1, row + radius); ++r)
      for (int c = std::max(0, col - radius); c <= std::min(w - 1, col + radius); ++c) {
        const bool inner = std::abs(r - row) <= kInner && std::abs(c - col) <= kInner;
        if (!inner && ((r - row) % stride != 0 || (c - col) % stride != 0))
          continue;
        const std::int32_t j =
            point_of_[static_cast<std::size_t>(r) * grid_.width + static_cast<std::size_t>(c)];
        if (j < 0)
          continue;
        const float d = squaredDistance(static_cast<std::int32_t>(index), j);
        if (d <= limit)
          found.emplace_back(d, j);
      }
  }

  /// The distance to the nearest of the 4-neighbor pixels' points: the pixel pitch across the ray
  /// (0 when none is filled).
  double pixelPitch(pcl::index_t index) const {
    const auto cell = grid_.cells[static_cast<std::size_t>(index)];
    const int w = static_cast<int>(grid_.width), h = static_cast<int>(grid_.height);
    const int row = cell / w, col = cell % w;
    float best = std::numeric_limits<float>::infinity();
    const int dr[4] = {-1, 1, 0, 0}, dc[4] = {0, 0, -1, 1};
    for (int t = 0; t < 4; ++t) {
      const int r = row + dr[t], c = col + dc[t];
      if (r < 0 || r >= h || c < 0 || c >= w)
        continue;
      const std::int32_t j =
          point_of_[static_cast<std::size_t>(r) * grid_.width + static_cast<std::size_t>(c)];
      if (j >= 0)
        best = std::min(best, squaredDistance(static_cast<std::int32_t>(index), j));
    }
    return std::isfinite(best) ? std::sqrt(static_cast<double>(best)) : 0.0;
  }

  /// This thread's candidate buffer (its capacity is kept between queries).
  static std::vector<std::pair<float, std::int32_t>>& buffer() {
    thread_local std::vector<std::pair<float, std::int32_t>> found;
    found.clear();
    return found;
  }

  /// The \a want nearest of \a found, nearest first (ties by index: deterministic).
  static int answer(std::vector<std::pair<float, std::int32_t>>& found, std::size_t want,
                    pcl::Indices& k_indices, std::vector<float>& k_sqr_distances) {
    want = std::min(want, found.size());
    const auto middle = found.begin() + static_cast<std::ptrdiff_t>(want);
    if (want < found.size())
      std::nth_element(found.begin(), middle, found.end());
    std::sort(found.begin(), middle);
    k_indices.resize(want);
    k_sqr_distances.resize(want);
    for (std::size_t j = 0; j < want; ++j) {
      k_sqr_distances[j] = found[j].first;
      k_indices[j] = found[j].second;
    }
    return static_cast<int>(want);
  }

  PixelGrid grid_;
  std::vector<std::int32_t> point_of_;
};

}  // namespace slipfit
