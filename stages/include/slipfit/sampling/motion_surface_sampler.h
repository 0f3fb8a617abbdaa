#pragma once
/// \file Seeded samplers of surfaces with exactly one slippable motion, for slippage tests and
/// users: a surface of revolution with a curved profile, linear extrusions of a closed and of an
/// open non-circular profile, a helicoid and a twisted column (helical surfaces). Points with
/// exact unit normals.

#include "slipfit/core/parameter_declaration.h"
#include "slipfit/sampling/sampler_parameters.h"

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <string_view>

namespace slipfit {

enum class MotionSurface {
  revolution,  ///< ρ(t) = radius (1 + 0.3 sin(2π t / length)) around z, t ∈ [0, length]: a vase
  extrusion,   ///< an ellipse with semi-axes radius and 0.5 radius swept along z over length
  helix,  ///< the helicoid (r cos θ, r sin θ, pitch θ), r ∈ [0.2, 1] radius, θ ∈ [0, length /
          ///< pitch]
  /// the sheet y = 0.3 radius sin(2π x / radius), x ∈ [−radius, radius], swept along z over length
  open_extrusion,
  /// the ellipse of extrusion turned by z / pitch radians at height z ∈ [0, length]: a twisted
  /// column, whose one motion is the screw (rotation about z, pitch per radian along it)
  twisted_column
};
constexpr std::array<std::pair<MotionSurface, std::string_view>, 5> kMotionSurfaceNames{{
    {MotionSurface::revolution, "revolution"},
    {MotionSurface::extrusion, "extrusion"},
    {MotionSurface::helix, "helix"},
    {MotionSurface::open_extrusion, "open_extrusion"},
    {MotionSurface::twisted_column, "twisted_column"},
}};

struct MotionSurfaceParameters {
  MotionSurface surface = MotionSurface::revolution;
  double radius = 1.0;  ///< > 0
  double length = 2.0;  ///< extent along the axis, > 0
  double pitch = 0.3;   ///< helix, twisted column: rise per radian, ≠ 0
  Eigen::Vector3d center = Eigen::Vector3d::Zero();  ///< where the surface's axis starts
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();   ///< direction of the axis (any length ≠ 0)
  std::size_t points = 5000;
  double noise = 0.0;  ///< σ of Gaussian position noise
  std::uint64_t seed = 1;

  /// Each user-facing field with its one declaration (parameter_declaration.h).
  template <typename Self, typename Visit>
  static void forEachParameter(Self& self, Visit&& visit) {
    visit(self.surface,
          parameter("shape",
                    "revolution: a vase ρ(t) = radius (1 + 0.3 sin(2π t / length)); extrusion: an "
                    "ellipse (radius, radius / 2) swept along the axis; helix: the helicoid (r cos "
                    "θ, r sin θ, pitch θ)."),
          kMotionSurfaceNames);
    visit(self.radius, parameter("radius", "Size across the axis.").in("units").above(0));
    visit(self.length, parameter("length", "Extent along the axis.").in("units").above(0));
    visit(self.pitch, parameter("pitch", "Helix: rise per radian (non-zero).").in("units/rad"));
    visit(self.center, parameter("center", "Where the surface's axis starts.").in("units"));
    visit(self.axis, parameter("axis", "Direction of the axis (normalised)."));
    visit(self.points, parameter("points", "Samples.").in("points").between(1, 1e9));
    visit(self.noise, positionNoiseParameter());
  }

  /// Throws InvalidParameterError naming the field, its value and the broken constraint.
  void validate() const;
};

/// Samples the surface in its own frame (axis z through the origin), adds the noise there, and
/// places it at \a center with its axis along \a axis: 3 × N points and unit normals.
void sampleMotionSurface(const MotionSurfaceParameters& parameters, Eigen::Matrix3Xd& points,
                         Eigen::Matrix3Xd& normals);

}  // namespace slipfit
