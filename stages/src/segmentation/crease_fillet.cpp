#include "slipfit/segmentation/crease_fillet.h"

#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <limits>

namespace slipfit {

namespace {

// The fillet radii tried, geometrically spaced between the smallest and the largest.
constexpr int kRadii = 48;
// A point's misfit counts at most this many of its σ (an outlier or a point of a third surface
// does not decide the radius).
constexpr double kCapSigmas = 6.0;

}  // namespace

std::optional<CreaseSection> creaseSection(const Plane& a, const Plane& b,
                                           const Eigen::Ref<const Eigen::Matrix3Xd>& points_a,
                                           const Eigen::Ref<const Eigen::Matrix3Xd>& points_b) {
  CreaseSection s;
  s.along = a.normal.cross(b.normal);
  const double sine = s.along.norm();
  if (!(sine > 1e-6) || points_a.cols() == 0 || points_b.cols() == 0)
    return std::nullopt;
  s.along /= sine;
  // The point of the crease line nearest the points' centroid: n_a·x = d_a, n_b·x = d_b.
  const Eigen::Vector3d centroid = 0.5 * (points_a.rowwise().mean() + points_b.rowwise().mean());
  Eigen::Matrix3d m;
  m.row(0) = a.normal.transpose();
  m.row(1) = b.normal.transpose();
  m.row(2) = s.along.transpose();
  s.origin = m.inverse() * Eigen::Vector3d(a.d, b.d, s.along.dot(centroid));
  // Each plane's direction away from the crease, towards its points: all of them (but a few at
  // the crease) on that side, or the planes cross rather than meet at an edge.
  auto side = [&](const Plane& plane, const Eigen::Ref<const Eigen::Matrix3Xd>& pts,
                  Eigen::Vector3d& dir) {
    dir = s.along.cross(plane.normal);
    Eigen::Index positive = 0;
    for (Eigen::Index j = 0; j < pts.cols(); ++j)
      positive += dir.dot(pts.col(j) - s.origin) > 0.0 ? 1 : 0;
    if (2 * positive < pts.cols()) {
      dir = -dir;
      positive = pts.cols() - positive;
    }
    return static_cast<double>(positive) >= 0.95 * static_cast<double>(pts.cols());
  };
  if (!side(a, points_a, s.ua) || !side(b, points_b, s.ub))
    return std::nullopt;
  s.na = a.normal;
  s.nb = b.normal;
  s.opening = std::acos(std::clamp(s.ua.dot(s.ub), -1.0, 1.0));
  return s;
}

FilletPiece filletDistance(const CreaseSection& s, double radius, const Eigen::Vector3d& p,
                           double* distance) {
  Eigen::Vector3d q = p - s.origin;
  q -= s.along.dot(q) * s.along;
  const double half = 0.5 * s.opening;
  const double tangent = radius / std::tan(half);  // the tangent points' distance from the crease
  auto ray = [&](const Eigen::Vector3d& u, const Eigen::Vector3d& n) {
    const double along = q.dot(u);
    return along >= tangent ? std::abs(q.dot(n)) : (q - tangent * u).norm();
  };
  const double da = ray(s.ua, s.na), db = ray(s.ub, s.nb);
  double dc = std::numeric_limits<double>::infinity();
  if (radius > 0.0) {
    const Eigen::Vector3d bisector = (s.ua + s.ub).normalized();
    const Eigen::Vector3d center = (radius / std::sin(half)) * bisector;
    const Eigen::Vector3d v = q - center;
    // The arc faces the crease: from the centre, towards −bisector, half-span (π − opening) / 2.
    const double vn = v.norm();
    if (vn > 0.0 && -v.dot(bisector) / vn >= std::cos(0.5 * (M_PI - s.opening)))
      dc = std::abs(vn - radius);
    else
      dc = std::min((q - tangent * s.ua).norm(), (q - tangent * s.ub).norm());
  }
  if (dc < da && dc < db) {
    *distance = dc;
    return FilletPiece::arc;
  }
  *distance = std::min(da, db);
  return da <= db ? FilletPiece::plane_a : FilletPiece::plane_b;
}

FilletChoice chooseFilletRadius(const CreaseSection& s, const Eigen::Ref<const Eigen::Matrix3Xd>& p,
                                const Eigen::Ref<const Eigen::VectorXd>& sigma, double smallest,
                                double largest) {
  FilletChoice c;
  const auto cost = [&](double radius, std::size_t* on_arc) {
    double sum = 0.0;
    std::size_t arc = 0;
    for (Eigen::Index j = 0; j < p.cols(); ++j) {
      double d = 0.0;
      arc += filletDistance(s, radius, p.col(j), &d) == FilletPiece::arc ? 1 : 0;
      const double z = d / sigma(j);
      sum += std::min(z * z, kCapSigmas * kCapSigmas);
    }
    if (on_arc)
      *on_arc = arc;
    return sum;
  };
  c.sharp_cost = cost(0.0, nullptr);
  c.cost = c.sharp_cost;
  if (!(smallest > 0.0) || !(largest > smallest))
    return c;
  const double ratio = std::pow(largest / smallest, 1.0 / (kRadii - 1));
  double best_r = 0.0;
  int best_k = -1;
  for (int k = 0; k < kRadii; ++k) {
    const double r = smallest * std::pow(ratio, k);
    const double v = cost(r, nullptr);
    if (v < c.cost) {
      c.cost = v;
      best_r = r;
      best_k = k;
    }
  }
  if (best_k < 0)
    return c;
  // Golden-section search between the grid's neighbours of the best radius.
  double lo = best_k > 0 ? best_r / ratio : best_r,
         hi = best_k + 1 < kRadii ? best_r * ratio : best_r;
  const double g = 0.5 * (std::sqrt(5.0) - 1.0);
  double x1 = hi - g * (hi - lo), x2 = lo + g * (hi - lo);
  double f1 = cost(x1, nullptr), f2 = cost(x2, nullptr);
  for (int it = 0; it < 20; ++it) {
    if (f1 < f2) {
      hi = x2;
      x2 = x1;
      f2 = f1;
      x1 = hi - g * (hi - lo);
      f1 = cost(x1, nullptr);
    } else {
      lo = x1;
      x1 = x2;
      f1 = f2;
      x2 = lo + g * (hi - lo);
      f2 = cost(x2, nullptr);
    }
  }
  const double r = f1 < f2 ? x1 : x2;
  const double v = std::min(f1, f2);
  if (v < c.cost) {
    c.cost = v;
    best_r = r;
  }
  c.radius = best_r;
  c.cost = cost(best_r, &c.on_arc);
  return c;
}

}  // namespace slipfit
