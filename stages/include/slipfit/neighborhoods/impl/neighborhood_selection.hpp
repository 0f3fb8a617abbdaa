#pragma once

#include "slipfit/core/exceptions.h"
#include "slipfit/core/threads.h"
#include "slipfit/neighborhoods/depth_quantization.h"
#include "slipfit/neighborhoods/eigen_entropy.h"
#include "slipfit/neighborhoods/grid_search.h"
#include "slipfit/neighborhoods/neighborhood_selection.h"
#include "slipfit/neighborhoods/spatial_order.h"

#include <pcl/common/point_tests.h>
#include <pcl/search/kdtree.h>
#include "slipfit/neighborhoods/nanoflann_search.h"

#include <omp.h>
#include <Eigen/Core>

#include <algorithm>
#include <exception>
#include <limits>
#include <string>
#include <vector>

namespace slipfit {

/// Keeps the \a k nearest of a sorted list and, of the rest, an evenly strided choice up to
/// \a cap entries in all: a wide neighborhood at the cost of a narrow one.
inline void thinWidened(pcl::Indices& indices, std::vector<float>& sqr_distances, std::size_t k,
                        std::size_t cap) {
  const std::size_t n = indices.size();
  if (n <= cap)
    return;
  const double stride = static_cast<double>(n - k) / static_cast<double>(cap - k);
  std::size_t out = k;
  for (std::size_t j = 0; j < cap - k; ++j) {
    const auto from = k + static_cast<std::size_t>(static_cast<double>(j) * stride);
    indices[out] = indices[from];
    sqr_distances[out] = sqr_distances[from];
    ++out;
  }
  indices.resize(out);
  sqr_distances.resize(out);
}

namespace detail {
inline std::string radiusTooLarge(double radius, std::size_t cap, std::size_t points) {
  return "neighborhood_selection: radius " + std::to_string(radius) + " holds more than " +
         std::to_string(cap) + " neighbors around some points (the lists of all " +
         std::to_string(points) +
         " points would pass 2^29 entries, 4 GB); use a smaller radius or set max_neighbors";
}
}  // namespace detail

namespace detail {
/// No exception may leave an OpenMP region (std::terminate): the first is kept, and thrown after
/// the region.
inline void keepFirstFailure(std::string& failure, const std::exception& e) {
#pragma omp critical(slipfit_neighborhood_failure)
  if (failure.empty())
    failure = e.what();
}
// knn on a quantized axis: a list whose k nearest lie within this many local steps is widened to
// every point within them, at most kWidenCap k points chosen from at most kSearchCap k.
constexpr double kSpanSteps = 1.5;
constexpr int kWidenCap = 8;
constexpr int kSearchCap = 64;
// Radius lists are bounded so that the memory cannot run away with a radius that covers much of
// the cloud: at most kMaxEntries entries in all (8 bytes each: 4 GB).
constexpr std::size_t kMaxEntries = std::size_t{1} << 29;
}  // namespace detail

template <typename PointT>
std::vector<char> NeighborhoodSelection<PointT>::checkInput() {
  parameters_.validate();
  if (!input_ || input_->empty())
    throw DegenerateInputError("neighborhood selection: the input cloud is empty");
  if (!this->initCompute())
    throw DegenerateInputError("neighborhood selection: the indices do not fit the input cloud");
  const auto& cloud = *input_;
  const std::size_t n = cloud.size();
  std::vector<char> queried(n, 0);
  for (const auto i : *indices_)
    queried[static_cast<std::size_t>(i)] = 1;
  std::size_t finite = 0;
  for (const auto& p : cloud.points)
    finite += pcl::isFinite(p) ? 1 : 0;
  if (finite < n && cloud.is_dense) {
    this->deinitCompute();
    throw DegenerateInputError(
        "neighborhood selection: the cloud has non-finite points but claims is_dense = true");
  }
  if (finite < 2) {
    this->deinitCompute();
    throw DegenerateInputError("neighborhood selection: fewer than two finite points in the cloud");
  }
  return queried;
}

template <typename PointT>
void NeighborhoodSelection<PointT>::prepareSearch() {
  if (!search_)
    search_.reset(new NanoflannSearch<PointT>(true));
  search_->setSortedResults(true);
  statistics_.pixel_grid = dynamic_cast<const GridSearch<PointT>*>(search_.get()) != nullptr;
  if (search_->getInputCloud() != input_) {
    search_->setInputCloud(input_);
    statistics_.tree_builds = statistics_.pixel_grid ? 0 : 1;
  }
}

template <typename PointT>
QuantizedAxis NeighborhoodSelection<PointT>::detectLattice() const {
  const NeighborhoodParameters& par = parameters_;
  if (!(par.span_quantization && par.mode == NeighborhoodMode::knn))
    return {};
  const auto& cloud = *input_;
  Eigen::Matrix3Xd xyz(3, static_cast<Eigen::Index>(cloud.size()));
  for (std::size_t i = 0; i < cloud.size(); ++i)
    xyz.col(static_cast<Eigen::Index>(i)) = cloud[i].getVector3fMap().template cast<double>();
  return detectQuantizedAxis(xyz);
}

template <typename PointT>
std::size_t NeighborhoodSelection<PointT>::radiusCap() {
  const NeighborhoodParameters& par = parameters_;
  // Per point the budget over the queried points (or max_neighbors, if smaller). A list that
  // reaches the bound ends the run with an error that says so, rather than a partial neighborhood
  // or an allocation failure.
  const std::size_t m = indices_->size();
  const std::size_t budget = detail::kMaxEntries / std::max<std::size_t>(1, m);
  std::size_t cap = par.max_neighbors ? std::min<std::size_t>(budget, *par.max_neighbors) : budget;
  cap = std::max<std::size_t>(cap, 1);
  // A look at 256 evenly spread points first: a radius that covers much of the cloud is told
  // before any list is built (their mean count, times the points, must fit the budget too).
  const auto& cloud = *input_;
  const std::size_t stride = std::max<std::size_t>(1, m / 256);
  std::size_t seen = 0, found = 0;
  bool over_budget = false;
  pcl::Indices ind;
  std::vector<float> d;
  for (std::size_t k = 0; k < m; k += stride) {
    const pcl::index_t index = (*indices_)[k];
    if (!pcl::isFinite(cloud[static_cast<std::size_t>(index)]))
      continue;
    search_->radiusSearch(cloud, index, *par.radius, ind, d, static_cast<unsigned>(cap + 1));
    ++seen;
    found += std::min(ind.size(), cap);
    over_budget = over_budget || (ind.size() > cap &&
                                  !(par.max_neighbors && cap == std::size_t(*par.max_neighbors)));
  }
  if (over_budget || (seen > 0 && found / seen * m > detail::kMaxEntries)) {
    this->deinitCompute();
    throw InvalidParameterError(detail::radiusTooLarge(*par.radius, cap, m));
  }
  return cap;
}

template <typename PointT>
void NeighborhoodSelection<PointT>::query(std::size_t i, const QuantizedAxis& lattice,
                                          std::size_t radius_cap, Eigen::Matrix3Xf& local,
                                          pcl::Indices& ind, std::vector<float>& d,
                                          bool& over_budget, std::size_t& widened) const {
  const NeighborhoodParameters& par = parameters_;
  const auto& cloud = *input_;
  const auto index = static_cast<pcl::index_t>(i);
  switch (par.mode) {
    case NeighborhoodMode::knn: {
      search_->nearestKSearch(cloud, index, par.k, ind, d);
      if (!lattice.detected() || d.empty())
        break;
      const double span =
          detail::kSpanSteps * lattice.stepAt(Eigen::Vector3d(cloud[i].x, cloud[i].y, cloud[i].z));
      if (static_cast<double>(d.back()) < span * span) {
        search_->radiusSearch(cloud, index, span, ind, d,
                              static_cast<unsigned>(detail::kSearchCap * par.k));
        thinWidened(ind, d, static_cast<std::size_t>(par.k),
                    static_cast<std::size_t>(detail::kWidenCap * par.k));
        ++widened;
      }
      break;
    }
    case NeighborhoodMode::radius: {
      // One beyond the cap tells a full list from one that reached it (unless the cap is
      // max_neighbors itself: then the nearest max_neighbors are what was asked for).
      const bool capped_by_user =
          par.max_neighbors && radius_cap == static_cast<std::size_t>(*par.max_neighbors);
      search_->radiusSearch(cloud, index, *par.radius, ind, d,
                            static_cast<unsigned>(radius_cap + (capped_by_user ? 0 : 1)));
      if (!capped_by_user && ind.size() > radius_cap) {
#pragma omp atomic write
        over_budget = true;
        ind.resize(radius_cap);
        d.resize(radius_cap);
      }
      break;
    }
    case NeighborhoodMode::hybrid: {
      search_->nearestKSearch(cloud, index, par.k, ind, d);
      const float r2 = static_cast<float>(*par.radius * *par.radius);
      const auto cut = std::upper_bound(d.begin(), d.end(), r2) - d.begin();
      ind.resize(cut);
      d.resize(cut);
      break;
    }
    case NeighborhoodMode::adaptive: {
      search_->nearestKSearch(cloud, index, par.k_max, ind, d);
      local.resize(3, static_cast<Eigen::Index>(ind.size()));
      for (std::size_t j = 0; j < ind.size(); ++j)
        local.col(j) = cloud[ind[j]].getVector3fMap();
      const int k = optimalNeighborhoodSize(local, par.k_min, par.k_max, par.k_step);
      ind.resize(k);
      d.resize(k);
      break;
    }
  }
}

template <typename PointT>
void NeighborhoodSelection<PointT>::summarise(const Neighborhoods& output, std::size_t queries) {
  std::size_t total = 0, lo = std::numeric_limits<std::size_t>::max(), hi = 0;
  for (std::size_t i = 0; i < output.size(); ++i) {
    const std::size_t s = output[i].size();
    if (s == 0)
      continue;
    total += s;
    lo = std::min(lo, s);
    hi = std::max(hi, s);
  }
  statistics_.min_size = hi == 0 ? 0 : lo;
  statistics_.max_size = hi;
  statistics_.mean_size = queries ? static_cast<double>(total) / static_cast<double>(queries) : 0.0;
}

template <typename PointT>
void NeighborhoodSelection<PointT>::compute(Neighborhoods& output) {
  const std::vector<char> queried = checkInput();
  const NeighborhoodParameters& par = parameters_;
  statistics_ = NeighborhoodStatistics{};
  prepareSearch();
  const QuantizedAxis lattice = detectLattice();
  if (par.span_quantization && par.mode == NeighborhoodMode::knn) {
    statistics_.quantized_axis = lattice.axis;
    statistics_.quantized_name = lattice.detected() ? lattice.name() : std::string();
    statistics_.min_step = lattice.minStep();
    statistics_.max_step = lattice.maxStep();
  }
  const std::size_t radius_cap = par.mode == NeighborhoodMode::radius ? radiusCap() : 0;
  // Lists of one size (knn, none widened) from the kd-tree are searched in spatial order; a
  // pixel grid's own order is spatial already.
  if (par.mode == NeighborhoodMode::knn && !lattice.detected() &&
      dynamic_cast<const NanoflannSearch<PointT>*>(search_.get()) != nullptr)
    searchInSpatialOrder(queried, output);
  else
    searchInCloudOrder(queried, lattice, radius_cap, output);
  // Levels no list was widened over (depth stored in millimetres under a noise of centimetres)
  // are finer than the k nearest reach: no levels for the neighborhoods.
  if (par.mode == NeighborhoodMode::knn && par.span_noise &&
      (!lattice.detected() || statistics_.widened == 0))
    spanNoise(queried, output);
  summarise(output, statistics_.queries);
  this->deinitCompute();
}

template <typename PointT>
void NeighborhoodSelection<PointT>::throwSearchFailure(const std::string& failure) {
  if (failure.empty())
    return;
  this->deinitCompute();
  throw DegenerateInputError("neighborhood selection: the search failed (" + failure + ")");
}

template <typename PointT>
void NeighborhoodSelection<PointT>::searchInCloudOrder(const std::vector<char>& queried,
                                                       const QuantizedAxis& lattice,
                                                       std::size_t radius_cap,
                                                       Neighborhoods& output) {
  const auto& cloud = *input_;
  const std::size_t n = cloud.size();
  const NeighborhoodParameters& par = parameters_;
  const int k_query = par.mode == NeighborhoodMode::adaptive ? par.k_max : par.k;
  output.clear();
  output.reserve(
      n, par.mode == NeighborhoodMode::radius ? n * 16 : n * static_cast<std::size_t>(k_query));

  // Points are searched in parallel a chunk at a time and appended in cloud order, which keeps the
  // result independent of the thread count and the transient memory bounded.
  constexpr std::size_t kChunk = 1 << 15;
  std::vector<pcl::Indices> chunk_indices(std::min(kChunk, n));
  std::vector<std::vector<float>> chunk_dists(std::min(kChunk, n));
  std::size_t queries = 0, skipped = 0, widened = 0;
  bool over_budget = false;
  std::string failure;
  const int threads = resolveThreads(par.threads);
  for (std::size_t begin = 0; begin < n; begin += kChunk) {
    const std::size_t end = std::min(n, begin + kChunk);
#pragma omp parallel num_threads(threads) reduction(+ : queries, skipped, widened)
    {
      Eigen::Matrix3Xf local;
#pragma omp for schedule(dynamic, 256)
      for (std::ptrdiff_t ii = static_cast<std::ptrdiff_t>(begin);
           ii < static_cast<std::ptrdiff_t>(end); ++ii)
        try {
          const auto i = static_cast<std::size_t>(ii);
          pcl::Indices& ind = chunk_indices[i - begin];
          std::vector<float>& d = chunk_dists[i - begin];
          ind.clear();
          d.clear();
          if (!queried[i])
            continue;
          if (!pcl::isFinite(cloud[i])) {
            ++skipped;
            continue;
          }
          ++queries;
          query(i, lattice, radius_cap, local, ind, d, over_budget, widened);
        } catch (const std::exception& e) {
          detail::keepFirstFailure(failure, e);
        }
    }
    throwSearchFailure(failure);
    if (over_budget) {
      this->deinitCompute();
      throw InvalidParameterError(
          detail::radiusTooLarge(*par.radius, radius_cap, indices_->size()));
    }
    // Widened or radius lists have no size known in advance: room for the whole cloud at the
    // mean size so far (and a twentieth more), so that the lists are moved about once, not at
    // every doubling of the vectors.
    std::size_t entries = output.entries();
    for (std::size_t i = begin; i < end; ++i)
      entries += chunk_indices[i - begin].size();
    if (end < n)
      output.reserve(n, entries + static_cast<std::size_t>(1.05 * static_cast<double>(entries) /
                                                           static_cast<double>(end) *
                                                           static_cast<double>(n - end)));
    for (std::size_t i = begin; i < end; ++i)
      output.append(chunk_indices[i - begin].data(), chunk_dists[i - begin].data(),
                    chunk_indices[i - begin].size());
  }
  statistics_.queries = queries;
  statistics_.skipped_nonfinite = skipped;
  statistics_.widened = widened;
}

template <typename PointT>
void NeighborhoodSelection<PointT>::searchInSpatialOrder(const std::vector<char>& queried,
                                                         Neighborhoods& output) {
  const auto& cloud = *input_;
  const std::size_t n = cloud.size();
  std::size_t finite = 0;
  for (const auto& p : cloud.points)
    finite += pcl::isFinite(p) ? 1 : 0;
  // Every finite queried point gets the k nearest of the finite points (all, when fewer).
  const auto k = static_cast<std::uint32_t>(
      std::min<std::size_t>(static_cast<std::size_t>(parameters_.k), finite));
  pcl::Indices points;
  {
    std::vector<std::uint32_t> sizes(n, 0);
    for (std::size_t i = 0; i < n; ++i)
      if (queried[i]) {
        points.push_back(static_cast<pcl::index_t>(i));
        sizes[i] = pcl::isFinite(cloud[i]) ? k : 0;
      }
    output.allocate(sizes);
  }
  const pcl::Indices order = spatialOrder(cloud, points);
  points = pcl::Indices();
  std::size_t queries = 0, skipped = 0;
  std::string failure;
  const auto m = static_cast<std::ptrdiff_t>(order.size());
#pragma omp parallel num_threads(resolveThreads(parameters_.threads)) reduction(+ : queries, skipped)
  {
    pcl::Indices ind;
    std::vector<float> d;
#pragma omp for schedule(dynamic, 256)
    for (std::ptrdiff_t o = 0; o < m; ++o)
      try {
        const auto i = static_cast<std::size_t>(order[static_cast<std::size_t>(o)]);
        if (!pcl::isFinite(cloud[i])) {
          ++skipped;
          continue;
        }
        ++queries;
        search_->nearestKSearch(cloud, static_cast<pcl::index_t>(i), static_cast<int>(k), ind, d);
        output.fill(i, ind.data(), d.data(), ind.size());
      } catch (const std::exception& e) {
        detail::keepFirstFailure(failure, e);
      }
  }
  throwSearchFailure(failure);
  statistics_.queries = queries;
  statistics_.skipped_nonfinite = skipped;
}

}  // namespace slipfit

#include "slipfit/neighborhoods/impl/noise_span.hpp"
