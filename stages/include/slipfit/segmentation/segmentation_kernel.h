#pragma once
/// \file The segmentation kernel as named phases, apart from its PCL front end
/// (SlippageSegmentation, segmentation.h). segmentBySlippage runs them in this order:
///
/// 1. estimateScale — noise σ̂ (on each point's own sheet where a thin wall puts both faces in its
///    neighborhood), spacing, a quantized depth axis → each point's distance tolerance;
/// 2. growSlippageSeeds — seeding where the neighbors agree on the local slippage type, growth
///    bounded by the region's own fit, the type re-chosen on the grown region (selection);
/// 3. growFreeSeeds — a second seeding round from the points still free (small faces whose
///    neighborhoods all straddle an edge), with the simplest adequate type of the seed's neighbors;
///    a seed's free neighbors must be sampled like the regions around them (isScattered: not
///    outliers scattered through the volume); on a wall about as thick as the spacing, the seed's
///    own sheet of its free 2-ring is its neighborhood;
/// 4. mergeRegions — adjacent regions whose union one primitive fits about as well;
/// 5. reviseTypes — a region's type re-chosen on the points of its neighbors it contests (the
///    band of a tangent fillet that read as a plane);
/// 5b. recoverFillets — two planes meeting at a crease whose points a fillet between them explains
///    better (its radius fitted on the cross-section, the gain weighed against its parameters)
///    give the fillet's points to a cylinder: a fillet of a few tens of σ lies mostly within the
///    planes' tolerance, and they take it whole as they grow;
/// 6. refineBoundaries — points that a neighboring segment's primitive explains better move;
/// 7. joinCreases — free points at creases join the nearest adjacent primitive within tolerance;
/// 8. recoverSmallFaces — a patch of free points that no adjacent primitive explains is a face too
///    small to seed (a hole's wall, a narrow fillet): fitted with the edge points it shares, when
///    it is sampled like the regions around it (isScattered);
/// 9. absorbFragments — a region that a neighbor four times its size explains as well as that
///    neighbor's own points joins it (specks of one noisy surface that grew apart);
/// 10. mergeSettledRegions — adjacent regions merge again, now that boundaries and creases have
///    settled, when one primitive fits their union no worse than the worse of the two;
/// 11. dropNonSurfaces — regions that fill their tolerance slab like random points, or lie on one
///     level of a quantized axis, are dropped;
/// 12. finalize — largest first, every segment refitted on all its members.
///
/// Each phase can be run and inspected on its own (regions()), which is how the tests look inside.
/// The design and its figures: docs/THEORY.md §6.

#include "slipfit/segmentation/region_grower.h"
#include "slipfit/segmentation/segmentation.h"

#include <Eigen/Core>

#include <cstdint>
#include <initializer_list>
#include <optional>
#include <set>
#include <vector>

namespace slipfit {

class SegmentationKernel {
 public:
  /// Checks the inputs (sizes, finite normals, parameters); throws DegenerateInputError or
  /// InvalidParameterError. The arrays must outlive the kernel.
  SegmentationKernel(const Eigen::Ref<const Eigen::Matrix3Xd>& points,
                     const Eigen::Ref<const Eigen::Matrix3Xd>& normals,
                     const Neighborhoods& neighborhoods,
                     const std::vector<SlippageType>& local_types,
                     const SegmentationParameters& parameters);

  /// The phases, in the order segmentBySlippage runs them (docs/THEORY.md §6).
  enum class Phase {
    estimate_scale,
    grow_slippage_seeds,
    grow_free_seeds,
    merge_regions,
    revise_types,
    recover_fillets,
    refine_boundaries,
    join_creases,
    recover_small_faces,
    absorb_fragments,
    merge_settled_regions,
    drop_non_surfaces,
  };
  /// Runs one phase.
  void run(Phase phase);
  /// Runs the phases from \a first to \a last in their order, except those in \a skip.
  void runPhases(Phase first, Phase last, std::initializer_list<Phase> skip = {});

  void estimateScale();
  void growSlippageSeeds();
  void growFreeSeeds();
  void mergeRegions();
  void reviseTypes();
  void recoverFillets();
  void refineBoundaries();
  void joinCreases();
  void recoverSmallFaces();
  void absorbFragments();
  void mergeSettledRegions();
  void dropNonSurfaces();
  /// Ends the run: the result with its segments largest first.
  SegmentationResult finalize();

  /// The regions so far (empty member lists are regions dropped or merged away).
  const std::vector<std::vector<int>>& regions() const { return regions_; }
  /// Each region's fit so far (that of a region dropped or merged away is stale).
  const std::vector<FitResult>& fits() const { return fits_; }
  /// The tolerances and counters so far (segments are filled by finalize()).
  const SegmentationResult& progress() const { return result_; }

 private:
  void growRegion(PrimitiveType type, std::vector<int> members, SlippageType seed_type,
                  bool type_chosen);
  /// A new region of \a members (their labels set to it).
  void addRegion(std::vector<int> members, FitResult fit, SlippageType seed_type);
  void relabelFromRegions();
  /// Merges adjacent regions, round after round: while the union's best fit has an RMS distance
  /// at most merge_factor × the larger of the two regions' (two planes at a crease: below both),
  /// or, \a settled, while unionIsSimpler.
  void mergeAdjacent(bool settled);
  /// One primitive of the larger region's type (\a joint) is the better model of regions a and b
  /// together than each region's own, by the Bayesian information criterion.
  bool unionIsSimpler(std::size_t a, std::size_t b, const FitResult& joint) const;
  /// For each live region, the regions its points have among their neighbors.
  std::vector<std::set<std::size_t>> touchingRegions() const;
  /// The best fit of regions a and b together, or nullopt when the larger (4 × the other) does
  /// not hold half of the smaller's points. Reads only.
  std::optional<FitResult> tryMerge(std::size_t a, std::size_t b) const;
  void shareEdges();
  void drop(std::size_t region);
  /// Angle between point i's normal and \a primitive's at it (unsigned), radians.
  double normalAngle(int i, const Primitive& primitive) const;
  /// Each live region's median nearest-neighbour distance (0 for the dead ones).
  std::vector<double> regionSpacings() const;
  /// The points \a set (free) lie further apart than kScattered × the points of the densest region
  /// among \a spacings (indexed by region; regions beyond it do not count) that holds a neighbor
  /// of theirs, or than the cloud's points when none does: scattered points, not a surface.
  /// \a stamp marks the set with a fresh \a generation.
  bool isScattered(const std::vector<int>& set, const std::vector<double>& spacings,
                   std::vector<std::uint32_t>& stamp, std::uint32_t& generation) const;
  /// RMS distance of \a members to \a primitive, each distance scaled by the members' smallest
  /// tolerance over its own (the RMS distance when all tolerances are equal).
  double precisionRms(const std::vector<int>& members, const Primitive& primitive) const;

  Eigen::Ref<const Eigen::Matrix3Xd> points_;  // views: the arrays outlive the object
  Eigen::Ref<const Eigen::Matrix3Xd> normals_;
  const Neighborhoods& hoods_;
  const std::vector<SlippageType>& local_types_;
  SegmentationParameters parameters_;
  std::size_t n_ = 0;

  SegmentationResult result_;  ///< tolerances, counters and the point labels
  std::optional<RegionGrower> grower_;
  std::vector<char> tried_;
  std::vector<std::vector<int>> regions_;
  std::vector<FitResult> fits_;
  std::vector<SlippageType> seed_types_;
  std::vector<char> alive_;
  double edge_margin_ = 0.0;  ///< distances within this are a tie (shareEdges), units
  double spacing_ = 0.0;      ///< the median nearest-neighbour distance, units
};

}  // namespace slipfit
