#pragma once
/// \file PrimitiveFitting: the weighted estimators as a PCL-style class, and the conversion of
/// slipfit's primitives into PCL's SAC model coefficient layouts.

#include "slipfit/fitting/weighted_fit.h"

#include <pcl/ModelCoefficients.h>
#include <pcl/pcl_base.h>
#include <pcl/point_cloud.h>

#include <memory>
#include <optional>
#include <vector>

namespace slipfit {

/// Fits one primitive to a cloud (or its indexed subset), PCL style: setInputCloud(),
/// setInputNormals() (cylinder, cone, auto), optionally setIndices() and setWeights(), then fit().
/// Coordinates are fitted in double precision.
template <typename PointT, typename NormalT = PointT>
class PrimitiveFitting : public pcl::PCLBase<PointT> {
 public:
  using Ptr = std::shared_ptr<PrimitiveFitting<PointT, NormalT>>;
  using ConstPtr = std::shared_ptr<const PrimitiveFitting<PointT, NormalT>>;
  using NormalCloudConstPtr = typename pcl::PointCloud<NormalT>::ConstPtr;

  void setInputNormals(const NormalCloudConstPtr& normals) { normals_ = normals; }
  /// One weight per *cloud* point, ≥ 0; unset: all 1.
  void setWeights(std::shared_ptr<const std::vector<float>> weights) {
    weights_ = std::move(weights);
  }
  /// The type to fit; unset (the default): all four, chosen by fitAuto's criterion.
  void setType(std::optional<PrimitiveType> type) { type_ = type; }
  void setOptions(const FitOptions& options) { options_ = options; }

  /// Throws DegenerateInputError (with the reason) when the fit fails, InvalidParameterError on
  /// mismatched inputs.
  FitResult fit();

 protected:
  using pcl::PCLBase<PointT>::input_;
  using pcl::PCLBase<PointT>::indices_;

 private:
  NormalCloudConstPtr normals_;
  std::shared_ptr<const std::vector<float>> weights_;
  std::optional<PrimitiveType> type_;
  FitOptions options_;
};

/// PCL's coefficient layouts: SACMODEL_PLANE [a b c d] with ax + by + cz + d = 0;
/// SACMODEL_SPHERE [cx cy cz r]; SACMODEL_CYLINDER [point on axis, axis direction, radius];
/// SACMODEL_CONE [apex, axis direction (into the opening), half opening angle in radians];
/// SACMODEL_TORUS (PCL ≥ 1.15) [major radius, minor radius, centre, axis direction].
pcl::ModelCoefficients toModelCoefficients(const Primitive& primitive);

}  // namespace slipfit
