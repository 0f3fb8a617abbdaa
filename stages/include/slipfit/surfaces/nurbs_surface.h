#pragma once
/// \file General rational tensor-product B-spline (NURBS) surfaces: any degrees, clamped knot
/// vectors, positive weights.

#include "slipfit/surfaces/surface_point.h"

#include <Eigen/Core>

#include <vector>

namespace slipfit {

/// S(u, v) = Σᵢⱼ Nᵢ,ₚ(u) Nⱼ,q(v) wᵢⱼ Pᵢⱼ / Σᵢⱼ Nᵢ,ₚ(u) Nⱼ,q(v) wᵢⱼ.
///
/// Control point (i, j) is points[i * count_v + j]. Knot vectors must be non-decreasing, clamped
/// (first and last value repeated degree + 1 times) and have count + degree + 1 entries; the
/// domain is [knots[p], knots[count]] in each direction.
class NurbsSurface {
 public:
  /// Throws InvalidParameterError naming what is wrong.
  NurbsSurface(int degree_u, int degree_v, std::vector<double> knots_u, std::vector<double> knots_v,
               int count_u, int count_v, std::vector<Eigen::Vector3d> points,
               std::vector<double> weights);

  int degreeU() const { return p_; }
  int degreeV() const { return q_; }
  int countU() const { return nu_; }
  int countV() const { return nv_; }
  const std::vector<double>& knotsU() const { return ku_; }
  const std::vector<double>& knotsV() const { return kv_; }
  double minU() const { return ku_[p_]; }
  double maxU() const { return ku_[nu_]; }
  double minV() const { return kv_[q_]; }
  double maxV() const { return kv_[nv_]; }

  /// Point, first derivatives and unit normal (Cox–de Boor basis functions and their
  /// derivatives, in homogeneous coordinates). Throws InvalidParameterError outside the domain.
  SurfacePoint evaluate(double u, double v) const;

 private:
  int p_, q_, nu_, nv_;
  std::vector<double> ku_, kv_;
  std::vector<Eigen::Vector4d> homogeneous_;  // [w; w x; w y; w z]
};

}  // namespace slipfit
