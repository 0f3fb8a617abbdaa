#pragma once
/// \file Robust wrappers around the weighted estimators: RANSAC hypotheses (seeded) and iteratively
/// reweighted least squares with Tukey's biweight, so that outliers stop pulling the fit.

#include "slipfit/core/parameter_declaration.h"
#include "slipfit/fitting/weighted_fit.h"

#include <cstdint>
#include <optional>
#include <string_view>
#include <vector>

namespace slipfit {

enum class RobustMethod {
  none,   ///< the plain weighted fit
  irls,   ///< Tukey-biweight reweighting from the plain fit (moderate outliers)
  ransac  ///< best of seeded minimal-sample hypotheses, then IRLS (many outliers)
};
constexpr std::array<std::pair<RobustMethod, std::string_view>, 3> kRobustMethodNames{{
    {RobustMethod::none, "none"},
    {RobustMethod::irls, "irls"},
    {RobustMethod::ransac, "ransac"},
}};

struct RobustOptions {
  RobustMethod method = RobustMethod::irls;
  /// Inlier distance. Unset: 2.5 × the robust residual scale 1.4826 · median |D| (of the best
  /// RANSAC hypothesis, or of the plain fit for IRLS).
  std::optional<double> threshold;
  int irls_iterations = 30;
  int ransac_iterations = 300;
  std::uint64_t seed = 1;

  /// Each user-facing field with its one declaration (parameter_declaration.h).
  template <typename Self, typename Visit>
  static void forEachParameter(Self& self, Visit&& visit) {
    visit(self.threshold,
          parameter("threshold",
                    "Inlier distance of the robust fit (unset: 2.5 × the robust residual scale).")
              .in("units")
              .above(0));
    visit(self.ransac_iterations,
          parameter("ransac_iterations", "RANSAC hypotheses.").between(1, 1000000));
  }

  /// Throws InvalidParameterError naming the field, its value and its declared range (and at
  /// least one IRLS iteration).
  void validate() const;
};

/// Fits \a type robustly. The returned fit is computed on the final weights wᵢ·ψᵢ (ψ the biweight);
/// \a inliers (optional) gets 1 for points within the final inlier distance, which is returned in
/// *inlier_distance.
FitResult fitRobust(PrimitiveType type, const Eigen::Ref<const Eigen::Matrix3Xd>& points,
                    const Eigen::Ref<const Eigen::Matrix3Xd>& normals,
                    const Eigen::Ref<const Eigen::VectorXd>& weights, const RobustOptions& robust,
                    const FitOptions& options = {}, std::vector<char>* inliers = nullptr,
                    double* inlier_distance = nullptr);

/// The robust fit of every type the data allow (cylinder, cone and torus need normals), and of
/// those the one with the most inlier weight within a common distance — the smallest of the types'
/// own inlier distances, so that a poor type cannot win by estimating a wide residual scale; within
/// 1 % of that weight, the type with fewer parameters. A type in its degenerate limit
/// (isNearlyDegenerate: a sphere of radius 76 m over a 1 m table) is left to its simpler type.
/// \a inlier_distance gets the common distance. Status degenerate when no type fits.
FitResult fitRobustAuto(const Eigen::Ref<const Eigen::Matrix3Xd>& points,
                        const Eigen::Ref<const Eigen::Matrix3Xd>& normals,
                        const Eigen::Ref<const Eigen::VectorXd>& weights,
                        const RobustOptions& robust, const FitOptions& options = {},
                        double* inlier_distance = nullptr);

}  // namespace slipfit
