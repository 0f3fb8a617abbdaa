#include "slipfit/sampling/motion_surface_sampler.h"

#include "slipfit/core/angle_units.h"
#include "slipfit/core/exceptions.h"
#include "slipfit/sampling/random_vector.h"

#include <Eigen/Geometry>

#include <cmath>
#include <random>

namespace slipfit {

namespace {}

void MotionSurfaceParameters::validate() const {
  validateDeclared(*this, "motion surface");
  if ((surface == MotionSurface::helix || surface == MotionSurface::twisted_column) &&
      !(std::abs(pitch) > 0.0 && std::isfinite(pitch)))
    throw InvalidParameterError("motion surface: a helix or twisted column needs a non-zero pitch");
  if (!center.allFinite())
    throw InvalidParameterError("motion surface: center must be finite");
  if (!axis.allFinite() || !(axis.norm() > 0.0))
    throw InvalidParameterError("motion surface: axis must be a finite non-zero vector");
}

void sampleMotionSurface(const MotionSurfaceParameters& p, Eigen::Matrix3Xd& points,
                         Eigen::Matrix3Xd& normals) {
  p.validate();
  std::mt19937_64 rng(p.seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::normal_distribution<double> gauss(0.0, 1.0);
  const auto n = static_cast<Eigen::Index>(p.points);
  const Eigen::Matrix3d rotation =
      Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), p.axis.normalized())
          .toRotationMatrix();
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
      case MotionSurface::open_extrusion: {
        const double u = p.radius * (2 * unit(rng) - 1), z = p.length * unit(rng);
        const double k = 2 * kPi / p.radius, amplitude = 0.3 * p.radius;
        x = Eigen::Vector3d(u, amplitude * std::sin(k * u), z);
        nn = Eigen::Vector3d(-amplitude * k * std::cos(k * u), 1.0, 0.0).normalized();
        break;
      }
      case MotionSurface::twisted_column: {
        // The section (a cos φ, b sin φ) turned by θ = z / pitch: x = R(θ) s(φ) + z e_z, with
        // ∂x/∂φ = R(θ) s'(φ) and ∂x/∂z = e_z × R(θ) s(φ) / pitch + e_z.
        const double phi = 2 * kPi * unit(rng), z = p.length * unit(rng), theta = z / p.pitch;
        const double a = p.radius, b = 0.5 * p.radius;
        const Eigen::Vector3d section(a * std::cos(phi), b * std::sin(phi), 0.0);
        const Eigen::Vector3d tangent(-a * std::sin(phi), b * std::cos(phi), 0.0);
        const Eigen::Matrix3d turn =
            Eigen::AngleAxisd(theta, Eigen::Vector3d::UnitZ()).toRotationMatrix();
        x = turn * section + z * Eigen::Vector3d::UnitZ();
        const Eigen::Vector3d dz =
            Eigen::Vector3d::UnitZ().cross(turn * section) / p.pitch + Eigen::Vector3d::UnitZ();
        nn = (turn * tangent).cross(dz).normalized();
        break;
      }
    }
    if (p.noise > 0.0)
      x += p.noise * randomVector<3>(gauss, rng);
    points.col(i) = rotation * x + p.center;
    normals.col(i) = rotation * nn;
  }
}

}  // namespace slipfit
