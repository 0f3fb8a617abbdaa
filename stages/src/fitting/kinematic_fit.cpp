#include "slipfit/fitting/kinematic_fit.h"

#include "slipfit/fitting/levenberg_marquardt.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <vector>

namespace slipfit {

namespace {

/// Motion parameters moved by the refinement, around a base surface: the axis turned in the
/// tangent plane of its base direction (x0, x1), its foot moved across it (x2, x3: revolution and
/// helix), the pitch (x4: helix). The extrusion's section placement is its profile's.
struct MotionChart {
  KinematicSurface base;
  Eigen::Vector3d u, v;

  explicit MotionChart(const KinematicSurface& s) : base(s) {
    u = s.axis.unitOrthogonal();
    v = s.axis.cross(u);
  }
  int size() const {
    return base.type == KinematicType::extrusion    ? 2
           : base.type == KinematicType::revolution ? 4
                                                    : 5;
  }
  KinematicSurface decode(const Eigen::VectorXd& x) const {
    KinematicSurface s = base;
    s.axis = (base.axis + x[0] * u + x[1] * v).normalized();
    // The reference stays across the axis, turned with it as little as possible.
    s.reference = (base.reference - base.reference.dot(s.axis) * s.axis).normalized();
    if (base.type != KinematicType::extrusion)
      s.point = base.point + x[2] * u + x[3] * v;
    if (base.type == KinematicType::helix)
      s.pitch = base.pitch + x[4];
    return s;
  }
};

/// The points' distances to the surface of the chart's motion x, its profile refitted to the
/// points as they map under that motion (refineProfileCurve from the chart's profile: variable
/// projection, the profile being linear least squares once the motion is fixed). The Jacobian is
/// by central differences: the motion has at most five parameters, and the profile's response to
/// them is part of each derivative.
struct ProfiledResiduals {
  const MotionChart* chart;
  const Eigen::Matrix3Xd* points;
  const Eigen::VectorXd* sqrt_w;

  KinematicSurface decode(const Eigen::VectorXd& x) const {
    KinematicSurface s = chart->decode(x);
    Eigen::Matrix2Xd q(2, points->cols());
    for (Eigen::Index i = 0; i < points->cols(); ++i)
      q.col(i) = profileCoordinates(s, points->col(i));
    refineProfileCurve(q, s.profile);
    return s;
  }
  void residuals(const Eigen::VectorXd& x, Eigen::VectorXd& f) const {
    const KinematicSurface s = decode(x);
    const KinematicProjector surface(s);
    f.resize(points->cols());
    for (Eigen::Index i = 0; i < points->cols(); ++i)
      f[i] = (*sqrt_w)[i] * surface.distance(points->col(i));
  }
  void normalEquations(const Eigen::VectorXd& x, const Eigen::VectorXd& f, Eigen::MatrixXd& a,
                       Eigen::VectorXd& g) const {
    const Eigen::Index p = x.size();
    Eigen::MatrixXd j(f.size(), p);
    Eigen::VectorXd plus, minus;
    constexpr double kStep = 1e-6;
    for (Eigen::Index k = 0; k < p; ++k) {
      Eigen::VectorXd y = x;
      y[k] = x[k] + kStep;
      residuals(y, plus);
      y[k] = x[k] - kStep;
      residuals(y, minus);
      j.col(k) = (plus - minus) / (2.0 * kStep);
    }
    a = j.transpose() * j;
    g = j.transpose() * f;
  }
};

/// The unscrewed heights of a helix, cut at the middle of their widest empty stretch: a profile
/// that does not fill its strip is then one piece.
void placeCut(KinematicSurface& s, const Eigen::Matrix3Xd& points) {
  s.cut = 0.0;
  const double period = s.period();
  std::vector<double> h(static_cast<std::size_t>(points.cols()));
  for (Eigen::Index i = 0; i < points.cols(); ++i)
    h[static_cast<std::size_t>(i)] = profileCoordinates(s, points.col(i)).x();
  std::sort(h.begin(), h.end());
  double gap = h.front() + period - h.back(), cut = h.back() + 0.5 * gap;
  for (std::size_t k = 1; k < h.size(); ++k)
    if (h[k] - h[k - 1] > gap) {
      gap = h[k] - h[k - 1];
      cut = 0.5 * (h[k] + h[k - 1]);
    }
  s.cut = cut - period * std::floor(cut / period);
}

/// Fits the profile of \a s to \a points in its profile plane; false when it cannot.
bool fitProfile(KinematicSurface& s, const Eigen::Matrix3Xd& points, double noise,
                std::string& reason) {
  if (s.type == KinematicType::helix)
    placeCut(s, points);
  Eigen::Matrix2Xd q(2, points.cols());
  for (Eigen::Index i = 0; i < points.cols(); ++i)
    q.col(i) = profileCoordinates(s, points.col(i));
  // The profile's own thickness where it is below the surface noise given: the quadrics of the
  // surface-noise estimate read the bending of a sparse, fast-turning surface as noise (a column
  // twisted by 4 radians per unit, 5000 points at σ 0.002: σ̂ 0.059), the profile's parabolas
  // over its plane do not once the motion is right.
  if (noise > 0.0) {
    const double thickness = estimateProfileNoise(q, noise);
    if (thickness > 0.0)
      noise = std::min(noise, thickness);
  }
  noise = std::max(noise, kProfileTolerance);
  ProfileFit fit = fitProfileCurve(q, noise);
  if (!fit.ok) {
    reason = fit.reason;
    return false;
  }
  s.profile = std::move(fit.curve);
  return true;
}

double weightedRms(const KinematicSurface& s, const Eigen::Matrix3Xd& points,
                   const Eigen::VectorXd& w) {
  const KinematicProjector surface(s);
  double sum = 0.0;
  for (Eigen::Index i = 0; i < points.cols(); ++i) {
    const double d = surface.distance(points.col(i));
    sum += w[i] * d * d;
  }
  return std::sqrt(sum / w.sum());
}

KinematicFit failed(FitStatus status, std::string reason) {
  KinematicFit r;
  r.status = status;
  r.reason = "kinematic fit: " + std::move(reason);
  return r;
}

}  // namespace

KinematicFit fitKinematicSurface(const KinematicStart& start,
                                 const Eigen::Ref<const Eigen::Matrix3Xd>& points,
                                 const Eigen::Ref<const Eigen::VectorXd>& weights, double noise) {
  if (points.cols() != weights.size())
    return failed(FitStatus::invalid_input, "the weights do not match the points");
  if (!start.axis.allFinite() || !(start.axis.norm() > 0.0) || !start.point.allFinite() ||
      !std::isfinite(start.pitch) || !std::isfinite(noise) || noise < 0.0)
    return failed(FitStatus::invalid_input, "the start or the noise is not finite");
  if (start.type == KinematicType::helix && start.pitch == 0.0)
    return failed(FitStatus::invalid_input, "a helix needs a non-zero pitch");
  std::vector<Eigen::Index> used;
  for (Eigen::Index i = 0; i < points.cols(); ++i) {
    if (!(weights[i] >= 0.0) || !points.col(i).allFinite())
      return failed(FitStatus::invalid_input, "a point or weight is not finite or negative");
    if (weights[i] > 0.0)
      used.push_back(i);
  }
  if (used.size() < 20)
    return failed(FitStatus::too_few_points, "fewer than 20 points with weight");

  // Normalise: centre on the weighted centroid, unit weighted RMS radius.
  double total = 0.0;
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (Eigen::Index i : used) {
    total += weights[i];
    c += weights[i] * points.col(i);
  }
  c /= total;
  double s2 = 0.0;
  for (Eigen::Index i : used)
    s2 += weights[i] * (points.col(i) - c).squaredNorm();
  const double scale = std::sqrt(s2 / total);
  if (!(scale > 0.0))
    return failed(FitStatus::degenerate, "the points are on one spot");
  const auto m = static_cast<Eigen::Index>(used.size());
  Eigen::Matrix3Xd q(3, m);
  Eigen::VectorXd w(m);
  for (Eigen::Index k = 0; k < m; ++k) {
    q.col(k) = (points.col(used[static_cast<std::size_t>(k)]) - c) / scale;
    w[k] = weights[used[static_cast<std::size_t>(k)]];
  }
  const std::size_t stride = (used.size() + kProfilePoints - 1) / kProfilePoints;
  const auto ms = static_cast<Eigen::Index>((used.size() + stride - 1) / stride);
  Eigen::Matrix3Xd sub(3, ms);
  Eigen::VectorXd sub_sqrt_w(ms);
  for (Eigen::Index k = 0; k < ms; ++k) {
    sub.col(k) = q.col(k * static_cast<Eigen::Index>(stride));
    sub_sqrt_w[k] = std::sqrt(w[k * static_cast<Eigen::Index>(stride)]);
  }
  const double sigma = noise / scale;
  // The motion's points: every other (or more) of the profile's. Its five parameters do not need
  // all of them; each of its Jacobians refits the profile ten times.
  const Eigen::Index motion_stride =
      std::max<Eigen::Index>(1, (ms + static_cast<Eigen::Index>(kMotionPoints) - 1) /
                                    static_cast<Eigen::Index>(kMotionPoints));
  const Eigen::Index mm = (ms + motion_stride - 1) / motion_stride;
  Eigen::Matrix3Xd motion_points(3, mm);
  Eigen::VectorXd motion_sqrt_w(mm);
  for (Eigen::Index k = 0; k < mm; ++k) {
    motion_points.col(k) = sub.col(k * motion_stride);
    motion_sqrt_w[k] = sub_sqrt_w[k * motion_stride];
  }

  KinematicSurface s;
  s.type = start.type;
  s.axis = start.axis.normalized();
  s.reference = referenceAcross(s.axis);
  const Eigen::Vector3d foot = (start.point - c) / scale;
  s.point = start.type == KinematicType::extrusion
                ? Eigen::Vector3d::Zero()
                : Eigen::Vector3d(foot - foot.dot(s.axis) * s.axis);
  s.pitch = start.pitch / scale;

  std::string reason;
  if (s.type == KinematicType::helix) {
    // The screw's sense from the spectrum can come out either way: the one whose profile is the
    // thinner wins.
    KinematicSurface other = s;
    other.pitch = -s.pitch;
    std::string other_reason;
    const bool ok = fitProfile(s, sub, sigma, reason);
    const bool other_ok = fitProfile(other, sub, sigma, other_reason);
    if (other_ok && (!ok || weightedRms(other, sub, sub_sqrt_w.cwiseAbs2()) <
                                weightedRms(s, sub, sub_sqrt_w.cwiseAbs2())))
      s = other;
    else if (!ok)
      return failed(FitStatus::degenerate, reason);
  } else if (!fitProfile(s, sub, sigma, reason)) {
    return failed(FitStatus::degenerate, reason);
  }
  // The motion refined with its profile refitted at each step, then the profile fitted afresh at
  // the new motion (its vertices as few as the noise allows there), in rounds while a round lowers
  // the RMS distance by 1 % or more (at most kRounds): a helix read 9° and 25 % off its axis and
  // pitch by the spectrum of PCA normals takes four to six.
  constexpr int kRounds = 8;
  const Eigen::VectorXd sub_w = sub_sqrt_w.cwiseAbs2();
  double rms = weightedRms(s, sub, sub_w);
  for (int round = 0; round < kRounds; ++round) {
    const double before = rms;
    const MotionChart chart(s);
    const ProfiledResiduals problem{&chart, &motion_points, &motion_sqrt_w};
    Eigen::VectorXd x = Eigen::VectorXd::Zero(chart.size());
    LevenbergMarquardtSettings settings;
    settings.max_evaluations = 30;
    minimizeLevenbergMarquardt(problem, x, settings);
    KinematicSurface moved = problem.decode(x);
    if (moved.type == KinematicType::helix && !(std::abs(moved.pitch) > 0.0))
      break;
    double moved_rms = weightedRms(moved, sub, sub_w);
    // A fresh profile at the moved motion, from all the profile's points: simpler
    // (Douglas–Peucker), so kept unless clearly worse than the refined one, which the next round
    // refines.
    KinematicSurface fresh = moved;
    if (fitProfile(fresh, sub, sigma, reason)) {
      const double fresh_rms = weightedRms(fresh, sub, sub_w);
      if (fresh_rms <= 1.1 * moved_rms) {
        moved = std::move(fresh);
        moved_rms = fresh_rms;
      }
    }
    if (moved_rms < rms) {
      s = std::move(moved);
      rms = moved_rms;
    }
    if (rms > 0.99 * before)
      break;
  }

  KinematicFit out;
  out.used_points = used.size();
  out.rms_distance = scale * weightedRms(s, q, w);
  out.tolerance = scale * kProfileTolerance;
  // Back to the input's frame.
  s.point = c + scale * s.point;
  s.pitch *= scale;
  s.cut *= scale;
  for (Eigen::Vector2d& vertex : s.profile.vertices)
    vertex *= scale;
  out.surface = std::move(s);
  if (!std::isfinite(out.rms_distance))
    return failed(FitStatus::degenerate, "the distances overflowed");
  return out;
}

}  // namespace slipfit
