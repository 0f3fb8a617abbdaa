#include "slipfit/neighborhoods/depth_quantization.h"
#include "slipfit/core/median.h"
#include "slipfit/core/radix_sort.h"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iomanip>
#include <limits>
#include <sstream>
#include <unordered_map>

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

/// The lattice of one axis, or an empty one. Values within \a span of a level's first are on it
/// (0: equal).
QuantizedAxis latticeOf(std::vector<double> values, int axis, double span = 0.0) {
  QuantizedAxis none;
  if (values.size() < kLevelPoints * kMinLevels)
    return none;
  radixSort(values);
  std::vector<double> levels;
  std::size_t on_levels = 0;
  for (std::size_t b = 0; b < values.size();) {
    std::size_t e = b;
    while (e < values.size() && values[e] - values[b] <= span)
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

// Levels across a direction (latticeAcross).
constexpr std::size_t kPatches = 3000;       // local patches examined, evenly spaced
constexpr std::size_t kPatchPoints = 12;     // a patch: a point and its nearest in its cell
constexpr double kCellPoints = 48.0;         // about this many points in a cell of a surface
constexpr double kRounding = 16.0 * 1.2e-7;  // float rounding, relative to |p|, with a margin
constexpr double kCollinear = 1e-3;          // a patch whose middle extent is below this: a line
constexpr std::size_t kMinPatches = 30;      // fewer flat patches: no direction
// A cell holds at most this many (the first in index order): where the points fill a volume and
// not a surface (a random scene), cells hold thousands, and their patches are not flat anyway.
constexpr std::size_t kCellCap = 256;

/// The unit vector of the smallest eigenvalue of \a scatter.
Eigen::Vector3d leastDirection(const Eigen::Matrix3d& scatter) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(scatter);
  return solver.eigenvectors().col(0);
}

/// Levels across a direction off the coordinate axes, or none (detectQuantizedAxis).
QuantizedAxis latticeAcross(const Eigen::Ref<const Eigen::Matrix3Xd>& all) {
  std::vector<Eigen::Index> finite;
  finite.reserve(static_cast<std::size_t>(all.cols()));
  Eigen::Vector3d low = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d high = -low;
  for (Eigen::Index i = 0; i < all.cols(); ++i) {
    const double x = all(0, i), y = all(1, i), z = all(2, i);
    if (!(std::isfinite(x) && std::isfinite(y) && std::isfinite(z)))
      continue;
    finite.push_back(i);
    low = low.cwiseMin(Eigen::Vector3d(x, y, z));
    high = high.cwiseMax(Eigen::Vector3d(x, y, z));
  }
  const std::size_t n = finite.size();
  if (n < kLevelPoints * kMinLevels)
    return {};
  const double magnitude = std::max(low.cwiseAbs().maxCoeff(), high.cwiseAbs().maxCoeff());
  const double rounding = kRounding * magnitude;
  // Cells of a grid holding about kCellPoints of a surface that spans the box: each patch is a
  // point and its nearest among its cell's.
  const double extent = (high - low).maxCoeff();
  const double cell = extent * std::sqrt(kCellPoints / static_cast<double>(n));
  if (!(cell > 0.0) || extent / cell > 2e6)
    return {};
  const double inverse = 1.0 / cell;
  const auto key = [&](Eigen::Index i) {
    const auto c = [&](int r) {
      return static_cast<std::uint64_t>((all(r, i) - low(r)) * inverse);  // ≥ 0: floor
    };
    return (c(0) << 42) | (c(1) << 21) | c(2);
  };
  // The cells of the patches' points, then one pass over the cloud to fill them.
  const std::size_t stride = std::max<std::size_t>(1, n / kPatches);
  std::unordered_map<std::uint64_t, std::vector<Eigen::Index>> cells;
  std::vector<std::uint64_t> marked(std::size_t{1} << 10, 0);  // 2¹⁶ bits: a first test
  const auto bucket = [](std::uint64_t k) { return (k * 0x9E3779B97F4A7C15ull) >> 48; };
  for (std::size_t j = 0; j < n; j += stride) {
    const std::uint64_t k = key(finite[j]);
    cells.emplace(k, std::vector<Eigen::Index>{});
    marked[bucket(k) >> 6] |= std::uint64_t{1} << (bucket(k) & 63);
  }
  for (const Eigen::Index i : finite) {
    const std::uint64_t k = key(i), b = bucket(k);
    if (!(marked[b >> 6] >> (b & 63) & 1))
      continue;
    const auto it = cells.find(k);
    if (it != cells.end() && it->second.size() < kCellCap)
      it->second.push_back(i);
  }
  Eigen::Matrix3d pooled = Eigen::Matrix3d::Zero();
  std::size_t flat = 0;
  std::vector<std::pair<double, Eigen::Index>> near;
  for (std::size_t j = 0; j < n; j += stride) {
    const std::vector<Eigen::Index>& members = cells.at(key(finite[j]));
    if (members.size() < kPatchPoints)
      continue;
    const Eigen::Vector3d p = all.col(finite[j]);
    near.clear();
    for (const Eigen::Index i : members)
      near.emplace_back((all.col(i) - p).squaredNorm(), i);
    std::nth_element(near.begin(), near.begin() + (kPatchPoints - 1), near.end());
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (std::size_t m = 0; m < kPatchPoints; ++m)
      mean += all.col(near[m].second);
    mean /= static_cast<double>(kPatchPoints);
    Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
    for (std::size_t m = 0; m < kPatchPoints; ++m) {
      const Eigen::Vector3d d = all.col(near[m].second) - mean;
      scatter += d * d.transpose();
    }
    const Eigen::Vector3d w =
        Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(scatter, Eigen::EigenvaluesOnly)
            .eigenvalues();
    // On one plane to the rounding, and not on a line.
    if (w(0) <= static_cast<double>(kPatchPoints) * rounding * rounding &&
        w(1) > kCollinear * w(2)) {
      pooled += scatter;
      ++flat;
    }
  }
  if (flat < kMinPatches)
    return {};
  Eigen::Vector3d direction = leastDirection(pooled);
  // Along a coordinate axis the exact test has spoken.
  if (direction.cwiseAbs().maxCoeff() > 1.0 - 1e-9)
    return {};
  // Refined on the levels it finds: within each, the points lie on one plane across it.
  const double span = 2.0 * rounding;
  std::vector<std::pair<double, Eigen::Index>> along(n);
  for (int pass = 0; pass < 2; ++pass) {
    for (std::size_t j = 0; j < n; ++j)
      along[j] = {direction.dot(all.col(finite[j])), finite[j]};
    std::sort(along.begin(), along.end());
    Eigen::Matrix3d within = Eigen::Matrix3d::Zero();
    for (std::size_t b = 0; b < n;) {
      std::size_t e = b;
      Eigen::Vector3d mean = Eigen::Vector3d::Zero();
      while (e < n && along[e].first - along[b].first <= span)
        mean += all.col(along[e++].second);
      if (e - b >= kLevelPoints) {
        mean /= static_cast<double>(e - b);
        for (std::size_t m = b; m < e; ++m) {
          const Eigen::Vector3d d = all.col(along[m].second) - mean;
          within += d * d.transpose();
        }
      }
      b = e;
    }
    if (within.isZero())
      return {};
    const Eigen::Vector3d refined = leastDirection(within);
    direction = refined.dot(direction) < 0.0 ? Eigen::Vector3d(-refined) : refined;
  }
  std::vector<double> values(n);
  for (std::size_t j = 0; j < n; ++j)
    values[j] = direction.dot(all.col(finite[j]));
  QuantizedAxis q = latticeOf(std::move(values), QuantizedAxis::kAlongDirection, span);
  if (q.detected()) {
    q.direction = direction;
    q.level_span = span;
  }
  return q;
}

}  // namespace

std::string QuantizedAxis::name() const {
  if (axis == kAlongDirection) {
    std::ostringstream text;
    text << std::setprecision(3) << "the coordinate along (" << direction.x() << ", "
         << direction.y() << ", " << direction.z() << ")";
    return text.str();
  }
  return std::string("coordinate ") + "xyz"[axis];
}

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
  if (!best.detected())
    return latticeAcross(points);
  return best_step >= kCoarserThanOthers * other_step ? best : QuantizedAxis{};
}

}  // namespace slipfit
