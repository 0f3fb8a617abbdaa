#pragma once
/// \file Rational tensor-product Bézier patches in homogeneous coordinates, evaluated by
/// de Casteljau's algorithm.

#include "slipfit/surfaces/surface_point.h"

#include <Eigen/Core>

#include <vector>

namespace slipfit {

/// Homogeneous site [w; x; y; z] (w first). w = 0 is a point at infinity (a direction); the zero
/// site [0; 0, 0, 0] is allowed: de Casteljau combines sites linearly and dehomogenizes only at
/// the end, so neither needs special care as long as the final weight is non-zero.
using HomogeneousPoint = Eigen::Vector4d;

/// A patch of degree (m, n): (m + 1) × (n + 1) sites, site(i, j) multiplying B_i^m(u) B_j^n(v),
/// u, v ∈ [0, 1].
class RationalBezierPatch {
 public:
  /// \param sites row-major: index i * (n + 1) + j. Throws InvalidParameterError on a count
  /// mismatch, a negative degree, or non-finite sites.
  RationalBezierPatch(int degree_u, int degree_v, std::vector<HomogeneousPoint> sites);

  int degreeU() const { return m_; }
  int degreeV() const { return n_; }
  const HomogeneousPoint& site(int i, int j) const {
    return sites_[static_cast<std::size_t>(i * (n_ + 1) + j)];
  }
  const std::vector<HomogeneousPoint>& sites() const { return sites_; }

  /// Homogeneous value at (u, v) by de Casteljau (no dehomogenization).
  HomogeneousPoint evaluateHomogeneous(double u, double v) const;
  /// Point, derivatives and unit normal. Throws InvalidParameterError for (u, v) outside [0, 1]²
  /// and DegenerateInputError where the weight vanishes.
  SurfacePoint evaluate(double u, double v) const;

 private:
  int m_, n_;
  std::vector<HomogeneousPoint> sites_;
};

}  // namespace slipfit
