#pragma once
/// \file One primitive fitted per label of a cloud (or one to the whole cloud): the kernel of the
/// primitive_fitting stage. The fit is the plain weighted fit of a type, fitAuto's choice of the
/// simplest adequate type, or a robust fit (robust_fit.h); each fit's inliers are counted at a
/// stated tolerance: the one given, else the robust fit's threshold, else 3 × the surface noise
/// measured from the fit's points (surface_noise.h), never the fit's own RMS.

#include "slipfit/core/parameter_declaration.h"
#include "slipfit/fitting/robust_fit.h"
#include "slipfit/fitting/weighted_fit.h"

#include <Eigen/Core>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace slipfit {

struct LabelledFitParameters {
  std::optional<PrimitiveType> type;  ///< unset: fitAuto's choice
  FitOptions fit;
  std::optional<double> inlier_distance;  ///< unset: see the file comment
  int min_points = 10;                    ///< labels with fewer points are reported, not fitted
  /// Unset: ransac for a whole-cloud fit (a scan holds several surfaces and outliers), none per
  /// label. `robust.method` is ignored: this decides.
  std::optional<RobustMethod> robust_method;
  RobustOptions robust;

  /// Each user-facing field with its one declaration (parameter_declaration.h).
  template <typename Self, typename Visit>
  static void forEachParameter(Self& self, Visit&& visit) {
    visit(self.type,
          parameter("primitive",
                    "Primitive to fit; auto fits every type and keeps the simplest adequate one "
                    "(RMS within 25 % of the best, flat limits recognised: docs/THEORY.md §4.4), "
                    "as the segmentation and the whole-cloud classification do."),
          "auto", kPrimitiveTypeNames);
    FitOptions::forEachParameter(self.fit, visit);
    visit(self.inlier_distance,
          parameter("inlier_distance",
                    "Points within this distance count as inliers (unset: a robust fit's own "
                    "threshold, else 3 × the surface noise measured from each fit's points, "
                    "surface_noise.h; never the fit's own RMS, which would call most points of "
                    "any fit inliers).")
              .in("units")
              .above(0));
    visit(self.min_points,
          parameter("min_points", "Labels with fewer points are reported, not fitted.")
              .in("points")
              .between(3, 1e9));
    visit(self.robust_method,
          parameter("robust",
                    "auto: ransac for a whole-cloud fit (a scan holds more than one surface and "
                    "outliers), none per label; none: plain weighted fit; irls: Tukey-biweight "
                    "reweighting; ransac: best of seeded minimal-sample hypotheses, then irls. "
                    "Robust with primitive auto: the type with the most inliers wins (within 1 "
                    "%, the simpler one)."),
          "auto", kRobustMethodNames);
    RobustOptions::forEachParameter(self.robust, visit);
  }

  /// The robust method of a whole-cloud fit (\a whole_cloud) or of a per-label one.
  RobustMethod robustMethod(bool whole_cloud) const {
    return robust_method.value_or(whole_cloud ? RobustMethod::ransac : RobustMethod::none);
  }

  /// Throws InvalidParameterError naming the field.
  void validate() const;
};

/// The fit of one label (or of the whole cloud).
struct LabelledFit {
  std::optional<int> label;  ///< unset: the whole cloud
  FitResult fit;             ///< status too_few_points (with the reason) below min_points
  int points = 0;            ///< members with positive weight
  int inliers = 0;           ///< of those, within inlier_distance of the refined fit
  double inlier_distance = 0.0;
  std::string tolerance_source;         ///< where inlier_distance came from, in words
  std::optional<double> surface_noise;  ///< when the tolerance was measured from the points
};

struct LabelledFits {
  std::vector<LabelledFit> fits;  ///< by ascending label; one when the cloud is unlabelled
  std::vector<float> distance;    ///< per point, to its fit's refined primitive; −1: not fitted
};

/// Fits 3 × N \a points (with 3 × N \a normals, or 3 × 0) weighted by \a weights (N, ≥ 0): one
/// primitive per label ≥ 0 of \a labels (N; negative and non-finite labels are left out), or one
/// to all points when \a labels is empty. \a seed: the robust fits' random choices.
LabelledFits fitLabelled(const Eigen::Ref<const Eigen::Matrix3Xd>& points,
                         const Eigen::Ref<const Eigen::Matrix3Xd>& normals,
                         const std::vector<double>& weights, const std::vector<double>& labels,
                         const LabelledFitParameters& parameters, std::uint64_t seed);

}  // namespace slipfit
