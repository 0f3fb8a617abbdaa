#include "slipfit/sampling/primitive_sampler.h"

#include "slipfit/core/angle_units.h"
#include "slipfit/core/exceptions.h"
#include "slipfit/sampling/random_vector.h"

#include <Eigen/Geometry>

#include <cmath>
#include <random>
#include <string>

namespace slipfit {

namespace {
[[noreturn]] void reject(const std::string& what) {
  throw InvalidParameterError("primitive sampling: " + what);
}
}  // namespace

Primitive PrimitiveDescription::primitive() const {
  validate();
  switch (type) {
    case PrimitiveType::plane:
      return Plane{normal.normalized(), d};
    case PrimitiveType::sphere:
      return Sphere{center, radius};
    case PrimitiveType::cylinder:
      return Cylinder{axis.normalized(), point, radius};
    case PrimitiveType::cone:
      return Cone{axis.normalized(), apex, half_angle};
    case PrimitiveType::torus:
      break;
  }
  return Torus{axis.normalized(), center, major_radius, minor_radius};
}

void PrimitiveSamplingParameters::validate() const {
  validateDeclared(*this, "primitive sampling");
  std::visit(
      [](const auto& s) {
        using T = std::decay_t<decltype(s)>;
        if constexpr (std::is_same_v<T, Plane>) {
          if (!(s.normal.allFinite() && s.normal.norm() > 0.0 && std::isfinite(s.d)))
            reject("the plane needs a finite non-zero normal and d");
        } else if constexpr (std::is_same_v<T, Sphere>) {
          if (!(s.center.allFinite() && s.radius > 0.0 && std::isfinite(s.radius)))
            reject("the sphere needs a finite centre and radius > 0");
        } else if constexpr (std::is_same_v<T, Cylinder>) {
          if (!(s.axis.allFinite() && s.axis.norm() > 0.0 && s.point.allFinite() &&
                s.radius > 0.0 && std::isfinite(s.radius)))
            reject("the cylinder needs a finite non-zero axis, a finite point and radius > 0");
        } else if constexpr (std::is_same_v<T, Torus>) {
          if (!(s.axis.allFinite() && s.axis.norm() > 0.0 && s.center.allFinite() &&
                s.minor_radius > 0.0 && s.minor_radius < s.major_radius &&
                std::isfinite(s.major_radius)))
            reject("the torus needs a finite non-zero axis, a finite centre and 0 < r < R");
        } else {
          if (!(s.axis.allFinite() && s.axis.norm() > 0.0 && s.apex.allFinite() &&
                s.half_angle > 0.0 && s.half_angle < kPi / 2))
            reject(
                "the cone needs a finite non-zero axis, a finite apex and 0 < half_angle < 90 "
                "degrees");
        }
      },
      primitive);
  if (points < 1)
    reject("points must be at least 1");
  if (!(extent > 0.0 && std::isfinite(extent)))
    reject("extent must be > 0");
  if (!(extent_min >= 0.0 && extent_min < extent))
    reject("extent_min must be in [0, extent)");
  if (!(angle_min >= 0.0 && angle_max <= 2 * kPi + 1e-12 && angle_min < angle_max))
    reject("the angle range must satisfy 0 <= min < max <= 360 degrees");
  if (!(cap > 0.0 && cap <= kPi + 1e-12))
    reject("cap must be in (0, 180] degrees");
  if (!(axis_hint.allFinite() && axis_hint.norm() > 0.0))
    reject("axis_hint must be non-zero");
  if (!(noise >= 0.0 && std::isfinite(noise)))
    reject("noise must be >= 0");
  if (!(normal_noise >= 0.0 && std::isfinite(normal_noise)))
    reject("normal_noise must be >= 0");
  if (!(outlier_fraction >= 0.0 && outlier_fraction <= 1.0))
    reject("outlier_fraction must be in [0, 1]");
  if (!(flip_fraction >= 0.0 && flip_fraction <= 1.0))
    reject("flip_fraction must be in [0, 1]");
}

void samplePrimitive(const PrimitiveSamplingParameters& p, Eigen::Matrix3Xd& points,
                     Eigen::Matrix3Xd& normals, std::vector<std::int32_t>* outlier) {
  p.validate();
  std::mt19937_64 rng(p.seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::normal_distribution<double> gauss(0.0, 1.0);
  const auto outliers =
      static_cast<std::size_t>(std::llround(p.outlier_fraction * static_cast<double>(p.points)));
  const auto total = static_cast<Eigen::Index>(p.points + outliers);
  points.resize(3, total);
  normals.resize(3, total);
  if (outlier)
    outlier->assign(static_cast<std::size_t>(total), 0);

  auto angle = [&]() { return p.angle_min + (p.angle_max - p.angle_min) * unit(rng); };
  for (Eigen::Index i = 0; i < static_cast<Eigen::Index>(p.points); ++i) {
    Eigen::Vector3d x, n;
    std::visit(
        [&](const auto& s) {
          using T = std::decay_t<decltype(s)>;
          if constexpr (std::is_same_v<T, Plane>) {
            const Eigen::Vector3d nn = s.normal.normalized();
            const Eigen::Vector3d u = nn.unitOrthogonal(), v = nn.cross(u);
            const double d = s.d / s.normal.norm();
            const Eigen::Vector2d w = randomVector<2>(unit, rng);
            x = nn * d + (2 * w(0) - 1) * p.extent * u + (2 * w(1) - 1) * p.extent * v;
            n = nn;
          } else if constexpr (std::is_same_v<T, Sphere>) {
            // Area-uniform on the cap: the height along the cap axis is uniform in [cos cap, 1].
            const Eigen::Vector3d a = p.axis_hint.normalized();
            const Eigen::Vector3d u = a.unitOrthogonal(), v = a.cross(u);
            const double z = std::cos(p.cap) + (1.0 - std::cos(p.cap)) * unit(rng);
            const double phi = 2 * kPi * unit(rng), r = std::sqrt(std::max(0.0, 1.0 - z * z));
            n = z * a + r * std::cos(phi) * u + r * std::sin(phi) * v;
            x = s.center + s.radius * n;
          } else if constexpr (std::is_same_v<T, Cylinder>) {
            const Eigen::Vector3d a = s.axis.normalized();
            const Eigen::Vector3d u = a.unitOrthogonal(), v = a.cross(u);
            const double phi = angle(), h = p.extent_min + (p.extent - p.extent_min) * unit(rng);
            n = std::cos(phi) * u + std::sin(phi) * v;
            x = s.point + h * a + s.radius * n;
          } else if constexpr (std::is_same_v<T, Torus>) {
            // Area element ∝ (R + r cos α) dα dβ: β uniform over the angle range, α by rejection.
            const Eigen::Vector3d a = s.axis.normalized();
            const Eigen::Vector3d u = a.unitOrthogonal(), v = a.cross(u);
            const double R = s.major_radius, r = s.minor_radius;
            double alpha = 0.0;
            do
              alpha = 2 * kPi * unit(rng);
            while (unit(rng) * (R + r) > R + r * std::cos(alpha));
            const double beta = angle();
            const Eigen::Vector3d radial = std::cos(beta) * u + std::sin(beta) * v;
            n = std::cos(alpha) * radial + std::sin(alpha) * a;
            x = s.center + R * radial + r * n;
          } else {
            const Eigen::Vector3d a = s.axis.normalized();
            const Eigen::Vector3d u = a.unitOrthogonal(), v = a.cross(u);
            // Area element ∝ h: h² uniform between the band's ends.
            const double h0 = p.extent_min, h1 = p.extent;
            const double h = std::sqrt(h0 * h0 + (h1 * h1 - h0 * h0) * unit(rng));
            const double phi = angle();
            const Eigen::Vector3d radial = std::cos(phi) * u + std::sin(phi) * v;
            x = s.apex + h * a + h * std::tan(s.half_angle) * radial;
            n = std::cos(s.half_angle) * radial - std::sin(s.half_angle) * a;
          }
        },
        p.primitive);
    if (p.noise > 0.0)
      x += p.noise * randomVector<3>(gauss, rng);
    if (p.normal_noise > 0.0)
      n = (n + p.normal_noise * randomVector<3>(gauss, rng)).normalized();
    if (p.flip_fraction > 0.0 && unit(rng) < p.flip_fraction)
      n = -n;
    points.col(i) = x;
    normals.col(i) = n;
  }
  if (outliers > 0) {
    const Eigen::Vector3d lo =
        points.leftCols(static_cast<Eigen::Index>(p.points)).rowwise().minCoeff();
    const Eigen::Vector3d hi =
        points.leftCols(static_cast<Eigen::Index>(p.points)).rowwise().maxCoeff();
    for (Eigen::Index i = static_cast<Eigen::Index>(p.points); i < total; ++i) {
      points.col(i) = lo + (hi - lo).cwiseProduct(randomVector<3>(unit, rng));
      Eigen::Vector3d n = randomVector<3>(gauss, rng);
      normals.col(i) = n.norm() > 0.0 ? n.normalized() : Eigen::Vector3d::UnitZ();
      if (outlier)
        (*outlier)[static_cast<std::size_t>(i)] = 1;
    }
  }
}

}  // namespace slipfit
