#include "slipfit/neighborhoods/neighborhoods.h"

#include <algorithm>
#include <cmath>

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
