#include "slipfit/neighborhoods/depth_quantization.h"
#include "slipfit/core/median.h"

#include <algorithm>
#include <cmath>

namespace slipfit {

namespace {

constexpr std::size_t kLevelPoints = 8;  // a level holds at least this many points
constexpr double kOnLevels = 0.99;       // the share of points on such levels
constexpr std::size_t kMinLevels = 16;   // fewer levels are faces, not a lattice
constexpr double kMaxStepRatio = 2.0;    // neighboring steps of a lattice change slowly
constexpr std::ptrdiff_t kStepWindow = 3;
constexpr double kCoarserThanOthers = 4.0;  // the depth lattice against any other axis's  // local
                                            // step: median of the 6 gaps around a level

double medianOf(std::vector<double> v) {
  return medianInPlace(v);
}

/// The lattice of one axis, or an empty one.
QuantizedAxis latticeOf(std::vector<double> values, int axis) {
  QuantizedAxis none;
  if (values.size() < kLevelPoints * kMinLevels)
    return none;
  std::sort(values.begin(), values.end());
  std::vector<double> levels;
  std::size_t on_levels = 0;
  for (std::size_t b = 0; b < values.size();) {
    std::size_t e = b;
    while (e < values.size() && values[e] == values[b])
      ++e;
    if (e - b >= kLevelPoints) {
      levels.push_back(values[b]);
      on_levels += e - b;
    }
    b = e;
  }
  if (static_cast<double>(on_levels) < kOnLevels * static_cast<double>(values.size()) ||
      levels.size() < kMinLevels)
    return none;
  std::vector<double> gaps(levels.size() - 1), ratios;
  for (std::size_t j = 0; j + 1 < levels.size(); ++j)
    gaps[j] = levels[j + 1] - levels[j];
  for (std::size_t j = 0; j + 1 < gaps.size(); ++j)
    ratios.push_back(std::max(gaps[j], gaps[j + 1]) / std::min(gaps[j], gaps[j + 1]));
  if (medianOf(ratios) > kMaxStepRatio)
    return none;
  QuantizedAxis q;
  q.axis = axis;
  q.levels = std::move(levels);
  q.steps.resize(q.levels.size());
  const auto g = static_cast<std::ptrdiff_t>(gaps.size());
  for (std::ptrdiff_t j = 0; j < static_cast<std::ptrdiff_t>(q.levels.size()); ++j) {
    // Gaps j − 3 .. j + 2 surround level j; the median ignores the jumps between objects.
    const std::ptrdiff_t lo = std::max<std::ptrdiff_t>(0, j - kStepWindow);
    const std::ptrdiff_t hi = std::min<std::ptrdiff_t>(g, j + kStepWindow);
    q.steps[static_cast<std::size_t>(j)] =
        medianOf(std::vector<double>(gaps.begin() + lo, gaps.begin() + hi));
  }
  return q;
}

}  // namespace

double QuantizedAxis::stepAt(double value) const {
  if (!detected())
    return 0.0;
  auto it = std::lower_bound(levels.begin(), levels.end(), value);
  if (it == levels.end())
    --it;
  else if (it != levels.begin() && value - *(it - 1) < *it - value)
    --it;
  return steps[static_cast<std::size_t>(it - levels.begin())];
}

double QuantizedAxis::minStep() const {
  return steps.empty() ? 0.0 : *std::min_element(steps.begin(), steps.end());
}

double QuantizedAxis::maxStep() const {
  return steps.empty() ? 0.0 : *std::max_element(steps.begin(), steps.end());
}

QuantizedAxis detectQuantizedAxis(const Eigen::Ref<const Eigen::Matrix3Xd>& points) {
  QuantizedAxis best;
  double best_step = 0.0, other_step = 0.0;
  for (int axis = 0; axis < 3; ++axis) {
    std::vector<double> values;
    values.reserve(static_cast<std::size_t>(points.cols()));
    for (Eigen::Index i = 0; i < points.cols(); ++i)
      if (points.col(i).allFinite())
        values.push_back(points(axis, i));
    QuantizedAxis q = latticeOf(std::move(values), axis);
    if (!q.detected())
      continue;
    const double step = medianOf(q.steps);
    if (step > best_step) {
      other_step = best_step;
      best_step = step;
      best = std::move(q);
    } else {
      other_step = std::max(other_step, step);
    }
  }
  // A depth sensor's levels are far coarser than anything on the other axes; two axes on lattices
  // of like steps are a regular grid sampling, where every point has its own neighbors.
  return best_step >= kCoarserThanOthers * other_step ? best : QuantizedAxis{};
}

}  // namespace slipfit
