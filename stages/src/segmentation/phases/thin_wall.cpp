#include "thin_wall.h"

#include "slipfit/segmentation/segmentation_tuning.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <utility>

namespace slipfit::phases {

namespace {

using T = SegmentationTuning;

/// Two sheets of a neighborhood: which of its points lie on the upper one, and how far apart the
/// sheets' means lie along their common normal against the points' RMS distance off them.
struct SheetSplit {
  std::vector<char> upper;
  double separation = 0.0;
  double rms = 0.0;
};

/// Splits the points \a idx in two sheets by alternating, from the start \a axis: split the
/// offsets along the axis at their widest gap (at least kSheetPoints each side), then take as the
/// axis the least principal direction of the two groups about their own means.
SheetSplit splitSheets(const Eigen::Ref<const Eigen::Matrix3Xd>& points,
                       const std::vector<pcl::index_t>& idx, Eigen::Vector3d axis) {
  constexpr std::size_t kSheetPoints = 2;
  const std::size_t k = idx.size();
  SheetSplit split;
  split.upper.assign(k, 0);
  std::vector<std::pair<double, std::size_t>> offset(k);
  for (int pass = 0; pass < 3; ++pass) {
    for (std::size_t j = 0; j < k; ++j)
      offset[j] = {axis.dot(points.col(idx[j])), j};
    std::sort(offset.begin(), offset.end());
    std::size_t cut = kSheetPoints;  // the upper group starts here
    for (std::size_t j = kSheetPoints; j + kSheetPoints <= k; ++j)
      if (offset[j].first - offset[j - 1].first > offset[cut].first - offset[cut - 1].first)
        cut = j;
    for (std::size_t j = 0; j < k; ++j)
      split.upper[offset[j].second] = j >= cut ? 1 : 0;
    Eigen::Vector3d mean[2] = {Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
    for (std::size_t j = 0; j < k; ++j)
      mean[split.upper[j] ? 1 : 0] += points.col(idx[j]);
    mean[0] /= static_cast<double>(cut);
    mean[1] /= static_cast<double>(k - cut);
    Eigen::Matrix3d within = Eigen::Matrix3d::Zero();
    for (std::size_t j = 0; j < k; ++j) {
      const Eigen::Vector3d d = points.col(idx[j]) - mean[split.upper[j] ? 1 : 0];
      within += d * d.transpose();
    }
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(within);
    axis = eigen.eigenvectors().col(0);
    split.separation = std::abs(axis.dot(mean[1] - mean[0]));
    split.rms = std::sqrt(std::max(0.0, eigen.eigenvalues()(0)) / static_cast<double>(k));
  }
  return split;
}

}  // namespace

// splitSheets starts from each principal axis of the neighborhood
// (with a dozen points a neighborhood is barely wider than the wall, and its least axis may lie
// along it) and the split whose sheets lie furthest apart for their RMS counts. Two sheets: their
// means lie apart by more than SegmentationTuning::sheet_separation times the RMS and a share of
// the neighborhood's radius. Faces meeting at a crease share no normal, and their RMS off it is
// large.
std::vector<pcl::index_t> ownSheet(const Eigen::Ref<const Eigen::Matrix3Xd>& points,
                                   const std::vector<pcl::index_t>& idx, pcl::index_t i,
                                   const Eigen::Matrix3d& axes, double radius) {
  const std::size_t k = idx.size();
  const auto at = std::find(idx.begin(), idx.end(), i);
  if (k < 8 || at == idx.end())
    return idx;
  SheetSplit best;
  for (int a = 0; a < 3; ++a) {
    SheetSplit split = splitSheets(points, idx, axes.col(a));
    if (best.upper.empty() || split.separation * best.rms > best.separation * split.rms)
      best = std::move(split);
  }
  if (!(best.separation > T::sheet_separation * best.rms &&
        best.separation > T::sheet_radius_share * radius))
    return idx;
  const char own = best.upper[static_cast<std::size_t>(at - idx.begin())];
  std::vector<pcl::index_t> sheet;
  for (std::size_t j = 0; j < k; ++j)
    if (best.upper[j] == own)
      sheet.push_back(idx[j]);
  return sheet;
}

// A wall about as thick as the spacing puts both of its
// sheets in every neighborhood; the normal is still the sheets' (they are parallel), but no
// primitive fits both.
std::vector<int> seedSheet(const Eigen::Ref<const Eigen::Matrix3Xd>& points,
                           const Eigen::Vector3d& normal, int seed,
                           const std::vector<int>& candidates, double gap) {
  std::vector<std::pair<double, int>> offset;  // (offset, index), the seed at 0
  offset.reserve(candidates.size() + 1);
  offset.emplace_back(0.0, seed);
  for (int j : candidates)
    if (j != seed)
      offset.emplace_back(normal.dot(points.col(j) - points.col(seed)), j);
  std::sort(offset.begin(), offset.end());
  const auto at = static_cast<std::size_t>(
      std::find_if(offset.begin(), offset.end(), [&](const auto& o) { return o.second == seed; }) -
      offset.begin());
  std::size_t lo = at;
  std::size_t hi = at;
  while (lo > 0 && offset[lo].first - offset[lo - 1].first <= gap)
    --lo;
  while (hi + 1 < offset.size() && offset[hi + 1].first - offset[hi].first <= gap)
    ++hi;
  if (lo == 0 && hi + 1 == offset.size())
    return {};
  std::vector<int> sheet;
  for (std::size_t k = lo; k <= hi; ++k)
    sheet.push_back(offset[k].second);
  std::sort(sheet.begin(), sheet.end());
  return sheet;
}

}  // namespace slipfit::phases
