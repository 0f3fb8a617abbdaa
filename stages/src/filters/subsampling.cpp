#include "slipfit/filters/subsampling.h"

#include "slipfit/core/exceptions.h"
#include "slipfit/neighborhoods/depth_quantization.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <random>
#include <unordered_map>
#include <unordered_set>

namespace slipfit {

namespace {

Eigen::AlignedBox3f finiteBox(const Eigen::Ref<const Eigen::Matrix3Xf>& points) {
  Eigen::AlignedBox3f box;
  for (Eigen::Index i = 0; i < points.cols(); ++i)
    if (points.col(i).allFinite())
      box.extend(points.col(i));
  return box;
}

}  // namespace

Subsample voxelSample(const Eigen::Ref<const Eigen::Matrix3Xf>& points, double leaf,
                      const std::optional<Eigen::Vector3d>& grid_origin) {
  const Eigen::AlignedBox3f box = finiteBox(points);
  Subsample s;
  s.leaf = leaf;
  s.representative.assign(static_cast<std::size_t>(points.cols()), -1);
  if (box.isEmpty())
    return s;
  constexpr double kCells = 1 << 21;
  const Eigen::Vector3d origin = grid_origin ? *grid_origin : box.min().cast<double>();
  if (grid_origin && (box.min().cast<double>() - origin).minCoeff() < 0.0)
    throw InvalidParameterError("voxel sampling: a point lies below the grid's origin");
  if (!(leaf > 0.0) || (box.max().cast<double>() - origin).maxCoeff() / leaf >= kCells - 1)
    throw InvalidParameterError("voxel sampling: leaf " + std::to_string(leaf) +
                                " is not positive or too small for the cloud's extent");
  std::unordered_map<std::uint64_t, std::int32_t> voxel;
  voxel.reserve(static_cast<std::size_t>(points.cols()) / 4);
  for (Eigen::Index i = 0; i < points.cols(); ++i) {
    if (!points.col(i).allFinite())
      continue;
    const Eigen::Vector3d c = (points.col(i).cast<double>() - origin) / leaf;
    const auto key = (static_cast<std::uint64_t>(c.x()) << 42) |
                     (static_cast<std::uint64_t>(c.y()) << 21) | static_cast<std::uint64_t>(c.z());
    const auto [it, fresh] = voxel.try_emplace(key, static_cast<std::int32_t>(s.kept.size()));
    if (fresh)
      s.kept.push_back(static_cast<std::int32_t>(i));
    s.representative[static_cast<std::size_t>(i)] = it->second;
  }
  return s;
}

namespace {

Subsample keepAll(const Eigen::Ref<const Eigen::Matrix3Xf>& points) {
  Subsample s;
  for (Eigen::Index i = 0; i < points.cols(); ++i) {
    const bool finite = points.col(i).allFinite();
    s.representative.push_back(finite ? static_cast<std::int32_t>(s.kept.size()) : -1);
    if (finite)
      s.kept.push_back(static_cast<std::int32_t>(i));
  }
  return s;
}

}  // namespace

Subsample randomSample(const Eigen::Ref<const Eigen::Matrix3Xf>& points, std::size_t target,
                       std::uint64_t seed) {
  if (target == 0)
    throw InvalidParameterError("random sampling: the target must be at least 1 point");
  if (static_cast<std::size_t>(points.cols()) <= target)
    return keepAll(points);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const double p = static_cast<double>(target) / static_cast<double>(points.cols());
  Subsample s;
  for (Eigen::Index i = 0; i < points.cols(); ++i)
    if (unit(rng) < p && points.col(i).allFinite()) {
      s.kept.push_back(static_cast<std::int32_t>(i));
    }
  if (s.kept.empty())
    return keepAll(points);
  // Representatives by a voxel grid over the kept points, about eight kept points a voxel: a point
  // is represented by the first kept point of its voxel, or by nothing when its voxel holds none
  // (isolated points, mostly outliers). Cheaper than a nearest-neighbor search for every point,
  // and the representative only proposes segments that are then tested by distance.
  Eigen::Matrix3Xf kept_points(3, static_cast<Eigen::Index>(s.kept.size()));
  for (std::size_t k = 0; k < s.kept.size(); ++k)
    kept_points.col(static_cast<Eigen::Index>(k)) = points.col(s.kept[k]);
  const Subsample grid = voxelSampleTo(kept_points, std::max<std::size_t>(1, s.kept.size() / 8));
  s.leaf = grid.leaf;
  s.representative.assign(static_cast<std::size_t>(points.cols()), -1);
  if (grid.leaf == 0.0) {
    for (std::size_t k = 0; k < s.kept.size(); ++k)
      s.representative[static_cast<std::size_t>(s.kept[k])] = static_cast<std::int32_t>(k);
    return s;
  }
  const Eigen::AlignedBox3f box = finiteBox(kept_points);
  const Eigen::Vector3d origin = box.min().cast<double>();
  const auto cells = std::floor(box.diagonal().cast<double>().maxCoeff() / grid.leaf) + 1;
  std::unordered_map<std::uint64_t, std::int32_t> voxel;
  voxel.reserve(grid.kept.size() * 2);
  auto key = [&](const Eigen::Vector3f& p, std::uint64_t* out) {
    const Eigen::Vector3d c = ((p.cast<double>() - origin) / grid.leaf).array().floor();
    if ((c.array() < 0.0).any() || (c.array() >= cells).any())
      return false;
    *out = (static_cast<std::uint64_t>(c.x()) << 42) | (static_cast<std::uint64_t>(c.y()) << 21) |
           static_cast<std::uint64_t>(c.z());
    return true;
  };
  std::uint64_t k = 0;
  for (std::int32_t g : grid.kept)  // the first kept point of each voxel, in index order
    if (key(kept_points.col(g), &k))
      voxel.emplace(k, g);
  for (Eigen::Index i = 0; i < points.cols(); ++i) {
    if (!points.col(i).allFinite() || !key(points.col(i), &k))
      continue;
    const auto it = voxel.find(k);
    if (it != voxel.end())
      s.representative[static_cast<std::size_t>(i)] = it->second;
  }
  for (std::size_t j = 0; j < s.kept.size(); ++j)
    s.representative[static_cast<std::size_t>(s.kept[j])] = static_cast<std::int32_t>(j);
  return s;
}

Subsample voxelSampleTo(const Eigen::Ref<const Eigen::Matrix3Xf>& points, std::size_t target,
                        const std::optional<Eigen::Vector3d>& origin) {
  if (target == 0)
    throw InvalidParameterError("voxel sampling: the target must be at least 1 point");
  if (static_cast<std::size_t>(points.cols()) <= target) {
    Subsample s;
    for (Eigen::Index i = 0; i < points.cols(); ++i) {
      s.representative.push_back(
          points.col(i).allFinite() ? static_cast<std::int32_t>(s.kept.size()) : -1);
      if (points.col(i).allFinite())
        s.kept.push_back(static_cast<std::int32_t>(i));
    }
    return s;
  }
  Subsample s;
  voxelLeafForTarget(finiteBox(points).sizes().cast<double>(), target, [&](double leaf) {
    s = voxelSample(points, leaf, origin);  // the last call is at the leaf returned
    return s.kept.size();
  });
  return s;
}

double voxelLeafForTarget(const Eigen::Vector3d& box_sizes, std::size_t target,
                          const std::function<std::size_t(double leaf)>& occupied) {
  if (target == 0)
    throw InvalidParameterError("voxel sampling: the target must be at least 1 point");
  // Start as if the points covered a surface of the box's largest face, then correct by the
  // count (kept ∝ leaf⁻² on surfaces).
  Eigen::Vector3d size = box_sizes;
  std::sort(size.data(), size.data() + 3);
  double leaf = std::sqrt(std::max(size[1] * size[2], 1e-300) / static_cast<double>(target));
  std::size_t kept = occupied(leaf);
  for (int pass = 0; pass < 4; ++pass) {
    const double ratio = static_cast<double>(kept) / static_cast<double>(target);
    if (ratio > 0.9 && ratio < 1.1)
      break;
    leaf *= std::sqrt(ratio);
    kept = occupied(leaf);
  }
  return leaf;
}

std::size_t occupiedVoxels(const Eigen::Ref<const Eigen::Matrix3Xd>& points, double leaf,
                           const Eigen::Vector3d& origin,
                           const std::function<bool(const Eigen::Vector3d& corner)>& counts) {
  struct Hash {
    std::size_t operator()(const std::array<std::int64_t, 3>& k) const {
      return std::hash<std::int64_t>()((k[0] * 73856093) ^ (k[1] * 19349663) ^ (k[2] * 83492791));
    }
  };
  std::unordered_set<std::array<std::int64_t, 3>, Hash> seen;
  std::size_t n = 0;
  for (Eigen::Index i = 0; i < points.cols(); ++i) {
    if (!points.col(i).allFinite())
      continue;
    // voxelSample's arithmetic: the same voxel for the same point.
    const Eigen::Vector3d c = ((points.col(i) - origin) / leaf).array().floor();
    const std::array<std::int64_t, 3> key{static_cast<std::int64_t>(c.x()),
                                          static_cast<std::int64_t>(c.y()),
                                          static_cast<std::int64_t>(c.z())};
    if (seen.insert(key).second && counts(origin + c * leaf))
      ++n;
  }
  return n;
}

RepresentedMean representedMean(const Eigen::Ref<const Eigen::Matrix3Xf>& points,
                                const Subsample& sample) {
  if (sample.representative.size() != static_cast<std::size_t>(points.cols()))
    throw InvalidParameterError("represented mean: the sample is not of these points");
  const std::size_t kept = sample.kept.size();
  Eigen::Matrix3Xd sum = Eigen::Matrix3Xd::Zero(3, static_cast<Eigen::Index>(kept));
  RepresentedMean out;
  out.count.assign(kept, 0);
  for (Eigen::Index i = 0; i < points.cols(); ++i) {
    const std::int32_t r = sample.representative[static_cast<std::size_t>(i)];
    if (r < 0)
      continue;
    if (static_cast<std::size_t>(r) >= kept || !points.col(i).allFinite())
      throw InvalidParameterError("represented mean: the sample is not of these points");
    sum.col(r) += points.col(i).cast<double>();
    ++out.count[static_cast<std::size_t>(r)];
  }
  out.mean.resize(3, static_cast<Eigen::Index>(kept));
  for (std::size_t k = 0; k < kept; ++k) {
    if (out.count[k] == 0)
      throw InvalidParameterError("represented mean: a kept point represents no point");
    out.mean.col(static_cast<Eigen::Index>(k)) =
        (sum.col(static_cast<Eigen::Index>(k)) / static_cast<double>(out.count[k])).cast<float>();
  }
  return out;
}

Subsample subsample(const Eigen::Ref<const Eigen::Matrix3Xf>& points, const SubsampleParameters& p,
                    std::uint64_t seed) {
  p.validate();
  if (p.mode == SubsampleMode::random)
    return randomSample(points, p.points, seed);
  return p.leaf ? voxelSample(points, *p.leaf, p.origin)
                : voxelSampleTo(points, p.points, p.origin);
}

VoxelPlacement voxelPlacement(const Eigen::Ref<const Eigen::Matrix3Xf>& points,
                              SubsamplePosition requested) {
  VoxelPlacement placement{requested, -1, {}};
  if (requested == SubsamplePosition::first)
    return placement;
  // A disparity sensor's levels lie c z² apart, their step growing with depth; levels of one
  // step are a grid (an airborne scanner's scan lines, 7 cm apart along x in the simulated
  // ones), which the means leave without harm: they are where the points are, not a rounding.
  constexpr double kVaryingStep = 1.01;  // rounding moves a grid's steps by about 1e-5
  const QuantizedAxis levels = detectQuantizedAxis(points.cast<double>());
  if (levels.detected() && levels.maxStep() > kVaryingStep * levels.minStep())
    placement = {SubsamplePosition::first, levels.axis, levels.name()};
  return placement;
}

}  // namespace slipfit
