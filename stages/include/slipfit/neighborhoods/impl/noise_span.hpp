#pragma once
// NeighborhoodSelection::spanNoise: knn lists widened where a sensor's noise is wider than the
// k nearest reach (docs/THEORY.md §1, "Neighborhoods that span the noise").

#include "slipfit/core/threads.h"
#include "slipfit/neighborhoods/neighborhood_selection.h"
#include "slipfit/neighborhoods/surface_thickness.h"

#include <pcl/common/point_tests.h>

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace slipfit {

namespace noise_span {
// The σ of a sampled point is the fixed point of "a neighborhood of radius r = kGrowth · σ(r)":
// the radius grows to kGrowth times the thickness it measures, while that is more than
// kSettled times the current radius. Noise stops the growth once the ball holds the noise's
// slab (r ≈ kGrowth σ); a crease, whose thickness grows with the radius at about a fifth of it
// (a right angle: 0.19 r off the best plane, less off the quadric), never starts it.
constexpr double kGrowth = 5.0;
constexpr double kSettled = 1.1;
constexpr int kMaxSteps = 8;
constexpr double kMaxGrowth = 16.0;  ///< radius at most this many times the k-th nearest's
// Two sheets of a thin wall within the k nearest have a thickness too, but not a noise's spread:
// residuals of one Gaussian have kurtosis 3, of two equal sheets 1. Below kSheetKurtosis the
// sample is geometry, not noise (its standard error at 100 points is about 0.5).
constexpr double kSheetKurtosis = 2.0;
// A point is widened to kSpan σ of its region when that is more than kMargin times its k-th
// nearest: where the noise across the surface is above about the sampling's spacing.
constexpr double kSpan = 4.0;
constexpr double kMargin = 2.0;
// The widening is for clouds whose noise is a sensor's: at least kShare of the samples.
constexpr double kShare = 0.25;
constexpr std::size_t kSamples = 4096;
}  // namespace noise_span

template <typename PointT>
std::vector<double> NeighborhoodSelection<PointT>::sampledNoise(
    const std::vector<pcl::index_t>& samples, const Neighborhoods& output,
    std::size_t finite) const {
  namespace ns = noise_span;
  const auto& cloud = *input_;
  const NeighborhoodParameters& par = parameters_;
  const auto search_cap = static_cast<unsigned>(detail::kSearchCap * par.k);
  std::vector<double> sigma(samples.size(), 0.0);
  std::string failure;
#pragma omp parallel num_threads(resolveThreads(par.threads))
  {
    pcl::Indices ind;
    std::vector<float> d;
#pragma omp for schedule(dynamic, 16)
    for (std::ptrdiff_t jj = 0; jj < static_cast<std::ptrdiff_t>(samples.size()); ++jj)
      try {
        const auto j = static_cast<std::size_t>(jj);
        const pcl::index_t i = samples[j];
        const NeighborView v = output[static_cast<std::size_t>(i)];
        const double r0 = std::sqrt(static_cast<double>(v.sqr_distances[v.size() - 1]));
        ind.assign(v.begin(), v.end());
        SurfaceThickness t = surfaceThickness(cloud, ind);
        double r = r0;
        // Settled: the radius holds kGrowth times the thickness it measures. A neighborhood that
        // reaches kMaxGrowth unsettled is no slab (a scatter of outliers, a corner): not noise.
        bool settled = ns::kGrowth * t.rms <= ns::kSettled * r;
        for (int step = 0; step < ns::kMaxSteps && !settled; ++step) {
          if (r >= ns::kMaxGrowth * r0)
            break;
          r = std::min(ns::kGrowth * t.rms, ns::kMaxGrowth * r0);
          search_->radiusSearch(cloud, i, r, ind, d, search_cap);
          const bool capped = ind.size() >= search_cap;
          if (capped)  // the nearest search_cap: a smaller ball
            r = std::sqrt(static_cast<double>(d.back()));
          t = surfaceThickness(cloud, ind);
          settled = ns::kGrowth * t.rms <= ns::kSettled * r;
          // Unsettled, a capped ball asks for a radius beyond its own: the next search would
          // return the same search_cap nearest, and the same thickness.
          if (capped && !settled)
            break;
        }
        // A ball that holds the whole cloud measures the cloud, not a surface's noise.
        const bool slab = t.kurtosis >= ns::kSheetKurtosis && ind.size() < finite;
        sigma[j] = settled && r > ns::kSettled * r0 && slab ? t.rms : 0.0;
      } catch (const std::exception& e) {
        detail::keepFirstFailure(failure, e);
      }
  }
  if (!failure.empty())
    throw DegenerateInputError("neighborhood selection: the search failed (" + failure + ")");
  return sigma;
}

template <typename PointT>
void NeighborhoodSelection<PointT>::spanNoise(const std::vector<char>& queried,
                                              Neighborhoods& output) {
  namespace ns = noise_span;
  const auto& cloud = *input_;
  const std::size_t n = cloud.size();
  const NeighborhoodParameters& par = parameters_;
  std::vector<pcl::index_t> samples;
  std::size_t listed = 0;
  for (std::size_t i = 0; i < n; ++i)
    listed += queried[i] && !output[i].empty() ? 1 : 0;
  const std::size_t stride = std::max<std::size_t>(1, listed / ns::kSamples);
  for (std::size_t i = 0, seen = 0; i < n; ++i)
    if (queried[i] && !output[i].empty() && seen++ % stride == 0)
      samples.push_back(static_cast<pcl::index_t>(i));
  const std::size_t m = samples.size();
  std::vector<double> sigma;
  try {
    sigma = sampledNoise(samples, output, listed);
  } catch (...) {
    this->deinitCompute();
    throw;
  }
  const auto noisy = static_cast<std::size_t>(
      std::count_if(sigma.begin(), sigma.end(), [](double s) { return s > 0.0; }));
  if (m == 0 || static_cast<double>(noisy) < ns::kShare * static_cast<double>(m))
    return;

  // Each point takes the σ of the sample its neighbor graph reaches first (ties to the earlier
  // sample); each sample's σ is the median over it and the samples whose points touch its own.
  constexpr std::int32_t kNone = -1;
  std::vector<std::int32_t> owner(n, kNone);
  std::vector<pcl::index_t> queue;
  queue.reserve(n);
  for (std::size_t j = 0; j < m; ++j) {
    owner[static_cast<std::size_t>(samples[j])] = static_cast<std::int32_t>(j);
    queue.push_back(samples[j]);
  }
  for (std::size_t head = 0; head < queue.size(); ++head) {
    const pcl::index_t i = queue[head];
    for (const pcl::index_t k : output[static_cast<std::size_t>(i)])
      if (owner[static_cast<std::size_t>(k)] == kNone) {
        owner[static_cast<std::size_t>(k)] = owner[static_cast<std::size_t>(i)];
        queue.push_back(k);
      }
  }
  std::vector<std::vector<std::int32_t>> adjacent(m);
  for (std::size_t i = 0; i < n; ++i) {
    const std::int32_t a = owner[i];
    if (a == kNone)
      continue;
    for (const pcl::index_t k : output[i]) {
      const std::int32_t b = owner[static_cast<std::size_t>(k)];
      if (b != kNone && b != a)
        adjacent[static_cast<std::size_t>(a)].push_back(b);
    }
  }
  std::vector<double> pooled(m), values;
  for (std::size_t j = 0; j < m; ++j) {
    auto& list = adjacent[j];
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
    values.assign(1, sigma[j]);
    for (const std::int32_t b : list)
      values.push_back(sigma[static_cast<std::size_t>(b)]);
    std::nth_element(values.begin(), values.begin() + values.size() / 2, values.end());
    pooled[j] = values[values.size() / 2];
  }

  // The points whose noise reaches beyond their k nearest: their span.
  std::vector<double> span(n, 0.0);
  std::vector<double> widened_sigma;
  for (std::size_t i = 0; i < n; ++i) {
    if (owner[i] == kNone || output[i].empty())
      continue;
    const NeighborView v = output[i];
    const double s = pooled[static_cast<std::size_t>(owner[i])];
    const double want = ns::kSpan * s;
    if (want * want >
        ns::kMargin * ns::kMargin * static_cast<double>(v.sqr_distances[v.size() - 1])) {
      span[i] = want;
      widened_sigma.push_back(s);
    }
  }
  if (widened_sigma.empty())
    return;
  statistics_.noise_widened = widened_sigma.size();
  std::sort(widened_sigma.begin(), widened_sigma.end());
  statistics_.noise_sigma_low = widened_sigma[widened_sigma.size() / 20];
  statistics_.noise_sigma_high = widened_sigma[widened_sigma.size() * 19 / 20];

  // The lists rebuilt in cloud order, a chunk at a time in parallel.
  const auto search_cap = static_cast<unsigned>(detail::kSearchCap * par.k);
  const auto keep = static_cast<std::size_t>(par.k);
  const auto cap = static_cast<std::size_t>(detail::kWidenCap * par.k);
  Neighborhoods rebuilt;
  rebuilt.reserve(n, output.entries() + widened_sigma.size() * cap);
  constexpr std::size_t kChunk = 1 << 15;
  std::vector<pcl::Indices> chunk_indices(std::min(kChunk, n));
  std::vector<std::vector<float>> chunk_dists(std::min(kChunk, n));
  std::string failure;
  for (std::size_t begin = 0; begin < n; begin += kChunk) {
    const std::size_t end = std::min(n, begin + kChunk);
#pragma omp parallel for num_threads(resolveThreads(par.threads)) schedule(dynamic, 256)
    for (std::ptrdiff_t ii = static_cast<std::ptrdiff_t>(begin);
         ii < static_cast<std::ptrdiff_t>(end); ++ii)
      try {
        const auto i = static_cast<std::size_t>(ii);
        pcl::Indices& ind = chunk_indices[i - begin];
        std::vector<float>& d = chunk_dists[i - begin];
        if (span[i] > 0.0) {
          search_->radiusSearch(cloud, static_cast<pcl::index_t>(i), span[i], ind, d, search_cap);
          thinWidened(ind, d, keep, cap);
        } else {
          const NeighborView v = output[i];
          ind.assign(v.begin(), v.end());
          d.assign(v.sqr_distances, v.sqr_distances + v.size());
        }
      } catch (const std::exception& e) {
        detail::keepFirstFailure(failure, e);
      }
    throwSearchFailure(failure);
    for (std::size_t i = begin; i < end; ++i)
      rebuilt.append(chunk_indices[i - begin].data(), chunk_dists[i - begin].data(),
                     chunk_indices[i - begin].size());
  }
  output = std::move(rebuilt);
}

}  // namespace slipfit
