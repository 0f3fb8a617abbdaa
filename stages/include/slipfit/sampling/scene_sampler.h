#pragma once
/// \file A labelled test scene: a box, a cylinder, a sphere and a cone standing on a ground
/// plane, sampled area-uniformly with known primitives per label — the ground truth for
/// segmentation tests and the segmentation benchmark.

#include "slipfit/fitting/primitives.h"

#include <Eigen/Core>

#include <cstdint>
#include <vector>

namespace slipfit {

struct SceneSamplingParameters {
  std::size_t points = 100000;  ///< surface samples (outliers come on top), >= 100
  /// σ of the Gaussian position noise as a fraction of the object size (1 unit: the box is
  /// 0.8 × 0.8 × 0.6, the ground 4 × 4). [0, 0.1].
  double noise = 0.0;
  double outlier_fraction = 0.0;  ///< outliers per surface sample, uniform in the scene's box
  std::uint64_t seed = 1;

  /// Throws InvalidParameterError naming the field.
  void validate() const;
};

/// One true primitive of the scene: the surface it lies on and a short name ("box top").
struct ScenePrimitive {
  Primitive primitive;
  const char* name;
};

/// The scene's primitives; label i of sampleScene is entry i. Ten of them: ground, the box's top
/// and four sides, the cylinder's side and top, the sphere, the cone's side.
const std::vector<ScenePrimitive>& scenePrimitives();

/// Samples the scene: 3 × N points, unit outward normals (exact, before noise) and per point the
/// true label (−1 for outliers). Deterministic for given parameters.
void sampleScene(const SceneSamplingParameters& parameters, Eigen::Matrix3Xd& points,
                 Eigen::Matrix3Xd& normals, std::vector<std::int32_t>& labels);

}  // namespace slipfit
