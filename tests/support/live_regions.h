#pragma once
/// \file The number of regions a segmentation kernel still holds (merged ones are left empty).

#include "slipfit/segmentation/segmentation_kernel.h"

#include <cstddef>

namespace slipfit::testing {

inline std::size_t liveRegions(const SegmentationKernel& kernel) {
  std::size_t count = 0;
  for (const auto& region : kernel.regions())
    count += region.empty() ? 0 : 1;
  return count;
}

}  // namespace slipfit::testing
