#pragma once
/// \file The torus (sqrt(x² + y²) − R)² + z² = r², 0 < r < R, about the z axis, as four rational
/// biquadratic Bézier quarter patches (Q = tan(α/2), T = tan(β/2)) and as a standard 9 × 9 NURBS
/// net. The derivation is in docs/THEORY.md §3.
///
/// Angles: α around the tube (α = 0 on the outer equator, π/2 on top), β around the z axis:
/// X = ((R + r cos α) cos β, (R + r cos α) sin β, r sin α).

#include "slipfit/surfaces/nurbs_surface.h"
#include "slipfit/surfaces/rational_bezier_patch.h"

#include <Eigen/Core>

#include <array>
#include <vector>

namespace slipfit {

struct TorusShape {
  double R = 1.0;   ///< centre-circle radius
  double r = 0.25;  ///< tube radius, 0 < r < R
  /// Throws InvalidParameterError unless 0 < r < R and both are finite.
  void validate() const;
};

/// Quarter k ∈ {0, 1, 2, 3} covers α ∈ [0, π] or [π, 2π] and β ∈ [0, π] or [π, 2π]:
/// bit 0 of k set means z < 0 (α ≥ π), bit 1 set means y < 0 (β ≥ π). Quarter 0 is Y > 0, Z > 0.
/// Its sites come from quarter 0's by the reflections z → −z and y → −y.
RationalBezierPatch torusQuarterPatch(const TorusShape& torus, int quarter);

/// The 9 homogeneous sites [w; x; y; z] of quarter 0, row-major (i along Q, j along T):
/// the zero site is index 4.
std::array<HomogeneousPoint, 9> torusQuarterSites(const TorusShape& torus);

/// Which quarter holds (α, β) and the patch parameters there, with (p, q) = (1 − u, u),
/// Q = q/p = tan(α'/2), α' the angle folded into [0, π] (likewise v from β).
struct QuarterParameter {
  int quarter = 0;
  double u = 0.0;
  double v = 0.0;
};
QuarterParameter quarterParameter(double alpha, double beta);

/// Patch parameter → angle in [0, π] for a quarter: α' = 2 atan(u / (1 − u)).
double quarterAngle(double u);

/// The analytic point and outward unit normal at angles (α, β).
Eigen::Vector3d torusPoint(const TorusShape& torus, double alpha, double beta);
Eigen::Vector3d torusNormal(double alpha, double beta);

/// The four quarter patches of one torus, built once for repeated evaluation.
class TorusBezier {
 public:
  /// Throws InvalidParameterError unless 0 < r < R.
  explicit TorusBezier(const TorusShape& torus);
  const RationalBezierPatch& quarter(int k) const { return quarters_[static_cast<std::size_t>(k)]; }
  /// Point, derivatives and outward unit normal at angles (α, β) (see evaluateTorusBezier).
  SurfacePoint evaluate(double alpha, double beta) const;

 private:
  std::vector<RationalBezierPatch> quarters_;
};

/// Evaluates the Bézier representation at angles (α, β): the point and the outward unit normal
/// (from the patch derivatives; the sign is fixed per quarter so that it points out of the tube).
SurfacePoint evaluateTorusBezier(const TorusShape& torus, double alpha, double beta);

/// The torus as a standard NURBS surface: the tensor product of two 9-point circles (degree 2,
/// knots 0,0,0,¼,¼,½,½,¾,¾,1,1,1, weights 1, √2/2, 1, ...), so the net's weights are products of
/// 1 and √2/2: 1, √2/2 and 1/2. u runs around the tube (α), v around the axis (β).
NurbsSurface torusNurbs(const TorusShape& torus);

/// NURBS parameters (u, v) ∈ [0, 1]² of the point at angles (α, β).
Eigen::Vector2d torusNurbsParameter(double alpha, double beta);

/// Residual of the implicit equation, (sqrt(x² + y²) − R)² + z² − r², for a point in the torus
/// frame.
double torusImplicit(const TorusShape& torus, const Eigen::Vector3d& p);

}  // namespace slipfit
