#include "slipfit/surfaces/nurbs_surface.h"

#include "slipfit/core/exceptions.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace slipfit {

namespace {

void checkKnots(const std::vector<double>& knots, int degree, int count, const char* dir) {
  const std::string where = std::string("NURBS surface, ") + dir + ": ";
  if (degree < 1)
    throw InvalidParameterError(where + "degree must be >= 1, got " + std::to_string(degree));
  if (count < degree + 1)
    throw InvalidParameterError(where + std::to_string(count) +
                                " control points are too few for degree " + std::to_string(degree));
  if (knots.size() != static_cast<std::size_t>(count + degree + 1))
    throw InvalidParameterError(where + "needs " + std::to_string(count + degree + 1) +
                                " knots, got " + std::to_string(knots.size()));
  for (std::size_t i = 0; i < knots.size(); ++i) {
    if (!std::isfinite(knots[i]))
      throw InvalidParameterError(where + "knot " + std::to_string(i) + " is not finite");
    if (i > 0 && knots[i] < knots[i - 1])
      throw InvalidParameterError(where + "knots must be non-decreasing (knot " +
                                  std::to_string(i) + ")");
  }
  for (int i = 1; i <= degree; ++i)
    if (knots[i] != knots[0] || knots[knots.size() - 1 - i] != knots.back())
      throw InvalidParameterError(
          where + "the knot vector must be clamped (end knots repeated degree + 1 times)");
  if (!(knots[degree] < knots[count]))
    throw InvalidParameterError(where + "the domain is empty");
}

/// The span index s with knots[s] <= t < knots[s + 1] (the last non-empty span at the end).
int findSpan(const std::vector<double>& knots, int degree, int count, double t) {
  if (t >= knots[count]) {
    int s = count - 1;
    while (s > degree && knots[s] == knots[s + 1])
      --s;
    return s;
  }
  const auto it = std::upper_bound(knots.begin() + degree, knots.begin() + count + 1, t);
  return static_cast<int>(it - knots.begin()) - 1;
}

/// Non-zero basis functions N_{s−p..s, p}(t) and their first derivatives (Piegl & Tiller A2.3).
void basisWithDerivatives(const std::vector<double>& knots, int span, int p, double t,
                          std::vector<double>& n, std::vector<double>& dn) {
  std::vector<double> left(p + 1), right(p + 1);
  std::vector<std::vector<double>> ndu(p + 1, std::vector<double>(p + 1));
  ndu[0][0] = 1.0;
  for (int j = 1; j <= p; ++j) {
    left[j] = t - knots[span + 1 - j];
    right[j] = knots[span + j] - t;
    double saved = 0.0;
    for (int r = 0; r < j; ++r) {
      ndu[j][r] = right[r + 1] + left[j - r];  // lower triangle: knot differences
      const double temp = ndu[r][j - 1] / ndu[j][r];
      ndu[r][j] = saved + right[r + 1] * temp;
      saved = left[j - r] * temp;
    }
    ndu[j][j] = saved;
  }
  n.resize(p + 1);
  dn.resize(p + 1);
  for (int r = 0; r <= p; ++r) {
    n[r] = ndu[r][p];
    // N'_{s−p+r,p} = p (N_{s−p+r,p−1}/(u_{s+r}−u_{s−p+r}) −
    // N_{s−p+r+1,p−1}/(u_{s+r+1}−u_{s−p+r+1})).
    double d = 0.0;
    if (r >= 1)
      d += ndu[r - 1][p - 1] / ndu[p][r - 1];
    if (r <= p - 1)
      d -= ndu[r][p - 1] / ndu[p][r];
    dn[r] = p * d;
  }
}

}  // namespace

NurbsSurface::NurbsSurface(int degree_u, int degree_v, std::vector<double> knots_u,
                           std::vector<double> knots_v, int count_u, int count_v,
                           std::vector<Eigen::Vector3d> points, std::vector<double> weights)
    : p_(degree_u),
      q_(degree_v),
      nu_(count_u),
      nv_(count_v),
      ku_(std::move(knots_u)),
      kv_(std::move(knots_v)) {
  checkKnots(ku_, p_, nu_, "u");
  checkKnots(kv_, q_, nv_, "v");
  const auto count = static_cast<std::size_t>(nu_) * static_cast<std::size_t>(nv_);
  if (points.size() != count || weights.size() != count)
    throw InvalidParameterError(
        "NURBS surface: " + std::to_string(nu_) + " × " + std::to_string(nv_) +
        " control points need as many points and weights, got " + std::to_string(points.size()) +
        " and " + std::to_string(weights.size()));
  homogeneous_.resize(count);
  for (std::size_t k = 0; k < count; ++k) {
    if (!(weights[k] > 0.0) || !std::isfinite(weights[k]))
      throw InvalidParameterError("NURBS surface: weight " + std::to_string(k) + " = " +
                                  std::to_string(weights[k]) + " must be positive and finite");
    if (!points[k].allFinite())
      throw InvalidParameterError("NURBS surface: control point " + std::to_string(k) +
                                  " is not finite");
    homogeneous_[k] << weights[k], weights[k] * points[k];
  }
}

SurfacePoint NurbsSurface::evaluate(double u, double v) const {
  if (!(u >= minU() && u <= maxU() && v >= minV() && v <= maxV()))
    throw InvalidParameterError("NURBS surface: parameter (" + std::to_string(u) + ", " +
                                std::to_string(v) + ") outside the domain [" +
                                std::to_string(minU()) + ", " + std::to_string(maxU()) + "] × [" +
                                std::to_string(minV()) + ", " + std::to_string(maxV()) + "]");
  const int su = findSpan(ku_, p_, nu_, u), sv = findSpan(kv_, q_, nv_, v);
  std::vector<double> nu, dnu, nv, dnv;
  basisWithDerivatives(ku_, su, p_, u, nu, dnu);
  basisWithDerivatives(kv_, sv, q_, v, nv, dnv);
  Eigen::Vector4d h = Eigen::Vector4d::Zero(), hu = Eigen::Vector4d::Zero(),
                  hv = Eigen::Vector4d::Zero();
  for (int a = 0; a <= p_; ++a)
    for (int b = 0; b <= q_; ++b) {
      const Eigen::Vector4d& c =
          homogeneous_[static_cast<std::size_t>((su - p_ + a) * nv_ + (sv - q_ + b))];
      h += nu[a] * nv[b] * c;
      hu += dnu[a] * nv[b] * c;
      hv += nu[a] * dnv[b] * c;
    }
  return dehomogenize(h, hu, hv);
}

}  // namespace slipfit
