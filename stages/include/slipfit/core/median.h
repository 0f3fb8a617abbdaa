#pragma once
/// \file The median by a partial sort (std::nth_element): the robust centre every noise and scale
/// estimate of the library takes.

#include <algorithm>
#include <cstddef>
#include <vector>

namespace slipfit {

/// The median of \a values — of an even count, the upper of the middle two — reordering them.
/// \a values must not be empty.
inline double medianInPlace(std::vector<double>& values) {
  const auto mid = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
  std::nth_element(values.begin(), mid, values.end());
  return *mid;
}

}  // namespace slipfit
