#include "slipfit/surfaces/torus.h"

#include "slipfit/core/angle_units.h"
#include "slipfit/core/exceptions.h"

#include <cmath>
#include <string>

namespace slipfit {

namespace {

/// Folds an angle into [0, 2π).
double wrap(double a) {
  a = std::fmod(a, 2.0 * kPi);
  return a < 0.0 ? a + 2.0 * kPi : a;
}

/// u ∈ [0, 1] with tan(a/2) = u / (1 − u), for a ∈ [0, π].
double quarterU(double a) {
  // tan(a/2) / (1 + tan(a/2)) = sin(a/2) / (sin(a/2) + cos(a/2)): no infinity at a = π.
  const double s = std::sin(0.5 * a), c = std::cos(0.5 * a);
  return s / (s + c);
}
}  // namespace

void TorusShape::validate() const {
  if (!(std::isfinite(R) && std::isfinite(r) && r > 0.0 && r < R))
    throw InvalidParameterError("torus: need 0 < minor_radius < major_radius, got major_radius = " +
                                std::to_string(R) + ", minor_radius = " + std::to_string(r));
}

std::array<HomogeneousPoint, 9> torusQuarterSites(const TorusShape& t) {
  // Homogenized with Q = q/p, T = t/s and multiplied by p² s²:
  //   w = (p² + q²)(s² + t²)          x = ((R + r) p² + (R − r) q²)(s² − t²)
  //   y = ((R + r) p² + (R − r) q²) 2st   z = 2r pq (s² + t²)
  // In the Bernstein basis p², 2pq, q² (and s², 2st, t²) the coefficients are the sites.
  const double a[3] = {1.0, 0.0, 1.0};                // p² + q²  (and s² + t²)
  const double rho[3] = {t.R + t.r, 0.0, t.R - t.r};  // (R + r) p² + (R − r) q²
  const double e[3] = {0.0, t.r, 0.0};                // 2 r pq
  const double c[3] = {1.0, 0.0, -1.0};               // s² − t²
  const double d[3] = {0.0, 1.0, 0.0};                // 2 st
  std::array<HomogeneousPoint, 9> sites;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      sites[i * 3 + j] << a[i] * a[j], rho[i] * c[j], rho[i] * d[j], e[i] * a[j];
  return sites;
}

RationalBezierPatch torusQuarterPatch(const TorusShape& torus, int quarter) {
  torus.validate();
  if (quarter < 0 || quarter > 3)
    throw InvalidParameterError("torus: quarter must be 0..3");
  const auto base = torusQuarterSites(torus);
  std::vector<HomogeneousPoint> sites(base.begin(), base.end());
  for (auto& s : sites) {
    if (quarter & 1)
      s[3] = -s[3];  // z → −z: α → 2π − α
    if (quarter & 2)
      s[2] = -s[2];  // y → −y: β → 2π − β
  }
  return RationalBezierPatch(2, 2, std::move(sites));
}

QuarterParameter quarterParameter(double alpha, double beta) {
  alpha = wrap(alpha);
  beta = wrap(beta);
  QuarterParameter q;
  if (alpha > kPi) {
    q.quarter |= 1;
    alpha = 2.0 * kPi - alpha;
  }
  if (beta > kPi) {
    q.quarter |= 2;
    beta = 2.0 * kPi - beta;
  }
  q.u = quarterU(alpha);
  q.v = quarterU(beta);
  return q;
}

double quarterAngle(double u) {
  return 2.0 * std::atan2(u, 1.0 - u);
}

Eigen::Vector3d torusPoint(const TorusShape& t, double alpha, double beta) {
  const double rho = t.R + t.r * std::cos(alpha);
  return {rho * std::cos(beta), rho * std::sin(beta), t.r * std::sin(alpha)};
}

Eigen::Vector3d torusNormal(double alpha, double beta) {
  return {std::cos(alpha) * std::cos(beta), std::cos(alpha) * std::sin(beta), std::sin(alpha)};
}

TorusBezier::TorusBezier(const TorusShape& torus) {
  quarters_.reserve(4);
  for (int k = 0; k < 4; ++k)
    quarters_.push_back(torusQuarterPatch(torus, k));
}

SurfacePoint TorusBezier::evaluate(double alpha, double beta) const {
  const QuarterParameter q = quarterParameter(alpha, beta);
  SurfacePoint s = quarter(q.quarter).evaluate(q.u, q.v);
  // Su × Sv points into the tube on quarter 0 (Sα × Sβ = −r(R + r cos α) n); each reflection
  // flips the orientation once more: outward = −det(M) Su × Sv with M = diag(1, ±1, ±1).
  const int reflections = (q.quarter & 1) + ((q.quarter >> 1) & 1);
  if (reflections % 2 == 0)
    s.normal = -s.normal;
  return s;
}

SurfacePoint evaluateTorusBezier(const TorusShape& torus, double alpha, double beta) {
  return TorusBezier(torus).evaluate(alpha, beta);
}

NurbsSurface torusNurbs(const TorusShape& torus) {
  torus.validate();
  const double h = std::sqrt(0.5);
  // The unit circle as 9 control points on the square, weights 1, √2/2 alternating.
  const double cx[9] = {1, 1, 0, -1, -1, -1, 0, 1, 1};
  const double cy[9] = {0, 1, 1, 1, 0, -1, -1, -1, 0};
  const double cw[9] = {1, h, 1, h, 1, h, 1, h, 1};
  const std::vector<double> knots = {0, 0, 0, 0.25, 0.25, 0.5, 0.5, 0.75, 0.75, 1, 1, 1};
  std::vector<Eigen::Vector3d> points;
  std::vector<double> weights;
  for (int i = 0; i < 9; ++i)      // around the tube: (ρ, z) = (R + r cos α, r sin α)
    for (int j = 0; j < 9; ++j) {  // around the axis
      const double rho = torus.R + torus.r * cx[i];
      points.emplace_back(rho * cx[j], rho * cy[j], torus.r * cy[i]);
      weights.push_back(cw[i] * cw[j]);
    }
  return NurbsSurface(2, 2, knots, knots, 9, 9, std::move(points), std::move(weights));
}

namespace {
/// Parameter t ∈ [0, 1] of the 9-point circle at angle a (each quarter arc spans a quarter of t).
double circleParameter(double a) {
  a = wrap(a);
  const int arc = std::min(3, static_cast<int>(a / (0.5 * kPi)));
  const double phi = a - arc * 0.5 * kPi;  // in [0, π/2]
  // On an arc with middle weight √2/2, s = t/(1 − t) solves s² + √2(1 − tan φ) s − tan φ = 0:
  // s = (tan φ − 1 + sec φ)/√2 = (sin φ − cos φ + 1)/(√2 cos φ); written to stay finite at π/2.
  const double s = std::sin(phi), c = std::cos(phi);
  const double t = (s - c + 1.0) / (s - c + 1.0 + std::sqrt(2.0) * c);
  return (arc + t) / 4.0;
}
}  // namespace

Eigen::Vector2d torusNurbsParameter(double alpha, double beta) {
  return {circleParameter(alpha), circleParameter(beta)};
}

double torusImplicit(const TorusShape& t, const Eigen::Vector3d& p) {
  const double d = std::hypot(p.x(), p.y()) - t.R;
  return d * d + p.z() * p.z() - t.r * t.r;
}

}  // namespace slipfit
