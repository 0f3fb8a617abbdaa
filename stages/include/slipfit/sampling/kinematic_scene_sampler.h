#pragma once
/// \file A labelled scene of kinematic surfaces among primitives, for the segmentation into
/// surfaces of revolution, extrusions and helices (issue 37): on a plate, a turned part (a random
/// meridian, its top a disc), an extruded random closed section (its top a flat face), a
/// threaded rod (a V-thread, its top a disc) and, unless left out, a cylinder and a sphere. Every
/// label comes with its exact truth: the primitive, or the kinematic surface with the polyline
/// profile its points were sampled from (kinematic_sampler.h). Points are uniform in area over
/// the whole scene, the plate's hidden under the parts left out.

#include "slipfit/core/parameter_declaration.h"
#include "slipfit/fitting/kinematic_surface.h"
#include "slipfit/fitting/primitives.h"

#include <Eigen/Core>

#include <cstdint>
#include <variant>
#include <vector>

namespace slipfit {

/// What a label truly is.
using SurfaceTruth = std::variant<Primitive, KinematicSurface>;

/// The type code of a truth: a primitive's PrimitiveType (0–4), then 5 + the KinematicType
/// (5 revolution, 6 extrusion, 7 helix).
std::int32_t truthTypeCode(const SurfaceTruth& truth);

struct KinematicSceneParameters {
  std::size_t points = 100000;  ///< surface samples in all, >= 100
  /// σ of the Gaussian position noise as a fraction of the median part size (a part's size: the
  /// larger of its height and its diameter). [0, 0.05].
  double noise = 0.0;
  bool primitives = true;  ///< also the cylinder and the sphere
  std::uint64_t seed = 1;

  /// Throws InvalidParameterError naming the field.
  void validate() const;
};

struct KinematicScene {
  Eigen::Matrix3Xd points, normals;  ///< 3 × N, exact unit normals (before the noise)
  std::vector<std::int32_t> labels;  ///< the true surface of each point
  std::vector<SurfaceTruth> truth;   ///< indexed by label: 0 the plate, then the parts' surfaces
  double median_size = 0.0;          ///< of the parts, units
};

/// Samples the scene: random profiles, sizes and places from the seed. Deterministic for given
/// parameters.
KinematicScene sampleKinematicScene(const KinematicSceneParameters& parameters);

}  // namespace slipfit
