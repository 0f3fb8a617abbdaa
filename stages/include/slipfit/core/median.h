#pragma once
/// \file The median and other quantiles by a partial sort (std::nth_element): the robust centres
/// and spreads every noise and scale estimate of the library takes.

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

/// The value of rank ⌊q (n − 1)⌋ among the n \a values (q in [0, 1]; for q = 0.5 and an even
/// count, the lower of the middle two); 0 for none.
inline double quantile(std::vector<double> values, double q) {
  if (values.empty())
    return 0.0;
  const auto at =
      values.begin() + static_cast<std::ptrdiff_t>(q * static_cast<double>(values.size() - 1));
  std::nth_element(values.begin(), at, values.end());
  return *at;
}

}  // namespace slipfit
