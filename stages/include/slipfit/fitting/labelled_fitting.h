#pragma once
/// \file LabelledFitting: one primitive per label of a cloud (or one to the whole cloud), plain,
/// of the simplest adequate type or robust — fitLabelled (labelled_fit.h) as a PCL-style class.

#include "slipfit/fitting/labelled_fit.h"

#include <pcl/pcl_base.h>
#include <pcl/point_cloud.h>

#include <cstdint>
#include <memory>
#include <vector>

namespace slipfit {

/// PCL style: setInputCloud(), setInputNormals() (needed by cylinders, cones, tori and auto),
/// optionally setIndices(), setWeights(), setLabels(), setParameters() and setSeed(), then
/// compute(). Coordinates are fitted in double precision. The per-point distances of the result
/// are index-aligned with the *cloud*: −1 for points outside the indices or not fitted.
template <typename PointT, typename NormalT = PointT>
class LabelledFitting : public pcl::PCLBase<PointT> {
 public:
  using Ptr = std::shared_ptr<LabelledFitting<PointT, NormalT>>;
  using ConstPtr = std::shared_ptr<const LabelledFitting<PointT, NormalT>>;
  using NormalCloudConstPtr = typename pcl::PointCloud<NormalT>::ConstPtr;

  void setInputNormals(const NormalCloudConstPtr& normals) { normals_ = normals; }
  /// One weight per cloud point (finite, ≥ 0); unset: all 1.
  void setWeights(std::shared_ptr<const std::vector<double>> weights) {
    weights_ = std::move(weights);
  }
  /// One label per cloud point: one primitive per label ≥ 0 (negative and non-finite labels are
  /// left out); unset: one primitive to all the points.
  void setLabels(std::shared_ptr<const std::vector<double>> labels) { labels_ = std::move(labels); }
  /// Checked when the work runs (one validation, PCL's initCompute convention).
  void setParameters(const LabelledFitParameters& parameters) { parameters_ = parameters; }
  /// The seed of the robust fits' random choices.
  void setSeed(std::uint64_t seed) { seed_ = seed; }

  /// Throws InvalidParameterError on mismatched inputs or parameters, DegenerateInputError on an
  /// empty input; a label that cannot be fitted is reported in its LabelledFit.
  void compute(LabelledFits& fits);

 protected:
  using pcl::PCLBase<PointT>::input_;
  using pcl::PCLBase<PointT>::indices_;

 private:
  NormalCloudConstPtr normals_;
  std::shared_ptr<const std::vector<double>> weights_, labels_;
  LabelledFitParameters parameters_;
  std::uint64_t seed_ = 1;
};

}  // namespace slipfit

#include "slipfit/fitting/impl/labelled_fitting.hpp"
