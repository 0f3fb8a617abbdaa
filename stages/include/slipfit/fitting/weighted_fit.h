#pragma once
/// \file Closed-form weighted estimators of planes, spheres, cylinders and cones (the SPFN
/// estimators of Li, Sung, Dubrovina, Yi, Guibas, CVPR 2019), refinement on the true geometric
/// distance, and automatic type selection. Inputs: 3 × N points, 3 × N normals (cylinder, cone),
/// N non-negative weights.
/// Normals are needed by the cylinder, cone and torus. Derivations: docs/THEORY.md §4.

#include "slipfit/core/parameter_declaration.h"
#include "slipfit/fitting/primitives.h"

#include <Eigen/Core>

#include <string>

namespace slipfit {

enum class FitStatus {
  ok,
  too_few_points,  ///< fewer points with positive weight than the type needs
  zero_weight,     ///< all weights are zero
  invalid_input,   ///< sizes differ, a NaN/inf value, a negative weight
  degenerate       ///< the data do not determine the primitive (collinear, coplanar for a sphere,
                   ///< parallel normals, ...)
};
constexpr std::array<std::pair<FitStatus, std::string_view>, 5> kFitStatusNames{{
    {FitStatus::ok, "ok"},
    {FitStatus::too_few_points, "too_few_points"},
    {FitStatus::zero_weight, "zero_weight"},
    {FitStatus::invalid_input, "invalid_input"},
    {FitStatus::degenerate, "degenerate"},
}};
std::string_view fitStatusName(FitStatus status);

/// Minimum number of points with positive weight per type: 3, 4, 5, 6, 7.
int minimumPoints(PrimitiveType type);

/// The outcome of one fit. Parameters are meaningful only when status == ok (they are never NaN).
struct FitResult {
  PrimitiveType type = PrimitiveType::plane;
  FitStatus status = FitStatus::ok;
  std::string reason;   ///< why the fit failed, or "" when ok
  Primitive algebraic;  ///< the closed-form estimate
  Primitive refined;    ///< after refinement on the geometric distance (= algebraic without)
  double loss_algebraic = 0.0;  ///< Σ wᵢ D²(pᵢ, algebraic)
  double loss_refined = 0.0;    ///< Σ wᵢ D²(pᵢ, refined) ≤ loss_algebraic
  double rms_distance = 0.0;    ///< sqrt(loss_refined / Σ wᵢ)
  double max_distance = 0.0;    ///< max D over points with positive weight
  std::size_t used_points = 0;  ///< points with positive weight
  double reciprocal_condition =
      1.0;  ///< of the closed form's linear system, in (0, 1]; small means ill-conditioned
  int iterations = 0;  ///< refinement iterations
  bool ok() const { return status == FitStatus::ok; }
};

struct FitOptions {
  bool refine = true;
  int max_iterations = 100;
  /// Below this reciprocal condition number the closed form is declared degenerate.
  double degenerate_rcond = 1e-10;

  /// Each user-facing field with its one declaration (parameter_declaration.h).
  template <typename Self, typename Visit>
  static void forEachParameter(Self& self, Visit&& visit) {
    visit(self.refine, parameter("refine",
                                 "Refine the closed-form estimate on the true geometric distance "
                                 "(Levenberg–Marquardt)."));
    visit(self.max_iterations,
          parameter("max_iterations", "Refinement iterations at most.").between(1, 10000));
  }

  /// Throws InvalidParameterError naming the field, its value and its declared range
  /// (degenerate_rcond: [0, 1)).
  void validate() const;
};

/// Closed-form estimates (no refinement, and no loss: loss_* and the distances are filled by
/// fitPrimitive). Plane and sphere read the data once. Normals need not be unit length or
/// consistently signed.
FitResult estimatePlane(const Eigen::Ref<const Eigen::Matrix3Xd>& points,
                        const Eigen::Ref<const Eigen::VectorXd>& weights,
                        const FitOptions& options = {});
FitResult estimateSphere(const Eigen::Ref<const Eigen::Matrix3Xd>& points,
                         const Eigen::Ref<const Eigen::VectorXd>& weights,
                         const FitOptions& options = {});
FitResult estimateCylinder(const Eigen::Ref<const Eigen::Matrix3Xd>& points,
                           const Eigen::Ref<const Eigen::Matrix3Xd>& normals,
                           const Eigen::Ref<const Eigen::VectorXd>& weights,
                           const FitOptions& options = {});
FitResult estimateCone(const Eigen::Ref<const Eigen::Matrix3Xd>& points,
                       const Eigen::Ref<const Eigen::Matrix3Xd>& normals,
                       const Eigen::Ref<const Eigen::VectorXd>& weights,
                       const FitOptions& options = {});
/// Cone from its axis: the line that meets every normal line (as the torus's, below), then the
/// generator line ρ = α z + β of (height along the axis, distance from it). A second start for
/// fitPrimitive where estimateCone's apex — the point nearest every tangent plane — is ill-posed:
/// a patch of a wide cone seen from one side, whose tangent planes are nearly parallel.
FitResult estimateConeAboutAxis(const Eigen::Ref<const Eigen::Matrix3Xd>& points,
                                const Eigen::Ref<const Eigen::Matrix3Xd>& normals,
                                const Eigen::Ref<const Eigen::VectorXd>& weights,
                                const FitOptions& options = {});

/// Cylinder from its axis: the line that meets every normal line (as the torus's, below; a
/// cylinder's normal lines also all meet the line at infinity along its axis, which leaves the
/// direction and the axis point determined), the radius the points' mean distance from it. A
/// second start for fitPrimitive where estimateCylinder's axis — the direction every normal is
/// perpendicular to — is ill-posed: a narrow band of a wide cylinder, whose normals barely turn.
FitResult estimateCylinderAboutAxis(const Eigen::Ref<const Eigen::Matrix3Xd>& points,
                                    const Eigen::Ref<const Eigen::Matrix3Xd>& normals,
                                    const Eigen::Ref<const Eigen::VectorXd>& weights,
                                    const FitOptions& options = {});

/// Torus: the axis is the line that meets every normal line (least squares in Plücker
/// coordinates, normalised), the major radius, height and minor radius the algebraic circle fit
/// of (distance from the axis, height) — docs/THEORY.md §4. Degenerate for a sphere, plane or
/// cylinder (the axis is not determined) and when the circle centre is not off the axis.
FitResult estimateTorus(const Eigen::Ref<const Eigen::Matrix3Xd>& points,
                        const Eigen::Ref<const Eigen::Matrix3Xd>& normals,
                        const Eigen::Ref<const Eigen::VectorXd>& weights,
                        const FitOptions& options = {});

/// Closed form, then (options.refine) Levenberg–Marquardt on Σ wᵢ D²; the refined loss never
/// exceeds the algebraic one. \a normals may be empty (0 columns) for plane and sphere.
FitResult fitPrimitive(PrimitiveType type, const Eigen::Ref<const Eigen::Matrix3Xd>& points,
                       const Eigen::Ref<const Eigen::Matrix3Xd>& normals,
                       const Eigen::Ref<const Eigen::VectorXd>& weights,
                       const FitOptions& options = {});

/// Refines \a initial on Σ wᵢ D²(pᵢ, A) in normalised coordinates; returns the better of the two.
Primitive refinePrimitive(const Primitive& initial,
                          const Eigen::Ref<const Eigen::Matrix3Xd>& points,
                          const Eigen::Ref<const Eigen::VectorXd>& weights, int max_iterations,
                          int* iterations = nullptr);

/// The fit of \a start's type to the points, refined from \a start (no closed form): a warm start
/// where a nearby primitive is known, e.g. the larger region's when two regions are tried as one.
/// The result's algebraic primitive is \a start; its losses and distances are those of
/// fitPrimitive. Fails (invalid_input, too_few_points) as fitPrimitive does.
FitResult fitFrom(const Primitive& start, const Eigen::Ref<const Eigen::Matrix3Xd>& points,
                  const Eigen::Ref<const Eigen::VectorXd>& weights, const FitOptions& options = {});

/// Fits every type (those that need normals only when \a normals has one per point) and keeps
/// the simplest adequate one (model_selection.h: within 25 % of the best RMS distance, plus a
/// floor of 1e-7 of the data's size and distance from the origin for noise-free float data), so
/// that a more complex type must explain the data clearly better and the degenerate limits (a
/// cylinder of huge radius, a cone near 90°, a torus of huge R) come out as the simpler type.
/// Failed fits are skipped; the result is failed only if all fail.
FitResult fitAuto(const Eigen::Ref<const Eigen::Matrix3Xd>& points,
                  const Eigen::Ref<const Eigen::Matrix3Xd>& normals,
                  const Eigen::Ref<const Eigen::VectorXd>& weights, const FitOptions& options = {});

}  // namespace slipfit
