#include "slipfit/segmentation/segmentation_state.h"

#include "slipfit/core/exceptions.h"
#include "slipfit/core/median.h"
#include "slipfit/core/threads.h"
#include "slipfit/segmentation/segmentation_tuning.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <limits>

namespace slipfit {

SegmentationState::SegmentationState(const Eigen::Ref<const Eigen::Matrix3Xd>& points_in,
                                     const Eigen::Ref<const Eigen::Matrix3Xd>& normals_in,
                                     const Neighborhoods& neighborhoods,
                                     const std::vector<SlippageType>& local_types_in,
                                     const SegmentationParameters& parameters_in)
    : points(points_in),
      normals(normals_in),
      hoods(neighborhoods),
      local_types(local_types_in),
      parameters(parameters_in),
      n(static_cast<std::size_t>(points_in.cols())) {
  parameters.validate();
  if (n == 0)
    throw DegenerateInputError("segmentation: the cloud is empty");
  if (static_cast<std::size_t>(normals.cols()) != n || hoods.size() != n || local_types.size() != n)
    throw DegenerateInputError(
        "segmentation: points, normals, neighborhoods and local types differ in number");
  if (!normals.allFinite())
    throw DegenerateInputError("segmentation: some normals are missing (NaN)");
}

void SegmentationState::addRegion(std::vector<int> members, FitResult fit, SlippageType seed_type) {
  const auto region = static_cast<std::int32_t>(regions.size());
  for (int i : members)
    label(i) = region;
  regions.push_back(std::move(members));
  fits.push_back(std::move(fit));
  seed_types.push_back(seed_type);
  alive.push_back(1);
}

void SegmentationState::drop(std::size_t region) {
  for (int i : regions[region])
    label(i) = -1;
  regions[region].clear();
  alive[region] = 0;
}

void SegmentationState::relabelFromRegions() {
  for (auto& region : regions)
    region.clear();
  for (std::size_t i = 0; i < n; ++i)
    if (result.labels[i] >= 0)
      regions[static_cast<std::size_t>(result.labels[i])].push_back(static_cast<int>(i));
}

void SegmentationState::moveInto(std::size_t from, std::size_t into) {
  for (int i : regions[from])
    label(i) = static_cast<std::int32_t>(into);
  regions[into].insert(regions[into].end(), regions[from].begin(), regions[from].end());
  regions[from].clear();
  alive[from] = 0;
}

std::vector<std::set<std::size_t>> SegmentationState::touchingRegions() const {
  std::vector<std::set<std::size_t>> touching(regions.size());
  for (std::size_t r = 0; r < regions.size(); ++r) {
    if (!alive[r])
      continue;
    for (int i : regions[r])
      for (pcl::index_t j : hood(i)) {
        const int other = label(j);
        if (other >= 0 && static_cast<std::size_t>(other) != r)
          touching[r].insert(static_cast<std::size_t>(other));
      }
  }
  return touching;
}

double SegmentationState::medianNearestDistance(const std::vector<int>& set) const {
  std::vector<double> d;
  d.reserve(set.size());
  for (int i : set) {
    const NeighborView v = hood(i);
    if (v.size() > 1)
      d.push_back(std::sqrt(static_cast<double>(v.sqr_distances[1])));
  }
  return d.empty() ? 0.0 : quantile(std::move(d), 0.5);
}

std::vector<double> SegmentationState::regionSpacings() const {
  std::vector<double> spacings(regions.size(), 0.0);
  for (std::size_t r = 0; r < regions.size(); ++r)
    if (alive[r])
      spacings[r] = medianNearestDistance(regions[r]);
  return spacings;
}

namespace {

/// The median distance from each of \a set to its nearest other member of the set (those whose
/// \a stamp is \a mark) among its neighbors; a point with none among them is not sampled with
/// the set (+inf): an outlier whose nearest are all points of a surface nearby.
double medianNearestWithin(const Neighborhoods& hoods, const std::vector<int>& set,
                           const std::vector<std::uint32_t>& stamp, std::uint32_t mark) {
  std::vector<double> d;
  d.reserve(set.size());
  for (int i : set) {
    const NeighborView v = hoods[static_cast<std::size_t>(i)];
    if (v.size() < 2)
      continue;
    std::size_t j = 1;
    while (j < v.size() && stamp[static_cast<std::size_t>(v[j])] != mark)
      ++j;
    d.push_back(j < v.size() ? std::sqrt(static_cast<double>(v.sqr_distances[j]))
                             : std::numeric_limits<double>::infinity());
  }
  return d.empty() ? 0.0 : quantile(std::move(d), 0.5);
}

}  // namespace

bool SegmentationState::isScattered(const std::vector<int>& set,
                                    const std::vector<double>& spacings,
                                    std::vector<std::uint32_t>& stamp,
                                    std::uint32_t& generation) const {
  // The densest region around, not its points next to the set: those are often outliers that
  // joined it within tolerance, as sparse as the set.
  double around = spacing;
  bool found = false;
  for (int i : set)
    for (pcl::index_t j : hood(i)) {
      const std::int32_t lj = label(j);
      const auto r = static_cast<std::size_t>(lj);
      if (lj >= 0 && r < spacings.size() && spacings[r] > 0.0 && (!found || spacings[r] < around)) {
        around = spacings[r];
        found = true;
      }
    }
  ++generation;
  for (int i : set)
    stamp[static_cast<std::size_t>(i)] = generation;
  if (medianNearestWithin(hoods, set, stamp, generation) <= SegmentationTuning::scattered * around)
    return false;
  if (found)
    return true;
  // No region around to compare with, and sparser than the cloud's median spacing: a post far
  // from a LiDAR has returns 5–7 cm apart where the ground near the scanner sets that spacing at
  // 1 cm (and a crop that removes the near ground would decide otherwise). Scattered unless the
  // set lies in a sheet (SegmentationTuning::isolated_thinness), as points thrown through a
  // volume do not.
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (int i : set)
    mean += points.col(i);
  mean /= static_cast<double>(set.size());
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for (int i : set) {
    const Eigen::Vector3d d = points.col(i) - mean;
    covariance.noalias() += d * d.transpose();
  }
  const Eigen::Vector3d lambda =
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(covariance, Eigen::EigenvaluesOnly)
          .eigenvalues();
  return !(lambda(1) > 0.0) ||
         std::sqrt(std::max(0.0, lambda(0)) / lambda(1)) >= SegmentationTuning::isolated_thinness;
}

double SegmentationState::normalAngle(int i, const Primitive& primitive) const {
  const double c = std::abs(surfaceNormal(points.col(i), primitive).dot(normals.col(i)));
  return std::acos(std::min(1.0, c));
}

double SegmentationState::rms(const std::vector<int>& members, const Primitive& primitive,
                              double* max_distance) const {
  double sum = 0.0, worst = 0.0;
  for (int i : members) {
    const double d = distance(points.col(i), primitive);
    sum += d * d;
    worst = std::max(worst, d);
  }
  if (max_distance)
    *max_distance = worst;
  return members.empty() ? 0.0 : std::sqrt(sum / static_cast<double>(members.size()));
}

double SegmentationState::precisionRms(const std::vector<int>& members,
                                       const Primitive& primitive) const {
  const Eigen::VectorXd w = grower->precisionWeights(members);
  double sum = 0.0;
  for (std::size_t j = 0; j < members.size(); ++j) {
    const double d = distance(points.col(members[j]), primitive);
    sum += w(static_cast<Eigen::Index>(j)) * d * d;
  }
  return members.empty() ? 0.0 : std::sqrt(sum / static_cast<double>(members.size()));
}

int SegmentationState::workers() const {
  return resolveThreads(parameters.threads);
}

}  // namespace slipfit
