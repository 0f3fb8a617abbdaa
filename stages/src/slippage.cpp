#include "slipfit/slippage.h"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <Eigen/SVD>

#include <cmath>

namespace slipfit {

std::string_view slippageTypeName(SlippageType type) {
  for (const auto& [t, name] : kSlippageTypeNames)
    if (t == type)
      return name;
  return "?";
}

Eigen::Matrix<double, 6, 6> slippageMatrix(const Eigen::Ref<const Eigen::Matrix3Xd>& points,
                                           const Eigen::Ref<const Eigen::Matrix3Xd>& normals,
                                           const Eigen::Ref<const Eigen::VectorXd>& weights) {
  Eigen::Matrix<double, 6, 6> c = Eigen::Matrix<double, 6, 6>::Zero();
  Eigen::Matrix<double, 6, 1> row;
  for (Eigen::Index i = 0; i < points.cols(); ++i) {
    if (!(weights[i] > 0.0))
      continue;
    // A motion (ω, v) moves pᵢ with velocity ω × pᵢ + v; it slides the surface along itself when
    // that velocity is tangent: nᵢ·(ω × pᵢ + v) = (pᵢ × nᵢ)·ω + nᵢ·v = 0.
    row << points.col(i).cross(normals.col(i)), normals.col(i);
    c.selfadjointView<Eigen::Lower>().rankUpdate(row, weights[i]);
  }
  return c.selfadjointView<Eigen::Lower>();
}

namespace {

SlippageResult degenerate(std::string reason) {
  SlippageResult r;
  r.type = SlippageType::degenerate;
  r.reason = std::move(reason);
  return r;
}

/// Number of singular values of the 3 × k rotational block above 0.2 of the largest (relative, so
/// that a small patch of a sphere, whose rotations about the far centre look like translations
/// with small ω, still shows three independent rotations).
int rotationalRank(const Eigen::Matrix3Xd& w, Eigen::Matrix3d* left, Eigen::MatrixXd* right) {
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(w, Eigen::ComputeFullU | Eigen::ComputeFullV);
  *left = svd.matrixU();
  *right = svd.matrixV();
  int rank = 0;
  const double largest = svd.singularValues().size() ? svd.singularValues()(0) : 0.0;
  if (largest < 0.1)
    return 0;  // no rotation at all: translations only
  for (Eigen::Index j = 0; j < svd.singularValues().size(); ++j)
    rank += svd.singularValues()(j) > 0.05 * largest ? 1 : 0;
  return rank;
}

}  // namespace

SlippageResult analyzeSlippage(const Eigen::Ref<const Eigen::Matrix3Xd>& points,
                               const Eigen::Ref<const Eigen::Matrix3Xd>& normals,
                               const Eigen::Ref<const Eigen::VectorXd>& weights,
                               const SlippageOptions& options) {
  const Eigen::Index n = points.cols();
  if (normals.cols() != n || weights.size() != n)
    return degenerate("slippage: points, normals and weights differ in number");
  // Normalise: centroid at the origin, unit RMS radius, unit normals.
  double w = 0.0;
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  Eigen::Index used = 0;
  for (Eigen::Index i = 0; i < n; ++i) {
    if (!(weights[i] > 0.0))
      continue;
    if (!points.col(i).allFinite() || !normals.col(i).allFinite() ||
        normals.col(i).squaredNorm() == 0.0)
      return degenerate("slippage: point " + std::to_string(i) +
                        " has a non-finite coordinate or no normal");
    w += weights[i];
    c += weights[i] * points.col(i);
    ++used;
  }
  if (used < 6)
    return degenerate("slippage: " + std::to_string(used) +
                      " points with positive weight, at least 6 needed");
  c /= w;
  double s2 = 0.0;
  for (Eigen::Index i = 0; i < n; ++i)
    if (weights[i] > 0.0)
      s2 += weights[i] * (points.col(i) - c).squaredNorm();
  const double s = std::sqrt(s2 / w);
  if (!(s > 0.0))
    return degenerate("slippage: all points coincide");
  Eigen::Matrix3Xd p(3, used), nn(3, used);
  Eigen::VectorXd ww(used);
  for (Eigen::Index i = 0, j = 0; i < n; ++i)
    if (weights[i] > 0.0) {
      p.col(j) = (points.col(i) - c) / s;
      nn.col(j) = normals.col(i).normalized();
      ww[j++] = weights[i] / w;
    }

  Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>> eig(slippageMatrix(p, nn, ww));
  const double lmax = eig.eigenvalues()(5);
  if (!(lmax > 0.0))
    return degenerate("slippage: the matrix vanishes");
  SlippageResult r;
  r.scale = s;
  r.spectrum = eig.eigenvalues().cwiseMax(0.0) / lmax;
  // The slippable motions are the eigenvalues below the threshold up to the largest relative gap:
  // noise lifts the near-zero eigenvalues together, and the gap to the first rigid direction
  // stays (Gelfand & Guibas read the count off the spectrum the same way).
  // Below 1e-6 eigenvalues are rounding, all alike.
  int k = 0;
  double best_gap = 0.0;
  constexpr double kFloor = 1e-6;
  for (int j = 1; j <= 5 && r.spectrum(j - 1) <= options.threshold; ++j) {
    const double gap = std::max(r.spectrum(j), kFloor) / std::max(r.spectrum(j - 1), kFloor);
    if (gap > best_gap) {
      best_gap = gap;
      k = j;
    }
  }
  r.motions = k;
  const Eigen::Matrix<double, 6, Eigen::Dynamic> basis = eig.eigenvectors().leftCols(k);
  // Back to world coordinates: x = c + s p' moves with ω × x + (s v' − ω × c).
  r.basis.resize(6, k);
  for (int j = 0; j < k; ++j) {
    const Eigen::Vector3d om = basis.col(j).head<3>(), v = basis.col(j).tail<3>();
    r.basis.col(j) << om, s * v - om.cross(c);
  }
  auto world = [&](const Eigen::Vector3d& q) -> Eigen::Vector3d { return c + s * q; };

  if (k == 0) {
    r.type = SlippageType::none;
    return r;
  }
  if (k >= 4) {
    SlippageResult d =
        degenerate("slippage: " + std::to_string(k) +
                   " slippable motions (collinear points, or too few to span a surface)");
    d.motions = k;
    d.spectrum = r.spectrum;
    return d;
  }
  const Eigen::Matrix3Xd om = basis.topRows(3);
  const Eigen::Matrix3Xd vel = basis.bottomRows(3);
  Eigen::Matrix3d left;
  Eigen::MatrixXd right;
  const int rank = rotationalRank(om, &left, &right);

  if (k == 3 && rank == 1) {
    r.type = SlippageType::plane;
    r.normal = left.col(0);
    r.primitive = Plane{*r.normal, r.normal->dot(c)};
    return r;
  }
  if (k == 3 && rank == 3) {
    // Rotations about the centre q: v = q × ω = −[ω]× q for every basis motion.
    Eigen::MatrixXd a(3 * k, 3);
    Eigen::VectorXd b(3 * k);
    for (int j = 0; j < k; ++j) {
      const Eigen::Vector3d wj = om.col(j);
      Eigen::Matrix3d cross;
      cross << 0, -wj.z(), wj.y(), wj.z(), 0, -wj.x(), -wj.y(), wj.x(), 0;
      a.middleRows(3 * j, 3) = -cross;
      b.segment(3 * j, 3) = vel.col(j);
    }
    const Eigen::Vector3d q = a.colPivHouseholderQr().solve(b);
    r.type = SlippageType::sphere;
    r.center = world(q);
    double rr = 0.0;
    for (Eigen::Index i = 0; i < used; ++i)
      rr += ww[i] * (p.col(i) - q).norm();
    r.primitive = Sphere{*r.center, rr * s};
    return r;
  }
  if (k == 2 && rank == 1) {
    // The combination with the largest rotation; the translation along the axis drops out of
    // the axis point q = ω × v / ‖ω‖².
    const Eigen::Vector2d mix = right.col(0);
    const Eigen::Vector3d w1 = om * mix, v1 = vel * mix;
    const Eigen::Vector3d a = w1.normalized();
    Eigen::Vector3d q = w1.cross(v1) / w1.squaredNorm();
    q -= a.dot(q) * a;  // foot of the perpendicular from the centroid (the origin here)
    r.type = SlippageType::cylinder;
    r.axis = a;
    r.point = world(q);
    double rho = 0.0;
    for (Eigen::Index i = 0; i < used; ++i) {
      const Eigen::Vector3d d = p.col(i) - q;
      rho += ww[i] * (d - d.dot(a) * a).norm();
    }
    r.primitive = Cylinder{a, *r.point, rho * s};
    return r;
  }
  if (k == 1) {
    const Eigen::Vector3d w1 = om.col(0), v1 = vel.col(0);
    if (w1.norm() < 0.1) {
      r.type = SlippageType::extrusion;
      r.axis = v1.normalized();
      return r;
    }
    const Eigen::Vector3d a = w1.normalized();
    const double h = w1.dot(v1) / w1.squaredNorm();
    Eigen::Vector3d q = w1.cross(v1) / w1.squaredNorm();
    r.axis = a;
    r.point = world(q);
    if (std::abs(h) > options.pitch_tolerance) {
      r.type = SlippageType::helix;
      r.pitch = h * s;
      return r;
    }
    // A surface of revolution: its profile in (t, ρ) = (axial, radial) coordinates tells which.
    Eigen::Matrix3d line_n = Eigen::Matrix3d::Zero(), circ_n = Eigen::Matrix3d::Zero();
    Eigen::Vector3d line_b = Eigen::Vector3d::Zero(), circ_b = Eigen::Vector3d::Zero();
    Eigen::VectorXd t(used), rho(used);
    for (Eigen::Index i = 0; i < used; ++i) {
      const Eigen::Vector3d d = p.col(i) - q;
      t[i] = d.dot(a);
      rho[i] = (d - t[i] * a).norm();
      const Eigen::Vector3d lrow(t[i], 1.0, 0.0), crow(2 * t[i], 2 * rho[i], 1.0);
      line_n.topLeftCorner<2, 2>() += ww[i] * lrow.head<2>() * lrow.head<2>().transpose();
      line_b.head<2>() += ww[i] * rho[i] * lrow.head<2>();
      circ_n += ww[i] * crow * crow.transpose();
      circ_b += ww[i] * (t[i] * t[i] + rho[i] * rho[i]) * crow;
    }
    const Eigen::Vector2d line = line_n.topLeftCorner<2, 2>().ldlt().solve(line_b.head<2>());
    const Eigen::Vector3d circ = circ_n.ldlt().solve(circ_b);
    const double circ_r =
        std::sqrt(std::max(0.0, circ.z() + circ.x() * circ.x() + circ.y() * circ.y()));
    double line_rms = 0.0, circ_rms = 0.0;
    for (Eigen::Index i = 0; i < used; ++i) {
      const double dl =
          (rho[i] - line.x() * t[i] - line.y()) / std::sqrt(1.0 + line.x() * line.x());
      const double dc = std::hypot(t[i] - circ.x(), rho[i] - circ.y()) - circ_r;
      line_rms += ww[i] * dl * dl;
      circ_rms += ww[i] * dc * dc;
    }
    line_rms = std::sqrt(line_rms);
    circ_rms = std::sqrt(circ_rms);
    if (line_rms <= options.profile_tolerance && line_rms <= circ_rms) {
      if (std::abs(line.x()) < 0.02) {
        r.type =
            SlippageType::cylinder;  // the translation along the axis fell just above the threshold
        Eigen::Vector3d foot = q - a.dot(q) * a;
        r.point = world(foot);
        r.primitive = Cylinder{a, *r.point, line.y() * s};
        return r;
      }
      // ρ = α t + β meets the axis at t₀ = −β/α; the opening is where ρ grows.
      const double t0 = -line.y() / line.x();
      const Eigen::Vector3d apex = world(q + t0 * a);
      const Eigen::Vector3d axis = line.x() > 0 ? a : Eigen::Vector3d(-a);
      r.type = SlippageType::cone;
      r.axis = axis;
      r.point = apex;
      r.primitive = Cone{axis, apex, std::atan(std::abs(line.x()))};
      return r;
    }
    r.type = circ_rms <= options.profile_tolerance ? SlippageType::torus : SlippageType::revolution;
    return r;
  }
  SlippageResult d =
      degenerate("slippage: " + std::to_string(k) + " motions with " + std::to_string(rank) +
                 " independent rotations fit no known surface");
  d.motions = k;
  d.spectrum = r.spectrum;
  return d;
}

}  // namespace slipfit
