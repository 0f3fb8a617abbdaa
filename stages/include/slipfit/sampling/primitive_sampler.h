#pragma once
/// \file Seeded, area-uniform sampling of planes, spheres, cylinders, cones and tori with known
/// parameters: noise, outliers, partial coverage, normal noise and random normal sign flips. The
/// test-cloud source with known answers for fitting and slippage.

#include "slipfit/core/angle_units.h"
#include "slipfit/core/parameter_declaration.h"
#include "slipfit/fitting/primitives.h"
#include "slipfit/sampling/sampler_parameters.h"

#include <Eigen/Core>

#include <cstdint>
#include <vector>

namespace slipfit {

/// One primitive written down field by field, as a config gives it: the type and the fields of
/// every type (those the type does not use are ignored). primitive() builds it.
struct PrimitiveDescription {
  PrimitiveType type = PrimitiveType::plane;
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  ///< plane: n of n·x = d (any length ≠ 0)
  double d = 0.0;                                     ///< plane: offset
  Eigen::Vector3d center = Eigen::Vector3d::Zero();   ///< sphere, torus
  double radius = 1.0;                                ///< sphere, cylinder
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();    ///< cylinder, cone, torus (any length ≠ 0)
  Eigen::Vector3d point = Eigen::Vector3d::Zero();    ///< cylinder: a point on the axis
  Eigen::Vector3d apex = Eigen::Vector3d::Zero();     ///< cone
  double half_angle = 30.0 * kDegree;                 ///< cone, radians
  double major_radius = 1.0, minor_radius = 0.25;     ///< torus

  /// Each user-facing field with its one declaration (parameter_declaration.h).
  template <typename Self, typename Visit>
  static void forEachParameter(Self& self, Visit&& visit) {
    visit(self.type, parameter("shape", "Primitive to sample."), kPrimitiveTypeNames);
    visit(self.normal, parameter("normal", "Plane: normal n (normalised) of n·x = d."));
    visit(self.d, parameter("d", "Plane: offset d of n·x = d.").in("units"));
    visit(self.center, parameter("center", "Sphere, torus: centre.").in("units"));
    visit(self.radius, parameter("radius", "Sphere, cylinder: radius.").in("units").above(0));
    visit(self.axis,
          parameter("axis",
                    "Cylinder, cone, torus: axis direction (cone: from the apex into the "
                    "opening)."));
    visit(self.point,
          parameter("point", "Cylinder: a point on the axis; heights are measured from it.")
              .in("units"));
    visit(self.apex, parameter("apex", "Cone: apex.").in("units"));
    visit(self.half_angle, parameter("half_angle", "Cone: half opening angle.")
                               .in("deg", kDegree)
                               .between(0.01, 89.99));
    visit(self.major_radius,
          parameter("major_radius", "Torus: radius R of the circle of tube centres.")
              .in("units")
              .above(0));
    visit(self.minor_radius,
          parameter("minor_radius", "Torus: tube radius r (0 < r < R).").in("units").above(0));
  }

  /// Throws InvalidParameterError naming a field out of its declared range.
  void validate() const { validateDeclared(*this, "primitive sampling"); }
  /// The primitive of `type`, its normal or axis normalised; validates first.
  Primitive primitive() const;
};

struct PrimitiveSamplingParameters {
  Primitive primitive = Plane{};
  std::size_t points = 10000;  ///< surface samples (outliers come on top), >= 1
  /// Extent along the surface, in the primitive's units:
  /// plane: the square [−extent, extent]² around the foot of the origin on the plane;
  /// cylinder: heights [extent_min, extent] along the axis from `point`;
  /// cone: axial distances [extent_min, extent] from the apex (a band away from it when > 0).
  double extent = 1.0;
  double extent_min = 0.0;
  /// Angular coverage around the axis (cylinder, cone, torus), radians, 0 ≤ min < max ≤ 2π.
  /// The torus is sampled all around its tube, area-uniform, and needs 0 < r < R.
  double angle_min = 0.0;
  double angle_max = 2.0 * kPi;
  /// Sphere: the cap of this half angle around +axis_hint (π: the whole sphere), radians.
  double cap = kPi;
  Eigen::Vector3d axis_hint = Eigen::Vector3d::UnitZ();  ///< sphere cap direction
  double noise = 0.0;             ///< σ of isotropic Gaussian position noise, units
  double normal_noise = 0.0;      ///< σ of the normal perturbation, radians
  double outlier_fraction = 0.0;  ///< outliers per surface sample, uniform in the samples' box
  double flip_fraction = 0.0;     ///< fraction of normals with flipped sign, [0, 1]
  std::uint64_t seed = 1;

  /// Each user-facing field with its one declaration (parameter_declaration.h); the primitive
  /// itself is declared by PrimitiveDescription.
  template <typename Self, typename Visit>
  static void forEachParameter(Self& self, Visit&& visit) {
    visit(self.extent,
          parameter("extent",
                    "Plane: half side of the square; cylinder: largest height; cone: largest "
                    "axial distance from the apex.")
              .in("units")
              .above(0));
    visit(self.extent_min,
          parameter("extent_min",
                    "Cylinder: smallest height; cone: smallest axial distance (a band away from "
                    "the apex).")
              .in("units")
              .atLeast(0));
    visit(self.angle_min,
          parameter("angle_min", "Cylinder, cone, torus: coverage around the axis starts here.")
              .in("deg", kDegree)
              .atLeast(0)
              .below(360));
    visit(self.angle_max,
          parameter("angle_max",
                    "Cylinder, cone, torus: coverage around the axis ends here (above "
                    "angle_min).")
              .in("deg", kDegree)
              .above(0)
              .atMost(360));
    visit(self.cap,
          parameter("cap",
                    "Sphere: half angle of the spherical cap around cap_axis (180: whole sphere).")
              .in("deg", kDegree)
              .between(0.01, 180));
    visit(self.axis_hint, parameter("cap_axis", "Sphere: direction of the cap's centre."));
    visit(self.points, surfaceSamplesParameter());
    visit(self.noise, positionNoiseParameter());
    visit(self.normal_noise, normalNoiseParameter());
    visit(self.outlier_fraction,
          parameter("outliers",
                    "Outliers per surface sample, uniform in the samples' box; field 'outlier'.")
              .between(0, 1));
    visit(self.flip_fraction,
          parameter("flips", "Fraction of normals with flipped sign.").between(0, 1));
  }

  /// Throws InvalidParameterError naming the field.
  void validate() const;
};

/// Samples: 3 × N points and unit normals (outward for surface samples before flips), and
/// optionally 1 for outliers / 0 for surface samples. Deterministic for given parameters.
void samplePrimitive(const PrimitiveSamplingParameters& parameters, Eigen::Matrix3Xd& points,
                     Eigen::Matrix3Xd& normals, std::vector<std::int32_t>* outlier = nullptr);

}  // namespace slipfit
