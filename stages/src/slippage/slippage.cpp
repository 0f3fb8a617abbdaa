#include "slipfit/slippage/slippage.h"

#include "slipfit/core/exceptions.h"
#include "slipfit/core/name_table.h"
#include "slipfit/fitting/weighted_fit.h"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <optional>
#include <string>
#include <vector>

namespace slipfit {

std::string_view slippageTypeName(SlippageType type) {
  return nameIn(kSlippageTypeNames, type);
}

std::optional<PrimitiveType> primitiveTypeOf(SlippageType type) {
  switch (type) {
    case SlippageType::plane:
      return PrimitiveType::plane;
    case SlippageType::sphere:
      return PrimitiveType::sphere;
    case SlippageType::cylinder:
      return PrimitiveType::cylinder;
    case SlippageType::cone:
      return PrimitiveType::cone;
    case SlippageType::torus:
      return PrimitiveType::torus;
    default:
      return std::nullopt;
  }
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

/// The point set in the normalised frame (centroid c, RMS radius s) with the eigenvectors of its
/// slippage matrix, smallest eigenvalue first.
struct NormalisedSet {
  const Eigen::Matrix3Xd& p;
  const Eigen::Matrix3Xd& n;  ///< unit normals
  const Eigen::VectorXd& w;
  Eigen::Vector3d c;
  double s;
  Eigen::Matrix<double, 6, 6> matrix;  ///< the slippage matrix divided by its largest eigenvalue
  Eigen::Matrix<double, 6, 6> vectors;
};

using Motion = Eigen::Matrix<double, 6, 1>;

/// Relative slippage energy xᵀCx / xᵀx of a motion (on the spectrum's scale).
double energy(const NormalisedSet& set, const Motion& x) {
  return x.dot(set.matrix * x) / x.squaredNorm();
}

/// A family read off k motions is accepted when its ideal motions (built from the recovered axis,
/// centre or normal) lie on the slippable side of the gap: energy below √(λ_k λ_{k+1}). With noise
/// the eigenvectors of nearly equal eigenvalues mix, and the rotational rank alone misreads them.
bool slippable(const NormalisedSet& set, const SlippageResult& r, int k,
               std::initializer_list<Motion> motions, double* worst) {
  const double bound = std::sqrt(std::max(r.spectrum(k - 1), r.noise_floor) * r.spectrum(k));
  *worst = 0.0;
  for (const Motion& m : motions)
    *worst = std::max(*worst, energy(set, m));
  return *worst <= bound;
}

/// Bayesian information criterion of a primitive on the normalised set (as fitAuto): the
/// geometric evidence that tells a nearly flat patch of a cylinder from a plane.
double bic(const NormalisedSet& set, const Primitive& primitive) {
  double ms = 0.0;
  for (Eigen::Index i = 0; i < set.p.cols(); ++i) {
    const double d = distance(set.c + set.s * set.p.col(i), primitive) / set.s;
    ms += set.w[i] * d * d;
  }
  const auto m = static_cast<double>(set.p.cols());
  return m * std::log(std::max(ms, 1e-18)) +
         static_cast<double>(minimumPoints(typeOf(primitive))) * std::log(m);
}

Motion rotationAbout(const Eigen::Vector3d& axis, const Eigen::Vector3d& point) {
  Motion m;
  m << axis, point.cross(axis);  // ω × (x − q) = ω × x + q × ω
  return m;
}

Motion translation(const Eigen::Vector3d& direction) {
  Motion m;
  m << Eigen::Vector3d::Zero(), direction;
  return m;
}

/// A point of the normalised set in world coordinates.
Eigen::Vector3d toWorld(const NormalisedSet& set, const Eigen::Vector3d& q) {
  return set.c + set.s * q;
}

/// Three motions read as a plane or a sphere. The ideal motions are built from the blocks of the
/// matrix rather than from the eigenvectors, which noise mixes when their eigenvalues are close;
/// both readings are tried and the better fit (BIC) kept. \a frame: the eigenvectors of the
/// normals' spread, ascending.
std::optional<SlippageResult> readThreeMotions(const NormalisedSet& set, const SlippageResult& r,
                                               const Eigen::Matrix3d& frame,
                                               const SlippageOptions& options) {
  const Eigen::Matrix3Xd& p = set.p;
  const Eigen::VectorXd& ww = set.w;
  const int k = r.motions;
  std::optional<SlippageResult> plane, sphere;
  double worst = 0.0;
  const Eigen::Vector3d nrm = frame.col(2);  // normal = widest spread
  if (slippable(set, r, k,
                {rotationAbout(nrm, Eigen::Vector3d::Zero()), translation(frame.col(0)),
                 translation(frame.col(1))},
                &worst)) {
    plane = r;
    plane->type = SlippageType::plane;
    plane->normal = nrm;
    plane->primitive = Plane{nrm, nrm.dot(set.c)};
  }
  // The centre is where the normal lines meet: min Σ w |(p − q) × n|².
  Eigen::Matrix3d lhs = Eigen::Matrix3d::Zero();
  Eigen::Vector3d rhs = Eigen::Vector3d::Zero();
  for (Eigen::Index i = 0; i < p.cols(); ++i) {
    const Eigen::Matrix3d proj =
        Eigen::Matrix3d::Identity() - set.n.col(i) * set.n.col(i).transpose();
    lhs += ww[i] * proj;
    rhs += ww[i] * proj * p.col(i);
  }
  const Eigen::Vector3d q = lhs.ldlt().solve(rhs);
  if (q.allFinite() && slippable(set, r, k,
                                 {rotationAbout(Eigen::Vector3d::UnitX(), q),
                                  rotationAbout(Eigen::Vector3d::UnitY(), q),
                                  rotationAbout(Eigen::Vector3d::UnitZ(), q)},
                                 &worst)) {
    sphere = r;
    sphere->type = SlippageType::sphere;
    sphere->center = toWorld(set, q);
    double rr = 0.0;
    for (Eigen::Index i = 0; i < p.cols(); ++i)
      rr += ww[i] * (p.col(i) - q).norm();
    sphere->primitive = Sphere{*sphere->center, rr * set.s};
  }
  // A sphere far larger than the patch bends it by less than the noise the normals carry, and
  // its free centre fits that noise: it reads as a plane.
  if (sphere && plane && std::get<Sphere>(*sphere->primitive).radius > options.flat_radius * set.s)
    sphere.reset();
  if (plane && (!sphere || bic(set, *plane->primitive) <= bic(set, *sphere->primitive)))
    return plane;
  return sphere;
}

/// Two motions read as a cylinder. The axis \a a is the translation that slips best (the normal
/// least spread along it); the axis point q ⟂ a minimises the energy of the rotation (a, q × a),
/// whose residual per point is (p × n)·a + q·(a × n): Σ w (a×n)(a×n)ᵀ q = −Σ w ((p×n)·a)(a×n),
/// from the blocks.
std::optional<SlippageResult> readTwoMotions(const NormalisedSet& set, SlippageResult r,
                                             const Eigen::Vector3d& a) {
  const Eigen::Matrix3d cvv = set.matrix.bottomRightCorner<3, 3>();
  Eigen::Matrix3d ax;
  ax << 0, -a.z(), a.y(), a.z(), 0, -a.x(), -a.y(), a.x(), 0;
  const Eigen::Matrix3d g = ax * cvv * ax.transpose();
  const Eigen::Vector3d h = ax * set.matrix.bottomLeftCorner<3, 3>() * a;
  Eigen::Vector3d q = g.completeOrthogonalDecomposition().solve(-h);
  q -= a.dot(q) * a;
  double worst = 0.0;
  if (!(q.allFinite() &&
        slippable(set, r, r.motions, {rotationAbout(a, q), translation(a)}, &worst)))
    return std::nullopt;
  r.type = SlippageType::cylinder;
  r.axis = a;
  r.point = toWorld(set, q);
  double rho = 0.0;
  for (Eigen::Index i = 0; i < set.p.cols(); ++i) {
    const Eigen::Vector3d d = set.p.col(i) - q;
    rho += set.w[i] * (d - d.dot(a) * a).norm();
  }
  r.primitive = Cylinder{a, *r.point, rho * set.s};
  return r;
}

/// A surface of revolution about the axis (\a a through \a q): its profile in (t, ρ) = (axial,
/// radial) coordinates tells which — a line (cylinder or cone), a circle (torus), or neither.
SlippageResult readProfile(const NormalisedSet& set, SlippageResult r, const Eigen::Vector3d& a,
                           const Eigen::Vector3d& q, const SlippageOptions& options) {
  const Eigen::Matrix3Xd& p = set.p;
  const Eigen::VectorXd& ww = set.w;
  const Eigen::Index used = p.cols();
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
    const double dl = (rho[i] - line.x() * t[i] - line.y()) / std::sqrt(1.0 + line.x() * line.x());
    const double dc = std::hypot(t[i] - circ.x(), rho[i] - circ.y()) - circ_r;
    line_rms += ww[i] * dl * dl;
    circ_rms += ww[i] * dc * dc;
  }
  line_rms = std::sqrt(line_rms);
  circ_rms = std::sqrt(circ_rms);
  if (line_rms <= options.profile_tolerance && line_rms <= circ_rms) {
    if (std::abs(line.x()) < 0.02) {
      r.type = SlippageType::cylinder;  // the translation along the axis fell just above the
                                        // threshold
      Eigen::Vector3d foot = q - a.dot(q) * a;
      r.point = toWorld(set, foot);
      r.primitive = Cylinder{a, *r.point, line.y() * set.s};
      return r;
    }
    // ρ = α t + β meets the axis at t₀ = −β/α; the opening is where ρ grows.
    const double t0 = -line.y() / line.x();
    const Eigen::Vector3d apex = toWorld(set, q + t0 * a);
    const Eigen::Vector3d axis = line.x() > 0 ? a : Eigen::Vector3d(-a);
    r.type = SlippageType::cone;
    r.axis = axis;
    r.point = apex;
    r.primitive = Cone{axis, apex, std::atan(std::abs(line.x()))};
    return r;
  }
  r.type = circ_rms <= options.profile_tolerance ? SlippageType::torus : SlippageType::revolution;
  if (r.type == SlippageType::torus && circ.y() > 0.0) {
    // The profile circle's centre (t₀, R) and radius: the torus, with its centre on the axis.
    r.center = toWorld(set, q + circ.x() * a);
    r.primitive = Torus{a, *r.center, circ.y() * set.s, circ_r * set.s};
  }
  return r;
}

/// One motion (ω, v): an extrusion (ω ≈ 0), a helix (pitch ω·v/|ω|² beyond the tolerance), or a
/// surface of revolution about the axis ω through q = ω × v/|ω|².
SlippageResult readOneMotion(const NormalisedSet& set, SlippageResult r,
                             const Eigen::Matrix<double, 6, 1>& motion,
                             const SlippageOptions& options) {
  const Eigen::Vector3d w1 = motion.head<3>(), v1 = motion.tail<3>();
  if (w1.norm() < 0.1) {
    r.type = SlippageType::extrusion;
    r.axis = v1.normalized();
    return r;
  }
  const Eigen::Vector3d a = w1.normalized();
  const double h = w1.dot(v1) / w1.squaredNorm();
  const Eigen::Vector3d q = w1.cross(v1) / w1.squaredNorm();
  r.axis = a;
  r.point = toWorld(set, q);
  if (std::abs(h) > options.pitch_tolerance) {
    r.type = SlippageType::helix;
    r.pitch = h * set.s;
    return r;
  }
  return readProfile(set, r, a, q, options);
}

/// The motions of the k smallest eigenvalues read as a surface family, in world coordinates.
SlippageResult classifyMotions(const NormalisedSet& set, const SlippageResult& base, int k,
                               const SlippageOptions& options) {
  SlippageResult r = base;
  r.motions = k;
  const Eigen::Matrix<double, 6, Eigen::Dynamic> basis = set.vectors.leftCols(k);
  // Back to world coordinates: x = c + s p' moves with ω × x + (s v' − ω × c).
  r.basis.resize(6, k);
  for (int j = 0; j < k; ++j) {
    const Eigen::Vector3d om = basis.col(j).head<3>(), v = basis.col(j).tail<3>();
    r.basis.col(j) << om, set.s * v - om.cross(set.c);
  }
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
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> normal_spread(
      set.matrix.bottomRightCorner<3, 3>());
  std::optional<SlippageResult> read;
  if (k == 3)
    read = readThreeMotions(set, r, normal_spread.eigenvectors(), options);
  else if (k == 2)
    read = readTwoMotions(set, r, normal_spread.eigenvectors().col(0));
  else
    return readOneMotion(set, r, basis.col(0), options);
  if (read)
    return *read;
  SlippageResult d =
      degenerate("slippage: " + std::to_string(k) + " motions that fit no known surface");
  d.motions = k;
  d.spectrum = r.spectrum;
  return d;
}

}  // namespace

namespace {

/// λ_{k+1} / λ_k with both raised to the noise floor (k = 0: the gap below the first).
double liftedGap(const Eigen::Matrix<double, 6, 1>& spectrum, int k, double floor) {
  const double below = k > 0 ? spectrum(k - 1) : 0.0;
  return k < 6 ? std::max(spectrum(k), floor) / std::max(below, floor) : 0.0;
}

/// Every reading that slips, the verdict first.
std::vector<SlippageResult> analyze(const Eigen::Ref<const Eigen::Matrix3Xd>& points,
                                    const Eigen::Ref<const Eigen::Matrix3Xd>& normals,
                                    const Eigen::Ref<const Eigen::VectorXd>& weights,
                                    const SlippageOptions& options) {
  const Eigen::Index n = points.cols();
  if (normals.cols() != n || weights.size() != n)
    return {degenerate("slippage: points, normals and weights differ in number")};
  // Normalise: centroid at the origin, unit RMS radius, unit normals.
  double w = 0.0;
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  Eigen::Index used = 0;
  for (Eigen::Index i = 0; i < n; ++i) {
    if (!(weights[i] > 0.0))
      continue;
    if (!points.col(i).allFinite() || !normals.col(i).allFinite() ||
        normals.col(i).squaredNorm() == 0.0)
      return {degenerate("slippage: point " + std::to_string(i) +
                         " has a non-finite coordinate or no normal")};
    w += weights[i];
    c += weights[i] * points.col(i);
    ++used;
  }
  if (used < 6)
    return {degenerate("slippage: " + std::to_string(used) +
                       " points with positive weight, at least 6 needed")};
  c /= w;
  double s2 = 0.0;
  for (Eigen::Index i = 0; i < n; ++i)
    if (weights[i] > 0.0)
      s2 += weights[i] * (points.col(i) - c).squaredNorm();
  const double s = std::sqrt(s2 / w);
  if (!(s > 0.0))
    return {degenerate("slippage: all points coincide")};
  Eigen::Matrix3Xd p(3, used), nn(3, used);
  Eigen::VectorXd ww(used);
  for (Eigen::Index i = 0, j = 0; i < n; ++i)
    if (weights[i] > 0.0) {
      p.col(j) = (points.col(i) - c) / s;
      nn.col(j) = normals.col(i).normalized();
      ww[j++] = weights[i] / w;
    }

  const Eigen::Matrix<double, 6, 6> matrix = slippageMatrix(p, nn, ww);
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>> eig(matrix);
  const double lmax = eig.eigenvalues()(5);
  if (!(lmax > 0.0))
    return {degenerate("slippage: the matrix vanishes")};
  SlippageResult r;
  r.scale = s;
  r.threshold = options.threshold;
  r.noise_floor = options.noise_floor;
  r.spectrum = eig.eigenvalues().cwiseMax(0.0) / lmax;
  // Candidate counts k: the eigenvalues below the threshold, ranked by the relative gap
  // λ_{k+1}/λ_k to the next one (noise lifts the near-zero eigenvalues together, and the gap to
  // the first rigid direction stays). Both are raised to the noise floor (options.noise_floor)
  // first: with exact normals a translation slips exactly (λ = 0) while position noise lifts the
  // rotations a little, and an unlifted ratio λ₂/λ₁ would be infinite. The count is the
  // best-ranked one whose motions form a known family: on a small, nearly flat patch of a
  // cylinder the third eigenvalue is small too, and "three motions" would fit nothing.
  std::vector<std::pair<double, int>> candidates;
  for (int j = 1; j <= 5 && r.spectrum(j - 1) <= options.threshold; ++j)
    candidates.emplace_back(liftedGap(r.spectrum, j, options.noise_floor), j);
  std::stable_sort(candidates.begin(), candidates.end(),
                   [](const auto& x, const auto& y) { return x.first > y.first; });
  if (candidates.empty()) {
    r.type = SlippageType::none;
    r.gap = liftedGap(r.spectrum, 0, options.noise_floor);
    return {r};
  }
  const NormalisedSet set{p, nn, ww, c, s, matrix / lmax, eig.eigenvectors()};
  // Four or more motions as the clearest gap is a verdict (collinear or too few points); a
  // weaker candidate with four or more is not a fallback. (classifyShape still tries the
  // primitives on such a set: a short band of a cylinder has four small eigenvalues.)
  const int clearest = candidates.front().second;
  SlippageResult first = classifyMotions(set, r, clearest, options);
  first.gap = candidates.front().first;
  if (first.type == SlippageType::degenerate && clearest >= 4)
    return {first};
  std::vector<SlippageResult> readings;
  for (const auto& [gap, k] : candidates)
    if (k < 4) {
      SlippageResult attempt = k == clearest ? first : classifyMotions(set, r, k, options);
      attempt.gap = gap;
      if (attempt.type != SlippageType::degenerate)
        readings.push_back(std::move(attempt));
    }
  if (readings.empty())
    return {first};
  // Several readings slip: a nearly flat patch of a cylinder also reads as a plane, with its third
  // eigenvalue above the noise yet below the threshold. The spectrum alone cannot tell; the
  // distances of the points to each implied primitive can (BIC, as fitAuto). The verdict goes
  // first.
  if (!readings.front().primitive)
    return readings;
  std::size_t best = 0;
  double best_bic = bic(set, *readings.front().primitive);
  for (std::size_t j = 1; j < readings.size(); ++j)
    if (readings[j].primitive) {
      const double b = bic(set, *readings[j].primitive);
      if (b < best_bic) {
        best_bic = b;
        best = j;
      }
    }
  std::rotate(readings.begin(), readings.begin() + static_cast<std::ptrdiff_t>(best),
              readings.begin() + static_cast<std::ptrdiff_t>(best) + 1);
  return readings;
}

/// Every number a result reports is finite.
bool finiteResult(const SlippageResult& r) {
  const auto ok = [](const std::optional<Eigen::Vector3d>& v) { return !v || v->allFinite(); };
  if (!r.spectrum.allFinite() || !r.basis.allFinite() || !ok(r.axis) || !ok(r.point) ||
      !ok(r.center) || !ok(r.normal) || (r.pitch && !std::isfinite(*r.pitch)) ||
      !std::isfinite(r.scale))
    return false;
  if (!r.primitive)
    return true;
  return allFinite(*r.primitive);
}

}  // namespace

void SlippageOptions::validate() const {
  validateDeclared(*this, "slippage");
  if (!(noise_floor >= 0.0 && std::isfinite(noise_floor)))
    throw InvalidParameterError("slippage: noise_floor must be >= 0, got " +
                                std::to_string(noise_floor));
}

std::vector<SlippageResult> slippageReadings(const Eigen::Ref<const Eigen::Matrix3Xd>& points,
                                             const Eigen::Ref<const Eigen::Matrix3Xd>& normals,
                                             const Eigen::Ref<const Eigen::VectorXd>& weights,
                                             const SlippageOptions& options) {
  options.validate();
  std::vector<SlippageResult> readings = analyze(points, normals, weights, options);
  // Finite inputs can still overflow (weights × coordinates near the double range; found by
  // tests/fuzz): never hand out a NaN.
  for (const SlippageResult& r : readings)
    if (r.type != SlippageType::degenerate && !finiteResult(r))
      return {degenerate(
          "slippage: the result overflowed (coordinates or weights too large to normalise)")};
  return readings;
}

SlippageResult analyzeSlippage(const Eigen::Ref<const Eigen::Matrix3Xd>& points,
                               const Eigen::Ref<const Eigen::Matrix3Xd>& normals,
                               const Eigen::Ref<const Eigen::VectorXd>& weights,
                               const SlippageOptions& options) {
  return slippageReadings(points, normals, weights, options).front();
}

}  // namespace slipfit
