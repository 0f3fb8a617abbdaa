#pragma once
/// \file Scene segmentation into primitives by region growing from local slippage (after Gelfand
/// & Guibas, SGP 2004): seeds where the per-point slippage is confidently one primitive, growth
/// over the shared kNN graph while points agree with the region's weighted fit, refits as regions
/// grow, merging of adjacent regions of one primitive, and label −1 for points that fit nothing.

#include "slipfit/core/angle_units.h"
#include "slipfit/core/parameter_declaration.h"
#include "slipfit/fitting/kinematic_fit.h"
#include "slipfit/fitting/weighted_fit.h"
#include "slipfit/neighborhoods/depth_quantization.h"
#include "slipfit/neighborhoods/neighborhoods.h"
#include "slipfit/slippage/local_slippage.h"
#include "slipfit/slippage/slippage.h"

#include <pcl/PointIndices.h>
#include <pcl/pcl_base.h>

#include <Eigen/Core>

#include <array>
#include <functional>
#include <string>
#include <string_view>

#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

namespace slipfit {

/// What segments may be: the five primitives, or also kinematic surfaces (kinematic_merge.h).
enum class SegmentSurfaces { primitives, kinematic };
constexpr std::array<std::pair<SegmentSurfaces, std::string_view>, 2> kSegmentSurfacesNames{{
    {SegmentSurfaces::primitives, "primitives"},
    {SegmentSurfaces::kinematic, "kinematic"},
}};

struct SegmentationParameters {
  /// Largest point-to-primitive distance of a member, units. Unset: 3 σ̂ + 1/20 of the median
  /// spacing, σ̂ the noise estimated from the lower quartile of the neighborhoods' residuals
  /// (docs/THEORY.md §6).
  std::optional<double> distance;
  /// Largest angle between a member's normal and the primitive's (unsigned), radians; also the
  /// crease angle of two planes (phases 4, 6 and 11).
  double max_angle = 30.0 * kDegree;
  /// Smallest segment, points. Unset: 20 (an absolute count, whatever N).
  std::optional<std::size_t> min_points;
  /// Adjacent segments merge when the fit of their union has an RMS distance at most this factor
  /// times the larger of theirs.
  double merge_factor = 1.5;
  /// Phase 6: fillets that two planes meeting at a crease took whole are given to a cylinder of
  /// their own; false keeps sharp creases only.
  bool fillets = true;
  /// primitives: the five primitives only; kinematic: adjacent segments that one surface of
  /// revolution, extrusion or helix explains become one segment of it (kinematic_merge.h).
  SegmentSurfaces surfaces = SegmentSurfaces::primitives;
  /// OpenMP threads for the fits tried in parallel (the result does not depend on them); 0 means as
  /// many as the machine has.
  int threads = 0;
  /// The cloud is a range sensor's view (an organized scan, or one with a sensor pose): pieces of
  /// one surface that an occluder cut apart are joined (phase 13), as on depth recorded on levels.
  /// Not a YAML option: the pipeline sets it from the input, and SlippageSegmentation from its
  /// cloud (organized, or a sensor_origin_ / sensor_orientation_ other than PCL's defaults).
  bool sensor_view = false;
  /// The cloud's share of a larger one that it is part of (a tile of a tiled run: its points over
  /// the whole cloud's), in (0, 1]: the noise estimate samples that share of the neighborhoods
  /// the whole cloud's would (SegmentationTuning::noise_sample, at least least_noise_sample), so
  /// that a tile samples at the untiled run's density and its local noise pools patches of the
  /// untiled run's size. Not a YAML option: a tiled run sets it for each tile.
  double noise_sample_share = 1.0;

  /// Each user-facing field with its one declaration (parameter_declaration.h).
  template <typename Self, typename Visit>
  static void forEachParameter(Self& self, Visit&& visit) {
    visit(self.distance,
          parameter("distance",
                    "Largest point-to-primitive distance of a member (unset: 3 × the noise "
                    "estimated from the neighborhoods + 1/20 of the median spacing).")
              .in("units")
              .above(0));
    visit(self.max_angle,
          parameter("max_angle",
                    "Largest angle between a member's normal and the primitive's; also the "
                    "crease angle: planes whose normals differ by more meet at a crease (they "
                    "merge only into a curved primitive, and a fillet is sought between them).")
              .in("deg", kDegree)
              .above(0)
              .atMost(90));
    visit(self.min_points,
          parameter("min_points", "Smallest segment (unset: 20).").in("points").between(3, 1e9));
    visit(self.fillets,
          parameter("fillets",
                    "Look for fillets that two planes meeting at a crease took whole as they grew, "
                    "and give their points to a cylinder (false: sharp creases only)."));
    visit(self.merge_factor,
          parameter("merge_factor",
                    "Adjacent segments merge when the best fit of their union has an RMS distance "
                    "at most this factor times the larger of theirs.")
              .between(1, 10));
    visit(self.surfaces,
          parameter("surfaces",
                    "primitives: planes, spheres, cylinders, cones and tori; kinematic: also "
                    "surfaces of revolution, extrusions and helices, where one explains a group "
                    "of adjacent primitive segments that share its axis or direction better than "
                    "they do (docs/THEORY.md §5.5)."),
          kSegmentSurfacesNames);
  }

  /// Throws InvalidParameterError naming the field, its value and its declared range.
  void validate() const;
};

/// One segment: its points and the weighted fit of its primitive (refined on the true distance).
struct Segment {
  std::vector<int> indices;                     ///< cloud indices, ascending
  FitResult fit;                                ///< type, parameters, losses
  SlippageType seed_type = SlippageType::none;  ///< the local slippage type of its seed
  double rms_distance = 0.0;                    ///< RMS point-to-surface distance
  double max_distance = 0.0;                    ///< largest point-to-surface distance
  /// The slippage of the whole segment; its primitive was the second starting point of the
  /// refinement (the better of the two is kept).
  std::optional<SlippageResult> slippage;
  /// A kinematic segment (kinematic_merge.h): the surface of revolution, extrusion or helix that
  /// explains its points, which then count rather than `fit` (the largest member's primitive).
  std::optional<KinematicFit> kinematic;
};

/// Distance from \a p to \a segment's surface: its kinematic surface when it has one, else its
/// refined primitive.
inline double distance(const Eigen::Vector3d& p, const Segment& segment) {
  return segment.kinematic ? distance(p, segment.kinematic->surface)
                           : distance(p, segment.fit.refined);
}

/// The type name of \a segment: its kinematic class or its primitive's type.
inline std::string_view segmentTypeName(const Segment& segment) {
  return segment.kinematic ? kinematicTypeName(segment.kinematic->surface.type)
                           : primitiveTypeName(segment.fit.type);
}

/// The type code of \a segment: its primitive's PrimitiveType (0–4), or 5 + its KinematicType
/// (5 revolution, 6 extrusion, 7 helix) — the codes of the scenes' truth_type.
inline std::int32_t segmentTypeCode(const Segment& segment) {
  return segment.kinematic ? 5 + static_cast<std::int32_t>(segment.kinematic->surface.type)
                           : static_cast<std::int32_t>(segment.fit.type);
}

/// The wall time of one phase of a run (docs/THEORY.md §6; phaseName's names, then
/// "finalize"): where the segmentation spends its time, for the report and the profile script.
/// Not part of the result's content: two runs give the same labels and segments, not the same
/// seconds.
struct PhaseTiming {
  std::string phase;
  double seconds = 0.0;
};

struct SegmentationResult {
  std::vector<std::int32_t> labels;  ///< per point: segment index, −1 unassigned
  std::vector<Segment> segments;     ///< largest first
  double distance = 0.0;  ///< the distance tolerance used (the floor of it, with a lattice)
  /// The coordinate recorded on levels, if any (Kinect-like depth): a point's tolerance is
  /// `distance` plus `step_factor` times the local step there.
  QuantizedAxis lattice;
  double step_factor = 0.0;
  /// The distance tolerance of a point at \a p.
  double tolerance(const Eigen::Vector3d& p) const {
    return distance + step_factor * lattice.stepAt(p);
  }
  /// Whether \a p lies within its tolerance of \a segment's refined primitive (an inlier).
  bool explains(const Segment& segment, const Eigen::Vector3d& p) const {
    return slipfit::distance(p, segment) <= tolerance(p);
  }
  double noise = 0.0;  ///< the noise estimate σ̂ (units)
  /// The 5th and 95th percentiles of the points' own σ (each point's tolerance follows it when
  /// the distance is automatic); both `noise` when the distance was given.
  std::pair<double, double> noise_range{0.0, 0.0};
  /// distance = noise_factor · noise + a floor from the spacing; 0 when the distance was given.
  double noise_factor = 0.0;
  double max_angle = 0.0;         ///< the angle tolerance used, radians
  std::size_t min_points = 0;     ///< the smallest segment allowed
  std::size_t regions_grown = 0;  ///< seeds that were grown (kept or not)
  std::size_t merges = 0;         ///< pairs of segments merged
  /// Regions joined to a neighbor that explains them as well as its own points (fragments of one
  /// surface, absorbFragments).
  std::size_t absorbed = 0;
  std::size_t revised = 0;    ///< regions whose type the contested points changed
  std::size_t fillets = 0;    ///< fillets found at creases of two planes (recoverFillets)
  std::size_t kinematic = 0;  ///< kinematic segments made (surfaces: kinematic)
  /// Regions dropped because their points fill the tolerance slab like random points (RMS
  /// distance above 0.45 ε), not a surface: a cloud of noise gives no segment.
  std::size_t volumes = 0;
  std::vector<PhaseTiming> timings;  ///< each phase run, in order, then finalize
};

/// Segments a cloud (3 × N points and normals, any sign) given each point's neighbors and local
/// slippage type. Deterministic; throws DegenerateInputError on mismatched sizes or an empty
/// cloud.
/// \a on_phase, when given, is called with each phase's name as it starts (a progress display).
SegmentationResult segmentBySlippage(const Eigen::Ref<const Eigen::Matrix3Xd>& points,
                                     const Eigen::Ref<const Eigen::Matrix3Xd>& normals,
                                     const Neighborhoods& neighborhoods,
                                     const std::vector<SlippageType>& local_types,
                                     const SegmentationParameters& parameters = {},
                                     const std::function<void(std::string_view)>& on_phase = {});

/// PCL-style front end: setInputCloud() (a point type with normals), setNeighborhoods() and
/// setLocalSlippage() (both over the whole cloud: LocalSlippage, NeighborhoodSelection), optionally
/// setIndices() (only those points are segmented, and a point's neighbors outside them are
/// ignored), then segment(), which returns one pcl::PointIndices per segment (cloud indices) like
/// pcl::RegionGrowing; result() has labels for every cloud point (−1 outside the indices) and the
/// fits.
template <typename PointT>
class SlippageSegmentation : public pcl::PCLBase<PointT> {
 public:
  using Ptr = std::shared_ptr<SlippageSegmentation<PointT>>;
  void setNeighborhoods(std::shared_ptr<const Neighborhoods> neighborhoods) {
    neighborhoods_ = std::move(neighborhoods);
  }
  void setLocalSlippage(typename pcl::PointCloud<PointSlippage>::ConstPtr slippage) {
    slippage_ = std::move(slippage);
  }
  /// The local slippage types themselves, one per cloud point, instead of LocalSlippage's cloud
  /// (a pipeline that carries them as a typed field).
  void setLocalTypes(std::shared_ptr<const std::vector<SlippageType>> types) {
    types_ = std::move(types);
  }
  /// Checked when the work runs (one validation, PCL's initCompute convention).
  void setParameters(const SegmentationParameters& parameters) { parameters_ = parameters; }
  /// Called with each phase's name as it starts (e.g. to show progress); none by default.
  void setPhaseListener(std::function<void(std::string_view)> listener) {
    on_phase_ = std::move(listener);
  }
  void segment(std::vector<pcl::PointIndices>& clusters);
  const SegmentationResult& result() const { return result_; }
  /// Moves the result out (result() is empty afterwards): no copy of the labels.
  SegmentationResult releaseResult() { return std::move(result_); }

 protected:
  using pcl::PCLBase<PointT>::input_;
  using pcl::PCLBase<PointT>::indices_;

 private:
  std::shared_ptr<const Neighborhoods> neighborhoods_;
  typename pcl::PointCloud<PointSlippage>::ConstPtr slippage_;
  std::shared_ptr<const std::vector<SlippageType>> types_;
  SegmentationParameters parameters_;
  std::function<void(std::string_view)> on_phase_;
  SegmentationResult result_;
};

}  // namespace slipfit

#include "slipfit/segmentation/impl/segmentation.hpp"
