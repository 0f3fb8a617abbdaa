#include "slipfit/fitting/weighted_fit.h"

#include "slipfit/core/angle_units.h"
#include "slipfit/core/exceptions.h"
#include "slipfit/core/name_table.h"
#include "slipfit/fitting/model_selection.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include <Eigen/Geometry>
#include <algorithm>

#include <cmath>
#include <limits>
#include <string>

namespace slipfit {

void FitOptions::validate() const {
  validateDeclared(*this, "fit");
  if (!(degenerate_rcond >= 0.0 && degenerate_rcond < 1.0))
    throw InvalidParameterError("fit: degenerate_rcond must be in [0, 1), got " +
                                std::to_string(degenerate_rcond));
}

std::string_view fitStatusName(FitStatus status) {
  return nameIn(kFitStatusNames, status);
}

int minimumPoints(PrimitiveType type) {
  return parameterCount(type);  // one point per free parameter
}

namespace {

using Points = Eigen::Ref<const Eigen::Matrix3Xd>;
using Weights = Eigen::Ref<const Eigen::VectorXd>;

FitResult failure(PrimitiveType type, FitStatus status, std::string reason) {
  FitResult r;
  r.type = type;
  r.status = status;
  r.reason = std::move(reason);
  return r;
}

/// Checks sizes, finiteness and weights; on success returns ok with used_points and the index of
/// the first point with positive weight (the origin of the running sums) in *first.
FitResult checkInput(PrimitiveType type, const Points& points, const Points* normals,
                     const Weights& weights, Eigen::Index* first) {
  const auto n = points.cols();
  const std::string name(primitiveTypeName(type));
  if (weights.size() != n)
    return failure(type, FitStatus::invalid_input,
                   name + " fit: " + std::to_string(weights.size()) + " weights for " +
                       std::to_string(n) + " points");
  if (normals && normals->cols() != n)
    return failure(type, FitStatus::invalid_input,
                   name + " fit: needs one normal per point, got " +
                       std::to_string(normals->cols()) + " for " + std::to_string(n));
  std::size_t used = 0;
  *first = -1;
  for (Eigen::Index i = 0; i < n; ++i) {
    const double w = weights[i];
    if (!(w >= 0.0) || !std::isfinite(w))
      return failure(type, FitStatus::invalid_input,
                     name + " fit: weight " + std::to_string(i) + " is negative or not finite");
    if (w == 0.0)
      continue;
    if (!points.col(i).allFinite())
      return failure(type, FitStatus::invalid_input,
                     name + " fit: point " + std::to_string(i) + " is not finite");
    if (normals && !(normals->col(i).allFinite() && normals->col(i).squaredNorm() > 0.0))
      return failure(type, FitStatus::invalid_input,
                     name + " fit: normal " + std::to_string(i) + " is zero or not finite");
    if (*first < 0)
      *first = i;
    ++used;
  }
  if (used == 0 && n > 0)
    return failure(type, FitStatus::zero_weight, name + " fit: every weight is zero");
  if (used < static_cast<std::size_t>(minimumPoints(type)))
    return failure(type, FitStatus::too_few_points,
                   name + " fit: " + std::to_string(used) +
                       " points with positive weight, at least " +
                       std::to_string(minimumPoints(type)) + " needed");
  FitResult ok;
  ok.type = type;
  ok.used_points = used;
  return ok;
}

/// Weighted moments about an origin o on the data: W, Σw d, Σw d dᵀ, Σw‖d‖², Σw d‖d‖² (d = p − o).
/// One pass; shifting to a data point keeps the sums free of cancellation far from the origin.
template <int Dim>
struct Moments {
  using Vec = Eigen::Matrix<double, Dim, 1>;
  using Mat = Eigen::Matrix<double, Dim, Dim>;
  double w = 0.0, q = 0.0;
  Vec s1 = Vec::Zero(), t = Vec::Zero();
  Mat s2 = Mat::Zero();
  void add(double weight, const Vec& d) {
    const double dd = d.squaredNorm();
    w += weight;
    s1 += weight * d;
    s2.noalias() += weight * d * d.transpose();
    q += weight * dd;
    t += (weight * dd) * d;
  }
  Vec mean() const { return s1 / w; }
  Mat covariance() const { return s2 / w - mean() * mean().transpose(); }
};

/// Centre and radius of the weighted least-squares sphere (Dim = 3) or circle (Dim = 2) in the
/// moments' frame: minimising Σ wᵢ(‖dᵢ − c‖² − r²)² with r² = Σ wᵢ‖dᵢ − c‖² / Σ wᵢ substituted
/// gives the linear system 4 W Cov c = 2 (Σ wᵢ dᵢ‖dᵢ‖² − m Σ wᵢ‖dᵢ‖²). Returns false when Cov is
/// (nearly) singular: the points lie on a plane (line), whose "sphere" has an infinite radius.
template <int Dim>
bool sphereFromMoments(const Moments<Dim>& m, double degenerate_rcond,
                       typename Moments<Dim>::Vec* center, double* radius, double* rcond) {
  using Mat = typename Moments<Dim>::Mat;
  const Mat cov = m.covariance();
  const double scale2 = cov.trace();
  if (!(scale2 > 0.0)) {
    *rcond = 0.0;
    return false;
  }
  // Normalised to unit trace, the matrix's entries and eigenvalues are O(1) whatever the units;
  // the right-hand side is scaled alike, so the solution is the centre itself.
  const Mat c_n = cov / scale2;
  Eigen::SelfAdjointEigenSolver<Mat> eig(c_n, Eigen::EigenvaluesOnly);
  *rcond = std::max(0.0, eig.eigenvalues()(0)) / eig.eigenvalues()(Dim - 1);
  if (*rcond < degenerate_rcond)
    return false;
  const typename Moments<Dim>::Vec rhs = (m.t - m.mean() * m.q) / (2.0 * m.w * scale2);
  *center = c_n.ldlt().solve(rhs);
  const double r2 = m.q / m.w - 2.0 * m.mean().dot(*center) + center->squaredNorm();
  if (!(r2 > 0.0) || !std::isfinite(r2))
    return false;
  *radius = std::sqrt(r2);
  return center->allFinite();
}

/// Unit vectors u, v completing a to an orthonormal frame.
void frame(const Eigen::Vector3d& a, Eigen::Vector3d* u, Eigen::Vector3d* v) {
  *u = a.unitOrthogonal();
  *v = a.cross(*u);
}

void finish(FitResult& r) {
  r.refined = r.algebraic;
}

/// Running sums of one pass (scalars, so that the compiler keeps them in registers).
struct Sums {
  double w = 0, x = 0, y = 0, z = 0, xx = 0, xy = 0, xz = 0, yy = 0, yz = 0, zz = 0, q = 0, tx = 0,
         ty = 0, tz = 0;
  template <bool full>
  void add(double wi, double dx, double dy, double dz) {
    const double wx = wi * dx, wy = wi * dy, wz = wi * dz;
    w += wi;
    x += wx;
    y += wy;
    z += wz;
    xx += wx * dx;
    xy += wx * dy;
    xz += wx * dz;
    yy += wy * dy;
    yz += wy * dz;
    zz += wz * dz;
    if constexpr (full) {
      const double dd = dx * dx + dy * dy + dz * dz;
      q += wi * dd;
      tx += wx * dd;
      ty += wy * dd;
      tz += wz * dd;
    }
  }
  void into(Moments<3>* m) const {
    m->w = w;
    m->q = q;
    m->s1 << x, y, z;
    m->t << tx, ty, tz;
    m->s2 << xx, xy, xz, xy, yy, yz, xz, yz, zz;
  }
};

/// The moments of all points with positive weight in one pass, validating on the way: the
/// bandwidth-bound path of the plane and sphere estimators. Weights multiply, so zero weights need
/// no branch, and two interleaved sets of sums halve the dependency chains. When the sums are not
/// finite — a NaN point with weight 0 poisons them — the pass is redone skipping zero weights.
/// Returns false when the input needs checkInput's full diagnosis. \a full adds the third-order
/// terms the sphere needs.
/// Σ over points of one interleaved pass; \a skip_zero leaves out zero weights altogether (a NaN
/// point times weight 0 would otherwise poison the sums). Points keep their parity either way, so
/// both variants round identically on the points they add.
template <bool full, bool skip_zero>
void interleavedSums(const Points& points, const Weights& weights, const Eigen::Vector3d& o,
                     Sums* out, std::size_t* count, double* wmin) {
  const Eigen::Index n = points.cols();
  Sums a, b;
  std::size_t c = 0;
  double lo = 0.0;
  const double* p = points.data();
  const auto stride = points.outerStride();
  const double ox = o.x(), oy = o.y(), oz = o.z();
  // Unrolled by two, even points into a and odd into b: two independent dependency chains.
  Eigen::Index i = 0;
  for (; i + 1 < n; i += 2) {
    const double w0 = weights[i], w1 = weights[i + 1];
    const double* p0 = p + i * stride;
    const double* p1 = p0 + stride;
    c += (w0 > 0.0) + (w1 > 0.0);
    lo = std::min(lo, std::min(w0, w1));
    if (!skip_zero || w0 > 0.0)
      a.add<full>(w0, p0[0] - ox, p0[1] - oy, p0[2] - oz);
    if (!skip_zero || w1 > 0.0)
      b.add<full>(w1, p1[0] - ox, p1[1] - oy, p1[2] - oz);
  }
  if (i < n) {
    const double w0 = weights[i];
    const double* p0 = p + i * stride;
    c += w0 > 0.0;
    lo = std::min(lo, w0);
    if (!skip_zero || w0 > 0.0)
      a.add<full>(w0, p0[0] - ox, p0[1] - oy, p0[2] - oz);
  }
  a.w += b.w, a.x += b.x, a.y += b.y, a.z += b.z, a.xx += b.xx, a.xy += b.xy, a.xz += b.xz;
  a.yy += b.yy, a.yz += b.yz, a.zz += b.zz, a.q += b.q, a.tx += b.tx, a.ty += b.ty, a.tz += b.tz;
  *out = a;
  *count = c;
  *wmin = lo;
}

/// The moments of all points with positive weight in one pass, validating on the way: the
/// bandwidth-bound path of the plane and sphere estimators. Weights multiply, so zero weights need
/// no branch, and two interleaved sets of sums halve the dependency chains. When the sums are not
/// finite the pass is redone skipping zero weights. Returns false when the input needs
/// checkInput's full diagnosis. \a full adds the third-order terms the sphere needs.
template <bool full>
bool onePassMoments(const Points& points, const Weights& weights, int min_points,
                    Eigen::Vector3d* origin, Moments<3>* m, std::size_t* used) {
  const Eigen::Index n = points.cols();
  if (weights.size() != n)
    return false;
  Eigen::Index first = 0;
  while (first < n && weights[first] == 0.0)
    ++first;
  if (first == n)
    return false;
  *origin = points.col(first);
  Sums sums;
  double wmin = 0.0;
  interleavedSums<full, false>(points, weights, *origin, &sums, used, &wmin);
  if (!(wmin >= 0.0) || *used < static_cast<std::size_t>(min_points))
    return false;
  auto finite = [&] {
    return std::isfinite(m->w) && std::isfinite(m->q) && m->s1.allFinite() && m->t.allFinite() &&
           m->s2.allFinite();
  };
  sums.into(m);
  if (finite())
    return true;
  interleavedSums<full, true>(points, weights, *origin, &sums, used, &wmin);
  sums.into(m);
  return finite();
}

/// checkInput's diagnosis when the fast pass refused the input (there is always a reason).
FitResult diagnose(PrimitiveType type, const Points& points, const Weights& weights) {
  Eigen::Index first = -1;
  FitResult r = checkInput(type, points, nullptr, weights, &first);
  if (r.ok())
    r = failure(type, FitStatus::invalid_input,
                std::string(primitiveTypeName(type)) +
                    " fit: the coordinates are too large (the sums overflow)");
  return r;
}

}  // namespace

FitResult estimatePlane(const Points& points, const Weights& weights, const FitOptions& options) {
  Eigen::Vector3d o;
  Moments<3> m;
  FitResult r;
  r.type = PrimitiveType::plane;
  if (!onePassMoments<false>(points, weights, minimumPoints(PrimitiveType::plane), &o, &m,
                             &r.used_points))
    return diagnose(PrimitiveType::plane, points, weights);
  // The plane through the weighted centroid with the normal of least weighted variance: the right
  // singular vector of diag(√w)(P − p̄) of the smallest singular value, i.e. the eigenvector of the
  // smallest eigenvalue of the weighted covariance.
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(m.covariance());
  const Eigen::Vector3d lambda = eig.eigenvalues();
  r.reciprocal_condition = lambda(2) > 0.0 ? std::max(0.0, lambda(1)) / lambda(2) : 0.0;
  if (r.reciprocal_condition < options.degenerate_rcond)
    return failure(PrimitiveType::plane, FitStatus::degenerate,
                   "plane fit: the points are collinear (or identical): no unique plane");
  Plane plane;
  plane.normal = eig.eigenvectors().col(0).normalized();
  plane.d = plane.normal.dot(o + m.mean());
  r.algebraic = plane;
  finish(r);
  return r;
}

FitResult estimateSphere(const Points& points, const Weights& weights, const FitOptions& options) {
  Eigen::Vector3d o;
  Moments<3> m;
  FitResult r;
  r.type = PrimitiveType::sphere;
  if (!onePassMoments<true>(points, weights, minimumPoints(PrimitiveType::sphere), &o, &m,
                            &r.used_points))
    return diagnose(PrimitiveType::sphere, points, weights);
  Eigen::Vector3d c;
  double radius = 0.0;
  if (!sphereFromMoments<3>(m, options.degenerate_rcond, &c, &radius, &r.reciprocal_condition))
    return failure(PrimitiveType::sphere, FitStatus::degenerate,
                   "sphere fit: the points are coplanar (the radius would be infinite)");
  Sphere sphere;
  sphere.center = o + c;
  sphere.radius = radius;
  r.algebraic = sphere;
  finish(r);
  return r;
}

FitResult estimateCylinder(const Points& points, const Points& normals, const Weights& weights,
                           const FitOptions& options) {
  Eigen::Index first = -1;
  FitResult r = checkInput(PrimitiveType::cylinder, points, &normals, weights, &first);
  if (!r.ok())
    return r;
  // Axis: every normal of a cylinder is ⟂ a, so a minimises Σ wᵢ (nᵢ·a)²: the eigenvector of the
  // smallest eigenvalue of Σ wᵢ nᵢnᵢᵀ (insensitive to the normals' signs).
  Eigen::Matrix3d nn = Eigen::Matrix3d::Zero();
  for (Eigen::Index i = 0; i < points.cols(); ++i)
    if (weights[i] > 0.0) {
      const Eigen::Vector3d n = normals.col(i).normalized();
      nn.noalias() += weights[i] * n * n.transpose();
    }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(nn);
  const Eigen::Vector3d lambda = eig.eigenvalues();
  const double axis_rcond = lambda(2) > 0.0 ? std::max(0.0, lambda(1)) / lambda(2) : 0.0;
  if (axis_rcond < options.degenerate_rcond)
    return failure(PrimitiveType::cylinder, FitStatus::degenerate,
                   "cylinder fit: the normals are parallel (a plane): no axis");
  const Eigen::Vector3d a = eig.eigenvectors().col(0).normalized();
  Eigen::Vector3d u, v;
  frame(a, &u, &v);
  // Circle in the plane ⟂ a, by the sphere estimator in 2D.
  const Eigen::Vector3d o = points.col(first);
  Moments<2> m2;
  Moments<3> m3;
  for (Eigen::Index i = 0; i < points.cols(); ++i)
    if (weights[i] > 0.0) {
      const Eigen::Vector3d d = points.col(i) - o;
      m2.add(weights[i], Eigen::Vector2d(d.dot(u), d.dot(v)));
      m3.add(weights[i], d);
    }
  Eigen::Vector2d c2;
  double radius = 0.0, circle_rcond = 0.0;
  if (!sphereFromMoments<2>(m2, options.degenerate_rcond, &c2, &radius, &circle_rcond))
    return failure(PrimitiveType::cylinder, FitStatus::degenerate,
                   "cylinder fit: the points project onto a line (no circle)");
  r.reciprocal_condition = std::min(axis_rcond, circle_rcond);
  Cylinder cyl;
  cyl.axis = a;
  const Eigen::Vector3d on_axis = o + c2.x() * u + c2.y() * v;
  const Eigen::Vector3d centroid = o + m3.mean();
  cyl.point = on_axis + a.dot(centroid - on_axis) * a;
  cyl.radius = radius;
  r.algebraic = cyl;
  finish(r);
  return r;
}

FitResult estimateCone(const Points& points, const Points& normals, const Weights& weights,
                       const FitOptions& options) {
  Eigen::Index first = -1;
  FitResult r = checkInput(PrimitiveType::cone, points, &normals, weights, &first);
  if (!r.ok())
    return r;
  const Eigen::Vector3d o = points.col(first);
  // Apex: every tangent plane of a cone passes through the apex, nᵢ·(pᵢ − c) = 0, so c minimises
  // Σ wᵢ (nᵢᵀ(pᵢ − c))²: (Σ wᵢ nᵢnᵢᵀ) c = Σ wᵢ nᵢnᵢᵀ pᵢ (sign-insensitive; solved about o).
  Eigen::Matrix3d nn = Eigen::Matrix3d::Zero();
  Eigen::Vector3d rhs = Eigen::Vector3d::Zero();
  double scale = 0.0, wsum = 0.0;
  for (Eigen::Index i = 0; i < points.cols(); ++i)
    if (weights[i] > 0.0) {
      const Eigen::Vector3d n = normals.col(i).normalized();
      const Eigen::Vector3d d = points.col(i) - o;
      nn.noalias() += weights[i] * n * n.transpose();
      rhs += weights[i] * n * n.dot(d);
      scale += weights[i] * d.squaredNorm();
      wsum += weights[i];
    }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(nn, Eigen::EigenvaluesOnly);
  const double apex_rcond = std::max(0.0, eig.eigenvalues()(0)) / eig.eigenvalues()(2);
  if (!(apex_rcond >= options.degenerate_rcond))
    return failure(
        PrimitiveType::cone, FitStatus::degenerate,
        "cone fit: the tangent planes do not meet in one point (parallel normals, or a cylinder)");
  const Eigen::Vector3d c = o + nn.ldlt().solve(rhs);
  // Axis: the unit directions gᵢ = (pᵢ − c)/‖pᵢ − c‖ along the generators all make the angle θ with
  // a, so they lie on a circle of the unit sphere: a is the normal of their weighted plane fit.
  // (SPFN fits that plane to the normals, which needs consistently signed normals; the generator
  // directions always point into the opening.)
  Moments<3> g;
  const double tiny = 1e-12 * std::sqrt(scale / wsum);
  for (Eigen::Index i = 0; i < points.cols(); ++i) {
    const Eigen::Vector3d d = points.col(i) - c;
    if (weights[i] > 0.0 && d.norm() > tiny)
      g.add(weights[i], d.normalized());
  }
  if (!(g.w > 0.0))
    return failure(PrimitiveType::cone, FitStatus::degenerate,
                   "cone fit: every point is at the apex");
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> geig(g.covariance());
  const Eigen::Vector3d gl = geig.eigenvalues();
  const double axis_rcond = gl(2) > 0.0 ? std::max(0.0, gl(1)) / gl(2) : 0.0;
  if (axis_rcond < options.degenerate_rcond)
    return failure(
        PrimitiveType::cone, FitStatus::degenerate,
        "cone fit: the generators do not spread around an axis (a plane through the apex)");
  Eigen::Vector3d a = geig.eigenvectors().col(0).normalized();
  if (a.dot(g.mean()) < 0.0)
    a = -a;  // into the opening
  double theta = 0.0;
  for (Eigen::Index i = 0; i < points.cols(); ++i) {
    const Eigen::Vector3d d = points.col(i) - c;
    if (weights[i] > 0.0 && d.norm() > tiny)
      theta += weights[i] * std::acos(std::clamp(a.dot(d.normalized()), -1.0, 1.0));
  }
  theta /= g.w;
  if (!(theta > 1e-9 && theta < 0.5 * kPi - 1e-9))
    return failure(PrimitiveType::cone, FitStatus::degenerate,
                   "cone fit: the half angle " + std::to_string(theta) + " rad is not in (0, π/2)");
  r.reciprocal_condition = std::min(apex_rcond, axis_rcond);
  r.algebraic = Cone{a, c, theta};
  finish(r);
  return r;
}

namespace {

/// The axis of a surface of revolution from its normal lines, in the frame centred on the weighted
/// centroid `o` at unit weighted RMS radius `scale`: every normal line of a surface of revolution
/// meets its axis, and the line (a, m) in Plücker coordinates (direction a, moment m = c × a)
/// meets the normal line (nᵢ, pᵢ × nᵢ) iff a·(pᵢ × nᵢ) + nᵢ·m = 0, linear in (a, m): the axis is
/// the eigenvector of the least eigenvalue of Σ wᵢ lᵢlᵢᵀ with lᵢ = (pᵢ × nᵢ, nᵢ)
/// (sign-insensitive; the motion of least slippage energy, docs/THEORY.md §4).
struct RevolutionAxis {
  Eigen::Vector3d o = Eigen::Vector3d::Zero();   ///< the frame's origin (weighted centroid)
  double scale = 0.0;                            ///< the frame's unit (weighted RMS radius)
  Eigen::Vector3d a = Eigen::Vector3d::UnitZ();  ///< unit direction
  Eigen::Vector3d c = Eigen::Vector3d::Zero();   ///< the axis point nearest o, in the frame
  /// Second least over greatest eigenvalue: small when the axis is not determined (a sphere,
  /// plane or cylinder).
  double rcond = 0.0;
  std::string failed;  ///< why there is no axis (empty on success)
};

RevolutionAxis revolutionAxis(const Points& points, const Points& normals, const Weights& weights,
                              Eigen::Index first) {
  RevolutionAxis axis;
  double wsum = 0.0;
  for (Eigen::Index i = 0; i < points.cols(); ++i)
    if (weights[i] > 0.0) {
      wsum += weights[i];
      axis.o += weights[i] * (points.col(i) - points.col(first));
    }
  axis.o = points.col(first) + axis.o / wsum;
  double s2 = 0.0;
  for (Eigen::Index i = 0; i < points.cols(); ++i)
    if (weights[i] > 0.0)
      s2 += weights[i] * (points.col(i) - axis.o).squaredNorm();
  axis.scale = std::sqrt(s2 / wsum);
  if (!(axis.scale > 0.0)) {
    axis.failed = "every point is at the same place";
    return axis;
  }
  Eigen::Matrix<double, 6, 6> lines = Eigen::Matrix<double, 6, 6>::Zero();
  for (Eigen::Index i = 0; i < points.cols(); ++i)
    if (weights[i] > 0.0) {
      const Eigen::Vector3d n = normals.col(i).normalized();
      const Eigen::Vector3d p = (points.col(i) - axis.o) / axis.scale;
      Eigen::Matrix<double, 6, 1> l;
      l << p.cross(n), n;
      lines.noalias() += weights[i] * l * l.transpose();
    }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>> eig(lines);
  const auto lambda = eig.eigenvalues();
  axis.rcond = lambda(5) > 0.0 ? std::max(0.0, lambda(1)) / lambda(5) : 0.0;
  const Eigen::Matrix<double, 6, 1> line = eig.eigenvectors().col(0);
  const double an = line.head<3>().norm();
  if (!(an > 1e-9)) {
    axis.failed = "the normal lines meet at infinity (parallel normals)";
    return axis;
  }
  axis.a = line.head<3>() / an;
  axis.c = axis.a.cross(line.tail<3>() / an);
  return axis;
}

}  // namespace

FitResult estimateConeAboutAxis(const Points& points, const Points& normals, const Weights& weights,
                                const FitOptions& options) {
  Eigen::Index first = -1;
  FitResult r = checkInput(PrimitiveType::cone, points, &normals, weights, &first);
  if (!r.ok())
    return r;
  const RevolutionAxis axis = revolutionAxis(points, normals, weights, first);
  if (!axis.failed.empty())
    return failure(PrimitiveType::cone, FitStatus::degenerate, "cone fit: " + axis.failed);
  // The generator: distance from the axis ρ = α z + β along the axis height z, by weighted least
  // squares; the apex is where ρ = 0 and tan θ = |α|.
  Eigen::Matrix2d ata = Eigen::Matrix2d::Zero();
  Eigen::Vector2d atb = Eigen::Vector2d::Zero();
  for (Eigen::Index i = 0; i < points.cols(); ++i)
    if (weights[i] > 0.0) {
      const Eigen::Vector3d v = (points.col(i) - axis.o) / axis.scale - axis.c;
      const double z = v.dot(axis.a);
      const Eigen::Vector2d row(z, 1.0);
      ata.noalias() += weights[i] * row * row.transpose();
      atb += weights[i] * (v - z * axis.a).norm() * row;
    }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> leig(ata, Eigen::EigenvaluesOnly);
  const double line_rcond = leig.eigenvalues()(1) > 0.0
                                ? std::max(0.0, leig.eigenvalues()(0)) / leig.eigenvalues()(1)
                                : 0.0;
  if (!(line_rcond >= options.degenerate_rcond))
    return failure(PrimitiveType::cone, FitStatus::degenerate,
                   "cone fit: the points do not spread along the axis");
  const Eigen::Vector2d ab = ata.ldlt().solve(atb);
  const double theta = std::atan(std::abs(ab(0)));
  if (!(theta > 1e-9 && theta < 0.5 * kPi - 1e-9))
    return failure(PrimitiveType::cone, FitStatus::degenerate,
                   "cone fit: the half angle " + std::to_string(theta) + " rad is not in (0, π/2)");
  const Eigen::Vector3d apex = axis.o + axis.scale * (axis.c - ab(1) / ab(0) * axis.a);
  r.reciprocal_condition = std::min(axis.rcond, line_rcond);
  r.algebraic = Cone{ab(0) > 0.0 ? axis.a : Eigen::Vector3d(-axis.a), apex, theta};
  finish(r);
  return r;
}

FitResult estimateCylinderAboutAxis(const Points& points, const Points& normals,
                                    const Weights& weights, const FitOptions&) {
  Eigen::Index first = -1;
  FitResult r = checkInput(PrimitiveType::cylinder, points, &normals, weights, &first);
  if (!r.ok())
    return r;
  const RevolutionAxis axis = revolutionAxis(points, normals, weights, first);
  if (!axis.failed.empty())
    return failure(PrimitiveType::cylinder, FitStatus::degenerate, "cylinder fit: " + axis.failed);
  // The radius minimising Σ wᵢ (ρᵢ − r)² for this axis: the weighted mean distance from it.
  double wsum = 0.0, rho = 0.0;
  for (Eigen::Index i = 0; i < points.cols(); ++i)
    if (weights[i] > 0.0) {
      const Eigen::Vector3d v = (points.col(i) - axis.o) / axis.scale - axis.c;
      wsum += weights[i];
      rho += weights[i] * (v - v.dot(axis.a) * axis.a).norm();
    }
  rho /= wsum;
  if (!(rho > 0.0 && std::isfinite(rho)))
    return failure(PrimitiveType::cylinder, FitStatus::degenerate,
                   "cylinder fit: the points lie on the axis the normal lines meet");
  r.reciprocal_condition = axis.rcond;
  r.algebraic = Cylinder{axis.a, axis.o + axis.scale * axis.c, axis.scale * rho};
  finish(r);
  return r;
}

FitResult estimateTorus(const Points& points, const Points& normals, const Weights& weights,
                        const FitOptions& options) {
  Eigen::Index first = -1;
  FitResult r = checkInput(PrimitiveType::torus, points, &normals, weights, &first);
  if (!r.ok())
    return r;
  const RevolutionAxis axis = revolutionAxis(points, normals, weights, first);
  if (!axis.failed.empty())
    return failure(PrimitiveType::torus, FitStatus::degenerate, "torus fit: " + axis.failed);
  // A second small eigenvalue means the axis is not determined (a sphere: every line through the
  // centre; a plane or a cylinder: lines at infinity and parallel lines).
  const double axis_rcond = axis.rcond;
  if (!(axis_rcond >= options.degenerate_rcond))
    return failure(PrimitiveType::torus, FitStatus::degenerate,
                   "torus fit: the normal lines do not meet one axis (a sphere, plane or "
                   "cylinder)");
  const Eigen::Vector3d& o = axis.o;
  const Eigen::Vector3d& a = axis.a;
  const double scale = axis.scale;
  Eigen::Vector3d c = axis.c;
  // Cross-section: in the half-plane through the axis, (ρᵢ, zᵢ) lie on the circle of radius r
  // about (R, z₀): the algebraic (Kåsa) circle ρ² + z² + Dρ + Ez + F = 0 by weighted least squares.
  Eigen::Matrix3d ata = Eigen::Matrix3d::Zero();
  Eigen::Vector3d atb = Eigen::Vector3d::Zero();
  for (Eigen::Index i = 0; i < points.cols(); ++i)
    if (weights[i] > 0.0) {
      const Eigen::Vector3d v = (points.col(i) - o) / scale - c;
      const double z = v.dot(a);
      const double rho = (v - z * a).norm();
      const Eigen::Vector3d row(rho, z, 1.0);
      ata.noalias() += weights[i] * row * row.transpose();
      atb += -weights[i] * (rho * rho + z * z) * row;
    }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> ceig(ata, Eigen::EigenvaluesOnly);
  const double circle_rcond = ceig.eigenvalues()(2) > 0.0
                                  ? std::max(0.0, ceig.eigenvalues()(0)) / ceig.eigenvalues()(2)
                                  : 0.0;
  if (!(circle_rcond >= options.degenerate_rcond))
    return failure(PrimitiveType::torus, FitStatus::degenerate,
                   "torus fit: the cross-section does not determine a circle");
  const Eigen::Vector3d def = ata.ldlt().solve(atb);
  const double major = -0.5 * def(0), z0 = -0.5 * def(1);
  const double minor2 = 0.25 * (def(0) * def(0) + def(1) * def(1)) - def(2);
  if (!(major > 0.0 && minor2 > 0.0 && std::isfinite(major) && std::isfinite(minor2)))
    return failure(PrimitiveType::torus, FitStatus::degenerate,
                   "torus fit: the cross-section circle is not off the axis (R ≤ 0)");
  c += z0 * a;
  r.reciprocal_condition = std::min(axis_rcond, circle_rcond);
  r.algebraic = Torus{a, o + scale * c, scale * major, scale * std::sqrt(minor2)};
  finish(r);
  return r;
}

}  // namespace slipfit
