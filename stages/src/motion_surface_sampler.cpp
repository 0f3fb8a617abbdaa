#include "slipfit/motion_surface_sampler.h"

#include "slipfit/exceptions.h"

#include <cmath>
#include <random>

namespace slipfit {

namespace {
constexpr double kPi = 3.14159265358979323846;
}

void MotionSurfaceParameters::validate() const {
  if (!(radius > 0.0 && std::isfinite(radius)))
    throw InvalidParameterError("motion surface: radius must be > 0");
  if (!(length > 0.0 && std::isfinite(length)))
    throw InvalidParameterError("motion surface: length must be > 0");
  if (surface == MotionSurface::helix && !(std::abs(pitch) > 0.0 && std::isfinite(pitch)))
    throw InvalidParameterError("motion surface: a helix needs a non-zero pitch");
  if (points < 1)
    throw InvalidParameterError("motion surface: points must be at least 1");
  if (!(noise >= 0.0 && std::isfinite(noise)))
    throw InvalidParameterError("motion surface: noise must be >= 0");
}

void sampleMotionSurface(const MotionSurfaceParameters& p, Eigen::Matrix3Xd& points,
                         Eigen::Matrix3Xd& normals) {
  p.validate();
  std::mt19937_64 rng(p.seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::normal_distribution<double> gauss(0.0, 1.0);
  const auto n = static_cast<Eigen::Index>(p.points);
  points.resize(3, n);
  normals.resize(3, n);
  for (Eigen::Index i = 0; i < n; ++i) {
    Eigen::Vector3d x = Eigen::Vector3d::Zero(), nn = Eigen::Vector3d::UnitZ();
    switch (p.surface) {
      case MotionSurface::revolution: {
        const double t = p.length * unit(rng), phi = 2 * kPi * unit(rng);
        const double k = 2 * kPi / p.length;
        const double rho = p.radius * (1.0 + 0.3 * std::sin(k * t));
        const double drho = p.radius * 0.3 * k * std::cos(k * t);
        const Eigen::Vector3d radial(std::cos(phi), std::sin(phi), 0.0);
        x = rho * radial + t * Eigen::Vector3d::UnitZ();
        nn = (radial - drho * Eigen::Vector3d::UnitZ())
                 .normalized();  // ⟂ the profile tangent (ρ', 1)
        break;
      }
      case MotionSurface::extrusion: {
        const double phi = 2 * kPi * unit(rng), z = p.length * unit(rng);
        const double a = p.radius, b = 0.5 * p.radius;
        x = Eigen::Vector3d(a * std::cos(phi), b * std::sin(phi), z);
        nn = Eigen::Vector3d(b * std::cos(phi), a * std::sin(phi), 0.0).normalized();
        break;
      }
      case MotionSurface::helix: {
        const double theta = p.length / std::abs(p.pitch) * unit(rng),
                     r = p.radius * (0.2 + 0.8 * unit(rng));
        x = Eigen::Vector3d(r * std::cos(theta), r * std::sin(theta), p.pitch * theta);
        // ∂x/∂r × ∂x/∂θ = (cos θ, sin θ, 0) × (−r sin θ, r cos θ, h).
        nn = Eigen::Vector3d(p.pitch * std::sin(theta), -p.pitch * std::cos(theta), r).normalized();
        break;
      }
    }
    if (p.noise > 0.0)
      x += p.noise * Eigen::Vector3d(gauss(rng), gauss(rng), gauss(rng));
    points.col(i) = x;
    normals.col(i) = nn;
  }
}

}  // namespace slipfit
