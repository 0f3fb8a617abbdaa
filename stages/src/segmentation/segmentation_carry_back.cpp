#include "slipfit/segmentation/segmentation_carry_back.h"
#include "slipfit/core/threads.h"

#include "slipfit/core/exceptions.h"
#include "slipfit/core/median.h"

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
  const int workers = resolveThreads(threads);
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
      const double d = distance(p, result.segments[static_cast<std::size_t>(candidate)]);
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
      const double sigma = medianInPlace(d) / 0.6744897501960817;
      if (sigma > result.noise) {
        result.distance += result.noise_factor * (sigma - result.noise);
        result.noise = sigma;
      }
    }
  }
  // The input points of each representative (counting sort: ascending indices).
  const std::size_t samples = sample_labels.size();
  std::vector<std::size_t> start(samples + 1, 0);
  for (const std::int32_t r : representative)
    if (r >= 0)
      ++start[static_cast<std::size_t>(r) + 1];
  for (std::size_t r = 0; r < samples; ++r)
    start[r + 1] += start[r];
  std::vector<Eigen::Index> order(start.back());
  {
    std::vector<std::size_t> next(start.begin(), start.end() - 1);
    for (Eigen::Index i = 0; i < n; ++i)
      if (representative[static_cast<std::size_t>(i)] >= 0)
        order[next[static_cast<std::size_t>(representative[static_cast<std::size_t>(i)])]++] = i;
  }
  // Where a point's distances to two segments differ by less than their noise (at a tangent
  // junction the second is r θ²/2 off a fillet of radius r, θ from the tangent line: within the
  // noise over a wide band), the point's own distance cannot choose: the mean signed distance of
  // the points of its representative and of the representative's neighbors can (one-signed
  // bias, noise shrunk by the square root of their count).
  const double margin = 2.0 * result.noise;
  const double cos_tangent = std::cos(result.max_angle);
  std::vector<std::int32_t> labels(static_cast<std::size_t>(n), -1);
#pragma omp parallel num_threads(workers)
  {
    std::vector<double> signed_distance;
#pragma omp for schedule(dynamic, 256)
    for (std::size_t r = 0; r < samples; ++r) {
      const std::size_t first = start[r], count = start[r + 1] - first;
      if (count == 0)
        continue;
      std::array<std::int32_t, 9> candidates{};
      std::size_t k = 0;
      const auto consider = [&](std::int32_t c) {
        if (c >= 0 && k < candidates.size() &&
            std::find(candidates.begin(), candidates.begin() + k, c) == candidates.begin() + k)
          candidates[k++] = c;
      };
      consider(sample_labels[r]);
      for (pcl::index_t j : sample_neighborhoods[r])
        consider(sample_labels[static_cast<std::size_t>(j)]);
      if (k == 0)
        continue;
      signed_distance.assign(count * k, 0.0);
      for (std::size_t m = 0; m < count; ++m) {
        const Eigen::Vector3d p = points.col(order[first + m]).cast<double>();
        for (std::size_t c = 0; c < k; ++c)
          signed_distance[m * k + c] = signedDistance(
              p, result.segments[static_cast<std::size_t>(candidates[c])].fit.refined);
      }
      // The mean signed distance of the input points of the representative and of its
      // neighbors, computed at the first tie: a voxel alone can hold one tail of the noise where
      // its leaf is about the noise's width, and its mean leans to the wrong side.
      std::array<double, 9> mean{};
      bool have_mean = false;
      const auto computeMean = [&] {
        std::size_t total = count;
        for (std::size_t m = 0; m < count; ++m)
          for (std::size_t c = 0; c < k; ++c)
            mean[c] += signed_distance[m * k + c];
        for (pcl::index_t j : sample_neighborhoods[r]) {
          const auto v = static_cast<std::size_t>(j);
          if (v == r)
            continue;
          for (std::size_t m = start[v]; m < start[v + 1]; ++m) {
            const Eigen::Vector3d p = points.col(order[m]).cast<double>();
            for (std::size_t c = 0; c < k; ++c)
              mean[c] += signedDistance(
                  p, result.segments[static_cast<std::size_t>(candidates[c])].fit.refined);
          }
          total += start[v + 1] - start[v];
        }
        for (std::size_t c = 0; c < k; ++c)
          mean[c] = std::abs(mean[c]) / static_cast<double>(total);
        have_mean = true;
      };
      for (std::size_t m = 0; m < count; ++m) {
        const double* d = &signed_distance[m * k];
        // The segmentation's own tolerance at the point: on depth recorded on levels, the
        // distance plus the local step (a far return of a subsampled depth frame is a step off
        // its surface as often as its representative is).
        const Eigen::Vector3d p = points.col(order[first + m]).cast<double>();
        const double tolerance = result.tolerance(p);
        std::size_t best = k;
        for (std::size_t c = 0; c < k; ++c)
          if (std::abs(d[c]) <= tolerance && (best == k || std::abs(d[c]) < std::abs(d[best])))
            best = c;
        if (best == k)
          continue;
        std::size_t choice = best;
        const Eigen::Vector3d normal = surfaceNormal(
            p, result.segments[static_cast<std::size_t>(candidates[best])].fit.refined);
        for (std::size_t c = 0; c < k; ++c)
          if (c != best && std::abs(d[c]) <= tolerance &&
              std::abs(d[c]) <= std::abs(d[best]) + margin &&
              std::abs(normal.dot(surfaceNormal(
                  p, result.segments[static_cast<std::size_t>(candidates[c])].fit.refined))) >=
                  cos_tangent) {
            if (!have_mean)
              computeMean();
            if (mean[c] < mean[choice])
              choice = c;
          }
        labels[static_cast<std::size_t>(order[first + m])] = candidates[choice];
      }
    }
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
      const double d = distance(points.col(i).cast<double>(), s);
      sum += d * d;
      s.max_distance = std::max(s.max_distance, d);
    }
    s.rms_distance = s.indices.empty() ? 0.0 : std::sqrt(sum / double(s.indices.size()));
  }
}

}  // namespace slipfit
