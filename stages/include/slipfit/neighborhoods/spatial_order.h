#pragma once
/// \file The order in which to visit a cloud's points so that consecutive ones lie near each
/// other: Morton (Z-order) over a 2^21-cell grid per axis spanning the points' bounding box. A
/// kd-tree answers a run of nearby queries from the nodes and coordinates the previous query left
/// in the cache; in a cloud's file order (a generated scene, a merged or shuffled scan) the
/// queries jump across the cloud and every one walks cold memory. The order changes which point
/// is visited when, never what a point's answer is.

#include <pcl/common/point_tests.h>
#include <pcl/point_cloud.h>
#include <pcl/types.h>

#include <algorithm>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

namespace slipfit {

/// The Morton code of a cell (each coordinate below 2^21): the bits of x, y and z interleaved.
std::uint64_t mortonCode(std::uint32_t x, std::uint32_t y, std::uint32_t z);

/// The positions in \a indices (points of \a cloud) along the Morton curve of the finite points;
/// ties (points in one cell) keep their order in \a indices, and non-finite points follow the
/// finite ones in that order too. The same input gives the same order.
template <typename PointT>
std::vector<std::uint32_t> spatialPositions(const pcl::PointCloud<PointT>& cloud,
                                            const pcl::Indices& indices) {
  float lo[3], hi[3];
  for (int a = 0; a < 3; ++a) {
    lo[a] = std::numeric_limits<float>::infinity();
    hi[a] = -std::numeric_limits<float>::infinity();
  }
  for (const pcl::index_t i : indices) {
    const PointT& p = cloud[static_cast<std::size_t>(i)];
    if (!pcl::isFinite(p))
      continue;
    const float v[3] = {p.x, p.y, p.z};
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::min(lo[a], v[a]);
      hi[a] = std::max(hi[a], v[a]);
    }
  }
  constexpr double kCells = 2097151.0;  // 2^21 - 1
  double scale[3];
  for (int a = 0; a < 3; ++a)
    scale[a] = hi[a] > lo[a] ? kCells / (static_cast<double>(hi[a]) - lo[a]) : 0.0;
  // (code, position): sorting the pairs keeps the given order within a cell.
  std::vector<std::pair<std::uint64_t, std::uint32_t>> keyed;
  keyed.reserve(indices.size());
  std::vector<std::uint32_t> non_finite;
  for (std::size_t k = 0; k < indices.size(); ++k) {
    const PointT& p = cloud[static_cast<std::size_t>(indices[k])];
    if (!pcl::isFinite(p)) {
      non_finite.push_back(static_cast<std::uint32_t>(k));
      continue;
    }
    const float v[3] = {p.x, p.y, p.z};
    std::uint32_t cell[3];
    for (int a = 0; a < 3; ++a)
      cell[a] = static_cast<std::uint32_t>(
          std::min(kCells, (static_cast<double>(v[a]) - lo[a]) * scale[a]));
    keyed.emplace_back(mortonCode(cell[0], cell[1], cell[2]), static_cast<std::uint32_t>(k));
  }
  std::sort(keyed.begin(), keyed.end());
  std::vector<std::uint32_t> positions;
  positions.reserve(indices.size());
  for (const auto& [code, k] : keyed)
    positions.push_back(k);
  positions.insert(positions.end(), non_finite.begin(), non_finite.end());
  return positions;
}

/// \a indices reordered by spatialPositions().
template <typename PointT>
pcl::Indices spatialOrder(const pcl::PointCloud<PointT>& cloud, const pcl::Indices& indices) {
  pcl::Indices order;
  order.reserve(indices.size());
  for (const std::uint32_t k : spatialPositions(cloud, indices))
    order.push_back(indices[k]);
  return order;
}

}  // namespace slipfit
