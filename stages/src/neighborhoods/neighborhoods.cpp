#include "slipfit/neighborhoods/neighborhoods.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace slipfit {

std::size_t Neighborhoods::maxSize() const {
  std::size_t best = 0;
  for (std::size_t i = 0; i < size(); ++i)
    best = std::max<std::size_t>(best, (*this)[i].size());
  return best;
}

float Neighborhoods::radius(std::size_t i) const {
  const NeighborView v = (*this)[i];
  if (v.empty())
    return 0.0f;
  // Lists are sorted by distance, but radius-mode lists from FLANN need not be: take the max.
  return std::sqrt(*std::max_element(v.sqr_distances, v.sqr_distances + v.count));
}

void Neighborhoods::append(const pcl::index_t* indices, const float* sqr_distances,
                           std::size_t count) {
  indices_.insert(indices_.end(), indices, indices + count);
  sqr_distances_.insert(sqr_distances_.end(), sqr_distances, sqr_distances + count);
  offsets_.push_back(indices_.size());
}

void Neighborhoods::allocate(const std::vector<std::uint32_t>& sizes) {
  offsets_.assign(sizes.size() + 1, 0);
  for (std::size_t i = 0; i < sizes.size(); ++i)
    offsets_[i + 1] = offsets_[i] + sizes[i];
  indices_.assign(offsets_.back(), 0);
  sqr_distances_.assign(offsets_.back(), 0.0f);
}

void Neighborhoods::fill(std::size_t i, const pcl::index_t* indices, const float* sqr_distances,
                         std::size_t count) {
  const auto b = offsets_[i];
  if (count != offsets_[i + 1] - b)
    throw std::logic_error("Neighborhoods::fill: point " + std::to_string(i) + " got " +
                           std::to_string(count) + " entries, " +
                           std::to_string(offsets_[i + 1] - b) + " were allocated");
  std::copy(indices, indices + count, indices_.begin() + static_cast<std::ptrdiff_t>(b));
  std::copy(sqr_distances, sqr_distances + count,
            sqr_distances_.begin() + static_cast<std::ptrdiff_t>(b));
}

void Neighborhoods::reserve(std::size_t points, std::size_t entries) {
  offsets_.reserve(points + 1);
  indices_.reserve(entries);
  sqr_distances_.reserve(entries);
}

void Neighborhoods::clear() {
  offsets_.assign(1, 0);
  indices_.clear();
  sqr_distances_.clear();
}

}  // namespace slipfit
