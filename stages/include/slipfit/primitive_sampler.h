#pragma once
/// \file Seeded, area-uniform sampling of planes, spheres, cylinders, cones and tori with known
/// parameters: noise, outliers, partial coverage, normal noise and random normal sign flips. The
/// test-cloud source with known answers for fitting and slippage.

#include "slipfit/angle_units.h"
#include "slipfit/primitives.h"

#include <Eigen/Core>

#include <cstdint>
#include <vector>

namespace slipfit {

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

  /// Throws InvalidParameterError naming the field.
  void validate() const;
};

/// Samples: 3 × N points and unit normals (outward for surface samples before flips), and
/// optionally 1 for outliers / 0 for surface samples. Deterministic for given parameters.
void samplePrimitive(const PrimitiveSamplingParameters& parameters, Eigen::Matrix3Xd& points,
                     Eigen::Matrix3Xd& normals, std::vector<std::int32_t>* outlier = nullptr);

}  // namespace slipfit
