#pragma once
/// \file Subsampling that remembers, for every point, which kept point stands for it — so that an
/// analysis run on the subsample can be carried back to every input point. Voxel sampling evens
/// out the density but keeps every isolated outlier (one per voxel); random sampling keeps the
/// proportions.

#include "slipfit/core/parameter_declaration.h"

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace slipfit {

/// How the analysis points are chosen.
enum class SubsampleMode {
  random,  ///< each point with probability points / N (randomSample)
  voxel    ///< one point per voxel (voxelSample, voxelSampleTo)
};
constexpr std::array<std::pair<SubsampleMode, std::string_view>, 2> kSubsampleModeNames{{
    {SubsampleMode::random, "random"},
    {SubsampleMode::voxel, "voxel"},
}};

/// Where a voxel's analysis point lies.
enum class SubsamplePosition {
  mean,  ///< the centroid of its voxel's points (representedMean)
  first  ///< the voxel's first input point
};
constexpr std::array<std::pair<SubsamplePosition, std::string_view>, 2> kSubsamplePositionNames{{
    {SubsamplePosition::mean, "mean"},
    {SubsamplePosition::first, "first"},
}};

/// The choices of a subsample, as the pipeline's subsample stage makes them.
struct SubsampleParameters {
  SubsampleMode mode = SubsampleMode::random;
  std::size_t points = 150000;  ///< about this many kept points
  std::optional<double> leaf;   ///< voxel mode: the voxel edge, overriding points
  /// Voxel mode: the lowest corner of the voxel grid (unset: the cloud's own lowest corner).
  std::optional<Eigen::Vector3d> origin;
  SubsamplePosition position = SubsamplePosition::mean;

  /// Each user-facing field with its one declaration (parameter_declaration.h).
  template <typename Self, typename Visit>
  static void forEachParameter(Self& self, Visit&& visit) {
    visit(self.mode,
          parameter("mode",
                    "random: each point kept with probability points / N (seeded; outliers keep "
                    "their proportion), represented by a kept point of its grid cell; voxel: one "
                    "point per voxel (even density, but every isolated outlier survives)."),
          kSubsampleModeNames);
    visit(self.points, parameter("points",
                                 "Keep about this many points, one per voxel (the leaf "
                                 "is found in a few passes).")
                           .in("points")
                           .between(100, 1e9));
    visit(self.leaf,
          parameter("leaf", "Voxel mode: voxel edge; overrides points.").in("units").above(0));
    visit(self.origin,
          parameter("origin",
                    "Voxel mode: the lowest corner of the voxel grid, in the input's frame "
                    "(unset: the cloud's own lowest corner); every point must lie above it. A "
                    "tiled run gives each tile the whole cloud's, so that its voxels are the "
                    "untiled run's.")
              .in("units"));
    visit(self.position,
          parameter("position",
                    "Voxel mode: where the analysis point lies. mean: at the centroid of its "
                    "voxel's points (as PCL's VoxelGrid): their noise averages down, so normals "
                    "and fits on dense surfaces see more than one sample's scatter; first: at the "
                    "voxel's first input point. Depth recorded on levels (a depth camera's) is "
                    "always placed at first points: a mean would leave the levels."),
          kSubsamplePositionNames);
  }

  /// Throws InvalidParameterError naming the field, its value and its declared range.
  void validate() const { validateDeclared(*this, "subsample"); }
};

struct Subsample {
  double leaf = 0.0;                         ///< voxel edge used, units
  std::vector<std::int32_t> kept;            ///< indices of the kept points, ascending
  std::vector<std::int32_t> representative;  ///< per input point: its position in `kept`
};

/// One point per occupied voxel of edge \a leaf (the first in index order: deterministic), the
/// voxels counted from \a origin (unset: the points' lowest corner); non-finite points are
/// represented by nothing (−1). Throws InvalidParameterError for a leaf that is not positive or
/// would overflow the 21-bit voxel keys, and for a point below the origin.
Subsample voxelSample(const Eigen::Ref<const Eigen::Matrix3Xf>& points, double leaf,
                      const std::optional<Eigen::Vector3d>& origin = std::nullopt);

/// voxelSample with the leaf adjusted (a few passes, each O(N)) so that about \a target points
/// are kept; no subsampling (leaf 0, every point kept) when there are at most \a target points.
Subsample voxelSampleTo(const Eigen::Ref<const Eigen::Matrix3Xf>& points, std::size_t target,
                        const std::optional<Eigen::Vector3d>& origin = std::nullopt);

/// voxelSampleTo's choice of the leaf: from the points' bounding box (\a box_sizes), then up to
/// four corrections by the count of occupied voxels, which \a occupied(leaf) returns (for points
/// held elsewhere: the tiles of an out-of-core run add theirs up). The last call is at the leaf
/// returned.
double voxelLeafForTarget(const Eigen::Vector3d& box_sizes, std::size_t target,
                          const std::function<std::size_t(double leaf)>& occupied);

/// The voxels of edge \a leaf counted from \a origin (voxelSample's grid) that hold at least one
/// of \a points and whose lowest corner \a counts: a tile counts those whose corner lies in its
/// core, so that the tiles' counts add up to the whole cloud's.
std::size_t occupiedVoxels(const Eigen::Ref<const Eigen::Matrix3Xd>& points, double leaf,
                           const Eigen::Vector3d& origin,
                           const std::function<bool(const Eigen::Vector3d& corner)>& counts);

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

/// Where a voxel sample's analysis points lie, and why.
struct VoxelPlacement {
  SubsamplePosition position = SubsamplePosition::mean;
  int levels_axis = -1;     ///< the coordinate recorded on levels that made it `first`, or −1
  std::string levels_name;  ///< its QuantizedAxis::name(), for reports
};

/// The placement a voxel sample of \a points takes when \a requested: `first` (an input point)
/// where a coordinate is recorded on levels whose step grows along it (detectQuantizedAxis: a
/// depth camera's disparity levels, c z² apart), whatever was requested. The mean of a voxel's
/// returns would lie on one level's flat slice where they share it, or between two levels where
/// they do not: the analysis no longer sees the levels it models and reads the slices as planes (a
/// 1280 × 960 simulated depth frame, subsampled to 400,000 means by the demo's budget: mean IoU
/// 0.01, every plane of RMS 0). An input point keeps its level. Otherwise \a requested.
VoxelPlacement voxelPlacement(const Eigen::Ref<const Eigen::Matrix3Xf>& points,
                              SubsamplePosition requested);

/// About \a target points drawn uniformly at random (seeded; each point with probability
/// target / N, so the result is reproducible). A point is represented by the first kept point of
/// its cell in a grid of about eight kept points per cell, or by nothing (−1) when its cell holds
/// none — isolated points, mostly outliers; `leaf` is that grid's cell. No subsampling when there
/// are at most \a target points.
Subsample randomSample(const Eigen::Ref<const Eigen::Matrix3Xf>& points, std::size_t target,
                       std::uint64_t seed);

/// The subsample \a parameters ask for: randomSample (mode random), voxelSample at `leaf` or
/// voxelSampleTo `points` (mode voxel). Validates \a parameters first.
Subsample subsample(const Eigen::Ref<const Eigen::Matrix3Xf>& points,
                    const SubsampleParameters& parameters, std::uint64_t seed);

}  // namespace slipfit
