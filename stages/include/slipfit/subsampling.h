#pragma once
/// \file Subsampling that remembers, for every point, which kept point stands for it — so that an
/// analysis run on the subsample can be carried back to every input point. Voxel sampling evens
/// out the density but keeps every isolated outlier (one per voxel); random sampling keeps the
/// proportions.

#include <Eigen/Core>

#include <cstdint>
#include <vector>

namespace slipfit {

struct Subsample {
  double leaf = 0.0;                         ///< voxel edge used, units
  std::vector<std::int32_t> kept;            ///< indices of the kept points, ascending
  std::vector<std::int32_t> representative;  ///< per input point: its position in `kept`
};

/// One point per occupied voxel of edge \a leaf (the first in index order: deterministic);
/// non-finite points are represented by nothing (−1). Throws InvalidParameterError for a leaf
/// that is not positive or would overflow the 21-bit voxel keys.
Subsample voxelSample(const Eigen::Ref<const Eigen::Matrix3Xf>& points, double leaf);

/// voxelSample with the leaf adjusted (a few passes, each O(N)) so that about \a target points
/// are kept; no subsampling (leaf 0, every point kept) when there are at most \a target points.
Subsample voxelSampleTo(const Eigen::Ref<const Eigen::Matrix3Xf>& points, std::size_t target);

/// The mean position of the input points each kept point stands for (its voxel's centroid in
/// voxel sampling, as PCL's VoxelGrid places its points) and how many they are. A mean of m
/// points with independent noise σ has noise σ/√m: the analysis of a dense surface sees it with
/// the noise of its density, not of one sample (see SegmentationKernel, `averaged`).
struct RepresentedMean {
  Eigen::Matrix3Xf mean;             ///< 3 × kept, in the order of `kept`
  std::vector<std::uint32_t> count;  ///< input points per kept point (≥ 1)
};

/// Means and counts of the points each kept point of \a sample represents (summed in double, in
/// index order: deterministic). Throws InvalidParameterError when \a sample is not of \a points.
RepresentedMean representedMean(const Eigen::Ref<const Eigen::Matrix3Xf>& points,
                                const Subsample& sample);

/// About \a target points drawn uniformly at random (seeded; each point with probability
/// target / N, so the result is reproducible). A point is represented by the first kept point of
/// its cell in a grid of about eight kept points per cell, or by nothing (−1) when its cell holds
/// none — isolated points, mostly outliers; `leaf` is that grid's cell. No subsampling when there
/// are at most \a target points.
Subsample randomSample(const Eigen::Ref<const Eigen::Matrix3Xf>& points, std::size_t target,
                       std::uint64_t seed);

}  // namespace slipfit
