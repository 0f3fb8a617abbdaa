#pragma once
/// \file Growth of one region of a segmentation over the shared neighborhood graph, bounded by the
/// region's own fit: a point joins when it lies within its distance tolerance of the primitive and
/// its normal within the angle tolerance of the primitive's there. Used by SegmentationKernel.

#include "slipfit/fitting/weighted_fit.h"
#include "slipfit/neighborhoods/neighborhoods.h"

#include <Eigen/Core>

#include <cstdint>
#include <vector>

namespace slipfit {

class RegionGrower {
 public:
  /// Fits see an evenly strided subset of at most this many members while a region grows or
  /// merges (statistically plenty: the final fit of each segment uses every member).
  static constexpr std::size_t kSubset = 20000;
  /// Choosing the type fits every type: an evenly strided 2,000 members decide it as well (the
  /// RMS of each type is estimated to ~2 % from 2,000 residuals, far below the 25 % margin of
  /// adequacy), and the chosen type is then refitted on up to kSubset.
  static constexpr std::size_t kTypeSubset = 2000;

  /// \a points, \a normals: 3 × N (normals of either sign; both must outlive the grower);
  /// \a tolerance: per point, the largest distance of a member (units); \a max_angle: radians.
  RegionGrower(const Eigen::Ref<const Eigen::Matrix3Xd>& points,
               const Eigen::Ref<const Eigen::Matrix3Xd>& normals, const Neighborhoods& hoods,
               std::vector<double> tolerance, double max_angle);

  /// Point \a i's distance tolerance.
  double tolerance(int i) const { return tolerance_[static_cast<std::size_t>(i)]; }
  /// The smallest tolerance of \a members (+inf for none).
  double smallestTolerance(const std::vector<int>& members) const;
  /// Point \a i lies within its tolerance of \a primitive.
  bool near(int i, const Primitive& primitive) const;
  /// Near, and the normals agree within the angle tolerance.
  bool accepts(int i, const Primitive& primitive) const;

  /// Fits \a type to the members; with \a all false, to an evenly strided subset of at most
  /// kSubset of them.
  FitResult fit(PrimitiveType type, const std::vector<int>& members, bool all = false) const;
  /// Fits \a type to an evenly strided subset of at most kTypeSubset members: a candidate of a
  /// type choice, refitted with fit() once chosen.
  FitResult screen(PrimitiveType type, const std::vector<int>& members) const;
  /// Each member's weight (t_min / t_i)², t_i its tolerance and t_min the smallest of the
  /// members': 1 for all when the tolerances are equal.
  Eigen::VectorXd precisionWeights(const std::vector<int>& members) const;
  /// Fits \a type to all the members, each weighing 1 / tolerance² (relative to the members'
  /// smallest): where the tolerance follows the noise (depth recorded on levels that grow with z²)
  /// that is the inverse-variance weight of least squares; with one tolerance for all members,
  /// every weight is 1 and this is fit(type, members, true).
  FitResult fitByPrecision(PrimitiveType type, const std::vector<int>& members) const;
  /// \a start's type refined from \a start on an evenly strided subset of at most kTypeSubset
  /// members (as fitBest's candidates): a trial of regions as one where one region's primitive
  /// is already near the union's. Failed (degenerate) when the result lies in a simpler type's
  /// limit, as fitBest drops such candidates.
  FitResult fitNear(const Primitive& start, const std::vector<int>& members) const;
  /// Whether a type simpler than \a type (fewer parameters) explains an evenly strided subset of
  /// at most kTypeSubset members within the margin of adequacy of \a rms (model_selection.h), out
  /// of its flat limit: fitBest could then choose it over a fit of \a type with that RMS.
  bool simplerTypeIsAdequate(PrimitiveType type, double rms, const std::vector<int>& members) const;
  /// The simplest adequate type for the members (with \a refine false: closed forms only, a
  /// quick look at a seed's neighborhood).
  FitResult fitBest(const std::vector<int>& members, bool refine = true) const;
  /// Median distance of the (strided) members to \a primitive.
  double medianDistance(const std::vector<int>& members, const Primitive& primitive) const;

  /// Grows from \a members (kept) over points with a negative label that the fit accepts,
  /// refitting each time the region doubles. Returns the final fit (type fixed).
  FitResult grow(PrimitiveType type, std::vector<int>& members, FitResult fit,
                 const std::vector<std::int32_t>& labels);
  /// Keeps the members the fit accepts.
  void prune(std::vector<int>& members, const Primitive& primitive) const;

 private:
  void gather(const std::vector<int>& members, bool all, Eigen::Matrix3Xd& p, Eigen::Matrix3Xd& n,
              std::size_t subset) const;

  Eigen::Ref<const Eigen::Matrix3Xd> points_;  // views: the arrays outlive the object
  Eigen::Ref<const Eigen::Matrix3Xd> normals_;
  const Neighborhoods& hoods_;
  std::vector<double> tolerance_;
  double cos_angle_;
  std::vector<std::uint32_t> stamp_;
  std::uint32_t generation_ = 0;
};

}  // namespace slipfit
