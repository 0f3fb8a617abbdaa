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
    SegmentationResult& result, int threads) {
  const auto n = points.cols();
  if (representative.size() != static_cast<std::size_t>(n))
    throw DegenerateInputError("carry-back: one representative per input point is needed");
  if (result.labels.size() != sample_neighborhoods.size())
    throw DegenerateInputError("carry-back: the labels and the sample's neighborhoods differ");
  for (const std::int32_t r : representative)
    if (r >= static_cast<std::int32_t>(result.labels.size()))
      throw DegenerateInputError("carry-back: a representative is not a sample point");
  const std::vector<std::int32_t> sample_labels = std::move(result.labels);
  std::vector<std::int32_t> labels(static_cast<std::size_t>(n), -1);
  // Per point: the distinct segments around its representative, each distance computed once.
#pragma omp parallel for schedule(static) num_threads(threads > 0 ? threads : omp_get_num_procs())
  for (Eigen::Index i = 0; i < n; ++i) {
    const std::int32_t r = representative[static_cast<std::size_t>(i)];
    if (r < 0)
      continue;
    const Eigen::Vector3d p = points.col(i).cast<double>();
    std::array<std::int32_t, 8> seen{};
    std::size_t count = 0;
    double best = result.distance;
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
    labels[static_cast<std::size_t>(i)] = label;
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
