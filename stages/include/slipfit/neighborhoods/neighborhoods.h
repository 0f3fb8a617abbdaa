#pragma once
/// \file Neighborhoods of every point of a cloud, computed once and shared by later stages.

#include <pcl/types.h>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace slipfit {

/// A read-only view of one point's neighbors (cloud indices), nearest first.
struct NeighborView {
  const pcl::index_t* indices = nullptr;
  const float* sqr_distances = nullptr;
  std::size_t count = 0;

  const pcl::index_t* begin() const { return indices; }
  const pcl::index_t* end() const { return indices + count; }
  std::size_t size() const { return count; }
  bool empty() const { return count == 0; }
  pcl::index_t operator[](std::size_t j) const { return indices[j]; }
};

/// The neighbor lists of all points of one cloud in compressed-row form.
///
/// Entry i belongs to cloud point i (not to the i-th query index): points that were not queried,
/// and non-finite points, have an empty list. A list contains the point itself (at distance 0)
/// and is sorted by increasing distance. Distances are squared, in the cloud's units.
class Neighborhoods {
 public:
  Neighborhoods() = default;
  /// An empty neighborhood for each of \a n points.
  explicit Neighborhoods(std::size_t n) : offsets_(n + 1, 0) {}

  std::size_t size() const { return offsets_.empty() ? 0 : offsets_.size() - 1; }
  NeighborView operator[](std::size_t i) const {
    const auto b = offsets_[i];
    return {indices_.data() + b, sqr_distances_.data() + b,
            static_cast<std::size_t>(offsets_[i + 1] - b)};
  }
  /// Total number of stored neighbor entries (sum of all list lengths).
  std::size_t entries() const { return indices_.size(); }
  /// Largest list length.
  std::size_t maxSize() const;
  /// Radius of point i's neighborhood: distance to its farthest listed neighbor (0 if empty).
  float radius(std::size_t i) const;

  /// Appends the list of the next point; lists must be appended in cloud order 0, 1, 2, ...
  /// \a count entries are taken from \a indices and \a sqr_distances.
  void append(const pcl::index_t* indices, const float* sqr_distances, std::size_t count);
  /// Lays out one list of \a sizes[i] entries for each point i, for lists found in any order
  /// (fill()); replaces what was there.
  void allocate(const std::vector<std::uint32_t>& sizes);
  /// Point i's list of an allocate()d layout: \a count must be the size allocated for it.
  /// Distinct points may be filled from several threads at once.
  void fill(std::size_t i, const pcl::index_t* indices, const float* sqr_distances,
            std::size_t count);
  /// Pre-allocates for \a points lists with \a entries entries in all.
  void reserve(std::size_t points, std::size_t entries);
  /// Restarts as an empty structure (no points).
  void clear();

 private:
  std::vector<std::uint64_t> offsets_{0};
  pcl::Indices indices_;
  std::vector<float> sqr_distances_;
};

}  // namespace slipfit
