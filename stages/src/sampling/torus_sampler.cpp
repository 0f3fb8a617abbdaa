#include "slipfit/sampling/torus_sampler.h"

#include "slipfit/core/angle_units.h"
#include "slipfit/core/exceptions.h"
#include "slipfit/sampling/random_vector.h"

#include <cmath>
#include <random>
#include <string>

namespace slipfit {

namespace {

[[noreturn]] void reject(const std::string& what) {
  throw InvalidParameterError("torus sampling: " + what);
}

bool inRange(double a, double lo, double hi) {
  // Coverage ranges are given in [0, 2π]; compare the angle folded into the same interval.
  a = std::fmod(a, 2.0 * kPi);
  if (a < 0.0)
    a += 2.0 * kPi;
  return a >= lo && a <= hi;
}
}  // namespace

void TorusSamplingParameters::validate() const {
  validateDeclared(*this, "torus sampling");
  shape.validate();
  if (!center.allFinite())
    reject("center must be finite");
  if (!axis.allFinite() || axis.norm() == 0.0)
    reject("axis must be a finite non-zero vector");
  if (!std::isfinite(spin))
    reject("spin must be finite");
  if (points < 1)
    reject("points must be at least 1");
  auto check_range = [](double lo, double hi, const char* name) {
    if (!(lo >= 0.0 && hi <= 2.0 * kPi + 1e-12 && lo < hi))
      reject(std::string(name) + " range must satisfy 0 <= min < max <= 360 degrees");
  };
  check_range(alpha_min, alpha_max, "alpha");
  check_range(beta_min, beta_max, "beta");
  if (!(noise >= 0.0 && std::isfinite(noise)))
    reject("noise must be >= 0, got " + std::to_string(noise));
  if (!(normal_noise >= 0.0 && std::isfinite(normal_noise)))
    reject("normal_noise must be >= 0, got " + std::to_string(normal_noise));
  if (!(outlier_fraction >= 0.0 && outlier_fraction <= 1.0))
    reject("outlier_fraction must be in [0, 1], got " + std::to_string(outlier_fraction));
}

Eigen::Isometry3d TorusSamplingParameters::pose() const {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), axis.normalized())
                   .toRotationMatrix() *
               Eigen::AngleAxisd(spin, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  t.translation() = center;
  return t;
}

void TorusSampler::sample(pcl::PointCloud<pcl::PointNormal>& cloud,
                          std::vector<std::int32_t>* outlier) const {
  Eigen::Matrix3Xd points, normals;
  sample(points, normals, outlier);
  cloud.resize(static_cast<std::size_t>(points.cols()));
  for (Eigen::Index i = 0; i < points.cols(); ++i) {
    cloud[i].getVector3fMap() = points.col(i).cast<float>();
    cloud[i].getNormalVector3fMap() = normals.col(i).cast<float>();
    cloud[i].curvature = std::numeric_limits<float>::quiet_NaN();
  }
  cloud.width = static_cast<std::uint32_t>(cloud.size());
  cloud.height = 1;
  cloud.is_dense = true;
}

void TorusSampler::sample(Eigen::Matrix3Xd& points, Eigen::Matrix3Xd& normals,
                          std::vector<std::int32_t>* outlier) const {
  const TorusSamplingParameters& p = parameters_;
  p.validate();
  const TorusShape& t = p.shape;
  const Eigen::Isometry3d pose = p.pose();
  const TorusBezier bezier(t);
  std::mt19937_64 rng(p.seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::normal_distribution<double> gauss(0.0, 1.0);

  const auto outliers =
      static_cast<std::size_t>(std::llround(p.outlier_fraction * static_cast<double>(p.points)));
  const std::size_t total = p.points + outliers;
  points.resize(3, static_cast<Eigen::Index>(total));
  normals.resize(3, static_cast<Eigen::Index>(total));
  if (outlier)
    outlier->assign(total, 0);

  // Rejection keeps every mode exact under partial coverage; give up when the coverage is so
  // small that almost nothing is accepted.
  const std::size_t max_attempts = 1000 * p.points + 100000;
  std::size_t attempts = 0;
  Eigen::Index count = 0;
  while (static_cast<std::size_t>(count) < p.points) {
    if (++attempts > max_attempts)
      throw DegenerateInputError("torus sampling: the coverage ranges accept almost no sample");
    double a = 0.0, b = 0.0;
    switch (p.sampling) {
      case TorusSampling::angle:
      case TorusSampling::area:
        a = p.alpha_min + (p.alpha_max - p.alpha_min) * unit(rng);
        b = p.beta_min + (p.beta_max - p.beta_min) * unit(rng);
        // Area element r (R + r cos α): accept with probability (R + r cos α) / (R + r).
        if (p.sampling == TorusSampling::area && unit(rng) * (t.R + t.r) > t.R + t.r * std::cos(a))
          continue;
        break;
      case TorusSampling::parameter: {
        const int quarter = static_cast<int>(unit(rng) * 4.0) & 3;
        const double ua = quarterAngle(unit(rng)), vb = quarterAngle(unit(rng));
        a = (quarter & 1) ? 2.0 * kPi - ua : ua;
        b = (quarter & 2) ? 2.0 * kPi - vb : vb;
        if (!inRange(a, p.alpha_min, p.alpha_max) || !inRange(b, p.beta_min, p.beta_max))
          continue;
        break;
      }
    }
    const SurfacePoint s = bezier.evaluate(a, b);
    Eigen::Vector3d x = pose * s.position;
    Eigen::Vector3d n = pose.linear() * s.normal;
    if (p.noise > 0.0)
      x += p.noise * randomVector<3>(gauss, rng);
    if (p.normal_noise > 0.0)
      n = (n + p.normal_noise * randomVector<3>(gauss, rng)).normalized();
    points.col(count) = x;
    normals.col(count) = n;
    ++count;
  }
  // Outliers: uniform in the torus' world bounding box, random unit normals.
  const double e = t.R + t.r;
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::max()), hi = -lo;
  for (int k = 0; k < 8; ++k) {
    const Eigen::Vector3d c =
        pose * Eigen::Vector3d((k & 1) ? e : -e, (k & 2) ? e : -e, (k & 4) ? t.r : -t.r);
    lo = lo.cwiseMin(c);
    hi = hi.cwiseMax(c);
  }
  for (std::size_t k = 0; k < outliers; ++k) {
    const Eigen::Vector3d x = lo + (hi - lo).cwiseProduct(randomVector<3>(unit, rng));
    Eigen::Vector3d n = randomVector<3>(gauss, rng);
    n = n.norm() > 0.0 ? n.normalized() : Eigen::Vector3d::UnitZ();
    points.col(count) = x;
    normals.col(count) = n;
    ++count;
    if (outlier)
      (*outlier)[p.points + k] = 1;
  }
}

}  // namespace slipfit
