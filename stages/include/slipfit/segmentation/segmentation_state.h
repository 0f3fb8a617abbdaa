#pragma once
/// \file What the segmentation phases share: the inputs, the regions grown so far with their fits,
/// the per-point labels and tolerances, and the helpers every phase uses (add or drop a region,
/// relabel, adjacency, the density test). The phases (stages/src/segmentation/phases/) each change
/// this state and never call one another; SegmentationKernel runs them in order.

#include "slipfit/segmentation/region_grower.h"
#include "slipfit/segmentation/segmentation.h"

#include <Eigen/Core>

#include <cstdint>
#include <optional>
#include <set>
#include <vector>

namespace slipfit {

struct SegmentationState {
  /// Checks the inputs (sizes, finite normals, parameters); throws DegenerateInputError or
  /// InvalidParameterError. The arrays must outlive the state.
  SegmentationState(const Eigen::Ref<const Eigen::Matrix3Xd>& points,
                    const Eigen::Ref<const Eigen::Matrix3Xd>& normals,
                    const Neighborhoods& neighborhoods,
                    const std::vector<SlippageType>& local_types,
                    const SegmentationParameters& parameters);

  // ---- inputs (read only) ---------------------------------------------------------------------
  Eigen::Ref<const Eigen::Matrix3Xd> points;   ///< 3 × N; a view: the array outlives the state
  Eigen::Ref<const Eigen::Matrix3Xd> normals;  ///< 3 × N, either sign
  const Neighborhoods& hoods;
  const std::vector<SlippageType>& local_types;
  SegmentationParameters parameters;
  std::size_t n = 0;  ///< the number of points

  // ---- set by phase 1 (estimate_scale) --------------------------------------------------------
  std::optional<RegionGrower> grower;  ///< per-point tolerances, fits, growth
  double edge_margin = 0.0;  ///< distances within this are a tie (no measurement tells), units
  double spacing = 0.0;      ///< the median nearest-neighbour distance, units
  /// Each point's noise σᵢ (units): the local estimate where the cloud is a sensor's (noisy, or
  /// depth on levels), else the cloud's σ̂. Empty when the distance tolerance was given.
  std::vector<double> noise;
  /// A sensor's frame: depth recorded on levels or a sensor's view (parameters.sensor_view), the
  /// tolerance automatic. Two pieces of one surface there were cut apart by an occluder; on a CAD
  /// part they are two faces (phase 13). Noise alone does not tell: a sparse CAD part's σ̂ reaches
  /// s/20 (Fit4CAD's PC113, whose two coaxial cylinders of one radius are two faces).
  bool sensor_frame = false;

  // ---- the regions ----------------------------------------------------------------------------
  /// Tolerances, counters and the point labels (segments are filled by finalize).
  SegmentationResult result;
  std::vector<std::vector<int>> regions;  ///< members; empty for a region dropped or merged away
  std::vector<FitResult> fits;            ///< each region's fit (stale for a dead region)
  std::vector<SlippageType> seed_types;   ///< the local type of each region's seed
  std::vector<char> alive;                ///< 0 for a region dropped or merged away
  std::vector<char> tried;                ///< seeding: points that seeded, or were grown over

  // ---- per-point access -----------------------------------------------------------------------
  /// Point \a i's neighbors (itself first).
  NeighborView hood(int i) const { return hoods[static_cast<std::size_t>(i)]; }
  /// Point \a i's region, −1 when free.
  std::int32_t label(int i) const { return result.labels[static_cast<std::size_t>(i)]; }
  std::int32_t& label(int i) { return result.labels[static_cast<std::size_t>(i)]; }
  bool isFree(int i) const { return label(i) < 0; }
  /// Region \a region's primitive (its fit's refined one).
  const Primitive& primitive(std::int32_t region) const {
    return fits[static_cast<std::size_t>(region)].refined;
  }
  /// Region \a region's member count.
  std::size_t size(std::int32_t region) const {
    return regions[static_cast<std::size_t>(region)].size();
  }

  // ---- regions --------------------------------------------------------------------------------
  /// A new region of \a members (their labels set to it).
  void addRegion(std::vector<int> members, FitResult fit, SlippageType seed_type);
  /// Frees the region's points; the region is dead.
  void drop(std::size_t region);
  /// Rebuilds every region's member list from the labels (ascending indices).
  void relabelFromRegions();
  /// Moves region \a from's points into region \a into (\a from is dead).
  void moveInto(std::size_t from, std::size_t into);
  /// For each live region, the regions its points have among their neighbors.
  std::vector<std::set<std::size_t>> touchingRegions() const;
  /// Each live region's median nearest-neighbour distance (0 for the dead ones).
  std::vector<double> regionSpacings() const;

  // ---- measures -------------------------------------------------------------------------------
  /// Angle between point i's normal and \a primitive's at it (unsigned), radians.
  double normalAngle(int i, const Primitive& primitive) const;
  /// RMS distance of \a members to \a primitive; the largest in \a max_distance when given.
  double rms(const std::vector<int>& members, const Primitive& primitive,
             double* max_distance = nullptr) const;
  /// RMS distance of \a members to \a primitive, each distance scaled by the members' smallest
  /// tolerance over its own (the RMS distance when all tolerances are equal).
  double precisionRms(const std::vector<int>& members, const Primitive& primitive) const;
  /// The points \a set (free) lie further apart than SegmentationTuning::scattered × the points of
  /// the densest region among \a spacings (indexed by region; regions beyond it do not count) that
  /// holds a neighbor of theirs, or than the cloud's points when none does: scattered points, not
  /// a surface. \a stamp marks the set with a fresh \a generation.
  bool isScattered(const std::vector<int>& set, const std::vector<double>& spacings,
                   std::vector<std::uint32_t>& stamp, std::uint32_t& generation) const;
  /// The median distance from each of \a set to its nearest other point (0 for an empty set).
  double medianNearestDistance(const std::vector<int>& set) const;

  /// OpenMP threads for the work done in parallel (parameters.threads, 0: all cores).
  int workers() const;
};

}  // namespace slipfit
