#pragma once
/// \file Normal estimation: pcl::NormalEstimationOMP on shared neighborhoods (or its own k/radius
/// search), followed by the chosen orientation.

#include "slipfit/core/parameter_declaration.h"
#include "slipfit/neighborhoods/neighborhoods.h"
#include "slipfit/neighborhoods/normal_orientation.h"

#include <pcl/pcl_base.h>
#include <pcl/search/search.h>

#include <Eigen/Core>

#include <memory>
#include <optional>

namespace slipfit {

/// Parameters of OrientedNormalEstimation.
struct NormalParameters {
  /// Neighbors per point when no neighborhoods are given. Range [3, 10000]; ignored with radius.
  int k = 16;
  /// Search radius in the cloud's units when no neighborhoods are given; overrides k. (0, ∞).
  std::optional<double> radius;
  NormalOrientation orientation = NormalOrientation::viewpoint;
  /// Viewpoint for NormalOrientation::viewpoint (unset: the origin, where a scanner sits) and the
  /// seed direction for NormalOrientation::consistent (unset: outward from the centroid).
  std::optional<Eigen::Vector3f> viewpoint;
  /// OpenMP threads; 0 means as many as the machine has.
  int threads = 0;

  /// Each user-facing field with its one declaration (parameter_declaration.h).
  template <typename Self, typename Visit>
  static void forEachParameter(Self& self, Visit&& visit) {
    visit(self.k,
          parameter("k",
                    "Neighbors per point when no earlier neighborhood_selection stage shared its "
                    "neighborhoods (or use_shared is false).")
              .in("points")
              .between(3, 10000));
    visit(self.radius, parameter("radius", "Search radius instead of k, under the same condition.")
                           .in("cloud units")
                           .above(0));
    visit(self.orientation,
          parameter("orientation",
                    "viewpoint: normals face the viewpoint; reference: keep the sign of the "
                    "input's own normals; consistent: minimum-spanning-tree propagation (Hoppe et "
                    "al. 1992), outward on closed surfaces; sensor: normals face the input's "
                    "sensor (a PCD's VIEWPOINT or an organized cloud's camera, PCL's "
                    "sensor_origin_), and the viewpoint when the input has no sensor pose."),
          kNormalOrientationNames);
    visit(self.viewpoint,
          parameter("viewpoint",
                    "Viewpoint for 'viewpoint' and for 'sensor' on an input without a sensor "
                    "pose (unset: the origin) and, when set, the seed direction for 'consistent' "
                    "(unset: outward from the centroid).")
              .in("cloud units"));
  }

  /// Throws InvalidParameterError naming the field, its value and the broken constraint.
  void validate() const;
};

struct NormalStatistics {
  std::size_t estimated = 0;          ///< normals computed
  std::size_t failed = 0;             ///< points left NaN (non-finite, or fewer than 3 neighbors)
  std::size_t flipped = 0;            ///< normals flipped by the orientation step
  std::size_t components = 0;         ///< graph components seeded (consistent orientation only)
  bool reused_neighborhoods = false;  ///< true when shared neighborhoods were used (no search)
};

/// Estimates oriented normals, PCL style.
///
/// Set the input with setInputCloud() (and setIndices()), optionally setNeighborhoods() with
/// lists computed by NeighborhoodSelection for the same cloud — then no search is made — and call
/// compute(). The output is index-aligned with the indices; PointOutT needs normal_x/y/z (and gets
/// curvature, the surface variation λ₀/(λ₀+λ₁+λ₂), when it has that field). A point whose normal
/// cannot be estimated gets NaN and the output's is_dense becomes false.
template <typename PointInT, typename PointOutT>
class OrientedNormalEstimation : public pcl::PCLBase<PointInT> {
 public:
  using Ptr = std::shared_ptr<OrientedNormalEstimation<PointInT, PointOutT>>;
  using ConstPtr = std::shared_ptr<const OrientedNormalEstimation<PointInT, PointOutT>>;
  using SearchPtr = typename pcl::search::Search<PointInT>::Ptr;

  /// Checked when the work runs (one validation, PCL's initCompute convention).
  void setParameters(const NormalParameters& parameters) { parameters_ = parameters; }
  const NormalParameters& getParameters() const { return parameters_; }

  /// Neighborhoods of the input cloud's points (one list per cloud point), used instead of
  /// k/radius.
  void setNeighborhoods(std::shared_ptr<const Neighborhoods> neighborhoods) {
    neighborhoods_ = std::move(neighborhoods);
  }
  /// Search structure for k/radius neighborhoods when none are given (default: a new
  /// NanoflannSearch, a kd-tree).
  void setSearchMethod(const SearchPtr& search) { search_ = search; }
  /// Reference normals for NormalOrientation::reference, one column per *cloud* point.
  void setReferenceNormals(std::shared_ptr<const Eigen::Matrix3Xf> reference) {
    reference_ = std::move(reference);
  }

  /// Throws DegenerateInputError (empty input, mismatched neighborhoods, missing reference) or
  /// InvalidParameterError.
  void compute(pcl::PointCloud<PointOutT>& output);

  const NormalStatistics& statistics() const { return statistics_; }

 protected:
  using pcl::PCLBase<PointInT>::input_;
  using pcl::PCLBase<PointInT>::indices_;

 private:
  NormalParameters parameters_;
  std::shared_ptr<const Neighborhoods> neighborhoods_;
  std::shared_ptr<const Eigen::Matrix3Xf> reference_;
  SearchPtr search_;
  NormalStatistics statistics_;
};

}  // namespace slipfit
