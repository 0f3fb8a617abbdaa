#include "slipfit/segmentation_carry_back.h"

#include "slipfit/exceptions.h"

#include <omp.h>

#include <algorithm>
#include <array>
#include <cmath>

namespace slipfit {

void carrySegmentationBack(
    const Eigen::Ref<const Eigen::Matrix3Xf, 0, Eigen::OuterStride<>>& points,
    const std::vector<std::int32_t>& representative, const Neighborhoods& sample_neighborhoods,
    SegmentationResult& result, int threads, bool averaged) {
  const auto n = points.cols();
  if (representative.size() != static_cast<std::size_t>(n))
    throw DegenerateInputError("carry-back: one representative per input point is needed");
  if (result.labels.size() != sample_neighborhoods.size())
    throw DegenerateInputError("carry-back: the labels and the sample's neighborhoods differ");
  for (const std::int32_t r : representative)
    if (r >= static_cast<std::int32_t>(result.labels.size()))
      throw DegenerateInputError("carry-back: a representative is not a sample point");
  const std::vector<std::int32_t> sample_labels = std::move(result.labels);
  const int workers = threads > 0 ? threads : omp_get_num_procs();
  // Per point: the nearest of the distinct segments around its representative (each distance
  // computed once) within \a limit, and that distance.
  const auto nearest = [&](Eigen::Index i, double limit, double& best) {
    best = limit;
    const std::int32_t r = representative[static_cast<std::size_t>(i)];
    if (r < 0)
      return std::int32_t{-1};
    const Eigen::Vector3d p = points.col(i).cast<double>();
    std::array<std::int32_t, 8> seen{};
    std::size_t count = 0;
    std::int32_t label = -1;
    for (pcl::index_t j : sample_neighborhoods[static_cast<std::size_t>(r)]) {
      const std::int32_t candidate = sample_labels[static_cast<std::size_t>(j)];
      if (candidate < 0 ||
          std::find(seen.begin(), seen.begin() + count, candidate) != seen.begin() + count)
        continue;
      if (count < seen.size())
        seen[count++] = candidate;
      const double d =
          distance(p, result.segments[static_cast<std::size_t>(candidate)].fit.refined);
      if (d <= best) {
        best = d;
        label = candidate;
      }
    }
    return label;
  };
  if (averaged && result.noise_factor > 0.0) {
    std::vector<double> d(static_cast<std::size_t>(n), -1.0);
#pragma omp parallel for schedule(static) num_threads(workers)
    for (Eigen::Index i = 0; i < n; ++i) {
      double best = 0.0;
      if (nearest(i, 3.0 * result.distance, best) >= 0)
        d[static_cast<std::size_t>(i)] = best;
    }
    d.erase(std::remove(d.begin(), d.end(), -1.0), d.end());
    if (!d.empty()) {
      auto mid = d.begin() + static_cast<std::ptrdiff_t>(d.size() / 2);
      std::nth_element(d.begin(), mid, d.end());
      const double sigma = *mid / 0.6744897501960817;
      if (sigma > result.noise) {
        result.distance += result.noise_factor * (sigma - result.noise);
        result.noise = sigma;
      }
    }
  }
  std::vector<std::int32_t> labels(static_cast<std::size_t>(n), -1);
#pragma omp parallel for schedule(static) num_threads(workers)
  for (Eigen::Index i = 0; i < n; ++i) {
    double best = 0.0;
    labels[static_cast<std::size_t>(i)] = nearest(i, result.distance, best);
  }
  for (auto& s : result.segments)
    s.indices.clear();
  for (Eigen::Index i = 0; i < n; ++i)
    if (labels[static_cast<std::size_t>(i)] >= 0)
      result.segments[static_cast<std::size_t>(labels[static_cast<std::size_t>(i)])]
          .indices.push_back(static_cast<int>(i));
  result.labels = std::move(labels);
  for (auto& s : result.segments) {
    double sum = 0.0;
    s.max_distance = 0.0;
    for (int i : s.indices) {
      const double d = distance(points.col(i).cast<double>(), s.fit.refined);
      sum += d * d;
      s.max_distance = std::max(s.max_distance, d);
    }
    s.rms_distance = s.indices.empty() ? 0.0 : std::sqrt(sum / double(s.indices.size()));
  }
}

}  // namespace slipfit
